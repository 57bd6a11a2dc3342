//! Issue 33 item 7: the Kalthoff–Winkler plate (`assets/scenes/kalthoff-winkler.toml`,
//! after Silling 2003), its cracks' angle from the notch tips with particle contact on
//! and off (`docs/contact.md`, "Contact and the Kalthoff–Winkler cracks"). The angle
//! is read from the model's bonds: the median polar angle, about the tip, of the
//! reference midpoints of the bonds that broke during the run (not the notches'), 2δ
//! to 45 mm from the tip, on the side away from the centreline; also by 15 mm shells and
//! the principal axis of their second moments. `KW_MAP` prints the broken bonds a 4 mm
//! cell, `KW_CONTACT_MAP` where the contact force acted, `KW_ZERO_WIDTH` cuts the
//! notches as zero-width pre-cuts instead of slots, `KW_LATTICE=aligned` meshes the
//! plate on the aligned lattice instead of the unstructured mesh, `KW_SEED` meshes it
//! with another seed.

use std::path::Path;

use perifrac_sim::crack_angle::{
    CrackAngle, KALTHOFF_WINKLER_NOTCHES, KALTHOFF_WINKLER_REACH, NotchCut, broken_during_run,
    crack_angle, kalthoff_winkler_variant,
};
use perifrac_sim::family::BROKEN;
use perifrac_sim::run;
use perifrac_sim::scene::{LatticeOrientation, Scene};

/// The shipped scene at λ = `lambda` with `cut` notches on `lattice`
/// (`kalthoff_winkler_variant`).
fn scene(lambda: f64, cut: NotchCut, lattice: LatticeOrientation) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/kalthoff-winkler.toml");
    let base = Scene::load(&path).expect("the Kalthoff–Winkler scene");
    kalthoff_winkler_variant(&base, lambda, cut, lattice).expect("a variant")
}

/// `scene` meshed with the seed `KW_SEED` when it is set (the measurements' other
/// random meshes).
fn seeded(mut scene: Scene) -> Scene {
    if let Ok(seed) = std::env::var("KW_SEED") {
        scene.scene.seed = seed.parse().expect("KW_SEED: an integer");
    }
    scene
}

/// Runs `scene` to its end and reads the cracks of the upper and lower notches
/// (`perifrac_sim::crack_angle`, 2δ to 45 mm from the tips).
fn crack_angles(scene: &Scene) -> [CrackAngle; 2] {
    // Where particle contact acts: Σ |F| Δt on each particle (N s) and the step it
    // first did, for KW_CONTACT_MAP.
    let (mut impulse, mut first) = (Vec::new(), Vec::new());
    let mut reference = Vec::new();
    let broken = broken_during_run(scene, |world, step| {
        let Some(c) = &world.contact else { return };
        let f = c.force(0);
        if impulse.is_empty() {
            impulse = vec![0.0f64; f.len()];
            first = vec![usize::MAX; f.len()];
            reference = world.parts[0].model.points().reference.to_vec();
        }
        for (i, f) in f.iter().enumerate() {
            let m = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
            if m > 0.0 {
                impulse[i] += m * world.dt;
                first[i] = first[i].min(step);
            }
        }
    })
    .expect("runs");
    if std::env::var_os("KW_CONTACT_MAP").is_some() {
        contact_map(&reference, &impulse, &first);
    }
    if std::env::var_os("KW_MAP").is_some() {
        // Broken bonds a 4 mm cell of the reference plate, x across, y down the page.
        let mut grid = vec![[0usize; 25]; 50];
        for m in &broken.midpoints {
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
    KALTHOFF_WINKLER_NOTCHES.map(|notch| crack_angle(&broken, notch, KALTHOFF_WINKLER_REACH))
}

/// Prints the contact impulse a 4 mm cell of the reference plate (log scale) and the
/// first steps it acted there.
fn contact_map(x: &[[f64; 3]], impulse: &[f64], first: &[usize]) {
    let mut grid = vec![[(0.0f64, usize::MAX); 25]; 50];
    for i in 0..impulse.len() {
        let (c, r) = (
            (x[i][0] / 0.004) as usize,
            ((0.1 - x[i][1]) / 0.004) as usize,
        );
        if c < 25 && r < 50 {
            grid[r][c].0 += impulse[i];
            grid[r][c].1 = grid[r][c].1.min(first[i]);
        }
    }
    eprintln!("contact impulse a 4 mm cell, log10 N s (' ' none, 0: < 1e-6 … 9: ≥ 1e2)");
    for row in &grid {
        let line: String = row
            .iter()
            .map(|&(j, _)| {
                if j == 0.0 {
                    ' '
                } else {
                    char::from(b'0' + (j.log10() + 6.0).clamp(0.0, 9.0) as u8)
                }
            })
            .collect();
        let when: Vec<String> = row
            .iter()
            .filter(|c| c.1 != usize::MAX)
            .map(|c| format!("{}", c.1))
            .take(3)
            .collect();
        eprintln!("|{line}| first steps {}", when.join(" "));
    }
    let total: f64 = impulse.iter().sum();
    let near_edge: f64 = (0..impulse.len())
        .filter(|&i| x[i][0] < 0.01)
        .map(|i| impulse[i])
        .sum();
    eprintln!(
        "contact impulse: {total:.3e} N s in all, {near_edge:.3e} within 10 mm of the impacted edge"
    );
}

/// Issue 33 item 7 in the suite, at a coarse λ = 4 mm on the aligned lattice (about
/// 11 s a run in release): the cracks leave both notch tips at 52° or more, and
/// particle contact (on by default) turns them by at most 2° from the run without
/// it (measured: 54.5° at both notches, with contact and without). The contact
/// before issue 33's fix turned them by 6–9° at 3 mm, to 47° (docs/contact.md,
/// "Contact and the Kalthoff–Winkler cracks"); the finer spacings' angles are
/// `perifrac bench accuracy`'s.
#[test]
fn contact_leaves_the_kalthoff_winkler_cracks_alone() {
    let on = scene(0.004, NotchCut::Slots, LatticeOrientation::Aligned);
    let mut off = on.clone();
    off.contact.particles = Some(false);
    let (on, off) = (crack_angles(&on), crack_angles(&off));
    for (notch, (on, off)) in ["upper", "lower"].iter().zip(on.iter().zip(&off)) {
        eprintln!(
            "{notch} notch: {:.1}° with contact, {:.1}° without",
            on.median, off.median
        );
        assert!(
            on.median >= 52.0 && off.median >= 52.0,
            "{notch} notch: the crack leaves at {:.1}° with contact, {:.1}° without (54.5° at 4 mm)",
            on.median,
            off.median
        );
        assert!(
            (on.median - off.median).abs() <= 2.0,
            "{notch} notch: contact turns the crack from {:.1}° to {:.1}°",
            off.median,
            on.median
        );
    }
}

/// Issue 33's goal at converged spacings, with the scene's defaults (contact on,
/// slotted notches): each notch's crack leaves at 65–72° (the experiment: 68–70°) on
/// the aligned lattice at λ = 2 mm (65.5° at both notches, 207 s in release) and on
/// the unstructured mesh at λ = 1.2 mm (1.04 million particles, 4.8 GB, 29–35
/// minutes on 2 cores; `KW_SEED` picks the mesh). Too long for the suite, whose check
/// at 4 mm is `contact_leaves_the_kalthoff_winkler_cracks_alone`; run it on purpose:
/// `cargo test --release -p perifrac-sim --test kalthoff_winkler -- --ignored
/// --nocapture converged`. At 1.5 mm the unstructured mesh's notches came to
/// 63.3–67.3° over three meshes, two of six under the goal (docs/contact.md).
#[test]
#[ignore = "35 minutes in release: run it on purpose"]
fn the_converged_cracks_leave_the_notches_at_65_to_72_degrees() {
    for (lattice, lambda) in [
        (LatticeOrientation::Aligned, 0.002),
        (LatticeOrientation::Unstructured, 0.0012),
    ] {
        let scene = seeded(scene(lambda, NotchCut::Slots, lattice));
        let start = std::time::Instant::now();
        let angles = crack_angles(&scene);
        for (notch, angle) in ["upper", "lower"].iter().zip(&angles) {
            eprintln!(
                "λ = {lambda} m on {lattice:?}, seed {}: {notch} notch {:.1}° ({:.0} s)",
                scene.scene.seed,
                angle.median,
                start.elapsed().as_secs_f64()
            );
            assert!(
                (65.0..=72.0).contains(&angle.median),
                "λ = {lambda} m on {lattice:?}: the {notch} notch's crack leaves at {:.1}°",
                angle.median
            );
        }
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
        let cut = if std::env::var_os("KW_ZERO_WIDTH").is_some() {
            NotchCut::ZeroWidth
        } else {
            NotchCut::Slots
        };
        let lattice = match std::env::var("KW_LATTICE").as_deref() {
            Ok("aligned") => LatticeOrientation::Aligned,
            Ok("rotated") => LatticeOrientation::Rotated,
            _ => LatticeOrientation::Unstructured,
        };
        let mut scene = seeded(scene(lambda, cut, lattice));
        match case {
            "on" => {}
            "frictionless" => scene.contact.friction = 0.0,
            "off" => scene.contact.particles = Some(false),
            "near" => scene.contact.distance = 0.5,
            "soft" => scene.contact.stiffness = 0.01,
            other => panic!("KW_CASES: on, frictionless, off, near or soft, not {other}"),
        }
        let start = std::time::Instant::now();
        let [upper, lower] = crack_angles(&scene);
        eprintln!(
            "λ = {lambda} m, {cut:?} on {lattice:?}, contact {case}: upper notch {:.1}° ({} bonds; 2δ–15, 15–30, 30–45 mm: {:.1?}, axis {:.1}°), \
             lower {:.1}° ({} bonds; {:.1?}, axis {:.1}°), {:.0} s",
            upper.median,
            upper.bonds,
            upper.shells,
            upper.axis,
            lower.median,
            lower.bonds,
            lower.shells,
            lower.axis,
            start.elapsed().as_secs_f64()
        );
    }
}

/// Measurement (`cargo test --release -p perifrac-sim --test kalthoff_winkler --
/// --ignored --nocapture notch_faces`): at the scene's λ = 3 mm the 1.5 mm notches
/// are not resolved by the particles: points of the two faces lie closer than a
/// spacing, no bond joining them, so sheared past each other they come within their
/// contact distance.
#[test]
#[ignore = "measurement: run it on purpose"]
fn notch_faces_within_contact_reach() {
    let scene = scene(0.003, NotchCut::Slots, LatticeOrientation::Unstructured);
    let p = run::prepare(&scene).expect("prepares");
    let model = p.world.parts[0].model.as_ref();
    let bonds = model.contact_points().and_then(|c| c.bonds).expect("bonds");
    let vol = model.contact_points().unwrap().volume;
    let x = model.points().reference;
    let cut = bonds
        .neighbours
        .iter()
        .filter(|&&n| n & BROKEN != 0)
        .count();
    eprintln!(
        "initially broken bonds: {cut} of {}",
        bonds.neighbours.len()
    );
    // Pairs across the upper notch (x < 0.05): the closest, and how many within 0.9 l.
    let (mut closest, mut within, mut bonded) = (1.0f64, 0, 0);
    let mut hist = [0usize; 8];
    for i in 0..x.len() {
        if x[i][0] > 0.05 || x[i][1] > 0.025 || x[i][1] < 0.015 {
            continue;
        }
        for j in 0..x.len() {
            if x[j][0] > 0.05 || x[j][1] < 0.025 || x[j][1] > 0.035 {
                continue;
            }
            let d = [x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]];
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            closest = closest.min(r);
            let l = 0.5 * (vol[i].cbrt() + vol[j].cbrt());
            if r < 2.0 * l {
                hist[((r / l) * 4.0) as usize] += 1;
            }
            if r < 0.9 * l {
                within += 1;
            }
            if bonds
                .range(i)
                .any(|k| bonds.neighbours[k] & !BROKEN == j as u32)
            {
                bonded += 1;
            }
        }
    }
    eprintln!(
        "across the notch: closest {closest:.2e} m, {within} pairs within 0.9 l, {bonded} bonds (any state); r/l histogram by quarters: {hist:?}"
    );
    let mean_l: f64 = vol.iter().map(|v| v.cbrt()).sum::<f64>() / vol.len() as f64;
    eprintln!("mean l {mean_l:.2e} m");
}
