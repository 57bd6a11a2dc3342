//! The state-based peridynamic elastoplastic model of Chen et al. 2018 (§4–5.1).
//!
//! With ω_ij = δ/|ξ| (Eq. 5, or δ/|Gξ| with anisotropy, Eq. 17) the force density on
//! particle i is (Eq. 2–3)
//!
//! ```text
//! f_i = Σ_j ½ (A_ij + A_ji) ŷ_ij V_j,     A = A_dil + A_dev
//! A_dil = 4 ω a_ij q_ij Λ θ_i                              (Eq. 4)
//! A_dev = 4 ω b p_ij (e_ij − (δ/4) q_ij Λ θ_i − e^p_ij)   (Eq. 8, 9, 12)
//! θ_i   = 9/(4πδ⁴) Σ_j ω s_ij Λ |ξ| q_ij V_j               (Eq. 6, 7)
//! ```
//!
//! where Λ = ŷ·ξ̂ as printed (`DilatationForm::Paper`) or 1 (`Objective`, the default:
//! the printed factor makes a stretched body's forces depend on its orientation), and
//! q_ij is the surface correction of [`crate::family`] (1 for a complete family).
//! With a = 9κ/(8πδ⁴), b = 15μ/(2πδ⁵) (Eq. 10) this is the derivative of the energy
//! density W_i = c θ_i² + b Σ_j p_ij ω (e − e^p)² V_j with c = (κ − 5μ/3)/2, which the
//! solver uses to check energy; b is scaled per bond by the surface correction p_ij
//! of [`crate::family`] (1 for a complete family), and Eq. 4's a by the matching
//! a + (p_ij − 1) bδ/4 so that κ is kept.
//!
//! Plasticity (Eq. 13–16) and fracture (Eq. 18–19) are optional stages; a scene
//! without them allocates no plastic state and runs kernels compiled without them.
//!
//! Crushing (ours, not in Chen et al.): a material with a `critical_compression` ε_c
//! breaks a bond compressed past the strain −ε_c, and the crushed bond then acts as
//! crushed glass does: it carries no tension, resists compression with the bond's
//! deviatoric stiffness, and yields at the strain ε_c (perfectly plastic), so
//! A = 4ω b p (e − e^c)  while e < e^c,  e^c = min(e^c, e + ε_c|ξ|),
//! with e^c set to e + ε_c|ξ| when it crushes (the force goes on from where it was)
//! and stored per bond ([`PdModel::crushed`]). Its energy, b p ω (e − e^c)² V_j
//! while compressed, is in W_i.

mod coefficients;
mod crack;
mod kernel;
pub mod share;
mod solver;
mod stable;

use std::ops::Range;
use std::sync::Arc;

use perifrac_math::{det_sum, dist, dot, norm, sub};
use rayon::prelude::*;

use crate::family::{BROKEN, Bonds, INDEX};
use crate::material::{Material, PdConstants};
use crate::ranks::{Ranks, Share};
use crate::scene::DilatationForm;

pub use coefficients::Coefficients;
pub use crack::cut_initial_cracks;
pub use kernel::StageTimes;
pub use solver::Peridynamics;
pub use stable::stable_time_step;

/// Particle state that is saved in checkpoints.
#[derive(Debug, Clone, Default)]
pub struct Particles {
    /// Current positions y.
    pub position: Vec<[f64; 3]>,
    /// Velocities.
    pub velocity: Vec<[f64; 3]>,
    /// Damage φ = 1 − n_i/N_i (Chen §5.1).
    pub damage: Vec<f64>,
}

/// Per-particle data that does not change during a run.
#[derive(Debug, Clone, Default)]
pub struct Reference {
    /// Reference positions x (tet barycentres).
    pub position: Vec<[f64; 3]>,
    /// Volumes V (tet volumes).
    pub volume: Vec<f64>,
    /// Body index of each particle.
    pub body: Vec<u32>,
    /// Initial bond count N_i (Chen §5.1).
    pub initial_bonds: Vec<u32>,
}

/// Per-body constants and options of the model.
#[derive(Debug, Clone)]
pub struct BodyModel {
    /// Material.
    pub material: Material,
    /// Chen's constants for this body's horizon.
    pub constants: PdConstants,
    /// a' = a − bδ/4 = 3c/(δ V_H∞): the dilatation coefficient of the energy form.
    pub a_prime: f64,
}

impl BodyModel {
    /// Builds the constants of a body of `material` with horizon δ = `delta`.
    pub fn new(material: Material, delta: f64) -> BodyModel {
        let constants = material.constants(delta);
        let a_prime = constants.a - constants.b * delta / 4.0;
        BodyModel {
            material,
            constants,
            a_prime,
        }
    }
}

/// Plastic bond state, allocated only when a material yields.
#[derive(Debug, Clone)]
pub struct Plastic {
    /// e^p per directed bond (Eq. 11), of every row: the force pass of i reads e^p_ji
    /// from j's row (the reverse index is [`Coefficients::reverse`]).
    pub extension: Vec<f64>,
    /// Whether any bond of a particle has yielded: the force pass reads e^p (a
    /// scattered read for j→i) only for particles that have.
    pub yielded: Vec<bool>,
}

/// How [`PdModel::new`] sets the model up.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Λ of Eq. 6 and 8 ([`DilatationForm`]).
    pub form: DilatationForm,
    /// Chen §6's surface correction of each family (the scene's `surface_correction`).
    pub surface_correction: bool,
    /// The ranks of a distributed run: the per-bond constants are built for this
    /// rank's rows alone; `None` in one process.
    pub share: Option<Share>,
}

/// What a scene needs of the model; picks the compiled kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Features {
    /// Any material yields.
    pub plastic: bool,
    /// Any material can break.
    pub fracture: bool,
    /// Any material is anisotropic.
    pub anisotropic: bool,
    /// Λ = ŷ·ξ̂ as printed.
    pub paper_form: bool,
}

/// The peridynamic model: particles, bonds and the stage kernels.
#[derive(Debug, Clone)]
pub struct PdModel {
    /// Saved particle state.
    pub particles: Particles,
    /// Fixed per-particle data.
    pub reference: Reference,
    /// Families (CSR).
    pub bonds: Bonds,
    /// Per-bond constants of the kernels, of the rows this process works on.
    pub coef: Coefficients,
    /// Plastic state, only when some material yields.
    pub plastic: Option<Plastic>,
    /// e^c per directed bond: the extension below which a crushed bond pushes back
    /// (infinite while the bond is intact or broken in tension; see the module doc),
    /// only when some material crushes.
    pub crushed: Option<Vec<f32>>,
    /// Per-body constants.
    pub bodies: Vec<BodyModel>,
    /// What the kernels do.
    pub features: Features,
    /// Dilatation θ (scratch, recomputed each step).
    pub theta: Vec<f64>,
    /// Internal force density f_i (scratch).
    pub force: Vec<[f64; 3]>,
    /// Time spent in each stage.
    pub times: StageTimes,
    /// Particles handed to the rigid phase ([`crate::rigid`]): their forces are not
    /// computed and their bonds neither stretch nor break; a crushed bond between a
    /// frozen particle and a free one pushes neither. `None` until a fragment goes
    /// rigid, so a scene without a rigid phase pays nothing.
    pub frozen: Option<Vec<bool>>,
    /// The ranks this model's bond work is split over in a distributed run
    /// ([`share`]); `None` in one process.
    pub share: Option<Share>,
}

/// V_H∞ = 4πδ³/3, the volume of a complete family.
pub fn family_volume(delta: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * delta.powi(3)
}

impl PdModel {
    /// Sets up the model from particles, their families and per-body materials; the
    /// per-bond constants only for the rows this process works on (`setup.share`).
    pub fn new(
        reference_position: Vec<[f64; 3]>,
        volume: Vec<f64>,
        body: Vec<u32>,
        bonds: Bonds,
        bodies: Vec<BodyModel>,
        setup: Setup,
    ) -> PdModel {
        let n = reference_position.len();
        let features = Features {
            plastic: bodies.iter().any(|b| b.material.is_plastic()),
            fracture: bodies.iter().any(|b| b.material.critical_stretch.is_some()),
            anisotropic: bodies.iter().any(|b| b.material.anisotropy.is_some()),
            paper_form: setup.form == DilatationForm::Paper,
        };
        let initial_bonds: Vec<u32> = (0..n).map(|i| bonds.range(i).len() as u32).collect();
        let rows = setup.share.as_ref().map_or(0..n, Share::owned);
        let coef = Coefficients::build(
            &bonds,
            rows,
            &coefficients::Inputs {
                position: &reference_position,
                volume: &volume,
                body: &body,
                bodies: &bodies,
                surface_correction: setup.surface_correction,
                keep_reverse: features.plastic,
            },
        );
        let plastic = features.plastic.then(|| Plastic {
            extension: vec![0.0f64; bonds.len()],
            yielded: vec![false; n],
        });
        let crushed = bodies
            .iter()
            .any(|b| b.material.critical_compression.is_some())
            .then(|| vec![f32::INFINITY; bonds.len()]);
        PdModel {
            particles: Particles {
                position: reference_position.clone(),
                velocity: vec![[0.0; 3]; n],
                damage: vec![0.0; n],
            },
            reference: Reference {
                position: reference_position,
                volume,
                body,
                initial_bonds,
            },
            bonds,
            coef,
            plastic,
            crushed,
            bodies,
            features,
            theta: vec![0.0; n],
            force: vec![[0.0; 3]; n],
            times: StageTimes::default(),
            frozen: None,
            share: setup.share,
        }
    }

    /// Splits the bond work over `ranks` ([`share`]): from the next step on, this
    /// rank computes its range of particles and takes in the others'. One rank keeps
    /// it whole.
    /// A model built with its share ([`Setup::share`]) keeps it; one built whole
    /// drops the per-bond constants of the rows other ranks work on.
    pub fn share(&mut self, ranks: Arc<dyn Ranks>) {
        if self.share.is_some() || ranks.size() < 2 {
            return;
        }
        let share = Share::by_bonds(ranks, &self.bonds.offsets);
        self.coef.keep(share.owned(), &self.bonds.offsets);
        self.share = Some(share);
    }

    /// The particles whose bond work this process does: all of them in one process.
    pub fn owned(&self) -> Range<usize> {
        self.share.as_ref().map_or(0..self.len(), Share::owned)
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.reference.position.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.reference.position.is_empty()
    }

    /// Mass of particle i.
    pub fn mass(&self, i: usize) -> f64 {
        self.reference.volume[i]
            * self.bodies[self.reference.body[i] as usize]
                .material
                .density
    }

    /// Computes θ, updates plastic extensions and broken bonds, and fills `force`
    /// with the internal force density at the current positions. Returns how many
    /// bonds broke.
    pub fn internal_forces(&mut self) -> usize {
        kernel::dispatch(self)
    }

    /// Breaks every intact bond i→j for which `cut(i, j)` holds (the predicate should
    /// be symmetric, so that j→i breaks too); returns the number of directed bonds
    /// broken.
    pub fn cut_bonds(&mut self, cut: impl Fn(usize, usize) -> bool + Sync) -> usize {
        let offsets = &self.bonds.offsets;
        let broken: usize = self
            .bonds
            .neighbours
            .par_iter_mut()
            .enumerate()
            .map(|(k, nb)| {
                let i = offsets.partition_point(|&o| o <= k) - 1;
                let j = (*nb & INDEX) as usize;
                if *nb & BROKEN == 0 && cut(i, j) {
                    *nb |= BROKEN;
                    1
                } else {
                    0
                }
            })
            .sum();
        self.update_damage();
        broken
    }

    /// Recomputes the per-particle `yielded` flags from the plastic extensions (after
    /// they were replaced wholesale, as when a checkpoint is restored).
    pub fn update_yielded(&mut self) {
        let bonds = &self.bonds;
        if let Some(p) = &mut self.plastic {
            let ext = &p.extension;
            p.yielded
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, y)| *y = ext[bonds.range(i)].iter().any(|&e| e != 0.0));
        }
    }

    /// φ_i = 1 − n_i/N_i from the broken bits.
    pub fn update_damage(&mut self) {
        let bonds = &self.bonds;
        let initial = &self.reference.initial_bonds;
        self.particles
            .damage
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, phi)| {
                let total = initial[i];
                if total == 0 {
                    *phi = 0.0;
                    return;
                }
                let intact = bonds.neighbours[bonds.range(i)]
                    .iter()
                    .filter(|&&nb| nb & BROKEN == 0)
                    .count();
                *phi = 1.0 - intact as f64 / total as f64;
            });
    }

    /// Total strain energy Σ_i V_i W_i (see the module doc); uses the current θ.
    pub fn strain_energy(&self) -> f64 {
        kernel::strain_energy(self)
    }

    /// Kinetic energy ½ Σ m v².
    pub fn kinetic_energy(&self) -> f64 {
        det_sum(self.len(), |i| {
            let v = self.particles.velocity[i];
            0.5 * self.mass(i) * dot(v, v)
        })
    }

    /// Connected components of intact bonds, numbered by their smallest particle
    /// index in increasing order (deterministic).
    pub fn fragments(&self) -> Vec<u32> {
        self.bonds.fragments()
    }

    /// Whether particle i has gone to the rigid phase.
    #[inline(always)]
    pub fn is_frozen(&self, i: usize) -> bool {
        self.frozen.as_ref().is_some_and(|f| f[i])
    }

    /// |ξ| of bond `k` of particle `i`: the stored length in this process's rows
    /// ([`Coefficients::rows`]), else from the reference positions as the build
    /// computes it, to the bit (another rank's rows in a distributed run).
    #[inline]
    fn rest_length(&self, i: usize, k: usize) -> f64 {
        if self.coef.rows.contains(&i) {
            return self.coef.rest_length[k - self.coef.first];
        }
        let x = &self.reference.position;
        dist(x[i], x[(self.bonds.neighbours[k] & INDEX) as usize])
    }

    /// ω (Eq. 17, as stored: f32) of bond `k` of particle `i` of an anisotropic
    /// material `g` and length `rest`, stored or recomputed as [`Self::rest_length`].
    #[inline]
    fn omega(&self, i: usize, k: usize, g: [[f64; 3]; 3], rest: f64) -> f64 {
        if let (true, Some(w)) = (self.coef.rows.contains(&i), &self.coef.omega) {
            return w[k - self.coef.first] as f64;
        }
        let x = &self.reference.position;
        let xi = sub(x[(self.bonds.neighbours[k] & INDEX) as usize], x[i]);
        let delta = self.bodies[self.reference.body[i] as usize].constants.delta;
        coefficients::omega(delta, Some(g), xi, rest) as f32 as f64
    }

    /// How near each particle's intact bonds are to breaking: the largest, over its
    /// intact bonds, of the weighted elastic stretch over its threshold, s^ω/((1 + αφ)
    /// s_c) (Eq. 18–19 as the force pass applies them), and of the compressive strain
    /// over a crushing material's ε_c; −1 for a particle of a body that cannot break.
    /// The rigid phase hands a fragment over only when this stays under its margin.
    pub fn breaking_ratios(&self) -> Vec<f64> {
        if !self.features.fracture {
            return vec![-1.0; self.len()];
        }
        let y = &self.particles.position;
        let bonds = &self.bonds;
        let phi = &self.particles.damage;
        (0..self.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let c = &self.bodies[self.reference.body[i] as usize].constants;
                if !c.critical_stretch.is_finite() && !c.critical_compression.is_finite() {
                    return -1.0;
                }
                let g = 1.0 + c.alpha * phi[i];
                let anisotropy = self.bodies[self.reference.body[i] as usize]
                    .material
                    .anisotropy;
                let mut worst = 0.0f64;
                for k in bonds.range(i) {
                    let nb = bonds.neighbours[k];
                    if nb & BROKEN != 0 {
                        continue;
                    }
                    let j = (nb & INDEX) as usize;
                    let r = self.rest_length(i, k);
                    let e = norm(sub(y[j], y[i]))
                        - r
                        - self.plastic.as_ref().map_or(0.0, |p| p.extension[k]);
                    let omega_r = match anisotropy {
                        Some(g) => self.omega(i, k, g, r) * r,
                        None => c.delta,
                    };
                    worst = worst
                        .max(e / (g * c.critical_stretch * omega_r))
                        .max(-e / (g * c.critical_compression * r));
                }
                worst
            })
            .collect()
    }

    /// Plastic strain measure per particle: mean |e^p|/|ξ| over its bonds (0 without
    /// plasticity).
    pub fn plastic_strain(&self) -> Vec<f64> {
        let Some(plastic) = &self.plastic else {
            return vec![0.0; self.len()];
        };
        (0..self.len())
            .into_par_iter()
            .map(|i| {
                let r = self.bonds.range(i);
                if r.is_empty() {
                    return 0.0;
                }
                let n = r.len() as f64;
                r.map(|k| plastic.extension[k].abs() / self.rest_length(i, k))
                    .sum::<f64>()
                    / n
            })
            .collect()
    }

    /// Bytes of bond storage in use: the neighbour words of every row, the per-bond
    /// constants of this process's rows, and the optional state of every row (e^p, e^c).
    pub fn bond_bytes(&self) -> usize {
        let n = self.bonds.len();
        let mut bytes = n * 4 + self.coef.bytes();
        if self.plastic.is_some() {
            bytes += n * 8;
        }
        if self.crushed.is_some() {
            bytes += n * 4;
        }
        bytes
    }
}

#[cfg(test)]
mod tests;
