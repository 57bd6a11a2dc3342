//! One member's correspondence state (Lyu Eq. 6.7–6.8): K and F^PD over its intact
//! bonds, its elastic part after its plastic flow, and the bond force state's P K⁻¹
//! (the module documentation of [`super`] has the equations and choices).

use perifrac_math::{inverse3, mat_mul, sub};

use super::Measure;
use super::integral::Strain;
use super::reference::{Member, Shape};
use crate::family::{BROKEN, INDEX};
use crate::mpm::constitutive::{self, Mat3};
use crate::mpm::plasticity::Plasticity;
use crate::mpm::{MpmMaterial, MpmParticles};

/// One member's correspondence state at the step's start.
#[derive(Debug, Clone, Copy)]
pub(super) struct State {
    pub(super) measure: Measure,
    /// P_p K_p⁻¹, so that T_pq = ω P_p K_p⁻¹ X (zero when free); for the
    /// integral-based MPM's bonds, P_μ K⁻¹ of their μ term ([`super::integral`]).
    pub(super) force: Mat3,
    /// c_p λ of the integral-based MPM's springs along the bonds (0 for SPB-MPM's
    /// correspondence members).
    pub(super) spring: f64,
    /// How the springs and the μ term take e^p off a bond's extension.
    pub(super) strain: Strain,
}

/// A plastic member's flow this step.
pub(super) struct Flow {
    /// F_P⁻¹ = (F^PD)⁻¹ F_E after the projection.
    pub(super) plastic_inverse: Mat3,
    /// Δε^p.
    pub(super) increment: f64,
    /// The adiabatic temperature rise (K).
    pub(super) heating: f64,
}

/// The member's state: F^PD over its intact bonds with its K's `shape` (Eq. 6.7),
/// its elastic part F_E after the plastic flow (the module documentation; F_E = F^PD
/// for an elastic material) from its F_P⁻¹ `plastic_inverse`, P and P K⁻¹.
pub(super) fn state(
    member: Member<'_>,
    shape: Shape,
    plastic_inverse: Option<&Mat3>,
    p: &MpmParticles,
    materials: &[MpmMaterial],
    delta: f64,
) -> (State, Option<Flow>) {
    let Member { i, family, table } = member;
    let free = State {
        measure: Measure::Free,
        force: [[0.0; 3]; 3],
        spring: 0.0,
        strain: Strain::Additive,
    };
    let Shape::Spanning(shape_inverse) = shape else {
        return (free, None);
    };
    let mut moment = [[0.0; 3]; 3];
    for (&nb, bond) in family.iter().zip(table) {
        if nb & BROKEN != 0 {
            continue;
        }
        let q = (nb & INDEX) as usize;
        let xi = sub(p.reference[q], p.reference[i]);
        let w = delta / bond.length * p.volume[q];
        let y = sub(p.position[q], p.position[i]);
        for a in 0..3 {
            for b in 0..3 {
                moment[a][b] += w * y[a] * xi[b];
            }
        }
    }
    let bonds = mat_mul(&moment, &shape_inverse);
    let material = &materials[p.body[i] as usize];
    let (measure, elastic, total, flow) = if constitutive::determinant(&bonds) > 0.0 {
        let (elastic, flow) = elastic_part(i, &bonds, plastic_inverse, p, material);
        (Measure::Bonds(elastic), elastic, bonds, flow)
    } else {
        let f = p.deformation[i];
        (Measure::Material, f, f, None)
    };
    let energy = p.internal_energy.get(i).copied().unwrap_or(0.0);
    let Some(piola) = piola(material, &elastic, &total, energy) else {
        return (free, None);
    };
    let state = State {
        measure,
        force: mat_mul(&piola, &shape_inverse),
        spring: 0.0,
        strain: Strain::Additive,
    };
    (state, flow)
}

/// Member `i`'s elastic part F_E of `bonds` = F^PD and its flow: F^PD itself for an
/// elastic material; else the trial F^PD F_P⁻¹ projected by the material's return
/// mapping, with F_P⁻¹ = `plastic_inverse` or, at the first measure,
/// (F^PD)⁻¹ F_E^MPM (the module documentation).
fn elastic_part(
    i: usize,
    bonds: &Mat3,
    plastic_inverse: Option<&Mat3>,
    p: &MpmParticles,
    material: &MpmMaterial,
) -> (Mat3, Option<Flow>) {
    if material.plasticity == Plasticity::None {
        return (*bonds, None);
    }
    let bonds_inverse = inverse3(bonds, constitutive::determinant(bonds));
    let plastic_inverse =
        plastic_inverse.map_or_else(|| mat_mul(&bonds_inverse, &p.deformation[i]), |f| *f);
    let mut elastic = mat_mul(bonds, &plastic_inverse);
    let temperature = p.temperature.get(i).copied().unwrap_or(0.0);
    let (increment, heating) = material.flow(&mut elastic, p.plastic[i], temperature, &p.affine[i]);
    let flow = Flow {
        plastic_inverse: mat_mul(&bonds_inverse, &elastic),
        increment,
        heating,
    };
    (elastic, Some(flow))
}

/// The first Piola–Kirchhoff stress P = τ(F_E) F⁻ᵀ of `material` in the reference
/// configuration, with `elastic` F_E and `total` F (the same for an elastic
/// material), or `None` if either is inverted.
fn piola(material: &MpmMaterial, elastic: &Mat3, total: &Mat3, energy: f64) -> Option<Mat3> {
    let (j_elastic, j) = (
        constitutive::determinant(elastic),
        constitutive::determinant(total),
    );
    if j_elastic.is_nan() || j_elastic <= 0.0 || j.is_nan() || j <= 0.0 {
        return None;
    }
    let tau = material.kirchhoff(elastic, energy);
    let f_inverse = inverse3(total, j);
    Some([0, 1, 2].map(|a| [0, 1, 2].map(|b| (0..3).map(|c| tau[a][c] * f_inverse[b][c]).sum())))
}
