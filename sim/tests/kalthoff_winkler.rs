//! Issue 33 item 7: the Kalthoff–Winkler plate (`assets/scenes/kalthoff-winkler.toml`,
//! after Silling 2003), its cracks' angle from the notch tips with particle contact on
//! and off. The angle is read from the model's bonds: a line through the tip fitted to
//! the reference midpoints of the bonds that broke during the run (not the notches'),
//! beyond 2δ of the tip.

use std::path::Path;

use perifrac_sim::family::BROKEN;
use perifrac_sim::run;
use perifrac_sim::scene::Scene;

/// The shipped scene at λ = `lambda` (its critical stretch scaled as δ^{-1/2}, Silling
/// & Askari 2005 Eq. 25), with `contact` appended to its text.
fn scene(lambda: f64, contact: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/kalthoff-winkler.toml");
    let text = std::fs::read_to_string(&path).expect("the Kalthoff–Winkler scene");
    let stretch = 0.00422 * (0.003 / lambda).sqrt();
    for part in ["resolution = 0.003 ", "critical_stretch = 0.00422\n"] {
        assert!(text.contains(part), "the scene changed: no {part:?}");
    }
    text.replace("resolution = 0.003 ", &format!("resolution = {lambda} "))
        .replace(
            "critical_stretch = 0.00422\n",
            &format!("critical_stretch = {stretch}\n"),
        )
        + contact
}

/// `text` with zero-width notches: the plate a plain box and the notches'
/// bonds cut (`[[body.crack]]`) instead of 1.5 mm slots.
fn zero_width(text: &str) -> String {
    let start = text
        .find("shape = { type = \"difference\"")
        .expect("the plate's shape");
    let end = start + text[start..].find('\n').expect("one line");
    let mut out = text[..start].to_string();
    out += "shape = { type = \"box\", center = [0.05, 0.0, 0.0], size = [0.1, 0.2, 0.009] }\n";
    for y in [0.025, -0.025] {
        out += &format!(
            "[[body.crack]]\npoint = [0.0, {y}, 0.0]\nnormal = [0.0, 1.0, 0.0]\n\
             region = {{ type = \"box\", center = [0.025, {y}, 0.0], size = [0.05, 0.01, 0.02] }}\n"
        );
    }
    out += &text[end + 1..];
    out
}

/// What a run gives: each notch's crack angle (degrees from the notch, +x, toward the
/// plate's outer edge) and the number of broken bonds the fit used.
#[derive(Debug)]
struct Angles {
    upper: (f64, usize),
    lower: (f64, usize),
}

/// Runs `text` to its end and fits the cracks.
fn crack_angles(text: &str) -> Angles {
    let scene = Scene::parse(text, Path::new("kw.toml"), Path::new(".")).expect("scene");
    let delta = scene.bodies[0].delta();
    let mut p = run::prepare(&scene).expect("prepares");
    let steps = p.steps_per_frame * (scene.scene.duration * scene.scene.fps).round() as usize;
    let cut: Vec<bool> = {
        let model = p.world.parts[0].model.as_ref();
        let bonds = model.contact_points().and_then(|c| c.bonds).expect("bonds");
        bonds.neighbours.iter().map(|&n| n & BROKEN != 0).collect()
    };
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let model = p.world.parts[0].model.as_ref();
    let bonds = model.contact_points().and_then(|c| c.bonds).expect("bonds");
    let x = model.points().reference;
    let mut midpoints = Vec::new();
    for i in 0..x.len() {
        for k in bonds.range(i) {
            let n = bonds.neighbours[k];
            if n & BROKEN == 0 || cut[k] {
                continue;
            }
            let j = (n & !BROKEN) as usize;
            midpoints.push([0.5 * (x[i][0] + x[j][0]), 0.5 * (x[i][1] + x[j][1])]);
        }
    }
    if std::env::var_os("KW_MAP").is_some() {
        // Broken bonds a 4 mm cell of the reference plate, x across, y down the page.
        let mut grid = vec![[0usize; 25]; 50];
        for m in &midpoints {
            let (c, r) = ((m[0] / 0.004) as usize, ((0.1 - m[1]) / 0.004) as usize);
            if c < 25 && r < 50 {
                grid[r][c] += 1;
            }
        }
        for row in &grid {
            let line: String = row
                .iter()
                .map(|&k| match k {
                    0 => ' ',
                    1..=9 => '.',
                    10..=49 => ':',
                    50..=199 => 'o',
                    _ => '#',
                })
                .collect();
            eprintln!("|{line}|");
        }
    }
    let fit = |side: f64| {
        // Tip at (0.05, ±0.025); the crack runs into x > 0.05, outward (side · y > 0.025).
        let (mut sxx, mut sxy, mut syy, mut n) = (0.0, 0.0, 0.0, 0usize);
        for m in &midpoints {
            let (dx, dy) = (m[0] - 0.05, side * m[1] - 0.025);
            let r = (dx * dx + dy * dy).sqrt();
            if dx < -delta || dy < 0.0 || r < 2.0 * delta || r > 0.045 {
                continue;
            }
            sxx += dx * dx;
            sxy += dx * dy;
            syy += dy * dy;
            n += 1;
        }
        // The principal axis of the second moments about the tip (a line through it).
        let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
        (angle.to_degrees(), n)
    };
    Angles {
        upper: fit(1.0),
        lower: fit(-1.0),
    }
}

/// Measurement (`KW_LAMBDA=0.003 cargo test --release -p perifrac-sim --test
/// kalthoff_winkler -- --ignored --nocapture`): the angles with contact as the scene
/// has it (on, by default), frictionless, and off.
#[test]
#[ignore = "measurement at the scene's resolution: run it on purpose"]
fn kalthoff_winkler_angles() {
    let lambda: f64 = std::env::var("KW_LAMBDA")
        .map(|s| s.parse().expect("KW_LAMBDA in m"))
        .unwrap_or(0.003);
    let cases = std::env::var("KW_CASES").unwrap_or_else(|_| "on frictionless off".into());
    for case in cases.split_whitespace() {
        let contact = match case {
            "on" => "",
            "frictionless" => "\n[contact]\nfriction = 0.0\n",
            "off" => "\n[contact]\nparticles = false\n",
            other => panic!("KW_CASES: on, frictionless or off, not {other}"),
        };
        let start = std::time::Instant::now();
        let mut text = scene(lambda, contact);
        if std::env::var_os("KW_ZERO_WIDTH").is_some() {
            text = zero_width(&text);
        }
        let a = crack_angles(&text);
        eprintln!(
            "λ = {lambda} m, contact {case}: upper notch {:.1}° ({} bonds), lower {:.1}° ({} bonds), {:.0} s",
            a.upper.0,
            a.upper.1,
            a.lower.0,
            a.lower.1,
            start.elapsed().as_secs_f64()
        );
    }
}
