//! Whole-simulation validation: waves, energy, momentum, plasticity, fracture,
//! determinism, stability and input errors. Scenes are small so the suite stays fast;
//! `perifrac bench` runs the full resolutions.

use std::path::Path;

use perifrac_sim::SimError;
use perifrac_sim::fem::{Fem, FemModel};
use perifrac_sim::pd::{PdModel, Peridynamics};
use perifrac_sim::run::{self, Prepared, RunOptions};
use perifrac_sim::scene::Scene;

fn scene(text: &str) -> Scene {
    Scene::parse(text, Path::new("test.toml"), Path::new(".")).expect("valid scene")
}

fn prepare(text: &str) -> Prepared {
    run::prepare(&scene(text)).expect("scene prepares")
}

/// The peridynamic model of a prepared scene.
fn pd(p: &Prepared) -> &PdModel {
    &p.world.model::<Peridynamics>().expect("peridynamic").model
}

/// The particle masses of a prepared peridynamic scene.
fn pd_masses(p: &Prepared) -> &[f64] {
    p.world.parts[0].model.points().mass
}

/// The FEM model of a prepared reference scene.
fn fem(p: &Prepared) -> &FemModel {
    &p.world.model::<Fem>().expect("FEM").model
}

const SOFT: &str = "density = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.25\n";

/// Mean x-displacement of the particles with reference x above `x0`.
fn mean_dx(p: &Prepared, x0: f64) -> f64 {
    let m = pd(p);
    let (mut s, mut n) = (0.0, 0);
    for i in 0..m.len() {
        if m.reference.position[i][0] > x0 {
            s += m.particles.position[i][0] - m.reference.position[i][0];
            n += 1;
        }
    }
    s / n as f64
}

#[test]
fn longitudinal_wave_speed_in_a_slender_bar() {
    let length = 1.0;
    let mut p = prepare(&format!(
        "[scene]\ngravity = [0, 0, 0]\nduration = 0.1\nfps = 100\n[materials.m]\n{SOFT}\n\
         [[body]]\nmaterial = \"m\"\nresolution = 0.0125\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [{length}, 0.05, 0.05] }}\n"
    ));
    // The first free–free longitudinal mode: v = v0 cos(π (x + L/2) / L); the end
    // displacement is −(v0/ω) sin ωt with ω = π c / L, so it crosses zero at t = L/c.
    p.world.set_velocity(
        |x| {
            [
                1e-3 * (std::f64::consts::PI * (x[0] + length / 2.0) / length).cos(),
                0.0,
                0.0,
            ]
        },
        0.1,
    );
    let c0 = (1.0e6f64 / 1000.0).sqrt();
    let mut previous = (0.0, 0.0);
    let mut crossing = None;
    while p.world.time < 1.6 * length / c0 {
        p.world.step().expect("stable");
        let u = mean_dx(&p, 0.45 * length);
        if p.world.time > 0.5 * length / c0 && previous.1 < 0.0 && u >= 0.0 {
            crossing =
                Some(previous.0 + (p.world.time - previous.0) * (-previous.1) / (u - previous.1));
            break;
        }
        previous = (p.world.time, u);
    }
    let t = crossing.expect("the end came back through zero");
    let c = length / t;
    println!(
        "wave speed {c:.3} m/s, √(E/ρ) = {c0:.3} m/s ({:+.2}%)",
        100.0 * (c / c0 - 1.0)
    );
    assert!((c / c0 - 1.0).abs() < 0.05, "c = {c}, √(E/ρ) = {c0}");
}

#[test]
fn energy_and_momentum_are_conserved() {
    let size = 0.1;
    let mut p = prepare(&format!(
        "[scene]\ngravity = [0, 0, 0]\nduration = 1\n[materials.m]\n{SOFT}\n\
         [[body]]\nmaterial = \"m\"\nresolution = 0.0125\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [{size}, {size}, {size}] }}\n"
    ));
    // A stretching and shearing vibration on top of a uniform drift.
    let pi = std::f64::consts::PI;
    let drift = [0.01, -0.02, 0.005];
    p.world.set_velocity(
        |x| {
            [
                drift[0] + 0.01 * (pi * x[0] / size).sin(),
                drift[1] + 0.01 * (pi * x[0] / size).sin(),
                drift[2],
            ]
        },
        1.0,
    );
    let m0 = p.world.total_mass();
    let momentum = |p: &Prepared| -> [f64; 3] {
        let m = pd(p);
        let mut s = [0.0; 3];
        for (v, mass) in m.particles.velocity.iter().zip(pd_masses(p)) {
            for (s, v) in s.iter_mut().zip(v) {
                *s += mass * v;
            }
        }
        s
    };
    let p0 = momentum(&p);
    let drift_energy = 0.5 * m0 * drift.iter().map(|d| d * d).sum::<f64>();
    let energy = |p: &Prepared| pd(p).kinetic_energy() + pd(p).strain_energy() - drift_energy;
    let period = 2.0 * size / (1.0e6f64 / 1000.0).sqrt();
    let mut samples = Vec::new();
    while p.world.time < 10.0 * period {
        p.world.step().expect("stable");
        samples.push((p.world.time, energy(&p)));
    }
    let mean_over = |t0: f64, t1: f64| {
        let v: Vec<f64> = samples
            .iter()
            .filter(|s| s.0 >= t0 && s.0 < t1)
            .map(|s| s.1)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let first = mean_over(0.0, period);
    let last = mean_over(9.0 * period, 10.0 * period);
    let drift_rel = (last - first).abs() / first;
    let p1 = momentum(&p);
    let dp = ((p1[0] - p0[0]).powi(2) + (p1[1] - p0[1]).powi(2) + (p1[2] - p0[2]).powi(2)).sqrt();
    let p_scale = m0 * 0.02;
    println!(
        "energy drift over 10 periods ({} steps): {:.3e}; momentum change {:.2e} of {p_scale:.2e}",
        samples.len(),
        drift_rel,
        dp
    );
    assert!(
        drift_rel < 0.005,
        "energy drifted by {:.3}%",
        100.0 * drift_rel
    );
    assert!(
        dp < 1e-12 * p_scale.max(1.0) * samples.len() as f64,
        "momentum changed by {dp:e}"
    );
}

/// A bar held at x = −L/2 and pulled at x = +L/2 by `stretch`, then released and
/// left to settle with damping for 0.25 s; returns the remaining elongation. The
/// damping takes the ring down as e^{−20 t}: after 0.25 s the elastic bar is back
/// within 2.5e-5 m (0.3 s: 3.4e-6 m; 0.2 s: 1.1e-5 m near a node of the ring, whose
/// envelope is still ~1e-4 m there), 8× inside the 2e-4 m it is allowed, while the
/// plastic bar's set has settled (5.44e-3 m at 0.25 s, 5.42e-3 m at 0.3 s).
fn permanent_set(plastic: &str, stretch: f64) -> f64 {
    let length = 0.2;
    let pull = 0.05;
    let mut p = prepare(&format!(
        "[scene]\ngravity = [0, 0, 0]\nduration = 1\n[materials.m]\n{SOFT}air_damping = 40.0\n{plastic}\n\
         [[body]]\nmaterial = \"m\"\nresolution = 0.0125\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [{length}, 0.05, 0.05] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [-0.1, 0, 0], size = [0.03, 0.1, 0.1] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0.1, 0, 0], size = [0.03, 0.1, 0.1] }}\n\
         velocity = [{}, 0, 0]\nuntil = {pull}\n",
        stretch * length / pull
    ));
    while p.world.time < pull + 0.25 {
        p.world.step().expect("stable");
    }
    mean_dx(&p, 0.085) - mean_dx(&p, -0.2)
}

#[test]
fn plasticity_leaves_a_permanent_set() {
    let stretch = 0.05;
    let applied = stretch * 0.2;
    let elastic = permanent_set("", stretch);
    let plastic = permanent_set("yield_stretch = 0.002\nplastic_limit = 0.5", stretch);
    println!(
        "elongation after unloading: elastic {elastic:.3e} m, plastic {plastic:.3e} m (applied {applied:.3e} m)"
    );
    assert!(
        elastic.abs() < 0.02 * applied,
        "an elastic bar came back {elastic} m long"
    );
    assert!(
        plastic > 0.3 * applied,
        "a plastic bar kept only {plastic} m of {applied} m"
    );
    assert!(plastic < applied, "it cannot keep more than it was given");
}

/// A bar with a notch on top at x = 0, pulled apart at both ends at `speed` until
/// `hold_after`, then held. α = 2 keeps single particles from flaking off the crack.
fn notched_bar(speed: f64, hold_after: f64) -> Prepared {
    let mut p = prepare(&format!(
        "[scene]\ngravity = [0, 0, 0]\nduration = 1\n[materials.m]\n{SOFT}critical_stretch = 0.02\nalpha = 2.0\n\
         [[body]]\nmaterial = \"m\"\nresolution = 0.0125\n\
         shape = {{ type = \"difference\", base = {{ type = \"box\", center = [0, 0, 0], size = [0.3, 0.06, 0.05] }}, \
         minus = {{ type = \"box\", center = [0, 0.03, 0], size = [0.012, 0.05, 0.1] }} }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [-0.15, 0, 0], size = [0.04, 0.1, 0.1] }}\n\
         velocity = [{}, 0, 0]\nuntil = {hold_after}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0.15, 0, 0], size = [0.04, 0.1, 0.1] }}\n\
         velocity = [{speed}, 0, 0]\nuntil = {hold_after}\n",
        -speed
    ));
    p.world
        .set_velocity(|x| [speed * x[0] / 0.15, 0.0, 0.0], 1.0);
    p
}

#[test]
fn notched_bar_breaks_at_the_notch_into_two_fragments() {
    let speed = 0.05;
    let mut p = notched_bar(speed, f64::INFINITY);
    let mut first_break = None;
    while p.world.time < 0.4 {
        let broken = p.world.step().expect("stable");
        if broken > 0 && first_break.is_none() {
            first_break = Some(p.world.time);
        }
        if p.world.steps % 20 == 0 {
            let f = pd(&p).fragments();
            let left = f.iter().filter(|&&x| x == f[0]).count();
            if left < f.len() * 9 / 10 {
                break;
            }
        }
    }
    let t_break = first_break.expect("the bar broke");
    let fragments = pd(&p).fragments();
    let count = fragments.iter().copied().max().unwrap_or(0) + 1;
    let m = pd(&p);
    let side_ok = (0..m.len()).all(|i| {
        let x = m.reference.position[i][0];
        (x.abs() < 0.03) || (x < 0.0) == (fragments[i] == fragments[0])
    });
    println!(
        "notched bar: first bond broke at t = {t_break:.4} s, {count} fragments, split at the notch: {side_ok}"
    );
    assert_eq!(count, 2, "expected exactly two fragments");
    assert!(side_ok, "the split is not at the notch");
    // Not before: pulled to half the elongation at the first break and held, no bond
    // breaks (the bar rings when its ends stop, overshooting the held stretch by up to
    // ~60%, so half keeps the peak below the critical stretch).
    let mut held = notched_bar(speed, 0.5 * t_break);
    let mut broken = 0;
    while held.world.time < t_break + 0.1 {
        broken += held.world.step().expect("stable");
    }
    assert_eq!(broken, 0, "bonds broke below the critical stretch");
}

fn shatter_fragments(alpha: f64) -> usize {
    let mut p = prepare(&format!(
        "[scene]\ngravity = [0, 0, 0]\nduration = 1\n[materials.m]\n{SOFT}critical_stretch = 0.01\nalpha = {alpha}\n\
         [[body]]\nmaterial = \"m\"\nresolution = 0.01\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [0.2, 0.2, 0.03] }}\n\
         [[collider]]\ntype = \"sphere\"\ncenter = [0, 0, 0.06]\nradius = 0.04\nvelocity = [0, 0, -30]\n"
    ));
    while p.world.time < 0.006 {
        p.world.step().expect("stable");
    }
    let f = pd(&p).fragments();
    f.iter().copied().max().unwrap_or(0) as usize + 1
}

#[test]
fn alpha_leaves_fewer_larger_fragments() {
    let plain = shatter_fragments(0.0);
    let damped = shatter_fragments(20.0);
    println!("shattering plate: {plain} fragments with α = 0, {damped} with α = 20");
    assert!(
        plain > 20,
        "the impact should shatter the plate: {plain} fragments"
    );
    assert!(
        (damped as f64) < 0.8 * plain as f64,
        "α = 20 gave {damped} fragments, α = 0 gave {plain}"
    );
}

const DETERMINISM_SCENE: &str = "[scene]\nname = \"det\"\nduration = 0.004\nfps = 1000\n\
    [materials.m]\ndensity = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.3\ncritical_stretch = 0.01\nyield_stretch = 0.004\nplastic_limit = 0.1\n\
    [[body]]\nmaterial = \"m\"\nresolution = 0.01\nshape = { type = \"box\", center = [0, 0.05, 0], size = [0.12, 0.1, 0.03] }\n\
    [[collider]]\ntype = \"ground\"\n\
    [[collider]]\ntype = \"sphere\"\ncenter = [0, 0.05, 0.05]\nradius = 0.02\nvelocity = [0, 0, -40]\nmass = 0.5\n\
    [output]\ntets = true\n";

#[test]
fn same_bytes_with_one_and_two_threads() {
    let s = scene(DETERMINISM_SCENE);
    let dirs: Vec<tempfile::TempDir> = (0..2)
        .map(|_| tempfile::tempdir().expect("temp dir"))
        .collect();
    for (threads, dir) in [1usize, 2].iter().zip(&dirs) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(*threads)
            .build()
            .expect("pool");
        pool.install(|| run::run(&s, dir.path(), &RunOptions::default(), &mut |_| {}))
            .expect("runs");
    }
    let frames = s.frame_count() + 1;
    for f in 1..=frames {
        for name in [format!("particles/{f:04}.ply"), format!("tets/{f:04}.vtu")] {
            let a = std::fs::read(dirs[0].path().join(&name)).expect("frame");
            let b = std::fs::read(dirs[1].path().join(&name)).expect("frame");
            assert!(a == b, "{name} differs between 1 and 2 threads");
        }
    }
    let last = perifrac_sim::cache::vtu::TetFrame::read(
        &dirs[0].path().join(format!("tets/{frames:04}.vtu")),
    )
    .expect("split tet mesh");
    assert!(
        last.parent.iter().any(|&p| p >= 0),
        "the impact split vertices of the embedded mesh"
    );
    let manifest = |d: &tempfile::TempDir| {
        perifrac_sim::cache::manifest::Manifest::read(&d.path().join("manifest.json"))
            .expect("manifest")
    };
    let (a, b) = (manifest(&dirs[0]), manifest(&dirs[1]));
    assert!(a.broken_bonds > 0, "the scene should break bonds");
    assert_eq!(a.deterministic_json(), b.deterministic_json());
}

#[test]
fn resume_continues_from_the_checkpoint() {
    let s = scene(&DETERMINISM_SCENE.replace("[output]\n", "[output]\ncheckpoint_every = 2\n"));
    let full = tempfile::tempdir().expect("temp dir");
    run::run(&s, full.path(), &RunOptions::default(), &mut |_| {}).expect("runs");
    let part = tempfile::tempdir().expect("temp dir");
    run::run(
        &s,
        part.path(),
        &RunOptions {
            frames: Some(3),
            ..RunOptions::default()
        },
        &mut |_| {},
    )
    .expect("runs");
    run::run(
        &s,
        part.path(),
        &RunOptions {
            frames: None,
            resume: true,
            ..RunOptions::default()
        },
        &mut |_| {},
    )
    .expect("resumes");
    // The split tet mesh keeps its vertex numbering across the resume.
    let f = s.frame_count() + 1;
    for last in [format!("particles/{f:04}.ply"), format!("tets/{f:04}.vtu")] {
        let a = std::fs::read(full.path().join(&last)).expect("frame");
        let b = std::fs::read(part.path().join(&last)).expect("frame");
        assert!(
            a == b,
            "{last}: a resumed run differs from an uninterrupted one"
        );
    }
}

fn blowup_scene(factor: f64, dt: f64) -> String {
    format!(
        "[scene]\ngravity = [0, 0, 0]\nduration = 0.05\nfps = 100\ndt = {}\nforce_dt = true\n[materials.m]\n{SOFT}\n\
         [[body]]\nmaterial = \"m\"\nresolution = 0.0125\nvelocity = [0.1, 0, 0]\nangular_velocity = [0, 0, 5]\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [0.1, 0.05, 0.05] }}\n",
        factor * dt
    )
}

#[test]
fn blow_up_is_caught_and_the_last_good_frame_kept() {
    let stable = prepare(&blowup_scene(1.0, 1e-4)).stable_dt.0;
    let dir = tempfile::tempdir().expect("temp dir");
    let fine = run::run(
        &scene(&blowup_scene(0.9, stable)),
        dir.path(),
        &RunOptions::default(),
        &mut |_| {},
    );
    assert!(
        fine.is_ok(),
        "0.9× the stable step was flagged: {:?}",
        fine.err()
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let err = run::run(
        &scene(&blowup_scene(2.0, stable)),
        dir.path(),
        &RunOptions::default(),
        &mut |_| {},
    )
    .expect_err("2× the stable step must blow up");
    let text = err.to_string();
    println!("{text}");
    match err {
        SimError::BlowUp {
            step,
            last_good_frame,
            ..
        } => {
            assert!(step < 2000, "caught only at step {step}");
            assert!(
                dir.path()
                    .join(format!("particles/{last_good_frame:04}.ply"))
                    .is_file()
            );
            assert!(
                !dir.path()
                    .join(format!("particles/{:04}.ply", last_good_frame + 1))
                    .exists()
            );
        }
        other => panic!("expected a blow-up, got {other}"),
    }
    assert!(text.contains("step") && text.contains("particle"));
}

#[test]
fn a_time_step_above_the_bound_is_refused_with_the_bound() {
    let s = scene(&blowup_scene(1.0, 1.0).replace("force_dt = true", "force_dt = false"));
    let err = run::prepare(&s).expect_err("refused").to_string();
    assert!(
        err.contains("stable time step") && err.contains("force_dt"),
        "{err}"
    );
}

/// A cantilever L × h × h along x, clamped at x = −L/2 (the vertices of the end face),
/// under gravity with air damping at the first mode's critical value 2ω₁ (the
/// transient is down to (1 + 7) e⁻⁷ < 1% after 7/ω₁); returns the
/// tip deflection at rest (mean over the tip face's vertices) and the Euler–Bernoulli
/// one, q L⁴ / (8 E I) with q = ρ g h², I = h⁴/12.
fn cantilever_tip(model: &str, lambda: f64) -> (f64, f64) {
    let (length, h, e, rho, g): (f64, f64, f64, f64, f64) = (1.0, 0.1, 2.0e8, 1000.0, 9.81);
    // ω₁ = 1.875² √(E I / (ρ A L⁴)).
    let omega = 1.875f64.powi(2) * (e * h * h / 12.0 / (rho * length.powi(4))).sqrt();
    let s = scene(&format!(
        "[scene]\ngravity = [0, -{g}, 0]\nduration = 1\ndt_safety = 0.9\n[materials.m]\ndensity = {rho}\n\
         youngs_modulus = {e}\npoisson_ratio = 0.25\nair_damping = {}\n\
         [[body]]\nmaterial = \"m\"\nmodel = \"{model}\"\nresolution = {lambda}\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [{length}, {h}, {h}] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [-0.5, 0, 0], size = [0.002, 0.2, 0.2] }}\n",
        2.0 * omega
    ));
    let mut p = run::prepare(&s).expect("prepares");
    let settle = 7.0 / omega;
    while p.world.time < settle {
        p.world.step().expect("stable");
    }
    let m = fem(&p);
    let tip: Vec<f64> = (0..m.len())
        .filter(|&i| m.rest[i][0] > 0.5 - 1e-6)
        .map(|i| m.position[i][1] - m.rest[i][1])
        .collect();
    let deflection = -tip.iter().sum::<f64>() / tip.len() as f64;
    let q = rho * g * h * h;
    let euler_bernoulli = q * length.powi(4) / (8.0 * e * h.powi(4) / 12.0);
    (deflection, euler_bernoulli)
}

#[test]
fn fem_cantilevers_match_euler_bernoulli() {
    for model in ["fem-linear", "fem-corotated"] {
        let (tip, eb) = cantilever_tip(model, 0.025);
        println!(
            "{model}: tip deflection {tip:.5e} m, Euler–Bernoulli {eb:.5e} m ({:+.2}%)",
            100.0 * (tip / eb - 1.0)
        );
        assert!((tip / eb - 1.0).abs() < 0.05, "{model}: {tip} vs {eb}");
    }
}

/// A soft bar (Chen Table 1's bar swing material) held at its left end, released
/// horizontal under gravity: half a swing.
fn bar_swing(model: &str) -> String {
    format!(
        "[scene]\nduration = 0.3\nfps = 30\n[materials.bar]\ndensity = 1000.0\nbulk_modulus = 5.0e6\nshear_modulus = 5.0e6\n\
         [[body]]\nmaterial = \"bar\"\nmodel = \"{model}\"\nresolution = 0.0333\nhorizon = 1.45\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [1.0, 0.1, 0.1] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [-0.5, 0, 0], size = [0.1, 0.2, 0.2] }}\n"
    )
}

/// A bar (Chen Table 1's bar twist material) with its left end fixed and its right
/// end turned a quarter turn about the bar's axis.
fn bar_twist(model: &str) -> String {
    format!(
        "[scene]\nduration = 0.5\nfps = 20\n[materials.bar]\ndensity = 1000.0\nbulk_modulus = 1.0e6\nshear_modulus = 6.0e5\n\
         [[body]]\nmaterial = \"bar\"\nmodel = \"{model}\"\nresolution = 0.0333\nhorizon = 1.45\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [0.6, 0.15, 0.15] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [-0.3, 0, 0], size = [0.1, 0.2, 0.2] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0.3, 0, 0], size = [0.1, 0.2, 0.2] }}\n\
         angular_velocity = [3.141592653589793, 0, 0]\ncenter = [0.3, 0, 0]\n"
    )
}

/// Peridynamics, corotated and linear FEM on the same tets; returns the deviations
/// (max over frames of the mean over particles, over the bounding-box diagonal) of
/// PD and of linear FEM from corotated FEM.
fn deviations_from_corotated(make: fn(&str) -> String) -> (f64, f64) {
    use perifrac_sim::accuracy::{deviation, diagonal, record};
    let runs: Vec<_> = ["fem-corotated", "peridynamics", "fem-linear"]
        .iter()
        .map(|m| {
            let s = scene(&make(m));
            record(&s, s.frame_count()).expect("runs")
        })
        .collect();
    let d = diagonal(&runs[0].particles.rest);
    let pd = deviation(&runs[1].particles, &runs[0].particles, d);
    let linear = deviation(&runs[2].particles, &runs[0].particles, d);
    (pd.max, linear.max)
}

/// Chen's claim is 10%; measured 0.41% (swing) and 0.28% (twist), so the bound is
/// 2%: linear FEM, the wrong physics for the twist's quarter turn, measures 3.3% on
/// the same metric there, and a 10% bound let it pass.
#[test]
fn peridynamics_stays_within_two_percent_of_corotated_fem_on_bar_swing_and_twist() {
    for (name, make) in [
        ("bar swing", bar_swing as fn(&str) -> String),
        ("bar twist", bar_twist),
    ] {
        let (pd, linear) = deviations_from_corotated(make);
        println!(
            "{name}: deviation from corotated FEM (max over frames of the mean over particles, / bbox diagonal): \
             peridynamics {:.2}%, linear FEM {:.2}%",
            100.0 * pd,
            100.0 * linear
        );
        assert!(pd < 0.02, "{name}: peridynamics deviates by {pd}");
    }
}

fn fem_blowup_scene(dt: f64) -> String {
    blowup_scene(1.0, dt).replace("[[body]]\n", "[[body]]\nmodel = \"fem-corotated\"\n")
}

#[test]
fn fem_blow_up_is_caught_and_the_last_good_frame_kept() {
    let stable = run::prepare(&scene(&fem_blowup_scene(1e-4)))
        .expect("prepares")
        .stable_dt
        .0;
    let dir = tempfile::tempdir().expect("temp dir");
    let fine = run::run(
        &scene(&fem_blowup_scene(0.9 * stable)),
        dir.path(),
        &RunOptions::default(),
        &mut |_| {},
    );
    assert!(
        fine.is_ok(),
        "0.9× the stable step was flagged: {:?}",
        fine.err()
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let err = run::run(
        &scene(&fem_blowup_scene(2.0 * stable)),
        dir.path(),
        &RunOptions::default(),
        &mut |_| {},
    )
    .expect_err("2× the stable step must blow up");
    let text = err.to_string();
    println!("{text}");
    match err {
        SimError::BlowUp {
            step,
            last_good_frame,
            ..
        } => {
            assert!(step < 2000, "caught only at step {step}");
            assert!(
                dir.path()
                    .join(format!("particles/{last_good_frame:04}.ply"))
                    .is_file()
            );
        }
        other => panic!("expected a blow-up, got {other}"),
    }
    assert!(text.contains("step") && text.contains("particle") && text.contains("vertex"));
}

#[test]
fn fem_scenes_are_validated() {
    let mixed = format!(
        "{}[[body]]\nmaterial = \"bar\"\nresolution = 0.05\n\
         shape = {{ type = \"box\", center = [0, 1, 0], size = [0.2, 0.2, 0.2] }}\n",
        bar_swing("fem-corotated")
    );
    let err = Scene::parse(&mixed, Path::new("mixed.toml"), Path::new("."))
        .expect_err("mixed solvers are refused")
        .to_string();
    assert!(err.contains("body.1.model") && err.contains("fem"), "{err}");
    let brittle = bar_swing("fem-linear").replace(
        "shear_modulus = 5.0e6\n",
        "shear_modulus = 5.0e6\ncritical_stretch = 0.01\n",
    );
    let err = Scene::parse(&brittle, Path::new("brittle.toml"), Path::new("."))
        .expect_err("fracture is refused")
        .to_string();
    assert!(err.contains("materials.bar.critical_stretch"), "{err}");
}

/// `assets/scenes/cantilever-release.toml`: a cantilever bent by an anchor that is
/// released vibrates at Euler–Bernoulli's first bending frequency (L/h = 10; the
/// shear of Timoshenko lowers it by ≈ 1%, linear tets' stiffness raises it).
#[test]
fn a_released_cantilever_vibrates_at_the_euler_bernoulli_frequency() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/cantilever-release.toml");
    let text = std::fs::read_to_string(&path).expect("scene file");
    // Released at 0.05 s rather than 0.1 s, run to 0.27 s rather than 0.4 s (1.6
    // periods, three crossings after the moving average), at 0.9 of the stable step: a
    // third of the scene's steps, the same mode.
    let text = text
        .replace("[[body]]\n", "[[body]]\nmodel = \"fem-corotated\"\n")
        .replace("[scene]\n", "[scene]\ndt_safety = 0.9\n")
        .replace("duration = 0.4 ", "duration = 0.27 ")
        .replace("until = 0.1", "until = 0.05");
    assert!(
        ["dt_safety", "duration = 0.27 ", "until = 0.05"]
            .iter()
            .all(|k| text.contains(k))
    );
    let s = Scene::parse(&text, &path, path.parent().expect("dir")).expect("valid scene");
    let f = perifrac_sim::analytic::first_bending_frequency(&s).expect("runs");
    let measured = f.measured.expect("at least a period after the release");
    println!(
        "corotated FEM cantilever: f1 {measured:.3} Hz, Euler–Bernoulli {:.3} Hz ({:+.2}%)",
        f.euler_bernoulli,
        100.0 * (measured / f.euler_bernoulli - 1.0)
    );
    assert!((measured / f.euler_bernoulli - 1.0).abs() < 0.10);
}

/// The FEM reference goes through the same checkpoints as peridynamics: a run stopped
/// and resumed gives the bytes of an uninterrupted one (the corotated tets' rotations,
/// the polar decomposition's warm start, are part of the saved state).
#[test]
fn fem_runs_resume_from_their_checkpoints() {
    let s = scene(&bar_swing("fem-corotated").replace(
        "[[body]]\n",
        "[output]\ncheckpoint_every = 2\npreview = false\n[[body]]\n",
    ));
    let frames = s.frame_count().min(6);
    let full = tempfile::tempdir().expect("temp dir");
    let options = |frames: usize, resume: bool| RunOptions {
        frames: Some(frames),
        resume,
        ..RunOptions::default()
    };
    run::run(&s, full.path(), &options(frames, false), &mut |_| {}).expect("runs");
    let part = tempfile::tempdir().expect("temp dir");
    run::run(&s, part.path(), &options(3, false), &mut |_| {}).expect("runs");
    run::run(&s, part.path(), &options(frames, true), &mut |_| {}).expect("resumes");
    for f in 1..=frames + 1 {
        let name = format!("particles/{f:04}.ply");
        let a = std::fs::read(full.path().join(&name)).expect("frame");
        let b = std::fs::read(part.path().join(&name)).expect("frame");
        assert!(
            a == b,
            "{name}: a resumed FEM run differs from an uninterrupted one"
        );
    }
}
