//! The USD export's peak memory does not grow with the number of frames: the same
//! 6,000-particle frame repeated 40 and 160 times (hard links), each exported by a
//! child process (this test binary run again, on two rayon threads) that reports its
//! peak resident memory (`VmHWM` in `/proc/self/status`). The writer that built the
//! whole stage in memory held every frame's samples (≈0.4 MB a frame here), so 120
//! more frames cost it ≈100 MiB; the value-clip writer holds a frame a thread
//! (docs/usd.md).
#![cfg(target_os = "linux")]

use std::path::Path;
use std::process::Command;

use perifrac_cache::Layout;
use perifrac_cache::manifest::Manifest;
use perifrac_cache::ply::ParticleFrame;

/// The child's environment variable: the cache it exports.
const CHILD: &str = "PERIFRAC_USD_MEMORY_CACHE";

const PARTICLES: usize = 6000;

/// A cache of `frames` frames, all the same particle frame.
fn cache(root: &Path, frames: usize) -> Layout {
    let layout = Layout::new(root);
    layout.create().unwrap();
    let scene = "[scene]\nname = \"memory\"\nfps = 1000.0\n\n[materials.m]\ndensity = 1000.0\n\
                 bulk_modulus = 1e5\nshear_modulus = 1e5\n\n[[body]]\nmaterial = \"m\"\n\
                 resolution = 0.02\nshape = { type = \"box\", center = [0, 0, 0], size = [0.1, 0.1, 0.1] }\n\n\
                 [[collider]]\ntype = \"ground\"\nheight = -1.0\n\n[output]\nplayback_fps = 30\n";
    std::fs::write(layout.scene(), scene).unwrap();
    let manifest = Manifest {
        scene: "memory".into(),
        fps: 1000.0,
        frame_times: (0..frames).map(|k| k as f64 * 1e-3).collect(),
        ..Manifest::default()
    };
    manifest.write(&layout.manifest()).unwrap();
    let wave = |i: usize| (i as f32 * 0.37).sin();
    ParticleFrame {
        frame: 1,
        time: 0.0,
        position: (0..PARTICLES)
            .map(|i| [wave(i), wave(i + 1), wave(i + 2)])
            .collect(),
        velocity: (0..PARTICLES).map(|i| [0.0, wave(i), 0.0]).collect(),
        damage: (0..PARTICLES).map(|i| wave(i).abs()).collect(),
        plastic: vec![0.0; PARTICLES],
        material: vec![0.0; PARTICLES],
        fragment: vec![0.0; PARTICLES],
        extra: vec![],
    }
    .write(&layout.particles(1))
    .unwrap();
    for frame in 2..=frames {
        std::fs::hard_link(layout.particles(1), layout.particles(frame)).unwrap();
    }
    layout
}

/// The peak resident memory (KiB) of a child process exporting the cache at `root`.
fn export_peak(root: &Path) -> u64 {
    let output = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "export_peak_memory_is_flat_in_the_frames",
            "--nocapture",
        ])
        .env(CHILD, root)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "child failed: {stdout}");
    stdout
        .lines()
        .find_map(|l| l.strip_prefix("peak KiB: "))
        .unwrap_or_else(|| panic!("no peak in the child's output: {stdout}"))
        .trim()
        .parse()
        .unwrap()
}

#[test]
fn export_peak_memory_is_flat_in_the_frames() {
    if let Some(root) = std::env::var_os(CHILD) {
        perifrac_usd::write_stage(&Layout::new(root)).unwrap();
        let status = std::fs::read_to_string("/proc/self/status").unwrap();
        let hwm = status
            .lines()
            .find_map(|l| l.strip_prefix("VmHWM:"))
            .expect("VmHWM in /proc/self/status");
        println!("peak KiB: {}", hwm.trim().trim_end_matches("kB").trim());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let short = cache(&dir.path().join("short"), 40);
    let long = cache(&dir.path().join("long"), 160);
    let frame_kib = std::fs::metadata(short.particles(1)).unwrap().len() / 1024;
    let (short_peak, long_peak) = (export_peak(&short.root), export_peak(&long.root));
    // 120 more frames: at most 20 frames' worth more (the one-layer writer: ≥ 120).
    assert!(
        long_peak < short_peak + 20 * frame_kib,
        "peak {short_peak} KiB for 40 frames, {long_peak} KiB for 160 ({frame_kib} KiB a frame)"
    );
    eprintln!(
        "peak {short_peak} KiB for 40 frames, {long_peak} KiB for 160 ({frame_kib} KiB a frame)"
    );
}
