//! Damaged checkpoints are refused, never resumed from and never a panic (issue 17:
//! of 54 corruptions of `checkpoint/state.bin`, 14 resumed silently into other frames
//! and 7 panicked at a neighbour index out of range in the peridynamic kernel).
//!
//! Two kinds of damage: bytes changed on disk (a bit flip, truncation, trailing
//! bytes), which the container's length and CRC-32 catch; and checkpoints whose
//! checksum was recomputed after the change (a crafted file, or a bug writing one),
//! which only the checks of every count, index and value before use can catch.

use std::path::Path;

use perifrac_sim::cache::checkpoint::{Checkpoint, Decoder, Encoder};
use perifrac_sim::run::{self, RunOptions};
use perifrac_sim::scene::Scene;
use perifrac_sim::{SimError, family};

/// A small peridynamic scene using everything a checkpoint carries: plasticity
/// (plastic extensions), fracture and a crack cut at set-up (broken bits), an
/// anchor, a kinematic and a dynamic sphere, the ground.
const SCENE: &str = "[scene]\nname = \"ckpt\"\nduration = 0.005\nfps = 1000\n\
    [materials.m]\ndensity = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.3\n\
    critical_stretch = 0.01\nyield_stretch = 0.004\nplastic_limit = 0.1\n\
    [[body]]\nmaterial = \"m\"\nresolution = 0.01\n\
    shape = { type = \"box\", center = [0, 0.03, 0], size = [0.06, 0.05, 0.03] }\n\
    [[body.anchor]]\nregion = { type = \"box\", center = [-0.03, 0.03, 0], size = [0.015, 0.06, 0.04] }\n\
    [[body.crack]]\npoint = [0.01, 0.03, 0]\nnormal = [1, 0, 0]\n\
    region = { type = \"box\", center = [0.01, 0.045, 0], size = [0.02, 0.03, 0.04] }\n\
    [[collider]]\ntype = \"ground\"\n\
    [[collider]]\ntype = \"sphere\"\ncenter = [0.01, 0.03, 0.03]\nradius = 0.012\nvelocity = [0, 0, -20]\nmass = 0.05\n\
    [[collider]]\ntype = \"sphere\"\ncenter = [0.05, 0.08, 0]\nradius = 0.01\nvelocity = [0, -1, 0]\n\
    [output]\ncheckpoint_every = 2\npreview = false\n";

fn scene() -> Scene {
    Scene::parse(SCENE, Path::new("ckpt.toml"), Path::new(".")).expect("valid scene")
}

/// A cache stopped after frame 4 (checkpointed at frame 2), and its checkpoint's
/// bytes.
fn stopped_run(dir: &Path) -> Vec<u8> {
    let options = RunOptions {
        frames: Some(3),
        ..RunOptions::default()
    };
    run::run(&scene(), dir, &options, &mut |_| {}).expect("runs");
    std::fs::read(dir.join("checkpoint/state.bin")).expect("checkpoint")
}

/// Resumes a copy of the cache in `base` with `state` as its checkpoint.
fn resume_with(base: &Path, state: &[u8]) -> Result<(), SimError> {
    let dir = tempfile::tempdir().expect("temp dir");
    for sub in ["", "particles", "checkpoint"] {
        std::fs::create_dir_all(dir.path().join(sub)).expect("dir");
        for entry in std::fs::read_dir(base.join(sub)).expect("dir") {
            let entry = entry.expect("entry");
            if entry.file_type().expect("type").is_file() {
                std::fs::copy(entry.path(), dir.path().join(sub).join(entry.file_name()))
                    .expect("copy");
            }
        }
    }
    std::fs::write(dir.path().join("checkpoint/state.bin"), state).expect("write");
    let options = RunOptions {
        resume: true,
        ..RunOptions::default()
    };
    run::run(&scene(), dir.path(), &options, &mut |_| {}).map(|_| ())
}

/// The error must be a refusal of the checkpoint (exit code 2), saying to rerun.
fn assert_refused(result: Result<(), SimError>, what: &str) {
    match result {
        Ok(()) => panic!("{what}: resumed from a damaged checkpoint"),
        Err(SimError::Cache(e)) if e.is_bad_input() => {
            let m = e.to_string();
            assert!(
                m.contains("checkpoint") || m.contains("tets/"),
                "{what}: {m}"
            );
            assert!(m.contains("rerun from frame 1"), "{what}: {m}");
        }
        Err(e) => panic!("{what}: not a checkpoint refusal: {e}"),
    }
}

/// The checkpoint with its checksum recomputed after `change`.
fn recrc(bytes: &[u8], change: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut body = bytes[..bytes.len() - 4].to_vec();
    change(&mut body);
    let crc = crc32fast::hash(&body);
    body.extend_from_slice(&crc.to_le_bytes());
    body
}

/// Where each field of the world's payload starts (after the 64-byte header), read
/// the way [`perifrac_sim::world::World::save`] and the peridynamic model write
/// them: `(name, offset, length of one value)`.
fn payload_fields(payload: &[u8]) -> Vec<(&'static str, usize, usize)> {
    let layout: [(&str, Option<usize>); 17] = [
        ("models", None),
        ("acceleration", Some(24)),
        ("positions", Some(24)),
        ("velocities", Some(24)),
        ("bonds", Some(4)),
        ("plastic extensions", Some(8)),
        ("anchor work", None),
        ("colliders", Some(24)),
        ("clock steps", None),
        ("clock time", None),
        ("clock frame", None),
        ("clock steps a frame", None),
        ("time step", None),
        ("frame length", None),
        ("rigid phase", None),
        ("closed faces count", None),
        ("closed faces", Some(4)),
    ];
    let mut at = 0;
    let mut out = Vec::new();
    for (name, slice) in layout {
        out.push((name, at, 8));
        at += 8;
        if let Some(size) = slice {
            let len = u64::from_le_bytes(payload[at - 8..at].try_into().unwrap()) as usize;
            if len > 0 {
                out.push((name, at, size));
            }
            at += len * size;
        }
    }
    assert_eq!(at, payload.len(), "the payload layout read by the test");
    out
}

/// Bytes before the payload: magic, version, hash, frame, steps, broken bonds, time,
/// payload length.
const HEADER: usize = 60;

fn put_u32(b: &mut [u8], at: usize, v: u32) {
    b[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

fn put_u64(b: &mut [u8], at: usize, v: u64) {
    b[at..at + 8].copy_from_slice(&v.to_le_bytes());
}

fn put_f64(b: &mut [u8], at: usize, v: f64) {
    b[at..at + 8].copy_from_slice(&v.to_le_bytes());
}

/// Every bit of the header and the checksum flipped; in the payload one bit of every
/// byte of each count and scalar and of each slice's first value, and of every 127th
/// byte besides (127 is prime to the value sizes, so values are hit at every byte
/// position; every 13th byte, as this once was, made 180,000 decodes of a 2.4 MB
/// checkpoint, 45 s of the suite); the file truncated at every length
/// and grown by trailing bytes: the container refuses each, naming the file.
#[test]
fn every_bit_flip_truncation_and_trailing_bytes_are_refused_by_the_container() {
    let dir = tempfile::tempdir().expect("temp dir");
    let good = stopped_run(dir.path());
    let path = Path::new("checkpoint/state.bin");
    Checkpoint::decode(&good, path).expect("the written checkpoint reads");
    let payload = HEADER..good.len() - 4;
    let mut flips: Vec<(usize, u8)> = (0..8)
        .flat_map(|bit| {
            (0..HEADER)
                .chain(payload.end..good.len())
                .map(move |at| (at, bit))
        })
        .collect();
    for (_, at, size) in payload_fields(&good[payload.clone()]) {
        flips.extend((HEADER + at..HEADER + at + size).map(|at| (at, (at % 8) as u8)));
    }
    flips.extend(payload.step_by(127).map(|at| (at, (at % 8) as u8)));
    for (at, bit) in flips {
        let mut bad = good.clone();
        bad[at] ^= 1 << bit;
        let e = Checkpoint::decode(&bad, path).expect_err("a flipped bit is refused");
        assert!(e.is_bad_input(), "byte {at} bit {bit}: {e}");
    }
    for len in 0..good.len() {
        assert!(
            Checkpoint::decode(&good[..len], path).is_err(),
            "{len} bytes"
        );
    }
    for extra in [1, 4, 100] {
        let mut long = good.clone();
        long.extend(std::iter::repeat_n(0x5a, extra));
        let m = Checkpoint::decode(&long, path).unwrap_err().to_string();
        assert!(m.contains("trailing bytes"), "{m}");
    }
}

/// Through a whole `--resume`: a sample of bit flips in every field (header, counts,
/// indices, floats, trailer), truncations and trailing bytes are refused with exit
/// code 2 and how to rerun; the untouched checkpoint resumes.
#[test]
fn damaged_checkpoints_are_refused_by_resume() {
    let dir = tempfile::tempdir().expect("temp dir");
    let good = stopped_run(dir.path());
    let payload = &good[HEADER..good.len() - 4];
    let mut offsets: Vec<usize> = vec![0, 7, 8, 11, 12, 19, 20, 27, 28, 35, 36, 43, 44, 51, 52, 59];
    for (_, at, size) in payload_fields(payload) {
        offsets.extend([HEADER + at, HEADER + at + size - 1]);
    }
    offsets.extend([good.len() - 4, good.len() - 1]);
    for &at in &offsets {
        let bit = at % 8;
        let mut bad = good.clone();
        bad[at] ^= 1 << bit;
        assert_refused(
            resume_with(dir.path(), &bad),
            &format!("byte {at} bit {bit}"),
        );
    }
    for len in [0, 10, HEADER, good.len() / 2, good.len() - 1] {
        assert_refused(
            resume_with(dir.path(), &good[..len]),
            &format!("truncated to {len}"),
        );
    }
    let mut long = good.clone();
    long.extend([0u8; 100]);
    assert_refused(resume_with(dir.path(), &long), "100 trailing bytes");
    resume_with(dir.path(), &good).expect("the untouched checkpoint resumes");
}

/// Checkpoints with a valid checksum but a wrong count, index, clock or value: every
/// one is refused before the model uses it (none panics, none resumes).
#[test]
fn checkpoints_with_a_valid_checksum_but_wrong_contents_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let good = stopped_run(dir.path());
    let payload = good[HEADER..good.len() - 4].to_vec();
    let fields = payload_fields(&payload);
    let field = |name: &str| -> (usize, usize) {
        let mut found = fields.iter().filter(|f| f.0 == name);
        let len_at = found.next().expect("length").1;
        let first = found.next().expect("first value").1;
        (HEADER + len_at, HEADER + first)
    };
    let (bonds_len, first_bond) = field("bonds");
    let (positions_len, first_position) = field("positions");
    let (_, first_plastic) = field("plastic extensions");
    let (_, first_collider) = field("colliders");
    let bond = move |b: &[u8], k: usize| {
        let at = first_bond + 4 * k;
        u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
    };
    let bond_count = (first_plastic - 8 - first_bond) / 4;
    let cut = (0..bond_count)
        .find(|&k| bond(&good, k) & family::BROKEN != 0)
        .expect("the crack cut bonds");
    let intact = (0..bond_count)
        .find(|&k| bond(&good, k) & family::BROKEN == 0)
        .expect("intact bonds");
    let anchor_work = fields.iter().find(|f| f.0 == "anchor work").unwrap().1 + HEADER;
    type Change = Box<dyn Fn(&mut Vec<u8>)>;
    let cases: Vec<(&str, Change)> = vec![
        // The index the old kernel panicked on, and one in range but wrong.
        (
            "neighbour out of range",
            Box::new(move |b| put_u32(b, first_bond, 0x7fff_fff0)),
        ),
        ("neighbour of another particle", {
            Box::new(move |b| {
                let v = bond(b, 0);
                put_u32(b, first_bond, v ^ 1)
            })
        }),
        (
            "a cut bond healed",
            Box::new(move |b| {
                let v = bond(b, cut) & family::INDEX;
                put_u32(b, first_bond + 4 * cut, v)
            }),
        ),
        (
            "a bond broken behind the header's count",
            Box::new(move |b| {
                let v = bond(b, intact) | family::BROKEN;
                put_u32(b, first_bond + 4 * intact, v)
            }),
        ),
        ("bond count", Box::new(move |b| put_u64(b, bonds_len, 7))),
        (
            "huge bond count",
            Box::new(move |b| put_u64(b, bonds_len, u64::MAX)),
        ),
        (
            "particle count",
            Box::new(move |b| put_u64(b, positions_len, 3)),
        ),
        ("model count", Box::new(|b| put_u64(b, HEADER, 2))),
        (
            "NaN position",
            Box::new(move |b| put_f64(b, first_position, f64::NAN)),
        ),
        (
            "infinite position",
            Box::new(move |b| put_f64(b, first_position + 8, f64::INFINITY)),
        ),
        (
            "NaN plastic extension",
            Box::new(move |b| put_f64(b, first_plastic, f64::NAN)),
        ),
        (
            "infinite anchor work",
            Box::new(move |b| put_f64(b, anchor_work, f64::NEG_INFINITY)),
        ),
        (
            "NaN collider centre",
            Box::new(move |b| put_f64(b, first_collider, f64::NAN)),
        ),
        // Collider 2 (the kinematic sphere): its centre is the scene's motion.
        (
            "kinematic collider moved",
            Box::new(move |b| {
                let at = first_collider + 4 * 24;
                let x = f64::from_le_bytes(b[at..at + 8].try_into().unwrap());
                put_f64(b, at, x + 1e-3)
            }),
        ),
        ("frame 0", Box::new(|b| put_u64(b, 20, 0))),
        ("frame past the end", Box::new(|b| put_u64(b, 20, 99))),
        (
            "frame off by one",
            Box::new(|b| {
                let f = u64::from_le_bytes(b[20..28].try_into().unwrap());
                put_u64(b, 20, f - 1)
            }),
        ),
        (
            "steps off by one",
            Box::new(|b| {
                let s = u64::from_le_bytes(b[28..36].try_into().unwrap());
                put_u64(b, 28, s + 1)
            }),
        ),
        ("steps huge", Box::new(|b| put_u64(b, 28, u64::MAX))),
        (
            "broken bond count",
            Box::new(|b| {
                let n = u64::from_le_bytes(b[36..44].try_into().unwrap());
                put_u64(b, 36, n + 1)
            }),
        ),
        (
            "time one ulp off",
            Box::new(|b| {
                let t = u64::from_le_bytes(b[44..52].try_into().unwrap());
                put_u64(b, 44, t + 1)
            }),
        ),
        ("scene hash", Box::new(|b| b[12] ^= 1)),
        (
            "payload of another layout",
            Box::new(|b| {
                b.extend([0u8; 8]);
                let n = u64::from_le_bytes(b[52..60].try_into().unwrap());
                put_u64(b, 52, n + 8)
            }),
        ),
    ];
    for (what, change) in &cases {
        assert_refused(resume_with(dir.path(), &recrc(&good, change)), what);
    }
    // And the checkpoint as written still resumes.
    resume_with(dir.path(), &good).expect("the untouched checkpoint resumes");
}

/// A model's own `restore` reports what is wrong through the decoder: a checkpoint
/// made by hand with an [`Encoder`] for the FEM and MPM models too.
#[test]
fn fem_and_mpm_restores_check_their_values() {
    let fem = "[scene]\nduration = 0.01\nfps = 100\n[materials.m]\ndensity = 1000.0\n\
        youngs_modulus = 1.0e6\npoisson_ratio = 0.3\n[[body]]\nmaterial = \"m\"\n\
        model = \"fem-corotated\"\nresolution = 0.02\n\
        shape = { type = \"box\", center = [0, 0.1, 0], size = [0.08, 0.04, 0.04] }\n";
    let mpm = fem.replace("fem-corotated", "mpm");
    for (text, model) in [(fem.to_string(), "fem"), (mpm, "mpm")] {
        let scene = Scene::parse(&text, Path::new("m.toml"), Path::new(".")).expect("scene");
        let mut prepared = run::prepare(&scene).expect("prepares");
        let mut saved = Encoder::new();
        prepared.world.save(&mut saved);
        let saved = saved.finish();
        let path = Path::new("state.bin");
        // The payload as saved restores.
        prepared
            .world
            .restore(&mut Decoder::new(&saved, path), 0.0, 0, 0)
            .expect("restores");
        // A NaN in the last f64 of the model's state (FEM: a rotation; MPM: a
        // plastic strain, before the lengths of its empty internal energies and
        // temperatures), before the anchor work, the (empty) colliders and the seven
        // words of the clock, time step, frame length and rigid phase.
        let mut bad = saved.clone();
        let at = bad.len() - (3 + 7) * 8 - if model == "mpm" { 2 * 8 } else { 0 };
        bad[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
        let e = prepared
            .world
            .restore(&mut Decoder::new(&bad, path), 0.0, 0, 0)
            .expect_err("a NaN is refused");
        assert!(e.to_string().contains("not a finite"), "{model}: {e}");
        if model == "fem" {
            let mut bad = saved.clone();
            bad[at..at + 8].copy_from_slice(&0.5f64.to_le_bytes());
            let e = prepared
                .world
                .restore(&mut Decoder::new(&bad, path), 0.0, 0, 0)
                .expect_err("a quaternion that is not a rotation");
            assert!(e.to_string().contains("unit quaternion"), "{e}");
        } else {
            let mut bad = saved.clone();
            bad[at..at + 8].copy_from_slice(&(-1.0f64).to_le_bytes());
            let e = prepared
                .world
                .restore(&mut Decoder::new(&bad, path), 0.0, 0, 0)
                .expect_err("a negative plastic strain");
            assert!(e.to_string().contains("negative plastic"), "{e}");
        }
    }
}
