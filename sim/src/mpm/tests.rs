use std::path::Path;

use perifrac_math::{mul_transpose, rotation_svd};

use super::constitutive::{Elastic, Mat3, determinant, mul, polar_rotation};
use super::plasticity::{FlowInput, Plasticity};
use super::*;
use crate::cache::checkpoint::Encoder;
use crate::run::{Prepared, prepare};
use crate::scene::MpmElasticity;
use crate::scene::Scene;
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

/// [`polar_rotation`] returns the polar factor of F = RS: R a rotation and S = RᵀF
/// symmetric, positive definite unless F is inverted (then the inversion-safe SVD's
/// UVᵀ, whose S has the one negative eigenvalue). Random rotations times random stretches: near the identity, singular values
/// 0.05–20 (condition numbers up to 400), and inverted. Higham's iteration is the more
/// accurate of the two: S = RᵀF is symmetric to 1e-15 relative where nalgebra's SVD
/// leaves up to 2e-8 when two singular values are close, so the SVD is only a coarse
/// check here (1e-7).
#[test]
fn polar_rotation_is_the_polar_factor() {
    let mut state = 7u64;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let transpose = |r: &Mat3| [0, 1, 2].map(|i| [0, 1, 2].map(|j| r[j][i]));
    let (mut asymmetry, mut orthogonality, mut from_svd) = (0.0f64, 0.0f64, 0.0f64);
    for case in 0..20_000 {
        let mut angle = || 6.3 * uniform();
        let (a, b, c, d, e, f) = (angle(), angle(), angle(), angle(), angle(), angle());
        let u = nalgebra::Rotation3::from_euler_angles(a, b, c).into_inner();
        let v = nalgebra::Rotation3::from_euler_angles(d, e, f).into_inner();
        let inverted = case % 3 == 2;
        let sigma = match case % 3 {
            0 => [0, 1, 2].map(|_| 1.0 + 0.02 * (uniform() - 0.5)),
            1 => [0, 1, 2].map(|_| 0.05 * 400f64.powf(uniform())),
            _ => [1.0 + 0.3 * uniform(), 1.0, -(0.1 + uniform())],
        };
        let m =
            u * nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::from(sigma)) * v.transpose();
        let f: Mat3 = [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[(i, j)]));
        let scale = sigma.iter().fold(0.0f64, |x, s| x.max(s.abs()));
        let r = polar_rotation(&f);
        let rtr = mul(&transpose(&r), &r);
        for (i, row) in rtr.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                let identity = if i == j { 1.0 } else { 0.0 };
                orthogonality = orthogonality.max((x - identity).abs());
            }
        }
        assert!((determinant(&r) - 1.0).abs() < 1e-13, "case {case}: det R");
        let stretch = mul(&transpose(&r), &f);
        if !inverted {
            for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                asymmetry = asymmetry.max((stretch[i][j] - stretch[j][i]).abs() / scale);
            }
        }
        let minors = [
            stretch[0][0],
            stretch[0][0] * stretch[1][1] - stretch[0][1] * stretch[1][0],
            determinant(&stretch),
        ];
        assert_eq!(
            minors.iter().all(|&x| x > 0.0),
            !inverted,
            "case {case}: S = RᵀF positive definite exactly when F is not inverted"
        );
        let svd = rotation_svd(&f);
        let expected = mul_transpose(&svd.u, &svd.v);
        for (row, row_expected) in r.iter().zip(&expected) {
            for (x, y) in row.iter().zip(row_expected) {
                from_svd = from_svd.max((x - y).abs());
            }
        }
    }
    assert!(orthogonality < 1e-14, "RᵀR − I up to {orthogonality:e}");
    assert!(asymmetry < 1e-14, "RᵀF asymmetric by {asymmetry:e} of |F|");
    assert!(
        from_svd < 1e-7,
        "R differs from the SVD's UVᵀ by {from_svd:e}"
    );
}

/// The closed-form Kirchhoff stresses equal P Fᵀ of the first Piola–Kirchhoff ones.
#[test]
fn kirchhoff_stress_is_first_piola_times_f_transpose() {
    let f: Mat3 = [[1.05, 0.02, -0.01], [-0.01, 0.97, 0.03], [0.02, 0.01, 1.02]];
    for energy in [
        MpmElasticity::FixedCorotated,
        MpmElasticity::NeoHookean,
        MpmElasticity::StableNeoHookean,
    ] {
        let e = Elastic::from_young(energy, 1e6, 0.3);
        let expected = mul_transpose(&e.first_piola(&f), &f);
        let tau = e.kirchhoff(&f);
        for (row, row_expected) in tau.iter().zip(&expected) {
            for (x, y) in row.iter().zip(row_expected) {
                assert!(
                    (x - y).abs() < 1e-9 * 1e6,
                    "{energy:?}: {tau:?} vs {expected:?}"
                );
            }
        }
    }
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
         shape = { type = \"box\", center = [0, 0.03, 0], size = [0.06, 0.06, 0.06] }\n\
         [[collider]]\ntype = \"ground\"\nfriction = 0.5\n",
    );
    let mut p = prepared(&text);
    let centroid = |w: &World| {
        let x = &mpm(w).particles.position;
        [0, 1, 2].map(|a| x.iter().map(|p| p[a]).sum::<f64>() / x.len() as f64)
    };
    // Let it settle under its weight, then hold still for 10⁴ steps.
    for _ in 0..500 {
        p.world.step().expect("no blow-up");
    }
    let start = centroid(&p.world);
    let steps = 10_000;
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

/// The world's checkpoint bytes (its whole state).
pub(super) fn state_bytes(world: &World) -> Vec<u8> {
    let mut out = Encoder::new();
    world.save(&mut out);
    out.finish()
}

/// Runs `run` in a pool of one thread, then in a pool of two, and asserts that both
/// runs give the same bytes.
pub(super) fn same_bytes_on_one_and_two_threads(run: impl Fn() -> Vec<u8> + Sync) {
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(&run)
    };
    assert!(on(1) == on(2), "the thread count changed the state");
}

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let text = scene(
        "",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [0, -2, 0]\n\
         shape = { type = \"sphere\", center = [0, 0.08, 0], radius = 0.06 }\n\
         [[collider]]\ntype = \"ground\"\n",
    );
    same_bytes_on_one_and_two_threads(|| {
        let mut p = prepared(&text);
        for _ in 0..100 {
            p.world.step().expect("steps");
        }
        state_bytes(&p.world)
    });
}

fn hardening(n: f64) -> plasticity::JohnsonCook {
    plasticity::JohnsonCook {
        a: 1e8,
        b: 2e8,
        n,
        c: 0.0,
        reference_rate: 1.0,
        thermal: None,
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
        thermal: None,
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
    // J = 0.8: ζ = 0.25; ρ₀c₀² = 1e7; 1e7 · 0.25 · (1 + 0.2 · 0.25) / (1 − 0.1 · 0.25)²
    // = 1e7 · 0.2625 / 0.950625 = 2 761 341.223 Pa; plus γ Δe = 1.6 · 1000.
    let p = eos.pressure(0.8, 1000.0);
    assert!((p - (2_761_341.222_879_684 + 1600.0)).abs() < 1e-3, "{p}");
    // With γ = 0 the pressure is the Hugoniot of u_s = c₀ + S u_p, ρ₀c₀²η/(1 − Sη)²
    // with η = 1 − J (the thesis' printed plus sign gives 0.957 of it here).
    let cold = plasticity::MieGruneisen { gamma: 0.0, ..eos };
    let eta: f64 = 0.1;
    let hugoniot = 1e7 * eta / (1.0 - 1.1 * eta).powi(2);
    let p = cold.pressure(1.0 - eta, 0.0);
    assert!((p / hugoniot - 1.0).abs() < 1e-12, "{p} {hugoniot}");
    // Past the compression limit ρ/ρ₀ = S/(S − 1) the pressure keeps rising.
    let limit = 1.0 / 1.1 * 0.1;
    let (a, b) = (
        eos.pressure(limit * 1.5, 0.0),
        eos.pressure(limit * 0.5, 0.0),
    );
    assert!(a.is_finite() && b > a && a > 0.0, "{a} {b}");
    // J = 1.25: ζ = −0.2, p = 1e7 · (−0.2) = −2e6 Pa.
    assert!((eos.pressure(1.25, 0.0) + 2e6).abs() < 1e-6);
    assert_eq!(eos.pressure(1.0, 0.0), 0.0);
    // Δe = Δt sym(C) : σ (Eq. 7.3): the skew part of C does no work.
    let c = [[1.0, 0.5, 0.0], [-0.5, 0.0, 0.0], [0.0, 0.0, 0.0]];
    let sigma = [[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 4.0]];
    assert!((plasticity::internal_energy_increment(0.1, &c, &sigma) - 0.2).abs() < 1e-15);
}

#[test]
fn stable_neo_hookean_is_rest_stable_linearizes_to_lame_and_is_its_energy_gradient() {
    let snh = Elastic::from_young(MpmElasticity::StableNeoHookean, 1e6, 0.3);
    let rest = snh.first_piola(&IDENTITY);
    assert!(rest.iter().flatten().all(|x| x.abs() < 1e-6), "{rest:?}");
    assert_eq!(snh.energy_density(&IDENTITY), 0.0);
    // Small strain: P ≈ μ(H + Hᵀ) + λ tr H I, as fixed corotated.
    let h: Mat3 = [[1e-5, 2e-6, 0.0], [0.0, -3e-6, 1e-6], [4e-6, 0.0, 2e-6]];
    let f = [0, 1, 2].map(|a| [0, 1, 2].map(|b| IDENTITY[a][b] + h[a][b]));
    let p = snh.first_piola(&f);
    let trace = h[0][0] + h[1][1] + h[2][2];
    for a in 0..3 {
        for b in 0..3 {
            let linear =
                snh.mu * (h[a][b] + h[b][a]) + if a == b { snh.lambda * trace } else { 0.0 };
            assert!(
                (p[a][b] - linear).abs() < 1e-3 * 1e6 * 1e-5,
                "{a}{b}: {} vs {linear}",
                p[a][b]
            );
        }
    }
    // Large strain, and inverted: P = ∂ψ/∂F by central differences, finite when inverted.
    for f in [
        [[1.3, 0.2, 0.0], [-0.1, 0.8, 0.1], [0.0, 0.05, 1.1]],
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -0.3]],
    ] {
        let p = snh.first_piola(&f);
        let step = 1e-6;
        for a in 0..3 {
            for b in 0..3 {
                let (mut up, mut down) = (f, f);
                up[a][b] += step;
                down[a][b] -= step;
                let numeric = (snh.energy_density(&up) - snh.energy_density(&down)) / (2.0 * step);
                assert!(
                    (numeric - p[a][b]).abs() < 1e-4 * (1.0 + p[a][b].abs()),
                    "{a}{b}"
                );
            }
        }
    }
}

#[test]
fn the_shock_model_replaces_the_pressure_by_mie_gruneisen() {
    let material = MpmMaterial {
        density: 1000.0,
        elastic: Elastic::from_young(MpmElasticity::Shock, 1e6, 0.3),
        eos: Some(plasticity::MieGruneisen {
            density: 1000.0,
            sound_speed: 100.0,
            slope: 1.1,
            gamma: 1.6,
        }),
        plasticity: Plasticity::None,
    };
    // Uniform compression J = 0.8: no shear, σ = −p I with p = 2 761 341.223 + 1.6 e.
    let s = 0.8f64.cbrt();
    let f = [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]];
    let tau = material.kirchhoff(&f, 1000.0);
    for (a, row) in tau.iter().enumerate() {
        let sigma = row[a] / 0.8;
        assert!(
            (sigma + 2_761_341.222_879_684 + 1600.0).abs() < 1e-3,
            "{sigma}"
        );
    }
    // Shear at J = 1: the pressure vanishes and the deviator is the stable Neo-Hookean one.
    let f = [[1.0, 0.01, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let tau = material.kirchhoff(&f, 0.0);
    assert!((tau[0][0] + tau[1][1] + tau[2][2]).abs() < 1e-6);
    let snh = plasticity::deviatoric(&mul_transpose(&material.elastic.first_piola(&f), &f));
    assert!((tau[0][1] - snh[0][1]).abs() < 1e-9);
}

fn hencky_equivalent_stress(f: &Mat3, mu: f64) -> (f64, f64) {
    let s = rotation_svd(f);
    let log = s.sigma.map(|x| x.ln());
    let mean = (log[0] + log[1] + log[2]) / 3.0;
    let tau = log.map(|e| 2.0 * mu * (e - mean));
    let deviator = [[tau[0], 0.0, 0.0], [0.0, tau[1], 0.0], [0.0, 0.0, tau[2]]];
    (plasticity::equivalent_stress(&deviator), determinant(f))
}

#[test]
fn j2_projection_of_a_particle_lands_on_the_yield_surface_and_keeps_its_volume() {
    let elastic = Elastic::from_young(MpmElasticity::FixedCorotated, 1e9, 0.3);
    for n in [0.0, 0.5, 1.0] {
        let jc = Plasticity::JohnsonCook(hardening(n));
        let mut f: Mat3 = [[1.02, 0.3, 0.0], [0.0, 0.97, 0.05], [0.01, 0.0, 1.0]];
        let j = determinant(&f);
        let eps = 0.05;
        let input = FlowInput {
            mu: elastic.mu,
            lambda: elastic.lambda,
            rate: 1.0,
            plastic_strain: eps,
            temperature: 0.0,
        };
        let increment = jc.project(&mut f, &input);
        assert!(increment > 0.0);
        let Plasticity::JohnsonCook(h) = jc else {
            unreachable!()
        };
        let yield_stress = h.yield_stress(eps + increment, 1.0);
        let (s, j_after) = hencky_equivalent_stress(&f, elastic.mu);
        assert!(
            (s - yield_stress).abs() <= 1e-6 * yield_stress,
            "n = {n}: {s} vs {yield_stress}"
        );
        assert!((j_after - j).abs() < 1e-12, "J2 flow is isochoric");
    }
}

/// Every projection through [`Plasticity::project`] (the invariant pre-checks, then the
/// eigen-solve of F̂ᵀF̂ or, for an inverted or degenerate F̂, the SVD) equals the same
/// projection on the exact SVD F was made of (and, more loosely, on nalgebra's), on
/// random deformation gradients: small strains around
/// the yield surface, two or three singular values equal to 1e-9 or exactly, condition
/// numbers up to 400, and nearly degenerate or inverted ones (singular values down to
/// 1e-7, negative).
#[test]
fn fast_projections_match_the_svd_ones() {
    let mut state = 11u64;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let elastic = Elastic::from_young(MpmElasticity::FixedCorotated, 1e9, 0.3);
    let materials = [
        Plasticity::JohnsonCook(plasticity::JohnsonCook {
            a: 2e6,
            b: 2e6,
            n: 0.5,
            c: 0.1,
            reference_rate: 1.0,
            thermal: None,
        }),
        Plasticity::Snow {
            critical_compression: 0.025,
            critical_stretch: 0.0075,
        },
        Plasticity::drucker_prager(30.0),
    ];
    let (mut worst_exact, mut increment_exact) = (0.0f64, 0.0f64);
    let (mut worst_svd, mut increment_svd) = (0.0f64, 0.0f64);
    let (mut eigen, mut svds, mut unchanged) = (0, 0, [0; 3]);
    for case in 0..30_000 {
        let mut angle = || 6.3 * uniform();
        let (a, b, c, d, e, f) = (angle(), angle(), angle(), angle(), angle(), angle());
        let u = nalgebra::Rotation3::from_euler_angles(a, b, c).into_inner();
        let v = nalgebra::Rotation3::from_euler_angles(d, e, f).into_inner();
        let s = 1.0 + 0.02 * (uniform() - 0.5);
        let sigma = match case % 6 {
            0 => [0, 1, 2].map(|_| 1.0 + 0.02 * (uniform() - 0.5)),
            1 => [
                s,
                s * (1.0 + 1e-9 * uniform()),
                1.0 + 0.02 * (uniform() - 0.5),
            ],
            2 => [s; 3],
            3 => [0, 1, 2].map(|_| 0.05 * 400f64.powf(uniform())),
            4 => [1.0 + 0.3 * uniform(), 1.0, 1e-7 + 1e-3 * uniform()],
            _ => [1.0 + 0.3 * uniform(), 1.0, -(0.01 + uniform())],
        };
        let m =
            u * nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::from(sigma)) * v.transpose();
        let f: Mat3 = [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[(i, j)]));
        let solved = matches!(
            plasticity::Stretch::of(&f),
            plasticity::Stretch::Eigen { .. }
        );
        if solved {
            eigen += 1;
        } else {
            svds += 1;
        }
        let input = FlowInput {
            mu: elastic.mu,
            lambda: elastic.lambda,
            rate: 10.0 * uniform(),
            plastic_strain: 0.1 * uniform(),
            temperature: 0.0,
        };
        // The exact SVD is the one F was made of, for the eigen-solve path; the SVD
        // path (inverted or degenerate F) must be rotation_svd's exactly.
        let svd = rotation_svd(&f);
        let exact = if solved {
            let to_mat =
                |r: nalgebra::Matrix3<f64>| [0, 1, 2].map(|i| [0, 1, 2].map(|j| r[(i, j)]));
            perifrac_math::RotationSvd {
                u: to_mat(u),
                sigma,
                v: to_mat(v),
            }
        } else {
            svd
        };
        let scale = f.iter().flatten().fold(0.0f64, |x, y| x.max(y.abs()));
        for (k, material) in materials.iter().enumerate() {
            let mut fast = f;
            let increment = material.project(&mut fast, &input);
            for (reference, worst_f, worst_increment) in [
                (exact, &mut worst_exact, &mut increment_exact),
                (svd, &mut worst_svd, &mut increment_svd),
            ] {
                let mut slow = f;
                let expected =
                    material.project_with(&mut slow, &input, &plasticity::Stretch::Svd(reference));
                if expected == 0.0 && reference == svd {
                    unchanged[k] += 1;
                }
                *worst_increment =
                    worst_increment.max((increment - expected).abs() / expected.abs().max(1e-3));
                for (row, row_slow) in fast.iter().zip(&slow) {
                    for (x, y) in row.iter().zip(row_slow) {
                        *worst_f = worst_f.max((x - y).abs() / scale);
                    }
                }
            }
        }
    }
    assert!(
        worst_exact < 1e-12 && increment_exact < 1e-9,
        "F differs from the exact SVD's projection by {worst_exact:e}, Δε^p by {increment_exact:e}"
    );
    // nalgebra's SVD itself errs by up to ~1e-8 when two singular values are close.
    assert!(
        worst_svd < 1e-7 && increment_svd < 1e-7,
        "F differs from nalgebra's SVD's projection by {worst_svd:e}, Δε^p by {increment_svd:e}"
    );
    // Both paths and both outcomes were exercised.
    assert!(
        eigen > 15_000 && svds > 5_000,
        "{eigen} eigen-solves, {svds} SVDs"
    );
    assert!(
        unchanged.iter().all(|&n| n > 1_000 && n < 29_000),
        "elastic cases per model: {unchanged:?}"
    );
}

/// [`plasticity::j2_surely_elastic`] is a bound: never true for a yielding trial state,
/// and tight at small strain (true from 1.02 times the equivalent stress of a simple shear up to γ = 0.01).
#[test]
fn the_j2_elastic_check_is_a_tight_bound() {
    let mu = 1e9;
    for gamma in [1e-4, 1e-3, 1e-2, 0.1, 0.5] {
        // Simple shear F = I + γ e₁⊗e₂: its equivalent stress from the SVD.
        let f: Mat3 = [[1.0, gamma, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let (s, _) = hencky_equivalent_stress(&f, mu);
        assert!(
            !plasticity::j2_surely_elastic(&f, mu, 0.999999 * s),
            "γ = {gamma}"
        );
        if gamma <= 1e-2 {
            assert!(
                plasticity::j2_surely_elastic(&f, mu, 1.01 * s),
                "γ = {gamma}"
            );
        }
    }
}

#[test]
fn snow_clamps_singular_values_and_drucker_prager_lands_on_its_cone() {
    let snow = Plasticity::Snow {
        critical_compression: 0.025,
        critical_stretch: 0.0075,
    };
    let input = FlowInput {
        mu: 1e6,
        lambda: 1e6,
        rate: 0.0,
        plastic_strain: 0.0,
        temperature: 0.0,
    };
    let mut f: Mat3 = [[1.1, 0.0, 0.0], [0.0, 0.9, 0.0], [0.0, 0.0, 1.001]];
    let change = snow.project(&mut f, &input);
    let s = rotation_svd(&f).sigma;
    let mut sorted = s;
    sorted.sort_by(f64::total_cmp);
    assert!((sorted[0] - 0.975).abs() < 1e-12 && (sorted[2] - 1.0075).abs() < 1e-12);
    assert!((sorted[1] - 1.001).abs() < 1e-12);
    let expected =
        ((1.1f64.ln() - 1.0075f64.ln()).powi(2) + (0.9f64.ln() - 0.975f64.ln()).powi(2)).sqrt();
    assert!((change - expected).abs() < 1e-12);
    // Drucker–Prager: compressed and sheared beyond the cone, projected onto it (δγ of
    // the projected state is 0), stretched goes to the tip.
    let dp = Plasticity::drucker_prager(30.0);
    let Plasticity::DruckerPrager { alpha } = dp else {
        unreachable!()
    };
    let mut f: Mat3 = [[0.95, 0.2, 0.0], [0.0, 0.97, 0.0], [0.0, 0.0, 0.99]];
    assert!(dp.project(&mut f, &input) > 0.0);
    let log = rotation_svd(&f).sigma.map(|x| x.ln());
    let trace: f64 = log.iter().sum();
    let dev_norm = log
        .iter()
        .map(|e| (e - trace / 3.0).powi(2))
        .sum::<f64>()
        .sqrt();
    let gamma = dev_norm + (3.0 * input.lambda + 2.0 * input.mu) / (2.0 * input.mu) * trace * alpha;
    assert!(gamma.abs() < 1e-9, "{gamma}");
    let mut stretched: Mat3 = [[1.05, 0.0, 0.0], [0.0, 1.01, 0.0], [0.0, 0.0, 1.0]];
    dp.project(&mut stretched, &input);
    assert!(
        rotation_svd(&stretched)
            .sigma
            .iter()
            .all(|s| (s - 1.0).abs() < 1e-12)
    );
}

/// A thermal Johnson–Cook aluminium-like material whose heat softens it visibly
/// (c = 100 J/(kg K), ten times below aluminium's, so 20% strain heats it ≈ 200 K).
fn thermal_johnson_cook() -> plasticity::JohnsonCook {
    plasticity::JohnsonCook {
        a: 2e8,
        b: 3e8,
        n: 0.5,
        c: 0.0,
        reference_rate: 1.0,
        thermal: Some(plasticity::Thermal {
            melting_temperature: 900.0,
            room_temperature: 300.0,
            exponent: 1.0,
            specific_heat: 100.0,
            taylor_quinney: 0.9,
        }),
    }
}

/// Adiabatic heating (Johnson & Cook 1983): one particle compressed uniaxially and
/// isochorically to 20% log strain in 2000 steps through `Mpm::plasticity` heats by
/// the Taylor–Quinney fraction of its plastic work over ρc. The plastic work is
/// measured independently of the return map: the deviatoric work ∫τ:dε of the
/// prescribed strain path (trapezoid rule on the Hencky stresses before and after each
/// step) less the elastic energy μ‖dev ε_E‖² left at the end.
#[test]
fn adiabatic_heating_of_a_uniaxial_compression_is_beta_times_the_plastic_work_over_rho_c() {
    let (density, jc) = (2700.0, thermal_johnson_cook());
    let material = MpmMaterial {
        density,
        elastic: Elastic::from_young(MpmElasticity::FixedCorotated, 70e9, 0.33),
        eos: None,
        plasticity: Plasticity::JohnsonCook(jc),
    };
    let mu = material.elastic.mu;
    let mut particles = at_rest(vec![[0.0; 3]], vec![1.0], vec![density], vec![0]);
    particles.temperature = vec![300.0];
    let mut model = Mpm::new(particles, vec![material], 0.1);
    let steps = 2000;
    let d = -0.2 / steps as f64;
    let step = [d, -0.5 * d, -0.5 * d];
    let hencky = |f: &Mat3| {
        let log = [0, 1, 2].map(|a| f[a][a].ln());
        let mean = (log[0] + log[1] + log[2]) / 3.0;
        log.map(|e| e - mean)
    };
    let mut work = 0.0;
    for _ in 0..steps {
        let before = hencky(&model.particles.deformation[0]);
        let f = &mut model.particles.deformation[0];
        for (a, e) in step.iter().enumerate() {
            f[a][a] *= e.exp();
        }
        model.plasticity();
        let after = hencky(&model.particles.deformation[0]);
        work += (0..3)
            .map(|a| 0.5 * 2.0 * mu * (before[a] + after[a]) * step[a])
            .sum::<f64>();
    }
    let elastic = hencky(&model.particles.deformation[0]);
    let stored = mu * elastic.iter().map(|e| e * e).sum::<f64>();
    let heat = 0.9 * (work - stored) / (density * 100.0);
    let rise = model.particles.temperature[0] - 300.0;
    assert!(
        (rise - heat).abs() < 2e-3 * heat,
        "heated by {rise} K, β W_p/(ρc) = {heat} K"
    );
    // The heat softened it: the flow stress at the end is the thermal one.
    let strain = model.particles.plastic[0];
    let (s, _) = hencky_equivalent_stress(&model.particles.deformation[0], mu);
    let softened = jc.at_temperature(300.0 + rise).yield_stress(strain, 0.0);
    assert!(
        rise > 100.0 && (s - softened).abs() < 1e-3 * softened,
        "{s} vs {softened}"
    );
    assert!(softened < 0.85 * jc.yield_stress(strain, 0.0));
}

/// The thermal factor 1 − T*^m is 1 at room temperature and 0 at the melting point,
/// where the return map takes away all the deviatoric stress.
#[test]
fn the_yield_stress_falls_to_zero_at_the_melting_point() {
    let jc = thermal_johnson_cook();
    let thermal = jc.thermal.expect("thermal");
    assert_eq!(thermal.softening(300.0), 1.0);
    assert_eq!(thermal.softening(250.0), 1.0);
    assert!((thermal.softening(600.0) - 0.5).abs() < 1e-15);
    assert_eq!(jc.at_temperature(900.0).yield_stress(0.3, 10.0), 0.0);
    assert_eq!(jc.at_temperature(1000.0).yield_stress(0.3, 10.0), 0.0);
    let mu = 26e9;
    let mut f: Mat3 = [[1.0, 0.01, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let j = determinant(&f);
    let input = FlowInput {
        mu,
        lambda: 50e9,
        rate: 0.0,
        plastic_strain: 0.1,
        temperature: 900.0,
    };
    let (trial, _) = hencky_equivalent_stress(&f, mu);
    let increment = Plasticity::JohnsonCook(jc).project(&mut f, &input);
    let (s, j_after) = hencky_equivalent_stress(&f, mu);
    assert!(s < 1e-9 * trial, "{s} Pa left of {trial}");
    assert!((increment - trial / (3.0 * mu)).abs() < 1e-12);
    assert!((j_after - j).abs() < 1e-14);
}

/// Mean equivalent plastic strain of a Johnson–Cook ball dropped on the ground.
fn johnson_cook_drop(exponent: f64) -> f64 {
    let text = format!(
        "[scene]\nduration = 1.0\nfps = 1000\n\
         [materials.metal]\ndensity = 1000\nyoungs_modulus = 1e7\npoisson_ratio = 0.35\n\
         [materials.metal.mpm]\nelasticity = \"stable-neo-hookean\"\n\
         plasticity = {{ type = \"johnson-cook\", yield_stress = 2e4, hardening = 2e5, exponent = {exponent} }}\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"metal\"\nresolution = 0.01\nvelocity = [0, -8, 0]\n\
         shape = {{ type = \"sphere\", center = [0, 0.035, 0], radius = 0.03 }}\n\
         [[collider]]\ntype = \"ground\"\n{OUTPUT}"
    );
    let mut p = prepared(&text);
    let steps = (0.01 / p.world.dt) as usize;
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let plastic = &mpm(&p.world).particles.plastic;
    plastic.iter().sum::<f64>() / plastic.len() as f64
}

#[test]
fn johnson_cook_hardening_reduces_the_plastic_strain_of_a_drop() {
    let strain = [0.0, 0.5, 1.0].map(johnson_cook_drop);
    eprintln!("mean ε^p for n = 0, 0.5, 1: {strain:?}");
    assert!(strain[0] > 0.01, "the drop yields: {strain:?}");
    assert!(strain[0] > strain[1] && strain[0] > strain[2], "{strain:?}");
}

#[test]
fn a_bar_rings_at_its_first_axial_frequency() {
    // A free–free bar with ν = 0 (λ = 0: the 1D wave speed c = √(E/ρ)), first mode
    // u = cos(πx/L), f = c/(2L).
    let (length, e, rho): (f64, f64, f64) = (0.4, 1e6, 1000.0);
    let text = format!(
        "[scene]\nduration = 1.0\nfps = 1000\ngravity = [0, 0, 0]\n\
         [materials.bar]\ndensity = {rho}\nyoungs_modulus = {e}\npoisson_ratio = 0\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"bar\"\nresolution = 0.02\nvelocity = [1e-3, 0, 0]\n\
         shape = {{ type = \"box\", center = [{}, 0, 0], size = [{length}, 0.04, 0.04] }}\n{OUTPUT}",
        length / 2.0
    );
    // The body's initial 1 mm/s sets the blow-up detector's energy budget; the
    // velocities are then replaced by the mode's.
    let mut p = prepared(&text);
    let amplitude = 1e-3;
    {
        let m = p.world.model_mut::<Mpm>().expect("an MPM model");
        let k = std::f64::consts::PI / length;
        for (x, v) in m.particles.position.iter().zip(&mut m.particles.velocity) {
            v[0] = amplitude * (k * x[0]).cos();
        }
    }
    let modal = |w: &World| {
        let m = mpm(w);
        let k = std::f64::consts::PI / length;
        m.particles
            .position
            .iter()
            .zip(&m.particles.velocity)
            .map(|(x, v)| v[0] * (k * x[0]).cos())
            .sum::<f64>()
    };
    let dt = p.world.dt;
    let mut crossings = Vec::new();
    let mut last = modal(&p.world);
    for step in 1..=2000 {
        p.world.step().expect("steps");
        let now = modal(&p.world);
        if last.signum() != now.signum() {
            // Linear interpolation of the zero crossing.
            crossings.push(dt * (step as f64 - 1.0 + last / (last - now)));
        }
        last = now;
        if crossings.len() == 5 {
            break;
        }
    }
    assert_eq!(crossings.len(), 5, "the bar rings");
    let period = (crossings[4] - crossings[0]) / 2.0;
    let analytic = 2.0 * length / (e / rho).sqrt();
    let error = (period - analytic).abs() / analytic;
    eprintln!(
        "period {period:.5e} s, analytic {analytic:.5e} s, error {:.2}%",
        100.0 * error
    );
    assert!(error < 0.05);
}

#[test]
fn a_fast_projectile_carries_its_grid_along() {
    let text = format!(
        "[scene]\nduration = 1.0\nfps = 1000\ngravity = [0, 0, 0]\n\
         [materials.lead]\ndensity = 11000\nyoungs_modulus = 1e8\npoisson_ratio = 0.3\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"lead\"\nresolution = 0.005\nvelocity = [500, 0, 0]\n\
         shape = {{ type = \"sphere\", center = [0, 0, 0], radius = 0.01 }}\n{OUTPUT}"
    );
    let mut p = prepared(&text);
    p.world.step().expect("steps");
    let start = mpm(&p.world).grid.memory_bytes();
    let start_blocks = mpm(&p.world).grid.block_count();
    let steps = (1.0 / (500.0 * p.world.dt)) as usize;
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let m = mpm(&p.world);
    let end = m.grid.memory_bytes();
    let travelled =
        m.particles.position.iter().map(|x| x[0]).sum::<f64>() / m.particles.len() as f64;
    eprintln!(
        "{} particles, {steps} steps, {travelled:.3} m: grid {start} B ({start_blocks} blocks) at the start, {end} B ({} blocks) at the end",
        m.particles.len(),
        m.grid.block_count()
    );
    assert!(travelled > 0.99);
    assert!((end as f64) < 2.0 * start as f64 && (start as f64) < 2.0 * end as f64);
}

#[test]
fn pic_flip_transfer_moves_and_conserves_momentum() {
    let text = scene(
        "gravity = [0, 0, 0]",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [3, 0, 0]\n\
         shape = { type = \"sphere\", center = [-0.06, 0.0, 0.0], radius = 0.05 }\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [-1, 0, 0]\n\
         shape = { type = \"sphere\", center = [0.06, 0.0, 0.0], radius = 0.05 }\n\
         [mpm]\ntransfer = \"pic-flip\"\nflip_ratio = 0.9\n",
    );
    let mut p = prepared(&text);
    assert_eq!(
        mpm(&p.world).transfer,
        Transfer::PicFlip { flip_ratio: 0.9 }
    );
    let before = mpm(&p.world).momentum();
    for _ in 0..(0.02 / p.world.dt) as usize {
        p.world.step().expect("steps");
    }
    let after = mpm(&p.world).momentum();
    let error = norm([0, 1, 2].map(|a| after[a] - before[a])) / norm(before);
    assert!(error < 1e-6, "{error:e}");
}
