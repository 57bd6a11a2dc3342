//! The MPM's plasticity (Lyu ch. 3 and 7): J2 and Johnson–Cook radial returns, the
//! shock model's Mie–Grüneisen pressure, stable Neo-Hookean, the fast projections
//! against the SVD ones, snow and Drucker–Prager, adiabatic heating.

use perifrac_math::{mul_transpose, rotation_svd};

use super::constitutive::{Elastic, Mat3, determinant};
use super::plasticity::{FlowInput, Plasticity};
use super::tests::{OUTPUT, mpm, prepared};
use super::*;
use crate::scene::MpmElasticity;

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
        volume_modulus: 0.0,
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
        volume_modulus: 0.0,
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
