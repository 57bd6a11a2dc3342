//! Snapshot-image tests of the offscreen renderer: small fixed scenes at 160×120
//! compared with `tests/snapshots/*.png` (see `perifrac_tests` for the tolerance and
//! `UPDATE_SNAPSHOTS=1`), deliberate perturbations that must fail, byte-identical
//! repeats, and the EGL → OSMesa fallback.
#![cfg(feature = "gl")]

use std::cell::RefCell;
use std::process::Command;

use image::RgbImage;
use perifrac_render::geometry::FrameGeometry;
use perifrac_render::gl::{Backend, Renderer, View};
use perifrac_tests::{SIZE, TOLERANCE, camera, camera_bounds, check_snapshot, difference};

thread_local! {
    static RENDERER: RefCell<Option<Renderer>> = const { RefCell::new(None) };
}

fn view() -> View {
    View {
        camera: camera(),
        bounds: camera_bounds(),
        ground: 0.0,
        key_strength: 1.0,
    }
}

/// Renders on this thread's renderer (one GL context a test thread).
fn render_with(geometry: &FrameGeometry, view: &View) -> (RgbImage, usize) {
    RENDERER.with(|cell| {
        let mut slot = cell.borrow_mut();
        if slot.is_none() {
            *slot =
                Some(Renderer::new(SIZE.0, SIZE.1).expect("a GL context (run scripts/setup.sh)"));
        }
        let r = slot
            .as_mut()
            .unwrap()
            .render(geometry, view)
            .expect("render");
        (r.image, r.in_view)
    })
}

fn render(geometry: &FrameGeometry) -> RgbImage {
    render_with(geometry, &view()).0
}

#[test]
fn mesh_matches_its_snapshot() {
    check_snapshot("mesh", &render(&perifrac_tests::torus([0.0; 3]))).unwrap();
}

#[test]
fn particles_match_their_snapshot() {
    check_snapshot("particles", &render(&perifrac_tests::particles())).unwrap();
}

#[test]
fn crack_faces_match_their_snapshot() {
    check_snapshot("crack", &render(&perifrac_tests::cracked_block())).unwrap();
}

#[test]
fn empty_frame_renders_the_ground_and_says_so() {
    let (image, in_view) = render_with(&perifrac_tests::empty(), &view());
    assert_eq!(in_view, 0, "an empty frame must be reported as such");
    check_snapshot("empty", &image).unwrap();
    // The ground is there: the bottom row is lit floor, not the flat backdrop of the
    // top row.
    let top = image.get_pixel(SIZE.0 / 2, 0);
    let bottom = image.get_pixel(SIZE.0 / 2, SIZE.1 - 1);
    assert_ne!(top, bottom, "no ground drawn");
}

/// A standing sheet of zero thickness (a 0.5 m square in the z = 0 plane, two
/// triangles) whose normals all point to `normal_z` (±1), as a membrane's sheet.
fn zero_thickness_sheet(normal_z: f32) -> FrameGeometry {
    let mut g = perifrac_tests::empty();
    let square = [
        [-0.25, 0.05, 0.0],
        [0.25, 0.05, 0.0],
        [0.25, 0.55, 0.0],
        [-0.25, 0.55, 0.0],
    ];
    g.push_mesh(
        &square,
        Some(&[[0.0, 0.0, normal_z]; 4]),
        &|_| perifrac_render::geometry::surface_color(),
        &[0, 1, 2, 0, 2, 3],
        perifrac_render::geometry::Shading::Surface,
    );
    g
}

/// Mean brightness (0–255) of the pixels of `image` that differ from `background`.
fn covered(image: &RgbImage, background: &RgbImage) -> (usize, f64) {
    let (mut n, mut sum) = (0, 0.0);
    for (p, q) in image.pixels().zip(background.pixels()) {
        if p != q {
            n += 1;
            sum += p.0.iter().map(|&c| c as f64).sum::<f64>() / 3.0;
        }
    }
    (n, sum / n.max(1) as f64)
}

/// A membrane's sheet has no thickness: seen from behind (its normals pointing away)
/// it must be neither culled nor black. The mesh shader turns a normal that faces
/// away towards the eye, so the sheet renders the same whichever way its normals
/// point, from the front and from behind.
#[test]
fn a_zero_thickness_sheet_is_lit_from_both_sides() {
    let empty = render(&perifrac_tests::empty());
    let front = render(&zero_thickness_sheet(1.0));
    let back_facing = render(&zero_thickness_sheet(-1.0));
    assert_eq!(
        front.as_raw(),
        back_facing.as_raw(),
        "shaded by the side seen"
    );
    let (pixels, brightness) = covered(&front, &empty);
    println!("front: {pixels} pixels, mean brightness {brightness:.0}");
    assert!(pixels > 1000, "the sheet covers {pixels} pixels");
    assert!(brightness > 100.0, "front mean brightness {brightness}");
    // From behind (azimuth 180° + the default): the same sheet, its normals away.
    let behind = View {
        camera: perifrac_render::camera::Camera::framing(
            &camera_bounds(),
            SIZE.0 as f32 / SIZE.1 as f32,
            perifrac_render::camera::AZIMUTH + std::f32::consts::PI,
        ),
        ..view()
    };
    let (empty_behind, _) = render_with(&perifrac_tests::empty(), &behind);
    let (back, _) = render_with(&zero_thickness_sheet(1.0), &behind);
    let (pixels, brightness) = covered(&back, &empty_behind);
    println!("behind: {pixels} pixels, mean brightness {brightness:.0}");
    assert!(
        pixels > 1000,
        "seen from behind the sheet covers {pixels} pixels"
    );
    assert!(
        brightness > 100.0,
        "seen from behind: mean brightness {brightness}"
    );
}

/// World-space shift that moves the torus by `pixels` pixels to the right of the image.
fn shift_by_pixels(pixels: f32) -> [f32; 3] {
    let cam = camera();
    let distance = perifrac_math::dist(cam.eye, cam.target);
    let metres_per_pixel = 2.0 * distance * (0.5 * cam.fov_y).tan() / SIZE.1 as f32;
    cam.right().map(|v| v * pixels * metres_per_pixel)
}

#[test]
fn a_two_pixel_move_fails_the_comparison() {
    let reference = render(&perifrac_tests::torus([0.0; 3]));
    let moved = render(&perifrac_tests::torus(shift_by_pixels(2.0)));
    let d = difference(&moved, &reference).unwrap();
    assert!(
        !d.passes(&TOLERANCE),
        "a 2-pixel move passed: {} px, mean {:.3}",
        d.pixels,
        d.mean
    );
    // And a repeat of the same scene passes.
    let again = render(&perifrac_tests::torus([0.0; 3]));
    assert!(difference(&again, &reference).unwrap().passes(&TOLERANCE));
}

#[test]
fn a_changed_light_fails_the_comparison() {
    let reference = render(&perifrac_tests::torus([0.0; 3]));
    let dimmer = View {
        key_strength: 0.8,
        ..view()
    };
    let (changed, _) = render_with(&perifrac_tests::torus([0.0; 3]), &dimmer);
    let d = difference(&changed, &reference).unwrap();
    assert!(
        !d.passes(&TOLERANCE),
        "a 20 % dimmer key light passed: {} px, mean {:.3}",
        d.pixels,
        d.mean
    );
}

#[test]
fn the_same_frame_twice_gives_identical_bytes() {
    let g = perifrac_tests::cracked_block();
    let a = render(&g);
    let b = render(&g);
    assert_eq!(a.as_raw(), b.as_raw());
    // A fresh context on another thread too.
    let c = std::thread::spawn(move || render(&g)).join().unwrap();
    assert_eq!(a.as_raw(), c.as_raw());
}

/// Runs one `#[ignore]`d test of this binary in a child process with `env` set.
fn run_child(test: &str, env: &[(&str, &str)]) -> std::process::Output {
    let exe = std::env::current_exe().unwrap();
    let mut cmd = Command::new(exe);
    cmd.args([
        test,
        "--exact",
        "--ignored",
        "--nocapture",
        "--test-threads",
        "1",
    ]);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().unwrap()
}

#[test]
fn without_egl_the_renderer_falls_back_to_osmesa() {
    let out = run_child(
        "child_renders_with_osmesa_and_matches",
        &[("PERIFRAC_EGL_LIB", "/nonexistent/libEGL.so.1")],
    );
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
#[ignore = "run by without_egl_the_renderer_falls_back_to_osmesa in a child process"]
fn child_renders_with_osmesa_and_matches() {
    let mut r = Renderer::new(SIZE.0, SIZE.1).unwrap();
    assert_eq!(r.backend(), Backend::OsMesa);
    let image = r
        .render(&perifrac_tests::cracked_block(), &view())
        .unwrap()
        .image;
    check_snapshot("crack", &image).unwrap();
}

#[test]
fn without_egl_and_osmesa_the_error_names_both() {
    let out = run_child(
        "child_reports_missing_libraries",
        &[
            ("PERIFRAC_EGL_LIB", "/nonexistent/libEGL.so.1"),
            ("PERIFRAC_OSMESA_LIB", "/nonexistent/libOSMesa.so.8"),
        ],
    );
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
#[ignore = "run by without_egl_and_osmesa_the_error_names_both in a child process"]
fn child_reports_missing_libraries() {
    let err = Renderer::new(SIZE.0, SIZE.1)
        .err()
        .expect("no context without libraries")
        .to_string();
    assert!(
        err.contains("libEGL.so.1") && err.contains("libOSMesa.so.8"),
        "{err}"
    );
    assert!(err.contains("setup.sh"), "{err}");
}
