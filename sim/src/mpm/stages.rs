//! The MPM step's per-particle stages around the grid ([`Mpm::step`]): the stress
//! stage before P2G (each particle's affine momentum, the shock model's internal
//! energy, the eroding bodies' raised histories) and the plastic projections after
//! G2P.

use rayon::iter::Either;
use rayon::prelude::*;

use super::constitutive::{self, IDENTITY, Mat3};
use super::grid::D_INVERSE_FACTOR;
use super::patches::Measure;
use super::plasticity::{self, Plasticity};
use super::{Mpm, Transfer};

impl Mpm {
    /// Each particle's affine momentum A_p = m_p C_p − Δt V_p⁰ D⁻¹ τ_p (MLS-MPM, Hu et
    /// al. 2018 Eq. 16–17; τ = P Fᵀ), without m_p C_p under PIC/FLIP; the shock
    /// model's internal energy advances by Eq. 7.3 with the same stress.
    pub(super) fn stress(&mut self, dt: f64) {
        let p = &mut self.particles;
        let n = p.len();
        let d_inv = D_INVERSE_FACTOR / (self.grid.dx * self.grid.dx);
        let materials = &self.materials;
        let affine_share = match self.transfer {
            Transfer::Apic => 1.0,
            Transfer::PicFlip { .. } => 0.0,
        };
        let (deformation, volume, mass, affine, body) =
            (&p.deformation, &p.volume, &p.mass, &p.affine, &p.body);
        let patches = self.patches.as_ref();
        let eroding = patches.filter(|patches| patches.erodes());
        // Each body's volume modulus where its bonds are viscous (`patches::integral`).
        let volume_moduli: Vec<Option<f64>> = (0..materials.len())
            .map(|b| patches.and_then(|patches| patches.volume_modulus(b)))
            .collect();
        let kernel = |i: usize, a: &mut Mat3, e: Option<&mut f64>, raised: Option<&mut f64>| {
            let b = body[i] as usize;
            let material = &materials[b];
            // A peridynamic particle's forces come from its bonds, not the grid; its
            // stress (for the shock model's Eq. 7.3) is σ(F^PD).
            let (f, member) = match patches.and_then(|patches| patches.measure(i)) {
                Some(Measure::Bonds(f)) => (Some(f), true),
                Some(Measure::Free) => (None, true),
                Some(Measure::Material) => (Some(deformation[i]), true),
                None => (Some(deformation[i]), false),
            };
            let energy = e.as_deref().copied().unwrap_or(0.0);
            // A member's stress is needed only for its internal energy and erosion.
            let wanted = !member || e.is_some() || raised.is_some();
            let stress = f
                .filter(|_| wanted)
                .map(|f| (material.kirchhoff(&f, energy), f));
            if let (Some(raised), Some(patches)) = (raised, eroding) {
                *raised = patches.raised_history(i, b, stress.as_ref().map(|(t, f)| (t, f)));
            }
            if let (Some(e), Some((tau, f))) = (e, &stress) {
                let j = constitutive::determinant(f);
                let sigma = tau.map(|row| row.map(|x| x / j));
                *e += plasticity::internal_energy_increment(dt, &affine[i], &sigma);
            }
            let tau = match (stress, volume_moduli[b]) {
                (Some((tau, _)), _) if !member => tau,
                // A member of a viscous body holds its volume on the grid: K ln J I,
                // J of the grid's F (`patches::integral`); none where F has inverted.
                (_, Some(bulk)) if member => {
                    let j = constitutive::determinant(&deformation[i]);
                    let pressure = if j > 0.0 { bulk * j.ln() } else { 0.0 };
                    IDENTITY.map(|row| row.map(|x| pressure * x))
                }
                _ => [[0.0; 3]; 3],
            };
            let scale = dt * volume[i] * d_inv;
            let m = affine_share * mass[i];
            for ((row, c_row), tau_row) in a.iter_mut().zip(&affine[i]).zip(&tau) {
                for ((x, c), t) in row.iter_mut().zip(c_row).zip(tau_row) {
                    *x = m * c - scale * t;
                }
            }
        };
        // The internal energies (shock materials) and the raised histories (eroding
        // bodies) where the scene has them, `None` a particle where not.
        let energies = if p.internal_energy.is_empty() {
            Either::Right((0..n).into_par_iter().map(|_| None))
        } else {
            Either::Left(p.internal_energy.par_iter_mut().map(Some))
        };
        self.raised
            .resize(if eroding.is_some() { n } else { 0 }, 0.0);
        let raised = if self.raised.is_empty() {
            Either::Right((0..n).into_par_iter().map(|_| None))
        } else {
            Either::Left(self.raised.par_iter_mut().map(Some))
        };
        self.momentum_affine
            .par_iter_mut()
            .zip(energies)
            .zip(raised)
            .enumerate()
            .with_min_len(256)
            .for_each(|(i, ((a, e), h))| kernel(i, a, e, h));
    }

    /// Projects each plastic particle's grown deformation gradient onto its material's
    /// admissible set and accumulates ε^p and the heating of [`MpmMaterial::flow`]. A
    /// peridynamic particle that measures F by its bonds has its flow counted by
    /// them ([`patches`]); its material point's F_E is still projected, since it
    /// stands in when the bonds measure an inverted F.
    pub(super) fn plasticity(&mut self) {
        if self
            .materials
            .iter()
            .all(|m| m.plasticity == Plasticity::None)
        {
            return;
        }
        let p = &mut self.particles;
        let materials = &self.materials;
        let patches = self.patches.as_ref();
        let (body, affine) = (&p.body, &p.affine);
        let kernel = |i: usize, f: &mut Mat3, plastic: &mut f64, temperature: Option<&mut f64>| {
            let material = &materials[body[i] as usize];
            if material.plasticity == Plasticity::None {
                return;
            }
            let at = temperature.as_deref().copied().unwrap_or(0.0);
            let (increment, heating) = material.flow(f, *plastic, at, &affine[i]);
            if patches.is_some_and(|patches| matches!(patches.measure(i), Some(Measure::Bonds(_))))
            {
                return;
            }
            *plastic += increment;
            if let Some(temperature) = temperature {
                *temperature += heating;
            }
        };
        if p.temperature.is_empty() {
            p.deformation
                .par_iter_mut()
                .zip(p.plastic.par_iter_mut())
                .enumerate()
                .with_min_len(256)
                .for_each(|(i, (f, plastic))| kernel(i, f, plastic, None));
        } else {
            p.deformation
                .par_iter_mut()
                .zip(p.plastic.par_iter_mut())
                .zip(p.temperature.par_iter_mut())
                .enumerate()
                .with_min_len(256)
                .for_each(|(i, ((f, plastic), t))| kernel(i, f, plastic, Some(t)));
        }
    }
}
