//! [`Spectrum`]'s powers of C = FᵀF, and the small-strain [`series`], against the
//! eigen-construction F was made of.

use nalgebra::{Matrix3, Rotation3, Vector3};
use perifrac_math::RotationSvd;

use super::constitutive::{Elastic, Mat3, determinant, gram};
use super::plasticity::{FlowInput, JohnsonCook, Plasticity, Stretch};
use super::series::{self, SERIES_STRAIN};
use super::spectral::Spectrum;
use crate::scene::MpmElasticity;

pub(super) fn uniform(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

pub(super) fn rotation(state: &mut u64) -> Matrix3<f64> {
    let mut angle = || 6.3 * uniform(state);
    Rotation3::from_euler_angles(angle(), angle(), angle()).into_inner()
}

pub(super) fn to_mat(m: Matrix3<f64>) -> Mat3 {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[(i, j)]))
}

/// e^b C^a of F = U Σ Vᵀ matches V e^b Σ^{2a} Vᵀ to 1e-13 of its largest entry, for exponents
/// of both signs (the projections use a in [−½, 0]) and singular values well apart,
/// two or three within 1e-12 to 1e-3 of each other (where the closed-form eigenvalues
/// are least accurate and the divided differences would cancel), exactly equal, and
/// spread to the condition floor.
#[test]
fn powers_of_c_match_the_eigen_construction() {
    let mut state = 5u64;
    let mut worst = 0.0f64;
    for case in 0..60_000 {
        let u = rotation(&mut state);
        let v = rotation(&mut state);
        let s = 0.8 + 0.4 * uniform(&mut state);
        let gap = 10f64.powf(-12.0 + 9.0 * uniform(&mut state));
        let other = 0.8 + 0.4 * uniform(&mut state);
        let sigma = match case % 6 {
            0 => [0, 1, 2].map(|_| 0.7 + 0.6 * uniform(&mut state)),
            1 => [s, s * (1.0 + gap), other],
            2 => [s, s * (1.0 + gap), s * (1.0 - gap)],
            3 => [s; 3],
            4 => [s, s * (1.0 + gap), s * 0.11 * (1.0 + uniform(&mut state))],
            _ => [0, 1, 2].map(|_| 0.1 + 0.9 * uniform(&mut state)),
        };
        let a = [-0.5, -0.25, -1e-7, 0.0, 0.3, 1.0][(case / 6) % 6];
        let f = to_mat(u * Matrix3::from_diagonal(&Vector3::from(sigma)) * v.transpose());
        let spectrum = Spectrum::of(&f).expect("well conditioned");
        let b = 0.2 * (uniform(&mut state) - 0.5);
        let power = spectrum.power(a, b, &spectrum.logs());
        let exact = to_mat(
            v * Matrix3::from_diagonal(&Vector3::from(sigma.map(|x| b.exp() * x.powf(2.0 * a))))
                * v.transpose(),
        );
        let scale = exact.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        for (row, row_exact) in power.iter().zip(&exact) {
            for (x, y) in row.iter().zip(row_exact) {
                worst = worst.max((x - y).abs() / scale);
            }
        }
        let mut logs = spectrum.logs().map(|l| 0.5 * l);
        logs.sort_by(f64::total_cmp);
        let mut expected = sigma.map(f64::ln);
        expected.sort_by(f64::total_cmp);
        for (l, e) in logs.iter().zip(&expected) {
            assert!(
                (l - e).abs() < 1e-8,
                "case {case}: log σ {logs:?} against {expected:?}"
            );
        }
    }
    assert!(
        worst < 1e-13,
        "e^b C^a differs from V e^b Σ^2a Vᵀ by {worst:e}"
    );
}

/// An inverted, a degenerate and a poorly conditioned F have no spectrum (the
/// projections take the SVD or the Jacobi eigen-solve instead).
#[test]
fn inverted_or_ill_conditioned_gradients_have_no_spectrum() {
    let diagonal = |d: [f64; 3]| [[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]];
    assert!(Spectrum::of(&diagonal([1.0, 1.0, -1.0])).is_none());
    assert!(Spectrum::of(&diagonal([1.0, 1.0, 0.0])).is_none());
    assert!(Spectrum::of(&diagonal([1.0, 1.0, 0.09])).is_none());
    assert!(Spectrum::of(&diagonal([f64::NAN, 1.0, 1.0])).is_none());
    assert!(Spectrum::of(&diagonal([1.0, 1.0, 0.11])).is_some());
}

/// Snow's clamp without eigenvectors matches U clamp(Σ) Vᵀ to 1e-12 of |F|, and its
/// increment ‖log Σ̂ − log Σ‖ to 1e-12, on singular values spread around the clamp's
/// bounds (each alone on a piece, pairs and triples within 1e-12 to 1e-3 of each other
/// on one piece or straddling a bound), and declines only where two eigenvalues on
/// different pieces are close.
#[test]
fn snow_clamps_by_pieces_as_the_svd_does() {
    let (lo, hi) = (0.975, 1.0075);
    let mut state = 17u64;
    let (mut worst, mut worst_increment) = (0.0f64, 0.0f64);
    let (mut clamped, mut declined, mut projectors) = (0, 0, 0);
    for case in 0..30_000 {
        let u = rotation(&mut state);
        let v = rotation(&mut state);
        let gap = 10f64.powf(-12.0 + 9.0 * uniform(&mut state));
        let mut around = || 0.95 + 0.08 * uniform(&mut state);
        let (s, other) = (around(), around());
        let sigma = match case % 5 {
            0 | 1 => [around(), around(), around()],
            2 => [s, s * (1.0 + gap), other],
            3 => [s, s * (1.0 + gap), s * (1.0 - gap)],
            _ => [hi * (1.0 + gap), hi * (1.0 - gap), other],
        };
        let f = to_mat(u * Matrix3::from_diagonal(&Vector3::from(sigma)) * v.transpose());
        let spectrum = Spectrum::of(&f).expect("well conditioned");
        let mut fast = f;
        let Some(increment) = spectrum.clamp(&mut fast, lo, hi) else {
            assert_eq!(fast, f, "a declined clamp leaves F alone");
            declined += 1;
            continue;
        };
        let target = sigma.map(|x| x.clamp(lo, hi));
        if target != sigma {
            clamped += 1;
        }
        let pieces: std::collections::BTreeSet<i8> = sigma
            .iter()
            .map(|&x| (x > hi) as i8 - (x < lo) as i8)
            .collect();
        if pieces.len() > 1 {
            projectors += 1;
        }
        let exact = to_mat(u * Matrix3::from_diagonal(&Vector3::from(target)) * v.transpose());
        for (row, row_exact) in fast.iter().zip(&exact) {
            for (x, y) in row.iter().zip(row_exact) {
                worst = worst.max((x - y).abs());
            }
        }
        let expected = (0..3)
            .map(|k| (sigma[k].ln() - target[k].ln()).powi(2))
            .sum::<f64>()
            .sqrt();
        worst_increment = worst_increment.max((increment - expected).abs());
    }
    assert!(
        worst < 1e-12 && worst_increment < 1e-12,
        "F differs from U clamp(Σ) Vᵀ by {worst:e}, the increment by {worst_increment:e}"
    );
    assert!(
        clamped > 15_000 && projectors > 8_000 && declined < 9_000,
        "{clamped} clamped, {projectors} with projectors, {declined} declined"
    );
}

/// The J2 and Drucker–Prager projections at small strain, where they take the series
/// in E = C − I ([`series::project`]), match the same projections on the exact SVD F
/// was made of (`project_with`) to 2e-15 of |F| and their increments to 2e-15 (the
/// round-off of F = U Σ Vᵀ itself): log singular values of magnitudes 10⁻¹⁶ to 10⁻²,
/// and a third of them 0.003 to 0.033 (either side of [`SERIES_STRAIN`]), two or three
/// of them equal or within 10⁻⁹ of each other, Johnson–Cook's yield stress within a
/// factor 2 of the trial stress. The test fails with a series tolerance of 1e-13.
#[test]
fn small_strain_projections_match_the_svd_ones() {
    let mut state = 23u64;
    let elastic = Elastic::from_young(MpmElasticity::FixedCorotated, 1e6, 0.3);
    let (mut worst, mut worst_increment) = (0.0f64, 0.0f64);
    let (mut by_series, mut yielded) = (0, 0);
    for case in 0..40_000 {
        let u = rotation(&mut state);
        let v = rotation(&mut state);
        let magnitude = if case % 3 == 0 {
            SERIES_STRAIN * (0.3 + 3.0 * uniform(&mut state))
        } else {
            10f64.powf(-16.0 + 14.0 * uniform(&mut state))
        };
        let mut around = || magnitude * (2.0 * uniform(&mut state) - 1.0);
        let (l, other) = (around(), around());
        let log = match case % 5 {
            0 | 1 => [around(), around(), around()],
            2 => [l, l, other],
            3 => [l, l + 1e-9 * magnitude, other],
            _ => [l; 3],
        };
        let sigma = log.map(f64::exp);
        let f = to_mat(u * Matrix3::from_diagonal(&Vector3::from(sigma)) * v.transpose());
        // The series take F where they return Some, whatever the map.
        let applies = series::project(&mut f.clone(), &gram(&f), determinant(&f), |_| None);
        by_series += usize::from(applies.is_some());
        let mean = log.iter().sum::<f64>() / 3.0;
        let dev = log.iter().map(|x| (x - mean).powi(2)).sum::<f64>().sqrt();
        let trial = 2.0 * elastic.mu * (1.5f64).sqrt() * dev;
        let materials = [
            Plasticity::drucker_prager(30.0),
            Plasticity::JohnsonCook(JohnsonCook {
                a: trial * (0.5 + uniform(&mut state)),
                b: trial,
                n: 0.5,
                c: 0.0,
                reference_rate: 1.0,
                thermal: None,
            }),
        ];
        let input = FlowInput {
            mu: elastic.mu,
            lambda: elastic.lambda,
            rate: 0.0,
            plastic_strain: 0.01 * uniform(&mut state),
            temperature: 0.0,
        };
        let exact = Stretch::Svd(RotationSvd {
            u: to_mat(u),
            sigma,
            v: to_mat(v),
        });
        for material in materials {
            let (mut fast, mut slow) = (f, f);
            let increment = material.project(&mut fast, &input);
            let expected = material.project_with(&mut slow, &input, &exact);
            yielded += usize::from(expected > 0.0);
            worst_increment = worst_increment.max((increment - expected).abs());
            for (row, row_slow) in fast.iter().zip(&slow) {
                for (x, y) in row.iter().zip(row_slow) {
                    worst = worst.max((x - y).abs());
                }
            }
        }
    }
    assert!(
        worst < 2e-15 && worst_increment < 2e-15,
        "F differs from the exact SVD's projection by {worst:e}, the increment by \
         {worst_increment:e}"
    );
    assert!(
        by_series > 20_000 && by_series < 36_000 && yielded > 20_000 && yielded < 60_000,
        "{by_series} by the series, {yielded} projections that yielded"
    );
}
