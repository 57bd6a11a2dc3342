//! Previews a supervisor signs off (issue 36): the demo's last frame framed on the
//! action with the ball in view, bodies coloured by material, and the movie read back
//! by decoders we did not write.
#![cfg(feature = "gl")]

use std::path::Path;
use std::process::Command;

use image::RgbImage;
use perifrac_render::cache::Cache;
use perifrac_render::geometry::{FrameGeometry, MESH_STRIDE, Shading};
use perifrac_render::gl::Renderer;
use perifrac_render::preview::{PreviewOptions, sequence_view, spreads};

mod common;
use common::perifrac_ok;

/// The demo (assets/scenes/demo.toml: a steel ball at 50 m/s through a glass wall on
/// the ground), coarse and short: λ = 0.025 m, 2.4 ms in 6 frames, particles only.
const SMALL_DEMO: &str = r#"[scene]
name = "small-demo"
duration = 0.0024
fps = 2500.0
gravity = [0.0, -9.81, 0.0]

[materials.glass]
density = 2200.0
bulk_modulus = 3.3e10
shear_modulus = 2.0e10
critical_stretch = 0.0005
critical_compression = 0.01

[[body]]
name = "wall"
material = "glass"
shape = { type = "box", center = [0.0, 0.2, 0.0], size = [0.4, 0.4, 0.05] }
resolution = 0.025
horizon = 1.45

[[collider]]
type = "ground"

[[collider]]
type = "sphere"
center = [0.0, 0.2, -0.08]
radius = 0.05
velocity = [0.0, 0.0, 50.0]
mass = 4.11
friction = 0.5

[output]
checkpoint_every = 0
preview = false
"#;

/// Two still blocks side by side, of two materials with their own colours.
const TWO_MATERIALS: &str = r##"[scene]
name = "two-materials"
duration = 0.002
fps = 1000.0

[materials.brick]
density = 1000.0
youngs_modulus = 1.0e6
poisson_ratio = 0.3
color = "#C83C28"

[materials.slate]
density = 1000.0
youngs_modulus = 1.0e6
poisson_ratio = 0.3
color = [0.15, 0.35, 0.85]

[[body]]
name = "left"
material = "brick"
shape = { type = "box", center = [-0.08, 0.05, 0.0], size = [0.1, 0.1, 0.1] }
resolution = 0.02

[[body]]
name = "right"
material = "slate"
shape = { type = "box", center = [0.08, 0.05, 0.0], size = [0.1, 0.1, 0.1] }
resolution = 0.02

[[collider]]
type = "ground"

[output]
checkpoint_every = 0
preview = false
playback_fps = 12
SURFACE
"##;

/// Runs `scene` into `dir/out`.
fn run(dir: &Path, scene: &str) -> std::path::PathBuf {
    let file = dir.join("scene.toml");
    std::fs::write(&file, scene).unwrap();
    let out = dir.join("out");
    perifrac_ok(&["run", file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    out
}

/// Pixels where `a` and `b` differ by more than a faint anti-aliasing edge.
fn differing(a: &RgbImage, b: &RgbImage) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| {
            (0..3)
                .map(|k| (p[k] as i32 - q[k] as i32).abs())
                .sum::<i32>()
                > 24
        })
        .count()
}

/// `g` without the colliders' triangles.
fn without_colliders(g: &FrameGeometry) -> FrameGeometry {
    let collider =
        |i: u32| g.mesh_vertices[i as usize * MESH_STRIDE + 9] == Shading::Collider as u32 as f32;
    let mut out = g.clone();
    out.mesh_indices = g
        .mesh_indices
        .chunks_exact(3)
        .filter(|t| !t.iter().any(|&i| collider(i)))
        .flatten()
        .copied()
        .collect();
    out
}

/// Issue 36: the demo's ball was hidden behind the wall in every default frame, and
/// the wall with its debris and shadow covered 13 % of the image. Measured from the
/// image of the last frame: removing the ball changes a visible patch of pixels, and
/// the subject (everything that differs from the empty studio) covers at least a
/// quarter of it (docs/previews.md).
#[test]
fn the_demo_s_last_frame_fills_the_image_and_shows_the_ball() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), SMALL_DEMO);
    let cache = Cache::open(&out).unwrap();
    let options = PreviewOptions {
        width: 480,
        height: 270,
        ..PreviewOptions::default()
    };
    let (view, _, ranges) = sequence_view(&cache, &options).unwrap();
    // The camera `perifrac run` uses by default (CameraMotion::Auto) is this fixed one:
    // the demo's pieces stay within a few times the wall's size.
    let framing = cache.sequence_framing(options.color_by).unwrap();
    assert!(!spreads(&framing), "the 4 ms demo keeps one camera");
    let last = *cache.frames.last().unwrap();
    let g = cache.geometry(last, options.color_by, &ranges).unwrap();
    let mut renderer = Renderer::new(options.width, options.height).expect("a GL context");
    let image = renderer.render(&g, &view).unwrap().image;
    let studio = FrameGeometry {
        ground: g.ground,
        ..FrameGeometry::default()
    };
    let empty = renderer.render(&studio, &view).unwrap().image;
    let no_ball = renderer
        .render(&without_colliders(&g), &view)
        .unwrap()
        .image;
    let pixels = (options.width * options.height) as f64;
    let subject = differing(&image, &empty) as f64 / pixels;
    let ball = differing(&image, &no_ball) as f64 / pixels;
    println!(
        "subject {:.1} %, ball {:.2} % of the image",
        100.0 * subject,
        100.0 * ball
    );
    assert!(
        subject >= 0.25,
        "the subject covers {:.1} % of the image",
        100.0 * subject
    );
    // The ball (radius 0.05 m, a quarter of the wall's width) shows as at least 0.3 %
    // of the image, about 390 pixels at 480×270.
    assert!(
        ball >= 0.003,
        "the ball shows in {:.2} % of the image",
        100.0 * ball
    );
}

/// Pixels of `image` near `color` (sRGB bytes) in chromaticity: each channel's share
/// of the sum within 0.06 of the colour's, and not dark.
fn near_color(image: &RgbImage, color: [u8; 3]) -> usize {
    let share = |c: [u8; 3]| {
        let sum = c.iter().map(|&v| v as f32).sum::<f32>().max(1.0);
        c.map(|v| v as f32 / sum)
    };
    let want = share(color);
    image
        .pixels()
        .filter(|p| {
            let s = share(p.0);
            p.0.iter().map(|&v| v as u32).sum::<u32>() > 120
                && (0..3).all(|k| (s[k] - want[k]).abs() < 0.06)
        })
        .count()
}

/// Two bodies of two materials (one `color` as "#RRGGBB", one as an sRGB triple):
/// both colours are found in the default render, as particles and as surfaces.
#[test]
fn two_materials_render_in_their_own_colours() {
    let brick = [0xC8, 0x3C, 0x28];
    let slate = [38, 89, 217];
    for surface in ["", "surface = \"embedded\""] {
        let dir = tempfile::tempdir().unwrap();
        let out = run(dir.path(), &TWO_MATERIALS.replace("SURFACE", surface));
        let o = out.to_str().unwrap();
        perifrac_ok(&["render", o, "--frame", "1", "--size", "320x180"]);
        let image = image::open(out.join("preview/frame_0001.png"))
            .unwrap()
            .to_rgb8();
        let (b, s) = (near_color(&image, brick), near_color(&image, slate));
        println!("{surface:?}: {b} brick pixels, {s} slate pixels");
        assert!(
            b > 300 && s > 300,
            "{surface:?}: {b} brick, {s} slate pixels"
        );
        // Coloured by damage instead, neither colour is there.
        perifrac_ok(&[
            "render",
            o,
            "--frame",
            "1",
            "--size",
            "320x180",
            "--color-by",
            "damage",
        ]);
        let image = image::open(out.join("preview/frame_0001.png"))
            .unwrap()
            .to_rgb8();
        assert!(
            near_color(&image, brick) < 30,
            "{surface:?}: brick without material colours"
        );
    }
}

/// `perifrac run` ends with the movie; `perifrac render --movie` writes it again: an
/// animated PNG of one frame per cache frame at `playback_fps`, read back by the png
/// crate here and by Pillow (and the MP4 by ffprobe where ffmpeg is installed) in
/// scripts/movie-check.sh.
#[test]
fn the_movie_has_every_frame_at_the_playback_rate() {
    let dir = tempfile::tempdir().unwrap();
    let scene = TWO_MATERIALS
        .replace("SURFACE", "")
        .replace("preview = false", "preview = true");
    let out = run(dir.path(), &scene);
    let movie = out.join("preview/movie.png");
    assert!(movie.is_file(), "run wrote no movie");
    std::fs::remove_file(&movie).unwrap();
    let o = out.to_str().unwrap();
    perifrac_ok(&[
        "render",
        o,
        "--movie",
        "--size",
        "96x54",
        "--turntable",
        "4",
    ]);
    let frames = std::fs::read_dir(out.join("particles")).unwrap().count();
    assert_eq!(frames, 3, "0.002 s at 1000 fps: frames 1–3");
    for (file, count) in [("movie.png", frames), ("turntable.png", 4)] {
        let decoder = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(out.join("preview").join(file)).unwrap(),
        ));
        let mut reader = decoder.read_info().unwrap();
        let control = reader.info().animation_control.expect("an animated PNG");
        assert_eq!(control.num_frames as usize, count, "{file}");
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        for _ in 0..count {
            let info = reader.next_frame(&mut buf).unwrap();
            assert_eq!((info.width, info.height), (96, 54));
            let fc = reader.info().frame_control.expect("frame control");
            assert_eq!(
                (fc.delay_num, fc.delay_den),
                (1, 12),
                "{file}: 1/playback_fps"
            );
        }
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/movie-check.sh");
    movie_check(&script, o, frames);
    // Frames rendered again without --movie take the movies they replace away.
    perifrac_ok(&["render", o, "--size", "64x36"]);
    assert!(!movie.exists(), "a stale movie of the old frames is left");
}

/// Runs scripts/movie-check.sh (which skips, exit code 77, where Pillow cannot be
/// installed).
fn movie_check(script: &Path, o: &str, frames: usize) {
    let result = Command::new("bash")
        .arg(script)
        .args([o, &frames.to_string(), "12"])
        .output()
        .expect("bash runs");
    let stderr = String::from_utf8_lossy(&result.stderr);
    if result.status.code() == Some(77) {
        eprintln!("\n*** SKIPPED the Pillow / ffprobe check: {stderr} ***\n");
        return;
    }
    assert!(
        result.status.success(),
        "movie-check failed:\n{}\n{stderr}",
        String::from_utf8_lossy(&result.stdout)
    );
    println!("{}", String::from_utf8_lossy(&result.stdout));
}
