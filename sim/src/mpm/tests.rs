use std::path::Path;

use super::constitutive::{Elastic, Mat3, determinant, mul, polar_rotation, rotation_svd};
use super::*;
use crate::run::{Prepared, prepare};
use crate::scene::MpmElasticity;
use crate::world::World;

fn prepared(text: &str) -> Prepared {
    let scene = Scene::parse(text, Path::new("mpm.toml"), Path::new(".")).expect("scene");
    prepare(&scene).expect("prepares")
}

fn mpm(world: &World) -> &Mpm {
    world.model::<Mpm>().expect("an MPM model")
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

const OUTPUT: &str = "[output]\ntets = false\nsurface = \"none\"\npreview = false\n";

fn scene(settings: &str, bodies: &str) -> String {
    format!(
        "[scene]\nduration = 1.0\nfps = 1000\n{settings}\n\
         [materials.soft]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.3\n\
         [materials.stiff]\ndensity = 1000\nyoungs_modulus = 1e6\npoisson_ratio = 0.3\n\
         {bodies}{OUTPUT}"
    )
}

#[test]
fn seeding_puts_a_fixed_count_per_cell_and_is_reproducible() {
    let text = scene(
        "gravity = [0, 0, 0]\nseed = 7",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\n\
         shape = { type = \"box\", center = [0.1, 0.1, 0.1], size = [0.1, 0.06, 0.04] }\n",
    );
    let a = prepared(&text);
    let b = prepared(&text);
    let p = &mpm(&a.world).particles;
    // 5 × 3 × 2 cells of 0.02 m, 8 particles each.
    assert_eq!(p.len(), 5 * 3 * 2 * 8);
    assert_eq!(p.position, mpm(&b.world).particles.position);
    let volume: f64 = p.volume.iter().sum();
    assert!((volume - 0.1 * 0.06 * 0.04).abs() < 1e-12);
}

#[test]
fn fixed_corotated_stress_vanishes_under_rotation_and_is_safe_when_inverted() {
    let e = Elastic::from_young(MpmElasticity::FixedCorotated, 1e6, 0.3);
    let r = polar_rotation(&[[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
    let p = e.first_piola(&r);
    assert!(p.iter().flatten().all(|x| x.abs() < 1e-9), "{p:?}");
    // A reflection: one negative singular value, R a rotation.
    let inverted: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -0.5]];
    let s = rotation_svd(&inverted);
    assert!((determinant(&s.u) - 1.0).abs() < 1e-12);
    assert!((determinant(&s.v) - 1.0).abs() < 1e-12);
    assert!((s.sigma.iter().product::<f64>() + 0.5).abs() < 1e-12);
    assert!(
        e.first_piola(&inverted)
            .iter()
            .flatten()
            .all(|x| x.is_finite())
    );
    // Uniaxial stretch: P₁₁ = 2μ(s − 1) + λ(J − 1)J/s with J = s.
    let st = 1.01;
    let f = [[st, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let p = e.first_piola(&f);
    let expected = 2.0 * e.mu * (st - 1.0) + e.lambda * (st - 1.0);
    assert!((p[0][0] - expected).abs() < 1e-6 * expected, "{}", p[0][0]);
}

#[test]
fn neo_hookean_stress_matches_finite_differences_of_its_energy() {
    let e = Elastic::from_young(MpmElasticity::NeoHookean, 1e6, 0.3);
    let f: Mat3 = [[1.05, 0.02, 0.0], [-0.01, 0.97, 0.03], [0.0, 0.01, 1.02]];
    let p = e.first_piola(&f);
    let h = 1e-6;
    for a in 0..3 {
        for b in 0..3 {
            let (mut up, mut down) = (f, f);
            up[a][b] += h;
            down[a][b] -= h;
            let numeric = (e.energy_density(&up) - e.energy_density(&down)) / (2.0 * h);
            assert!(
                (numeric - p[a][b]).abs() < 1e-3 * (1.0 + p[a][b].abs()),
                "{a}{b}"
            );
        }
    }
    let fc = Elastic::from_young(MpmElasticity::FixedCorotated, 1e6, 0.3);
    let p = fc.first_piola(&f);
    for a in 0..3 {
        for b in 0..3 {
            let (mut up, mut down) = (f, f);
            up[a][b] += h;
            down[a][b] -= h;
            let numeric = (fc.energy_density(&up) - fc.energy_density(&down)) / (2.0 * h);
            assert!(
                (numeric - p[a][b]).abs() < 1e-3 * (1.0 + p[a][b].abs()),
                "{a}{b}"
            );
        }
    }
    let r = polar_rotation(&f);
    let rtr = mul(
        &r,
        &[
            [r[0][0], r[1][0], r[2][0]],
            [r[0][1], r[1][1], r[2][1]],
            [r[0][2], r[1][2], r[2][2]],
        ],
    );
    assert!((rtr[0][0] - 1.0).abs() < 1e-12 && rtr[0][1].abs() < 1e-12);
}

#[test]
fn two_elastic_spheres_colliding_conserve_momentum() {
    let text = scene(
        "gravity = [0, 0, 0]",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [3, 0, 0]\n\
         shape = { type = \"sphere\", center = [-0.06, 0.0, 0.0], radius = 0.05 }\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [-1, 0.2, 0]\n\
         shape = { type = \"sphere\", center = [0.06, 0.01, 0.0], radius = 0.05 }\n",
    );
    let mut p = prepared(&text);
    let before = mpm(&p.world).momentum();
    let steps = (0.03 / p.world.dt) as usize;
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let m = mpm(&p.world);
    let after = m.momentum();
    let error = norm([0, 1, 2].map(|a| after[a] - before[a])) / norm(before);
    eprintln!(
        "{} particles, {steps} steps: momentum {before:?} → {after:?}, relative change {error:.2e}",
        m.particles.len()
    );
    assert!(error < 1e-6);
    // They met: the first sphere slowed down.
    let body0: Vec<usize> = (0..m.particles.len())
        .filter(|&i| m.particles.body[i] == 0)
        .collect();
    let vx: f64 = body0
        .iter()
        .map(|&i| m.particles.velocity[i][0])
        .sum::<f64>()
        / body0.len() as f64;
    assert!(vx < 2.5, "mean x velocity of the first sphere {vx}");
}

#[test]
fn a_free_spinning_body_keeps_its_angular_momentum() {
    let text = scene(
        "gravity = [0, 0, 0]",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"stiff\"\nresolution = 0.02\n\
         angular_velocity = [1, 2, 3]\nvelocity = [0.1, 0, 0]\n\
         shape = { type = \"box\", center = [0.02, 0.03, -0.01], size = [0.1, 0.06, 0.04] }\n",
    );
    let mut p = prepared(&text);
    let before = mpm(&p.world).angular_momentum();
    for _ in 0..1000 {
        p.world.step().expect("steps");
    }
    let after = mpm(&p.world).angular_momentum();
    let error = norm([0, 1, 2].map(|a| after[a] - before[a])) / norm(before);
    eprintln!("1000 steps: angular momentum {before:?} → {after:?}, relative change {error:.2e}");
    assert!(error < 1e-6);
}

#[test]
fn a_block_rests_on_the_ground() {
    let text = scene(
        "",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"stiff\"\nresolution = 0.02\n\
         shape = { type = \"box\", center = [0, 0.05, 0], size = [0.1, 0.1, 0.1] }\n\
         [[collider]]\ntype = \"ground\"\nfriction = 0.5\n",
    );
    let mut p = prepared(&text);
    let centroid = |w: &World| {
        let x = &mpm(w).particles.position;
        [0, 1, 2].map(|a| x.iter().map(|p| p[a]).sum::<f64>() / x.len() as f64)
    };
    let start = centroid(&p.world);
    let steps = 3_000;
    for _ in 0..steps {
        p.world.step().expect("no blow-up");
    }
    let end = centroid(&p.world);
    let drift = norm([0, 1, 2].map(|a| end[a] - start[a]));
    let dx = mpm(&p.world).grid.dx;
    eprintln!(
        "{steps} steps of {:.3e} s: centroid drift {drift:.3e} m ({:.3}% of a cell)",
        p.world.dt,
        100.0 * drift / dx
    );
    assert!(drift < 0.01 * dx);
}

#[test]
fn twice_the_stable_step_is_caught_by_the_blowup_detector() {
    let body = "[[body]]\nmodel = \"mpm\"\nmaterial = \"stiff\"\nresolution = 0.02\n\
         shape = { type = \"box\", center = [0, 0.05, 0], size = [0.1, 0.1, 0.1] }\n\
         [[collider]]\ntype = \"ground\"\n";
    let stable = prepared(&scene("", body)).stable_dt.0;
    // One frame a second, so that the step is not shortened to fit a frame.
    let text = scene(&format!("dt = {:e}\nforce_dt = true", 2.0 * stable), body)
        .replace("fps = 1000", "fps = 1");
    let mut p = prepared(&text);
    let caught = (0..20_000).find_map(|_| p.world.step().err());
    assert!(
        matches!(caught, Some(SimError::BlowUp { .. })),
        "{caught:?}"
    );
}

fn state_bytes(world: &World) -> Vec<u8> {
    let mut out = Encoder::new();
    world.save(&mut out);
    out.finish()
}

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let text = scene(
        "",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [0, -2, 0]\n\
         shape = { type = \"sphere\", center = [0, 0.08, 0], radius = 0.06 }\n\
         [[collider]]\ntype = \"ground\"\n",
    );
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| {
                let mut p = prepared(&text);
                for _ in 0..100 {
                    p.world.step().expect("steps");
                }
                state_bytes(&p.world)
            })
    };
    assert!(run(1) == run(2), "the thread count changed the state");
}

fn hardening(n: f64) -> plasticity::JohnsonCook {
    plasticity::JohnsonCook {
        a: 1e8,
        b: 2e8,
        n,
        c: 0.0,
        reference_rate: 1.0,
    }
}

/// σ* = diag(2, −1, −1)·10⁸ Pa: s* = √(3/2 · 6)·10⁸ = 3·10⁸ Pa.
const TRIAL: Mat3 = [[2e8, 0.0, 0.0], [0.0, -1e8, 0.0], [0.0, 0.0, -1e8]];
const SHEAR: f64 = 1e9;

#[test]
fn j2_radial_return_matches_hand_worked_values() {
    use plasticity::{equivalent_stress, radial_return};
    assert!((equivalent_stress(&TRIAL) - 3e8).abs() < 1e-6);
    // Linear hardening n = 1: f = 3e8 − 1e8 = 2e8; Δε = f/(3μ + B) = 2e8/3.2e9 = 0.0625
    // (Eq. B.5); σ_y = 1e8 + 2e8 · 0.0625 = 1.125e8 (Eq. B.7); σ = 0.375 σ* (Eq. B.8).
    let r = radial_return(&TRIAL, SHEAR, 0.0, &hardening(1.0), 1.0);
    assert!((r.plastic_increment - 0.0625).abs() < 1e-12);
    assert!((r.deviatoric[0][0] - 0.375 * 2e8).abs() < 1e-3);
    // Perfect plasticity (B = 0): Δε = (3e8 − 1e8)/3e9 and s = A.
    let perfect = plasticity::JohnsonCook {
        b: 0.0,
        ..hardening(0.0)
    };
    let r = radial_return(&TRIAL, SHEAR, 0.0, &perfect, 1.0);
    assert!((r.plastic_increment - 2.0 / 30.0).abs() < 1e-12);
    assert!((equivalent_stress(&r.deviatoric) - 1e8).abs() < 1e-6 * 1e8);
    // Below the yield surface nothing changes.
    let small = TRIAL.map(|row| row.map(|x| 0.1 * x));
    let r = radial_return(&small, SHEAR, 0.0, &hardening(0.5), 1.0);
    assert_eq!(r.deviatoric, small);
    assert_eq!(r.plastic_increment, 0.0);
}

#[test]
fn after_radial_return_the_equivalent_stress_is_the_yield_stress() {
    use plasticity::{equivalent_stress, radial_return};
    for n in [0.0, 0.26, 0.5, 1.0] {
        for eps in [0.0, 0.01, 0.3] {
            let jc = hardening(n);
            let r = radial_return(&TRIAL, SHEAR, eps, &jc, 1.0);
            let yield_stress = jc.yield_stress(eps + r.plastic_increment, 1.0);
            let s = equivalent_stress(&r.deviatoric);
            assert!(
                (s - yield_stress).abs() <= 1e-6 * yield_stress,
                "n = {n}, ε^p = {eps}: s = {s}, σ_y = {yield_stress}"
            );
            // J2 flow keeps the stress deviatoric and its direction.
            let trace = r.deviatoric[0][0] + r.deviatoric[1][1] + r.deviatoric[2][2];
            assert!(trace.abs() < 1e-6);
            assert!((r.deviatoric[1][1] / r.deviatoric[0][0] + 0.5).abs() < 1e-12);
        }
    }
}

#[test]
fn johnson_cook_yield_stress_and_modulus_match_hand_worked_values() {
    let jc = plasticity::JohnsonCook {
        a: 1e8,
        b: 2e8,
        n: 0.5,
        c: 0.1,
        reference_rate: 1.0,
    };
    // (1e8 + 2e8 · √0.04)(1 + 0.1 ln 10) = 1.4e8 · 1.2302585093.
    let expected = 1.4e8 * (1.0 + 0.1 * 10f64.ln());
    assert!((jc.yield_stress(0.04, 10.0) - expected).abs() < 1e-6);
    assert!((jc.yield_stress(0.04, 10.0) - 1.722_361_913e8).abs() < 1.0);
    // E^p = B n ε^(n−1) (Eq. 7.8) = 2e8 · 0.5 / √0.04 = 5e8 at the reference rate.
    assert!((jc.plastic_modulus(0.04, 1.0) - 5e8).abs() < 1e-3);
    // Slower than the reference rate does not soften.
    assert_eq!(jc.yield_stress(0.04, 0.1), 1.4e8);
}

#[test]
fn mie_gruneisen_pressure_matches_hand_worked_values() {
    let eos = plasticity::MieGruneisen {
        density: 1000.0,
        sound_speed: 100.0,
        slope: 1.1,
        gamma: 1.6,
    };
    // J = 0.8: ζ = 0.25; ρ₀c₀² = 1e7; 1e7 · 0.25 · (1 + 0.2 · 0.25) / (1 + 0.1 · 0.25)²
    // = 1e7 · 0.2625 / 1.050625 = 2 498 512.790 Pa; plus γ Δe = 1.6 · 1000.
    let p = eos.pressure(0.8, 1000.0);
    assert!((p - (2_498_512.790_005_95 + 1600.0)).abs() < 1e-3, "{p}");
    // J = 1.25: ζ = −0.2, p = 1e7 · (−0.2) = −2e6 Pa.
    assert!((eos.pressure(1.25, 0.0) + 2e6).abs() < 1e-6);
    assert_eq!(eos.pressure(1.0, 0.0), 0.0);
    // Δe = Δt sym(C) : σ (Eq. 7.3): the skew part of C does no work.
    let c = [[1.0, 0.5, 0.0], [-0.5, 0.0, 0.0], [0.0, 0.0, 0.0]];
    let sigma = [[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 4.0]];
    assert!((plasticity::internal_energy_increment(0.1, &c, &sigma) - 0.2).abs() < 1e-15);
}
