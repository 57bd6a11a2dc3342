//! Helpers of perifrac's snapshot-image tests: the small fixed scenes they render and
//! the comparison of a rendered image with a reference PNG under `tests/snapshots/`.
//!
//! A comparison fails when more than [`Tolerance::max_pixels`] pixels differ by more
//! than [`Tolerance::threshold`] in some channel, or when the mean absolute error over
//! all channels exceeds [`Tolerance::max_mean`]. `UPDATE_SNAPSHOTS=1` rewrites the
//! references instead; a failure writes `NAME.actual.png` and `NAME.diff.png` next to
//! the reference.
//!
//! Main items: [`check_snapshot`] and [`difference`] against [`TOLERANCE`] (a
//! [`Tolerance`]); the scenes [`torus`], [`particles`], [`cracked_block`], [`empty`],
//! framed by [`camera`] at [`SIZE`].
#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use image::{Rgb, RgbImage};
use perifrac_render::camera::{AZIMUTH, Bounds, Camera};
use perifrac_render::geometry::{self, FrameGeometry, Shading};

/// How far an image may stray from its reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// A pixel counts as different when a channel differs by more than this (0–255).
    pub threshold: u8,
    /// How many different pixels are allowed.
    pub max_pixels: usize,
    /// Largest allowed mean absolute error a channel (0–255).
    pub max_mean: f64,
}

/// The tests' tolerance: rasteriser rounding passes, a 2-pixel move or a changed light
/// does not (see `tests/tests/snapshots.rs`).
pub const TOLERANCE: Tolerance = Tolerance {
    threshold: 16,
    max_pixels: 20,
    max_mean: 0.35,
};

/// The result of a comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// Pixels over the threshold.
    pub pixels: usize,
    /// Mean absolute error a channel.
    pub mean: f64,
    /// The per-pixel difference, scaled ×4 for visibility.
    pub image: RgbImage,
}

impl Difference {
    /// Whether the difference is within `tolerance`.
    pub fn passes(&self, tolerance: &Tolerance) -> bool {
        self.pixels <= tolerance.max_pixels && self.mean <= tolerance.max_mean
    }
}

/// Compares two images of the same size.
pub fn difference(actual: &RgbImage, reference: &RgbImage) -> Result<Difference, String> {
    if actual.dimensions() != reference.dimensions() {
        return Err(format!(
            "size {:?} differs from the reference's {:?}",
            actual.dimensions(),
            reference.dimensions()
        ));
    }
    let mut pixels = 0;
    let mut sum = 0u64;
    let mut image = RgbImage::new(actual.width(), actual.height());
    for ((a, r), d) in actual
        .pixels()
        .zip(reference.pixels())
        .zip(image.pixels_mut())
    {
        let delta: [u8; 3] = std::array::from_fn(|k| a[k].abs_diff(r[k]));
        sum += delta.iter().map(|&v| v as u64).sum::<u64>();
        if delta.iter().any(|&v| v > TOLERANCE.threshold) {
            pixels += 1;
        }
        *d = Rgb(delta.map(|v| v.saturating_mul(4)));
    }
    Ok(Difference {
        pixels,
        mean: sum as f64 / (3 * actual.width() as u64 * actual.height() as u64).max(1) as f64,
        image,
    })
}

/// The directory of the reference images.
pub fn snapshot_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("snapshots")
}

/// Checks `actual` against `snapshots/NAME.png`: rewrites it with `UPDATE_SNAPSHOTS=1`;
/// on failure writes `NAME.actual.png` and `NAME.diff.png` beside it and says why.
pub fn check_snapshot(name: &str, actual: &RgbImage) -> Result<(), String> {
    let dir = snapshot_dir();
    let reference_path = dir.join(format!("{name}.png"));
    let actual_path = dir.join(format!("{name}.actual.png"));
    let diff_path = dir.join(format!("{name}.diff.png"));
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
        actual.save(&reference_path).map_err(|e| e.to_string())?;
        let _ = std::fs::remove_file(&actual_path);
        let _ = std::fs::remove_file(&diff_path);
        return Ok(());
    }
    let reference = image::open(&reference_path)
        .map_err(|e| {
            format!(
                "{}: {e}; run with UPDATE_SNAPSHOTS=1 to create it",
                reference_path.display()
            )
        })?
        .to_rgb8();
    let diff = match difference(actual, &reference) {
        Ok(d) => d,
        Err(message) => {
            let _ = actual.save(&actual_path);
            return Err(format!("{}: {message}", reference_path.display()));
        }
    };
    if diff.passes(&TOLERANCE) {
        let _ = std::fs::remove_file(&actual_path);
        let _ = std::fs::remove_file(&diff_path);
        return Ok(());
    }
    let _ = actual.save(&actual_path);
    let _ = diff.image.save(&diff_path);
    Err(format!(
        "{}: {} pixels differ by more than {} (allowed {}), mean error {:.3} (allowed {}); see {} and {}",
        reference_path.display(),
        diff.pixels,
        TOLERANCE.threshold,
        TOLERANCE.max_pixels,
        diff.mean,
        TOLERANCE.max_mean,
        actual_path.display(),
        diff_path.display()
    ))
}

/// The size the snapshot scenes render at.
pub const SIZE: (u32, u32) = (160, 120);

/// A torus (major radius 0.3 m, minor 0.1 m) standing on the ground, tilted, offset by
/// `shift` — the "mesh" scene.
pub fn torus(shift: [f32; 3]) -> FrameGeometry {
    let (major, minor, nu, nv) = (0.3f32, 0.1f32, 64u32, 24u32);
    let tilt = 0.5f32;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for i in 0..nu {
        let u = std::f32::consts::TAU * i as f32 / nu as f32;
        for j in 0..nv {
            let v = std::f32::consts::TAU * j as f32 / nv as f32;
            let n = [v.cos() * u.cos(), v.sin(), v.cos() * u.sin()];
            let p = [
                (major + minor * v.cos()) * u.cos(),
                minor * v.sin(),
                (major + minor * v.cos()) * u.sin(),
            ];
            // Tilt about x, then stand it up on the ground at y = 0.
            let rot = |a: [f32; 3]| {
                [
                    a[0],
                    a[1] * tilt.cos() - a[2] * tilt.sin(),
                    a[1] * tilt.sin() + a[2] * tilt.cos(),
                ]
            };
            let q = rot(p);
            positions.push([q[0] + shift[0], q[1] + 0.3 + shift[1], q[2] + shift[2]]);
            normals.push(rot(n));
        }
    }
    let mut indices = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let a = i * nv + j;
            let b = ((i + 1) % nu) * nv + j;
            let c = ((i + 1) % nu) * nv + (j + 1) % nv;
            let d = i * nv + (j + 1) % nv;
            indices.extend_from_slice(&[a, d, b, b, d, c]);
        }
    }
    let mut g = FrameGeometry {
        ground: Some(0.0),
        ..FrameGeometry::default()
    };
    let color = geometry::surface_color();
    g.push_mesh(
        &positions,
        Some(&normals),
        &|_| color,
        &indices,
        Shading::Surface,
    );
    g
}

/// A 0.4 m cube of particles (16³, radius 0.0125 m) coloured by a damage ramp along x,
/// above the ground — the "particles" scene.
pub fn particles() -> FrameGeometry {
    let mut g = FrameGeometry {
        ground: Some(0.0),
        ..FrameGeometry::default()
    };
    let n = 16;
    let h = 0.4 / n as f32;
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let p = [
                    -0.2 + (i as f32 + 0.5) * h,
                    0.05 + (j as f32 + 0.5) * h,
                    -0.2 + (k as f32 + 0.5) * h,
                ];
                g.push_point(
                    p,
                    0.5 * h,
                    geometry::damage_color(i as f32 / (n - 1) as f32),
                );
            }
        }
    }
    g
}

/// A block broken in two with the crack faces exposed (crack material) and a steel
/// ball — the "crack" scene.
pub fn cracked_block() -> FrameGeometry {
    let mut g = FrameGeometry {
        ground: Some(0.0),
        ..FrameGeometry::default()
    };
    for (x0, x1, crack_at_max) in [(-0.3f32, -0.02f32, true), (0.02, 0.3, false)] {
        let (y0, y1, z0, z1) = (0.0f32, 0.35f32, -0.12f32, 0.12f32);
        let mut block = FrameGeometry::default();
        block.push_box(
            [0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)],
            [x1 - x0, y1 - y0, z1 - z0],
            geometry::surface_color(),
        );
        // Re-shade: the face towards the crack is a crack face, the rest surface.
        for v in block.mesh_vertices.chunks_exact_mut(geometry::MESH_STRIDE) {
            let on_crack = if crack_at_max {
                v[3] > 0.5
            } else {
                v[3] < -0.5
            };
            let (color, shading) = if on_crack {
                (geometry::crack_color(), Shading::Crack)
            } else {
                (geometry::surface_color(), Shading::Surface)
            };
            v[6..9].copy_from_slice(&color);
            v[9] = shading as u32 as f32;
        }
        let base = g.vertex_count() as u32;
        g.mesh_vertices.extend_from_slice(&block.mesh_vertices);
        g.mesh_indices
            .extend(block.mesh_indices.iter().map(|i| i + base));
    }
    g.push_sphere([0.0, 0.45, 0.25], 0.08, geometry::collider_color());
    g
}

/// Nothing but the ground (everything fell out of view) — the "empty" scene.
pub fn empty() -> FrameGeometry {
    FrameGeometry {
        ground: Some(0.0),
        ..FrameGeometry::default()
    }
}

/// The fixed camera of the snapshot scenes (framing a 0.8 m box on the ground).
pub fn camera_bounds() -> Bounds {
    Bounds {
        min: [-0.4, 0.0, -0.4],
        max: [0.4, 0.6, 0.4],
    }
}

/// The fixed camera of the snapshot scenes.
pub fn camera() -> Camera {
    Camera::framing(&camera_bounds(), SIZE.0 as f32 / SIZE.1 as f32, AZIMUTH)
}
