//! What the integration tests share: the same bytes with 1 and 2 threads and after a
//! stop and a resume, and the sums they check a prepared scene's model with.
// Each test file is its own crate and uses only some of these.
#![allow(dead_code)]

use std::path::Path;

use perifrac_sim::model::Model;
use perifrac_sim::run::{self, Prepared, RunOptions};
use perifrac_sim::scene::Scene;

/// Asserts that the particle frames 1..=`frames` of caches `a` and `b` are byte for
/// byte the same.
fn same_frames(a: &Path, b: &Path, frames: usize, what: &str) {
    for f in 1..=frames {
        let name = format!("particles/{f:04}.ply");
        let x = std::fs::read(a.join(&name)).expect("frame");
        let y = std::fs::read(b.join(&name)).expect("frame");
        assert!(x == y, "{name}: {what}");
    }
}

/// Runs `s` to the end with 1 and with 2 threads, and a third time stopped after
/// `stop_after` frames and resumed from its checkpoint; asserts that all three write
/// the same particle frames. Returns the three caches (the 1-thread run first) for
/// the test's own checks.
pub fn threads_and_resume(s: &Scene, stop_after: usize) -> [tempfile::TempDir; 3] {
    let frames = s.frame_count() + 1;
    let dirs = [(); 3].map(|()| tempfile::tempdir().expect("temp dir"));
    for (threads, dir) in [1usize, 2].iter().zip(&dirs) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(*threads)
            .build()
            .expect("pool");
        let manifest = pool
            .install(|| run::run(s, dir.path(), &RunOptions::default(), &mut |_| {}))
            .expect("runs");
        assert_eq!(manifest.status.to_string(), "complete");
    }
    same_frames(
        dirs[0].path(),
        dirs[1].path(),
        frames,
        "1 and 2 threads differ",
    );
    let stop = RunOptions {
        frames: Some(stop_after),
        ..RunOptions::default()
    };
    let stopped = run::run(s, dirs[2].path(), &stop, &mut |_| {}).expect("runs");
    assert_eq!(stopped.status.to_string(), "interrupted");
    let resume = RunOptions {
        resume: true,
        ..RunOptions::default()
    };
    let resumed = run::run(s, dirs[2].path(), &resume, &mut |_| {}).expect("resumes");
    assert_eq!(resumed.status.to_string(), "complete");
    same_frames(
        dirs[0].path(),
        dirs[2].path(),
        frames,
        "a resumed run differs from an uninterrupted one",
    );
    dirs
}

/// The first model of a prepared scene.
pub fn model(p: &Prepared) -> &dyn Model {
    p.world.parts[0].model.as_ref()
}

/// Σ m v over every point of the first model.
pub fn momentum(p: &Prepared) -> [f64; 3] {
    let points = model(p).points();
    let mut total = [0.0; 3];
    for (m, v) in points.mass.iter().zip(points.velocity) {
        for a in 0..3 {
            total[a] += m * v[a];
        }
    }
    total
}

/// The lowest particle's height (m) and the fastest particle's speed (m/s) of a frame.
pub fn lowest_and_fastest(frame: &perifrac_sim::cache::ply::ParticleFrame) -> (f32, f32) {
    let lowest = frame.position.iter().map(|x| x[1]).fold(f32::MAX, f32::min);
    let fastest = frame
        .velocity
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0f32, f32::max);
    (lowest, fastest)
}
