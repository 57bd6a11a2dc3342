//! The integral-based MPM's force state against its energy.
use super::*;
use crate::mpm::patches::reference::shape;
use perifrac_math::{cross, det3, inverse3};

const DELTA: f64 = 0.03;
const BONDS: IntegralBonds = IntegralBonds {
    lambda: 4e5,
    mu: 3e5,
    yield_stress: None,
    critical_stretch: None,
};

/// A particle at the origin and its neighbours on a 1 cm lattice within δ = 3 cm,
/// moved by y = x + A x + b x₀x₁ and a scatter of up to 1 mm (non-uniform: a
/// symmetric lattice under a smooth field alone balances its torques pair by pair).
fn family() -> (MpmParticles, Vec<u32>) {
    let mut x0 = vec![[0.0; 3]];
    for k in -3i32..=3 {
        for j in -3i32..=3 {
            for i in -3i32..=3 {
                let x = [i, j, k].map(|c| 0.01 * f64::from(c));
                if (i, j, k) != (0, 0, 0) && norm(x) <= DELTA {
                    x0.push(x);
                }
            }
        }
    }
    let n = x0.len();
    let mut p = crate::mpm::at_rest(x0.clone(), vec![1e-6; n], vec![1e-3; n], vec![0; n]);
    let a = [
        [0.03, 0.02, -0.01],
        [-0.04, 0.01, 0.05],
        [0.02, -0.03, 0.02],
    ];
    p.position = x0
        .iter()
        .enumerate()
        .map(|(q, x)| {
            let ax = mat_vec(a, *x);
            let scatter = [0, 1, 2].map(|c| 1e-3 * (((7 * q + 3 * c) % 11) as f64 / 5.0 - 1.0));
            [0, 1, 2].map(|c| x[c] + ax[c] + [4.0, -3.0, 2.0][c] * x[0] * x[1] + scatter[c])
        })
        .collect();
    (p, (1..n as u32).collect())
}

/// The bonds of particle 0's `family` as [`Patches::settle`] fixes them, in a body
/// whose fullest family has Σ ω V = `whole` (one member: no mirrors).
fn table(p: &MpmParticles, family: &[u32], whole: f64) -> Vec<Bond> {
    let corrections = surface_corrections(0, family, p, whole, DELTA);
    family
        .iter()
        .zip(corrections)
        .map(|(&q, correction)| Bond {
            length: norm(sub(p.reference[q as usize], p.reference[0])),
            correction,
            mirror: NO_MIRROR,
        })
        .collect()
}

/// Particle 0's state, its bonds elastic.
fn state_of(p: &MpmParticles, family: &[u32], table: &[Bond], whole: f64) -> State {
    let member = Member {
        i: 0,
        family,
        table,
    };
    let shape = shape(member, p, DELTA);
    state(member, shape, &mut [], p, &BONDS, whole, DELTA)
}

/// ψ_p of the module documentation at the particles' positions.
fn energy(p: &MpmParticles, family: &[u32]) -> f64 {
    let (x0, x, v) = (&p.reference, &p.position, &p.volume);
    let (mut shape, mut moment, mut whole) = ([[0.0; 3]; 3], [[0.0; 3]; 3], 0.0);
    for &q in family {
        let q = q as usize;
        let (xi, y) = (sub(x0[q], x0[0]), sub(x[q], x[0]));
        let w = DELTA / norm(xi) * v[q];
        whole += w;
        for a in 0..3 {
            for b in 0..3 {
                shape[a][b] += w * xi[a] * xi[b];
                moment[a][b] += w * y[a] * xi[b];
            }
        }
    }
    let f = mat_mul(&moment, &inverse3(&shape, det3(&shape)));
    let c = UNIAXIAL_WEIGHT / whole;
    // A full lattice family: its surface correction is that of the cubic lattice.
    let table = table(p, family, whole);
    family
        .iter()
        .zip(&table)
        .map(|(&q, bond)| {
            let q = q as usize;
            let (xi, y) = (sub(x0[q], x0[0]), sub(x[q], x[0]));
            let l = norm(xi);
            let (average, stretch) = (norm(mat_vec(f, xi)) / l - 1.0, norm(y) / l - 1.0);
            c * bond.correction * DELTA / l
                * v[q]
                * (BONDS.mu * average * average + BONDS.lambda / 2.0 * stretch * stretch)
        })
        .sum()
}

/// The force state is the gradient of ψ_p (central differences, 1e-6), its torques
/// about p cancel, and Eq. 5.6 as printed (Ȳ's term along F X) leaves a torque.
#[test]
fn the_force_state_is_the_gradient_of_the_bond_energy_and_keeps_angular_momentum() {
    let (p, family) = family();
    let whole: f64 = family
        .iter()
        .map(|&q| DELTA / norm(sub(p.reference[q as usize], p.reference[0])) * p.volume[q as usize])
        .sum();
    let table = table(&p, &family, whole);
    let state = state_of(&p, &family, &table, whole);
    let (x0, x) = (&p.reference, &p.position);
    // Particle q is the family's bond q − 1.
    let t = |q: usize| {
        let bond = &table[q - 1];
        force_state(&state, sub(x0[q], x0[0]), sub(x[q], x[0]), bond, 0.0, DELTA)
    };
    let h = 1e-7;
    let mut worst: f64 = 0.0;
    for q in [1, 7, 40, family.len() / 2, family.len()] {
        for a in 0..3 {
            let (mut plus, mut minus) = (p.clone(), p.clone());
            plus.position[q][a] += h;
            minus.position[q][a] -= h;
            let gradient = (energy(&plus, &family) - energy(&minus, &family)) / (2.0 * h);
            let scale = norm(t(q)) * p.volume[q];
            worst = worst.max((gradient - t(q)[a] * p.volume[q]).abs() / scale);
        }
    }
    assert!(
        worst < 1e-6,
        "the force state differs from ∂ψ/∂Y by {worst:.2e}"
    );
    let torque = |force: &dyn Fn(usize) -> [f64; 3]| {
        let (mut sum, mut size) = ([0.0; 3], 0.0);
        for &q in &family {
            let q = q as usize;
            let y = sub(x[q], x[0]);
            sum = add(sum, cross(force(q), y));
            size += norm(force(q)) * norm(y);
        }
        norm(sum) / size
    };
    let ours = torque(&t);
    let Measure::Bonds(f) = state.measure else {
        panic!("{:?}", state.measure)
    };
    let c = UNIAXIAL_WEIGHT / whole;
    let printed = |q: usize| {
        let (xi, y) = (sub(x0[q], x0[0]), sub(x[q], x[0]));
        let (l, average) = (norm(xi), mat_vec(f, xi));
        let w = c * table[q - 1].correction * DELTA / l;
        let shear = scale(
            normalize(average),
            2.0 * BONDS.mu * w / l * (norm(average) / l - 1.0),
        );
        let spring = scale(normalize(y), BONDS.lambda * w / l * (norm(y) / l - 1.0));
        add(shear, spring)
    };
    let eq_5_6 = torque(&printed);
    eprintln!("net torque over Σ|T||Y|: {ours:.1e} (through F), {eq_5_6:.1e} (Eq. 5.6 as printed)");
    assert!(ours < 1e-12, "{ours:.2e}");
    assert!(eq_5_6 > 1e-3, "{eq_5_6:.2e}");
}
