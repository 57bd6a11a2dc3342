//! Values that used to pass validation (issue 17): a duration whose frame count
//! wraps, infinite anchor centres and crack points, NaN release times, a file that
//! is not UTF-8, raw control bytes echoed into messages.

use std::path::Path;

use super::{Clamp, Scene};
use crate::CacheError;

const GOOD: &str = "[scene]\nname = \"t\"\n[materials.m]\ndensity = 1000.0\n\
    youngs_modulus = 1e6\npoisson_ratio = 0.3\n[[body]]\nmaterial = \"m\"\n\
    resolution = 0.1\nshape = { type = \"box\", center = [0, 0, 0], size = [1, 1, 1] }\n";

/// The scene error of `text`: (line, column, key, message).
fn error(text: &str) -> (usize, usize, String, String) {
    match Scene::parse(text, Path::new("bad.toml"), Path::new(".")) {
        Err(CacheError::Scene {
            line,
            column,
            key,
            message,
            ..
        }) => (line, column, key, message),
        other => panic!("expected a scene error, got {other:?}"),
    }
}

#[test]
fn a_duration_beyond_the_frame_limit_is_refused() {
    for duration in ["1e300", "5e5"] {
        let text = GOOD.replace("name = \"t\"", &format!("duration = {duration}\nfps = 24"));
        let (line, _, key, message) = error(&text);
        assert_eq!((line, key.as_str()), (2, "scene.duration"), "{message}");
        assert!(
            message.contains("frames") && message.contains("at most"),
            "{message}"
        );
    }
    let inf = GOOD.replace("name = \"t\"", "duration = inf");
    let (_, _, key, message) = error(&inf);
    assert!(
        key == "scene.duration" && message.contains("finite"),
        "{message}"
    );
    let ok = GOOD.replace("name = \"t\"", "duration = 4e5\nfps = 24");
    let scene = Scene::parse(&ok, Path::new("ok.toml"), Path::new(".")).expect("9.6e6 frames");
    assert_eq!(scene.frame_count(), 9_600_000);
}

#[test]
fn infinite_anchor_centres_and_crack_points_are_refused() {
    let anchor = format!(
        "{GOOD}[[body.anchor]]\nregion = {{ type = \"sphere\", center = [0, 0, 0], radius = 0.2 }}\n\
         center = [-inf, 0, 0]\n"
    );
    let (line, _, key, message) = error(&anchor);
    assert_eq!(
        (line, key.as_str()),
        (13, "body.0.anchor.0.center"),
        "{message}"
    );
    assert!(message.contains("finite"), "{message}");
    let until = anchor.replace("center = [-inf, 0, 0]", "until = nan");
    let (_, _, key, message) = error(&until);
    assert_eq!(key, "body.0.anchor.0.until", "{message}");
    let until = anchor.replace("center = [-inf, 0, 0]", "until = -1.0");
    assert_eq!(error(&until).2, "body.0.anchor.0.until");
    let crack = format!(
        "{GOOD}[[body.crack]]\npoint = [0, -inf, 0]\nnormal = [1, 0, 0]\n\
         region = {{ type = \"box\", center = [0, 0, 0], size = [1, 1, 1] }}\n"
    );
    let (line, _, key, message) = error(&crack);
    assert_eq!(
        (line, key.as_str()),
        (12, "body.0.crack.0.point"),
        "{message}"
    );
}

#[test]
fn a_file_that_is_not_utf8_is_refused_with_its_position() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("latin1.toml");
    // "name = "café"" in Latin-1: é is the single byte 0xe9.
    let mut bytes = GOOD.replace("name = \"t\"", "name = \"caf").into_bytes();
    let at = bytes.iter().position(|&b| b == b'f').unwrap() + 1;
    bytes.insert(at, 0xe9);
    std::fs::write(&path, &bytes).expect("write");
    let e = Scene::load(&path).expect_err("not UTF-8");
    assert!(e.is_bad_input(), "{e}");
    let m = e.to_string();
    assert!(
        m.contains("latin1.toml:2:12:") && m.contains(&format!("byte {at} (0xe9) is not UTF-8")),
        "{m}"
    );
}

#[test]
fn control_bytes_of_the_input_are_escaped_in_messages() {
    // A terminal escape in a key and a carriage return in a material name.
    let (_, _, key, message) =
        error(&GOOD.replace("density = 1000.0", "density = 1000.0\n\"x\\u001b[2J\" = 1"));
    let shown = format!("{key}: {message}");
    assert!(!shown.chars().any(char::is_control), "{shown:?}");
    assert!(shown.contains("\\u{1b}[2J"), "{shown}");
    let (_, _, key, message) = error(&GOOD.replace("material = \"m\"", "material = \"m\\r\""));
    let shown = format!("{key}: {message}");
    assert!(!shown.chars().any(char::is_control), "{shown:?}");
    assert!(shown.contains("m\\r"), "{shown}");
    let raw = GOOD.replace("resolution = 0.1", "resolution = 0.1\u{7}");
    let (_, _, key, message) = error(&raw);
    assert!(
        !format!("{key}{message}").chars().any(char::is_control),
        "{message:?}"
    );
}

#[test]
fn bad_clamps_are_refused_with_their_key_and_fix() {
    let clamp = format!(
        "{GOOD}[[body.anchor]]\nregion = {{ type = \"box\", center = [-0.5, 0, 0], size = [0.2, 2, 2] }}\n\
         clamp = {{ point = [-0.4, 0, 0], normal = [1, 0, 0] }}\n"
    );
    Scene::parse(&clamp, Path::new("ok.toml"), Path::new(".")).expect("a good clamp");
    let zero = clamp.replace("normal = [1, 0, 0]", "normal = [0, 0, 0]");
    let (line, _, key, message) = error(&zero);
    assert_eq!(
        (line, key.as_str()),
        (13, "body.0.anchor.0.clamp.normal"),
        "{message}"
    );
    assert!(message.contains("into the free body"), "{message}");
    let point = clamp.replace("point = [-0.4, 0, 0]", "point = [nan, 0, 0]");
    assert_eq!(error(&point).2, "body.0.anchor.0.clamp.point");
    let moving = clamp.replace("clamp = {", "velocity = [0, 1, 0]\nclamp = {");
    let (_, _, key, message) = error(&moving);
    assert_eq!(key, "body.0.anchor.0.velocity", "{message}");
    assert!(message.contains("a clamp is fixed"), "{message}");
    let fem = clamp.replace(
        "material = \"m\"",
        "material = \"m\"\nmodel = \"fem-linear\"",
    );
    let (_, _, key, message) = error(&fem);
    assert_eq!(key, "body.0.anchor.0.clamp", "{message}");
    assert!(message.contains("peridynamics"), "{message}");
    let unknown = clamp.replace("normal = [1, 0, 0]", "normal = [1, 0, 0], depth = 1");
    assert!(error(&unknown).3.contains("depth"));
}

/// Issue 33, item 6: `clamp = false` asks for the whole region held (no clamp by
/// default at the box's face), for moving anchors too, and is written back as such;
/// `clamp = true` and other values are refused with what to write.
#[test]
fn clamp_false_holds_the_region_and_other_values_are_refused() {
    let plain = format!(
        "{GOOD}[[body.anchor]]\nregion = {{ type = \"box\", center = [-0.5, 0, 0], size = [0.2, 2, 2] }}\n"
    );
    let parse = |text: &str| Scene::parse(text, Path::new("ok.toml"), Path::new(".")).expect(text);
    assert_eq!(parse(&plain).bodies[0].anchors[0].clamp, None);
    let held = format!("{plain}clamp = false\n");
    let scene = parse(&held);
    assert_eq!(scene.bodies[0].anchors[0].clamp, Some(Clamp::Held));
    let again = parse(&scene.to_toml());
    assert_eq!(again.bodies[0].anchors[0].clamp, Some(Clamp::Held));
    let plane = held.replace(
        "clamp = false",
        "clamp = { point = [-0.4, 0, 0], normal = [1, 0, 0] }",
    );
    let scene = parse(&plane);
    assert_eq!(
        parse(&scene.to_toml()).bodies[0].anchors[0].clamp,
        scene.bodies[0].anchors[0].clamp
    );
    parse(&held.replace("clamp = false", "velocity = [0, 1, 0]\nclamp = false"));
    let (line, _, key, message) = error(&held.replace("clamp = false", "clamp = true"));
    assert_eq!((line, key.as_str()), (13, "body.anchor.clamp"), "{message}");
    assert!(
        message.contains("clamp = false") && message.contains("perifrac check"),
        "{message}"
    );
    let (line, _, key, message) = error(&held.replace("clamp = false", "clamp = \"held\""));
    assert_eq!((line, key.as_str()), (13, "body.anchor.clamp"), "{message}");
    assert!(
        message.contains("false (the whole region held)"),
        "{message}"
    );
}

/// Regression (issue 34): `gravity` with 4 or 2,000,001 components was read as its
/// first three (serde's `[f64; 3]` stops after three and toml drops the rest); every
/// fixed-size array of a plain table is now read with its length checked.
#[test]
fn arrays_of_the_wrong_length_are_refused() {
    let four = GOOD.replace("name = \"t\"", "gravity = [0.0, -9.81, 0.0, 5.0]");
    let (line, _, key, message) = error(&four);
    assert_eq!((line, key.as_str()), (2, "scene.gravity"), "{message}");
    assert!(
        message.contains("invalid length 4") && message.contains("3 elements"),
        "{message}"
    );
    let huge = GOOD.replace(
        "name = \"t\"",
        &format!("gravity = [{}]", vec!["0.0"; 2_000_001].join(",")),
    );
    let (_, _, key, message) = error(&huge);
    assert!(
        key == "scene.gravity" && message.contains("invalid length 2000001"),
        "{message}"
    );
    let crack = format!(
        "{GOOD}[[body.crack]]\npoint = [0, 0, 0, 1]\nnormal = [0, 1, 0]\n\
         region = {{ type = \"sphere\", center = [0, 0, 0], radius = 0.2 }}\n"
    );
    let (_, _, key, message) = error(&crack);
    assert!(
        key == "body.crack.point" && message.contains("invalid length 4"),
        "{key}: {message}"
    );
    let anisotropy = GOOD.replace(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\nanisotropy = [[1, 0, 0], [0, 1, 0], [0, 0]]",
    );
    let (_, _, key, message) = error(&anisotropy);
    assert!(
        key == "materials.m.anisotropy" && message.contains("invalid length 2"),
        "{key}: {message}"
    );
    let three = GOOD.replace("name = \"t\"", "gravity = [0.0, -1.0, 0.0]");
    let scene = Scene::parse(&three, Path::new("ok.toml"), Path::new(".")).expect("3 components");
    assert_eq!(scene.scene.gravity, [0.0, -1.0, 0.0]);
}

#[test]
fn material_colours_parse_default_to_the_palette_and_bad_ones_are_placed() {
    let two = format!(
        "{GOOD}[materials.steel]\ndensity = 7800.0\nyoungs_modulus = 2e11\npoisson_ratio = 0.3\n\
         [[body]]\nmaterial = \"steel\"\nresolution = 0.1\n\
         shape = {{ type = \"box\", center = [2, 0, 0], size = [1, 1, 1] }}\n"
    );
    let scene = Scene::parse(&two, Path::new("ok.toml"), Path::new(".")).expect("two bodies");
    let colors = scene.body_colors();
    assert_eq!(colors, [super::PALETTE[0], super::PALETTE[1]]);
    let named = two.replace("density = 7800.0", "density = 7800.0\ncolor = \"#336699\"");
    let named = named.replace(
        "density = 1000.0",
        "density = 1000.0\ncolor = [1.0, 0.5, 0.0]",
    );
    let scene = Scene::parse(&named, Path::new("ok.toml"), Path::new(".")).expect("colours");
    assert_eq!(
        scene.body_colors(),
        [
            [1.0, 0.5, 0.0],
            [
                0x33 as f32 / 255.0,
                0x66 as f32 / 255.0,
                0x99 as f32 / 255.0
            ]
        ]
    );
    // The resolved scene keeps the colours.
    let again = Scene::parse(&scene.to_toml(), Path::new("r.toml"), Path::new("."));
    assert_eq!(
        again.expect("round trip").body_colors(),
        scene.body_colors()
    );
    let bad = GOOD.replace("density = 1000.0", "density = 1000.0\ncolor = \"orange\"");
    let (line, _, key, message) = error(&bad);
    assert_eq!((line, key.as_str()), (5, "materials.m.color"), "{message}");
    assert!(message.contains("#RRGGBB"), "{message}");
}

#[test]
fn bad_rigid_values_are_refused_with_their_key() {
    let rigid = format!("{GOOD}[rigid]\nenabled = true\nreenter = 2\n");
    Scene::parse(&rigid, Path::new("ok.toml"), Path::new(".")).expect("a good [rigid]");
    for (bad, key) in [
        ("reenter = -1", "rigid.reenter"),
        ("reenter = nan", "rigid.reenter"),
        ("reenter = 2\nrestitution = 1.5", "rigid.restitution"),
        (
            "reenter = 2\nrolling_resistance = -0.01",
            "rigid.rolling_resistance",
        ),
        (
            "reenter = 2\nrolling_resistance = inf",
            "rigid.rolling_resistance",
        ),
    ] {
        let text = rigid.replace("reenter = 2", bad);
        let (_, _, found, message) = error(&text);
        assert_eq!(found, key, "{message}");
    }
}
