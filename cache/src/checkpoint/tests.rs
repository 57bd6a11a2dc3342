use super::*;

fn sample() -> Checkpoint {
    let mut e = Encoder::new();
    e.put_f64x3_slice(&[[1.0, 2.0, 3.0], [0.1 + 0.2, -0.0, 1e-300]]);
    e.put_u32_slice(&[0, 1, 7]);
    e.put_f32_slice(&[0.5]);
    e.put_f64(1.0 / 3.0);
    e.put_u64(42);
    Checkpoint {
        scene_hash: 0xfeed_beef,
        frame: 12,
        steps: 3456,
        broken_bonds: 78,
        time: 0.5 + 1e-17,
        payload: e.finish(),
    }
}

fn message(bytes: &[u8]) -> String {
    Checkpoint::decode(bytes, Path::new("out/checkpoint/state.bin"))
        .unwrap_err()
        .to_string()
}

#[test]
fn round_trip_through_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("state.bin");
    let c = sample();
    c.write(&path).unwrap();
    let back = Checkpoint::read(&path).unwrap();
    assert_eq!(back, c);
    assert_eq!(back.time.to_bits(), c.time.to_bits());
    let mut d = Decoder::new(&back.payload, &path);
    let p = d.take_f64x3_slice("position", 2).unwrap();
    assert_eq!(p[1][0].to_bits(), (0.1f64 + 0.2).to_bits());
    assert_eq!(
        d.take_u32_slice_bounded("neighbours", 3, 8).unwrap(),
        [0, 1, 7]
    );
    assert_eq!(d.take_f32_slice("damage", 1).unwrap(), [0.5]);
    assert_eq!(d.take_f64("work").unwrap(), 1.0 / 3.0);
    assert_eq!(d.take_u64("count").unwrap(), 42);
    d.finish().unwrap();
}

/// A state of 2.5 spill chunks encoded into `e`.
fn large_state(e: &mut Encoder) {
    let values: Vec<f64> = (0..SPILL_CHUNK * 5 / 16).map(|i| i as f64 / 7.0).collect();
    e.put_f64_slice(&values);
    e.put_u32(7);
}

#[test]
fn a_checkpoint_encoded_into_its_file_is_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let (streamed, whole) = (dir.path().join("a.bin"), dir.path().join("b.bin"));
    let mut c = sample();
    let mut e = Encoder::new();
    large_state(&mut e);
    c.payload = e.finish();
    let len = Checkpoint {
        payload: Vec::new(),
        ..c.clone()
    }
    .write_encoded(&streamed, large_state)
    .unwrap();
    c.write(&whole).unwrap();
    assert_eq!(len, c.payload.len() as u64);
    assert!(len as usize > 2 * SPILL_CHUNK, "the payload spills");
    assert!(std::fs::read(&streamed).unwrap() == std::fs::read(&whole).unwrap());
    assert_eq!(Checkpoint::read(&streamed).unwrap(), c);
    // A small state, held whole until the end.
    let small = sample();
    let payload = small.payload.clone();
    small
        .write_encoded(&streamed, |e| {
            let mut d = Decoder::new(&payload, &streamed);
            e.put_f64x3_slice(&d.take_f64x3_slice("x", 2).unwrap());
            e.put_u32_slice(&d.take_u32_slice_bounded("n", 3, 8).unwrap());
            e.put_f32_slice(&d.take_f32_slice("d", 1).unwrap());
            e.put_f64(d.take_f64("w").unwrap());
            e.put_u64(d.take_u64("c").unwrap());
        })
        .unwrap();
    assert_eq!(Checkpoint::read(&streamed).unwrap(), small);
}

#[test]
fn a_failed_streamed_write_names_the_file_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("gone").join("state.bin");
    let m = sample()
        .write_encoded(&path, large_state)
        .unwrap_err()
        .to_string();
    assert!(m.contains("gone/state.bin"), "{m}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn damage_is_refused_with_the_file_and_the_reason() {
    let good = sample().encode();
    let mut flipped = good.clone();
    flipped[HEADER_LEN + 5] ^= 0x10;
    let m = message(&flipped);
    assert!(
        m.starts_with("out/checkpoint/state.bin: checksum mismatch")
            && m.contains("damaged")
            && m.contains("frame")
            && m.contains("12")
            && m.contains("without --resume"),
        "{m}"
    );
    let m = message(&good[..good.len() - 9]);
    assert!(m.contains("truncated"), "{m}");
    let m = message(&good[..20]);
    assert!(m.contains("truncated"), "{m}");
    let mut long = good.clone();
    long.push(0);
    assert!(message(&long).contains("trailing bytes"));
    let mut old = good.clone();
    old[..8].copy_from_slice(b"PFCKPT01");
    assert!(message(&old).contains("another perifrac version"));
    assert!(message(b"hello").contains("not a perifrac checkpoint"));
    let mut version = good.clone();
    version[8] = 9;
    assert!(message(&version).contains("format version 9"));
}

#[test]
fn decoder_names_short_and_invalid_fields() {
    let c = sample();
    let path = Path::new("state.bin");
    let mut d = Decoder::new(&c.payload, path);
    let m = d.take_f64x3_slice("position", 3).unwrap_err().to_string();
    assert!(
        m.contains("'position'") && m.contains("scene gives 3"),
        "{m}"
    );
    let mut d = Decoder::new(&c.payload, path);
    d.take_f64x3_slice("position", 2).unwrap();
    let m = d
        .take_u32_slice_bounded("neighbours", 3, 7)
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("'neighbours'") && m.contains("value 7 at 2"),
        "{m}"
    );
    let mut d = Decoder::new(&c.payload[..c.payload.len() - 3], path);
    d.take_f64x3_slice("position", 2).unwrap();
    d.take_u32_slice("neighbours", 3).unwrap();
    d.take_f32_slice("damage", 1).unwrap();
    d.take_f64("work").unwrap();
    let m = d.take_u64("count").unwrap_err().to_string();
    assert!(m.contains("'count'") && m.contains("truncated"), "{m}");
    let mut d = Decoder::new(&c.payload, path);
    d.take_f64x3_slice("position", 2).unwrap();
    let m = d.finish().unwrap_err().to_string();
    assert!(m.contains("bytes left"), "{m}");
}
