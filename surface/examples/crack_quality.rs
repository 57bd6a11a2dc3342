//! The defects a viewer sees in a cache's split tet mesh and its crack surfaces, frame
//! by frame (used by `scripts/crack-quality.sh`, figures in docs/embedded.md):
//!
//! - inverted tets of `tets/NNNN.vtu` (signed volume ≤ 0), their count and the most
//!   negative volume, also over the largest tet volume of frame 1;
//! - the longest crack-triangle edge of the smoothed surface (what `surface/NNNN.glb`
//!   holds), in λ, and how many crack edges are longer than 3λ;
//! - tets inverted after smoothing, moves the smoothing backed off and vertices it
//!   put back;
//! - the crack surface's zig-zag before and after smoothing, in λ (the median distance
//!   of a smoothed vertex from the plane fitted through its ring,
//!   `SmoothingStats::roughness`).
//!
//! `cargo run --release -p perifrac-surface --example crack_quality -- OUT [PASSES]`

use std::path::PathBuf;
use std::process::ExitCode;

use perifrac_cache::Layout;
use perifrac_cache::manifest::Manifest;
use perifrac_cache::scene::Scene;
use perifrac_cache::vtu::TetFrame;
use perifrac_math::{norm, signed_volume, sub};
use perifrac_surface::embedded::surface;
use rayon::prelude::*;

/// One frame's figures.
struct Row {
    tets: usize,
    inverted: usize,
    worst: f64,
    longest: f64,
    over: usize,
    inverted_smoothed: usize,
    backed_off: usize,
    reverted: usize,
    zig_zag: [f64; 2],
}

fn volumes(points: &[[f64; 3]], tets: &[[u32; 4]]) -> Vec<f64> {
    tets.iter()
        .map(|t| {
            let [a, b, c, d] = t.map(|v| points[v as usize]);
            signed_volume(a, b, c, d)
        })
        .collect()
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(out) = args.first() else {
        eprintln!("usage: crack_quality OUT [PASSES]");
        return ExitCode::from(2);
    };
    let layout = Layout::new(PathBuf::from(out));
    let run = || -> Result<(), String> {
        let scene = Scene::load(&layout.scene()).map_err(|e| e.to_string())?;
        let lambda = scene
            .bodies
            .iter()
            .map(|b| b.resolution)
            .fold(f64::INFINITY, f64::min);
        let passes = match args.get(1) {
            Some(p) => p.parse().map_err(|_| format!("PASSES: not a count: {p}"))?,
            None => scene.output.embedded.smoothing_passes,
        };
        let manifest = Manifest::read(&layout.manifest()).map_err(|e| e.to_string())?;
        let frames = manifest.frame_times.len();
        let first = TetFrame::read(&layout.tets(1)).map_err(|e| e.to_string())?;
        let largest = volumes(&first.points, &first.tets)
            .into_iter()
            .fold(0.0, f64::max);
        let rows: Vec<Row> = (1..=frames)
            .into_par_iter()
            .map(|k| -> Result<Row, String> {
                let frame = TetFrame::read(&layout.tets(k)).map_err(|e| e.to_string())?;
                let v = volumes(&frame.points, &frame.tets);
                let s = surface(&frame, passes);
                let mut longest = 0.0f64;
                let mut over = 0;
                for (f, _) in s.triangles.iter().zip(&s.crack).filter(|(_, c)| **c) {
                    for e in 0..3 {
                        let (a, b) = (f[e] as usize, f[(e + 1) % 3] as usize);
                        let l = norm(sub(s.points[a], s.points[b])) / lambda;
                        longest = longest.max(l);
                        // Each crack edge is seen from both its triangles.
                        if l > 3.0 && a < b {
                            over += 1;
                        }
                    }
                }
                Ok(Row {
                    tets: frame.tets.len(),
                    inverted: v.iter().filter(|&&x| x <= 0.0).count(),
                    worst: v.iter().copied().fold(f64::INFINITY, f64::min),
                    longest,
                    over,
                    inverted_smoothed: volumes(&s.points, &frame.tets)
                        .iter()
                        .filter(|&&x| x <= 0.0)
                        .count(),
                    backed_off: s.stats.backed_off,
                    reverted: s.stats.reverted,
                    zig_zag: s.stats.roughness.map(|h| h / lambda),
                })
            })
            .collect::<Result<_, _>>()?;
        println!(
            "{out}: λ = {lambda} m, {passes} smoothing passes, largest tet of frame 1 \
             {largest:.3e} m³"
        );
        println!(
            "| frame | tets | inverted | worst volume (m³) | worst / largest | longest crack \
             edge (λ) | crack edges > 3λ | inverted after smoothing | moves backed off | \
             vertices put back | crack zig-zag before → after smoothing (λ) |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|");
        for (k, r) in rows.iter().enumerate() {
            println!(
                "| {} | {} | {} | {:.2e} | {:.2} | {:.2} | {} | {} | {} | {} | {:.3} → {:.3} |",
                k + 1,
                r.tets,
                r.inverted,
                r.worst,
                r.worst / largest,
                r.longest,
                r.over,
                r.inverted_smoothed,
                r.backed_off,
                r.reverted,
                r.zig_zag[0],
                r.zig_zag[1]
            );
        }
        let total = |f: fn(&Row) -> usize| rows.iter().map(f).sum::<usize>();
        println!(
            "all frames: {} inverted tets (worst {:.2e} m³), longest crack edge {:.2}λ, {} crack \
             edges > 3λ, {} inverted after smoothing, {} moves backed off, {} vertices put back; \
             crack zig-zag at the last frame {:.3}λ, {:.3}λ after smoothing",
            total(|r| r.inverted),
            rows.iter().map(|r| r.worst).fold(f64::INFINITY, f64::min),
            rows.iter().map(|r| r.longest).fold(0.0, f64::max),
            total(|r| r.over),
            total(|r| r.inverted_smoothed),
            total(|r| r.backed_off),
            total(|r| r.reverted),
            rows.last().map_or(0.0, |r| r.zig_zag[0]),
            rows.last().map_or(0.0, |r| r.zig_zag[1]),
        );
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
