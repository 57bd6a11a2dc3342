//! The invariant checks that spare a particle inside its yield surface the
//! decomposition of F̂: [`plasticity::drucker_prager_surely_elastic`] against the
//! cone test on the exact singular values F̂ was made of.

use nalgebra::{Matrix3, Vector3};
use perifrac_math::RotationSvd;

use super::constitutive::Elastic;
use super::plasticity::{self, FlowInput, Plasticity, Stretch};
use super::spectral_tests::{rotation, to_mat, uniform};
use crate::scene::MpmElasticity;

/// [`plasticity::drucker_prager_surely_elastic`] never accepts a state that yields:
/// on 200,000 random F̂ = U exp(l) Vᵀ compressed by −tr l = −ln J from 10⁻⁸ to 0.5
/// (log-uniform), with ‖dev l‖ from 0 to twice the cone's radius kα(−ln J), most of
/// them within 10% of it (and 2,000 within 10⁻⁶), along random deviatoric directions
/// and the two axial ones (where the bound on the most compressed axis is tightest),
/// for friction angles 10°–45° and Poisson ratios 0.2–0.45, the exact projection of
/// the SVD F̂ was made of (`project_with`) leaves every accepted state alone. And it is
/// tight: every state within 0.9 of the radius at −ln J in [10⁻⁵, 10⁻²] is accepted.
#[test]
fn the_drucker_prager_elastic_check_never_accepts_a_yielding_state() {
    let mut state = 33u64;
    let (mut accepted, mut elastic, mut yielding) = (0, 0, 0);
    for case in 0..200_000 {
        let degrees = [10.0, 30.0, 45.0][case % 3];
        let poisson = [0.2, 0.3, 0.45][(case / 3) % 3];
        let material = Plasticity::drucker_prager(degrees);
        let Plasticity::DruckerPrager { alpha } = material else {
            unreachable!()
        };
        let elastic_law = Elastic::from_young(MpmElasticity::FixedCorotated, 1e6, poisson);
        let (mu, lambda) = (elastic_law.mu, elastic_law.lambda);
        let compression = 1e-8 * 5e7f64.powf(uniform(&mut state));
        let radius = (3.0 * lambda + 2.0 * mu) / (2.0 * mu) * alpha * compression;
        let share = match case % 10 {
            0 => 2.0 * uniform(&mut state),
            1 => 1.0 + 1e-6 * (uniform(&mut state) - 0.5),
            _ => 0.9 + 0.2 * uniform(&mut state),
        };
        let direction = match (case / 10) % 4 {
            0 => [2.0, -1.0, -1.0],
            1 => [-2.0, 1.0, 1.0],
            _ => [0, 1, 2].map(|_| uniform(&mut state) - 0.5),
        };
        let mean = direction.iter().sum::<f64>() / 3.0;
        let dev = direction.map(|d| d - mean);
        let norm = dev.iter().map(|d| d * d).sum::<f64>().sqrt();
        let log = dev.map(|d| -compression / 3.0 + share * radius * d / norm);
        let sigma = log.map(f64::exp);
        let (u, v) = (rotation(&mut state), rotation(&mut state));
        let f = to_mat(u * Matrix3::from_diagonal(&Vector3::from(sigma)) * v.transpose());
        let input = FlowInput {
            mu,
            lambda,
            rate: 0.0,
            plastic_strain: 0.0,
            temperature: 0.0,
        };
        let exact = Stretch::Svd(RotationSvd {
            u: to_mat(u),
            sigma,
            v: to_mat(v),
        });
        let yields = material.project_with(&mut f.clone(), &input, &exact) > 0.0;
        let surely = plasticity::drucker_prager_surely_elastic(&f, alpha, mu, lambda);
        assert!(
            !(surely && yields),
            "accepted a yielding state: −ln J = {compression:e}, ‖dev l‖ = {share} of the \
             radius, φ = {degrees}°, ν = {poisson}"
        );
        if (1e-5..=1e-2).contains(&compression) && share <= 0.9 {
            assert!(
                surely,
                "missed: −ln J = {compression:e}, {share} of the radius"
            );
        }
        accepted += usize::from(surely);
        elastic += usize::from(!yields);
        yielding += usize::from(yields);
    }
    // Both sides of the cone were sampled, and the check took most of the inside.
    assert!(
        yielding > 50_000 && elastic > 50_000 && accepted > elastic / 2,
        "{yielding} yielding, {elastic} elastic, {accepted} accepted"
    );
}
