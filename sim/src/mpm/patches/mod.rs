//! SPB-MPM (Lyu 2021 ch. 6): peridynamic particles superposed on the MLS-MPM where
//! the grid's released energy erodes a cell, with bonds that break by their energy.
//! The integral-based MPM (ch. 5, `integral.rs`) keeps its bonds here too: its
//! bodies' particles are all members from the start, with their own bond model.
//!
//! **Eigenerosion** (Eq. 6.9–6.10). Each particle of a fracturing material keeps the
//! history EE_p = max(EE_p, Φ(σ_p⁺)) (§6.2.3, after Wolper et al. 2019), with σ⁺ the
//! positive eigenvalues of its Cauchy stress and Φ(σ⁺) = σ⁺:σ⁺ / (2E). The thesis
//! prints σ⁺:σ⁺, in Pa², which makes G_i Pa²·m and not an energy release rate; over 2E
//! it is the tensile part of the linear elastic energy density, so G_i compares with
//! G_p in J/m². P2G carries it: G_i = l₀ Σ_p w_ip m_p EE_p / m_i, with l₀ = 2δ (Eq. 6.9:
//! eroding a neighbourhood of radius ε = δ releases ψ|C_ε| against G_p |C_ε| / (2ε)).
//! A particle whose nearest node (the cell it lies in) reaches G_i ≥ the material's
//! `erosion_release_rate` joins Ω^PD for good.
//!
//! **Families** are built when a particle joins (only Ω^PD pays for bonds): its
//! reference neighbours within δ = [`HORIZON_CELLS`] Δx in its body, through its shape
//! as for peridynamic bodies (issue 13), MPM particles or not.
//!
//! **Correspondence** (Eq. 6.7–6.8): over a member's intact bonds,
//! K_p = Σ ω X⊗X V_q and F_p^PD = (Σ ω Y⊗X V_q) K_p⁻¹ with ω = δ/|X|, decreasing with
//! the bond length as §6.2.2 says (Algorithm 3 prints |X|/l₀, which grows); the bond
//! force state is T_pq = ω P_p K_p⁻¹ X with P = J σ F⁻ᵀ the first Piola–Kirchhoff stress
//! of the material's own MPM model at F^PD (Eq. 6.8 prints det F F⁻¹ σ K⁻¹ X = Pᵀ K⁻¹ X,
//! the transpose, which differs from P whenever F is not symmetric; the ω of Eq. 6.6
//! is the bond's 0/1 state, not a second weight).
//!
//! **Forces** (Eq. 6.2–6.6). Each particle's stress acts once: a material point's
//! through the grid (MLS-MPM), a member's through its bonds. A member puts no stress on
//! the grid; a bond from member p to member q carries T_pq − T_qp (Eq. 6.6), a bond to
//! a material point q of the MPM region (the halo) only T_pq, with −T_pq on q, since
//! q's own stress is on the grid already. The forces reach the particles as any
//! particle force does in MPM, Δt f_p / m_p on v_p before P2G, so every particle moves
//! with the grid's velocities: an intact patch deforms as the MPM region around it,
//! and momentum is kept pair by pair. Two departures from Algorithm 3, each measured
//! on the bar half peridynamic of the tests: (1) Algorithm 3 corrects x and v after
//! G2P; positions moved apart from the grid's flow leave F^MPM behind them, and the
//! MPM region next to the patch let go of it (4 mm of a 6 mm stretch opened at the
//! patch's edge; with the forces through P2G the two halves carry σ_yy within 0.2%);
//! (2) counting a halo particle's stress on its bonds as well as on the grid pulled
//! the halo off the MPM region below it (a gap of the same size). An anchored
//! particle's bond force is its anchor's reaction and does not reach the grid
//! ([`Patches::apply`]): its motion is prescribed, so its δu vanishes in the weak
//! form (Eq. 5.1, 6.3).
//!
//! **Plasticity.** The thesis' SPB-MPM runs plastic materials (Table 6.2 clamps the
//! bars' and chocolates' F by θ_c, θ_s) but says nothing of how a peridynamic
//! particle flows. Here a member of a plastic material keeps its plastic part as
//! F_P⁻¹, the multiplicative split F^PD = F_E F_P of MPM (§3.3.3) with F^PD in the
//! place of the grid-grown F: each step the trial F_E = F^PD F_P⁻¹ is projected by
//! the material's own return mapping (the MPM's, [`MpmMaterial::flow`]: ε^p and the
//! heating accumulate as for a material point), F_P⁻¹ ← (F^PD)⁻¹ F_E, and the stress
//! on the bonds is the first Piola–Kirchhoff stress of the reference configuration,
//! P = τ(F_E) (F^PD)⁻ᵀ (τ F^PD⁻ᵀ with τ the Kirchhoff stress: the elastic P when
//! F_P = I). F_P⁻¹ is set at a member's first measure, (F^PD)⁻¹ F_E^MPM, so its
//! elastic state, and its stress, carry on from the material point it was. Tested
//! as the elastic bar: a J2 bar half peridynamic, pulled past yield, carries the
//! stress and the plastic strain of its MPM half.
//!
//! **Failure** (Eq. 6.11–6.13): W = (T_pq − T_qp)·U with U = Y − X; a bond breaks for
//! good when W > W_c = 4G_p/(π δ⁴) (3D). Only bonds between two peridynamic particles
//! break: cracks live in Ω^PD, which eigenerosion grows ahead of them.
//!
//! **Zero-energy modes.** A correspondence model's particle-scale modes leave F^PD
//! unchanged. Here the particles move with the grid's velocity field, which is smooth
//! on the scale Δx, so those modes cannot be excited and no penalty term is added
//! (tested: the half peridynamic bar stretches as smoothly as its MPM half).
//!
//! Order in a step: [`Patches::prepare`] (states at x^n, failure, bond forces) →
//! stress (none for members) → [`Patches::erode`] (Φ at F^PD, G_i, joins) →
//! [`Patches::apply`] (the bond forces) → P2G → grid → G2P. Everything a step needs
//! follows from the checkpointed positions, histories and bonds, so a resumed run
//! gives the same bytes.

use perifrac_math::{dot, mat_vec, sub};
use rayon::prelude::*;

mod correspondence;
mod forces;
mod integral;
mod pieces;
mod reference;

use correspondence::{Flow, State, state};
pub use integral::{IntegralBonds, flows_per_bond};
use reference::{Bond, Member, Reference, Shape};

use super::MpmMaterial;
use super::MpmParticles;
use super::constitutive::{self, Mat3};
use super::grid::SparseGrid;
use crate::error::Result;
use crate::family::{BROKEN, INDEX};
use crate::geometry::Sdf;

/// The horizon δ in grid spacings: 3 particle spacings at 8 particles a cell, about
/// 110 neighbours (Table 6.2 uses H_p = 100).
pub const HORIZON_CELLS: f64 = 1.5;
/// The bonds a particle's family holds inside a body: its neighbours within δ at
/// [`PARTICLES_PER_CELL_AXIS`]³ particles a cell (about 112).
///
/// [`PARTICLES_PER_CELL_AXIS`]: crate::mpm::PARTICLES_PER_CELL_AXIS
pub fn interior_family() -> f64 {
    let per_cell = crate::mpm::PARTICLES_PER_CELL_AXIS.pow(3) as f64;
    4.0 / 3.0 * std::f64::consts::PI * HORIZON_CELLS.powi(3) * per_cell - 1.0
}

/// l₀ of Eq. 6.10 in horizons (see the module documentation).
pub const RELEASE_LENGTH_HORIZONS: f64 = 2.0;
/// A member measures F and carries stress while the smallest eigenvalue of its shape
/// tensor over the intact bonds is at least this share of its whole family's mean
/// one, tr K⁰/3; below it the member has lost its bonds (a loose particle). A family
/// cut in half by a crack keeps 1/2 across it; one with a few bonds left (a line, a
/// sliver) has a K⁻¹ that makes the bond forces of Eq. 6.8 too stiff for the step:
/// with det K > 0 the only bound, a particle with 8% of its bonds left blew the
/// notched bar up within 4 steps. At 0.2 the 2 cm grid's bar shattered a 4 cm band
/// into loose particles; at 0.1 it splits within 1 cm of the notch.
pub const MIN_SHAPE: f64 = 0.1;
/// Bytes a directed bond of Ω^PD takes while the run steps: its family entry (u32),
/// its `Bond` (the reference length, correction and mirror) and its T_p⟨q⟩ in the
/// step's scratch forces. Checked against the peak memory of the integral-based boards
/// (docs/memory.md).
pub const BYTES_PER_BOND: usize = size_of::<u32>() + size_of::<Bond>() + size_of::<[f64; 3]>();
/// Bytes more a bond takes for each plastic extension e^p it keeps (the
/// integral-based MPM's: one with a `yield_stress`, two with a `viscosity`).
pub const PLASTIC_BYTES_PER_BOND: usize = size_of::<f64>();
/// The slot of a particle outside Ω^PD.
const OUTSIDE: u32 = u32::MAX;

/// A fracturing material's keys (`[materials.NAME.mpm]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fracture {
    /// G_p of the bonds (J/m², Eq. 6.12).
    pub release_rate: f64,
    /// The released energy G_i at which a cell erodes (J/m², Eq. 6.10).
    pub erosion_rate: f64,
    /// Young's modulus E of Φ = σ⁺:σ⁺ / (2E) (Pa).
    pub young: f64,
}

/// What a body brings to the patches.
pub struct PatchBody {
    /// Its fracture, or `None`: its particles never join Ω^PD by erosion.
    pub fracture: Option<Fracture>,
    /// The integral-based MPM's bonds (Lyu ch. 5, [`IntegralBonds`]), or `None`: given,
    /// all its particles are peridynamic from the start, with these bonds.
    pub bonds: Option<IntegralBonds>,
    /// Its shape when it is not convex: bonds stay inside it.
    pub shape: Option<Box<dyn Sdf>>,
    /// Its resolution λ (the shape's sampling step, [`crate::family::Solid::of`]).
    pub resolution: f64,
}

/// The stress a member puts on the grid this step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Measure {
    /// σ(F_E) of the F^PD of its intact bonds: F_E = F^PD for an elastic material,
    /// F^PD F_P⁻¹ after its flow for a plastic one.
    Bonds(Mat3),
    /// σ(F^MPM): its bonds measure an inverted F^PD, so the material point's own F
    /// stands in.
    Material,
    /// None: its intact bonds span a plane or a line (a free fragment of one particle).
    Free,
}

/// Wall time of the patches' stages (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PatchTimes {
    /// States, failure and bond forces ([`Patches::prepare`], [`Patches::apply`]).
    pub evolve: f64,
    /// Φ, G_i and joins ([`Patches::erode`]).
    pub erode: f64,
}

/// The peridynamic particles of an MPM model and their bonds.
pub struct Patches {
    bodies: Vec<PatchBody>,
    /// The horizon δ (m).
    pub horizon: f64,
    /// The grid spacing Δx (m).
    dx: f64,
    /// EE_p = max Φ(σ_p⁺) so far (J/m³), one entry a particle.
    history: Vec<f64>,
    /// Each particle's member slot, or [`OUTSIDE`].
    slot: Vec<u32>,
    /// The members (particle indices) in the order they joined.
    members: Vec<u32>,
    /// Each member's family: neighbour indices, [`BROKEN`] set on broken bonds.
    families: Vec<Vec<u32>>,
    /// Each member's F_P⁻¹ (plastic materials, from its first measure on).
    plastic_inverse: Vec<Option<Mat3>>,
    /// Each integral-based member's bonds' plastic extensions e^p, in family order
    /// (empty for elastic bonds and SPB-MPM members).
    extensions: Vec<Vec<f64>>,
    /// Each member's bonds as the reference configuration fixes them, in family
    /// order (`reference.rs`).
    table: Vec<Vec<Bond>>,
    /// Each member's K over its intact bonds, kept until one of them breaks
    /// (`reference.rs`).
    shapes: Vec<Shape>,
    /// Each body's Σ ω V over its fullest family (bodies with bonds; 0 for the
    /// others), the bulk that the bonds' weights are scaled to (`integral.rs`).
    full_weights: Vec<f64>,
    /// Scratch: each member's state this step.
    states: Vec<State>,
    /// Scratch: each member's T_p⟨q⟩ of this step, in family order (zero on broken
    /// bonds).
    tractions: Vec<Vec<[f64; 3]>>,
    /// Scratch: this step's bond accelerations of the members and their halo.
    accelerations: Vec<(u32, [f64; 3])>,
    /// Scratch: each halo particle's sum of its bonds' reactions this step, zero
    /// between steps (one entry a particle), and whether it has one.
    halo_totals: Vec<[f64; 3]>,
    halo_seen: Vec<bool>,
    /// The reference neighbour search, built when the first particle joins.
    reference: Option<Reference>,
    /// Stage timers.
    pub times: PatchTimes,
}

impl std::fmt::Debug for Patches {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Patches")
            .field("horizon", &self.horizon)
            .field("members", &self.members.len())
            .finish_non_exhaustive()
    }
}

impl Patches {
    /// The patches of `particles` on a grid of spacing `dx`; `None` when no body
    /// fractures or has bonds (the scene pays nothing). The particles of bodies with
    /// bonds join with [`Patches::join_bonded`].
    pub fn new(bodies: Vec<PatchBody>, n: usize, dx: f64) -> Option<Patches> {
        bodies
            .iter()
            .any(|b| b.fracture.is_some() || b.bonds.is_some())
            .then(|| Patches {
                full_weights: vec![0.0; bodies.len()],
                bodies,
                horizon: HORIZON_CELLS * dx,
                dx,
                history: vec![0.0; n],
                slot: vec![OUTSIDE; n],
                members: Vec::new(),
                families: Vec::new(),
                plastic_inverse: Vec::new(),
                extensions: Vec::new(),
                table: Vec::new(),
                shapes: Vec::new(),
                states: Vec::new(),
                tractions: Vec::new(),
                accelerations: Vec::new(),
                halo_totals: Vec::new(),
                halo_seen: Vec::new(),
                reference: None,
                times: PatchTimes::default(),
            })
    }

    /// The particles in Ω^PD, in the order they joined.
    pub fn members(&self) -> &[u32] {
        &self.members
    }

    /// The bulk modulus K of body `b`'s volume term where its bonds are viscous (the
    /// module documentation of `integral.rs`): its particles put the Kirchhoff stress
    /// K ln J I of the grid's J on the grid, as material points do. `None` for every
    /// other body.
    pub fn volume_modulus(&self, b: usize) -> Option<f64> {
        let bonds = self.bodies[b].bonds?;
        bonds
            .viscosity
            .map(|_| constitutive::bulk_modulus(bonds.lambda, bonds.mu))
    }

    /// Whether particle `p` is peridynamic.
    pub fn is_member(&self, p: usize) -> bool {
        self.slot[p] != OUTSIDE
    }

    /// The stress measure of member `p` this step (`None` outside Ω^PD; a particle
    /// that joined this step measures with its material point's F until the next).
    pub fn measure(&self, p: usize) -> Option<Measure> {
        match self.slot[p] {
            OUTSIDE => None,
            s => Some(
                self.states
                    .get(s as usize)
                    .map_or(Measure::Material, |s| s.measure),
            ),
        }
    }

    /// Broken bonds over all bonds of each particle (0 outside Ω^PD).
    pub fn damage(&self) -> Vec<f32> {
        let mut damage = vec![0.0; self.slot.len()];
        for (&p, family) in self.members.iter().zip(&self.families) {
            let broken = family.iter().filter(|&&nb| nb & BROKEN != 0).count();
            damage[p as usize] = broken as f32 / family.len().max(1) as f32;
        }
        damage
    }

    /// The number of bonds (each counted from both ends, as for peridynamics).
    pub fn bonds(&self) -> usize {
        self.families.iter().map(Vec::len).sum()
    }

    /// The number of broken bonds (each counted from both ends).
    pub fn broken_bonds(&self) -> usize {
        self.families
            .iter()
            .flatten()
            .filter(|&&nb| nb & BROKEN != 0)
            .count()
    }

    /// W_c = 4G_p / (π δ⁴) of body `b` (Eq. 6.12, 3D).
    pub fn critical_energy(&self, b: usize) -> f64 {
        self.bodies[b].fracture.map_or(f64::INFINITY, |f| {
            4.0 * f.release_rate / (std::f64::consts::PI * self.horizon.powi(4))
        })
    }

    /// T_pq − T_qp of the bond of reference length `length` from `p` to `q` (Eq.
    /// 6.8), with the states of this step.
    fn bond_force(&self, p: usize, q: usize, length: f64, x0: &[[f64; 3]]) -> [f64; 3] {
        let xi = sub(x0[q], x0[p]);
        let omega = self.horizon / length;
        let fp = self.states[self.slot[p] as usize].force;
        let fq = self.states[self.slot[q] as usize].force;
        let tpq = mat_vec(fp, xi);
        let tqp = mat_vec(fq, xi.map(|c| -c));
        [0, 1, 2].map(|a| omega * tpq[a] - omega * tqp[a])
    }

    /// At the step's start: each member's K, F^PD, its plastic flow and P at the
    /// positions x^n (Eq. 6.7–6.8); bonds whose energy W exceeds W_c break (Eq.
    /// 6.11–6.13); each member's and halo particle's acceleration by the bonds (see
    /// the module documentation). Returns how many directed bonds broke.
    pub fn prepare(
        &mut self,
        particles: &mut MpmParticles,
        materials: &[MpmMaterial],
        dt: f64,
    ) -> usize {
        let started = std::time::Instant::now();
        let delta = self.horizon;
        let p = &*particles;
        // Each integral-based body's bonds' law this step.
        let laws: Vec<Option<integral::Law>> = self
            .bodies
            .iter()
            .zip(&self.full_weights)
            .map(|(body, &full)| body.bonds.map(|bonds| bonds.law(full, dt)))
            .collect();
        let measured: Vec<(State, Option<Flow>)> = self
            .members
            .par_iter()
            .zip(&self.families)
            .zip(&self.table)
            .zip(&self.plastic_inverse)
            .zip(self.extensions.par_iter_mut())
            .zip(self.shapes.par_iter_mut())
            .map(|(((((&i, family), table), inverse), extensions), shape)| {
                let i = i as usize;
                let member = Member { i, family, table };
                if *shape == Shape::Stale {
                    *shape = reference::shape(member, p, delta);
                }
                match &laws[p.body[i] as usize] {
                    Some(law) => {
                        let state = integral::state(member, *shape, extensions, p, law, delta);
                        (state, None)
                    }
                    None => state(member, *shape, inverse.as_ref(), p, materials, delta),
                }
            })
            .collect();
        self.states.clear();
        for (s, (state, flow)) in measured.into_iter().enumerate() {
            self.states.push(state);
            if let Some(largest) = self.extensions[s].iter().map(|e| e.abs()).reduce(f64::max) {
                // The cache's plastic strain of a particle with plastic bonds: the
                // largest plastic extension of its bonds.
                particles.plastic[self.members[s] as usize] = largest;
            }
            if let Some(flow) = flow {
                let i = self.members[s] as usize;
                self.plastic_inverse[s] = Some(flow.plastic_inverse);
                particles.plastic[i] += flow.increment;
                if let Some(temperature) = particles.temperature.get_mut(i) {
                    *temperature += flow.heating;
                }
            }
        }
        let p = &*particles;
        let critical: Vec<f64> = (0..self.bodies.len())
            .map(|b| self.critical_energy(b))
            .collect();
        let inactive = self.inactive_shares(p);
        let this = &*self;
        let mut broken: Vec<Vec<usize>> = self
            .members
            .par_iter()
            .zip(&self.families)
            .enumerate()
            .map(|(s, (&i, family))| {
                let i = i as usize;
                if let Some(bonds) = &this.bodies[p.body[i] as usize].bonds {
                    return this.stretched(s, bonds, &inactive, p);
                }
                let w_c = critical[p.body[i] as usize];
                let free = this.states[this.slot[i] as usize].measure == Measure::Free;
                family
                    .iter()
                    .enumerate()
                    .filter(|&(_, &nb)| nb & BROKEN == 0)
                    .filter(|&(k, &nb)| {
                        let q = (nb & INDEX) as usize;
                        if free {
                            // A member that measures no F has lost its bonds.
                            return true;
                        }
                        if !this.is_member(q) {
                            return false;
                        }
                        if this.states[this.slot[q] as usize].measure == Measure::Free {
                            return true;
                        }
                        let u = sub(
                            sub(p.position[q], p.position[i]),
                            sub(p.reference[q], p.reference[i]),
                        );
                        let length = this.table[s][k].length;
                        dot(this.bond_force(i, q, length, &p.reference), u) > w_c
                    })
                    .map(|(k, _)| k)
                    .collect()
            })
            .collect();
        self.cut(&mut broken, &inactive, p);
        let mut count = 0;
        for ((family, shape), broken) in self.families.iter_mut().zip(&mut self.shapes).zip(broken)
        {
            count += broken.len();
            if !broken.is_empty() {
                *shape = Shape::Stale;
            }
            for k in broken {
                family[k] |= BROKEN;
            }
        }
        self.forces(p);
        self.times.evolve += started.elapsed().as_secs_f64();
        count
    }

    /// Whether any body erodes: the stress stage then raises each particle's history
    /// ([`Patches::raised_history`]) for [`Patches::erode`].
    pub fn erodes(&self) -> bool {
        self.bodies.iter().any(|b| b.fracture.is_some())
    }

    /// Eigenerosion's history (Eq. 6.9): particle `i`'s EE_p raised to Φ(σ⁺) =
    /// Σ max(σ_k, 0)² / (2E) under its stress this step, given as the Kirchhoff stress
    /// τ = J σ of the stress stage with its F (`None` for a free member, whose history
    /// stays), so that σ is not evaluated twice.
    pub fn raised_history(&self, i: usize, body: usize, stress: Option<(&Mat3, &Mat3)>) -> f64 {
        let history = self.history[i];
        let (Some(fracture), Some((tau, f))) = (self.bodies[body].fracture, stress) else {
            return history;
        };
        let j = constitutive::determinant(f);
        let scale = 1.0 / (2.0 * fracture.young * j * j);
        // Φ(σ⁺) ≤ σ:σ / (2E): no eigen-solve when that cannot raise EE_p.
        let whole: f64 = tau.iter().flatten().map(|t| t * t).sum::<f64>() * scale;
        if whole <= history {
            return history;
        }
        let values = constitutive::symmetric_eigenvalues(tau);
        let tension: f64 = values.iter().map(|&s| s.max(0.0).powi(2)).sum();
        history.max(tension * scale)
    }

    /// Eigenerosion (Eq. 6.9–6.10): takes each particle's history EE_p as the stress
    /// stage raised it ([`Patches::raised_history`], one entry a particle), carries it
    /// to the grid (a P2G that leaves the nodes to the real one after it) and adds the
    /// particles of eroded cells to Ω^PD, each with its family. Hands back the old
    /// histories' buffer for the next step's. Returns how many joined.
    ///
    /// # Errors
    /// [`crate::error::SimError::Refused`] if the neighbour search cannot be built.
    pub fn erode(
        &mut self,
        particles: &MpmParticles,
        grid: &mut SparseGrid,
        raised: &mut Vec<f64>,
    ) -> Result<usize> {
        let started = std::time::Instant::now();
        let p = particles;
        std::mem::swap(&mut self.history, raised);
        grid.p2g_scalar(&p.position, &p.mass, &self.history);
        let length = RELEASE_LENGTH_HORIZONS * self.horizon;
        let released = grid.centre_ratio(&p.position);
        let joining: Vec<usize> = (0..p.len())
            .filter(|&i| self.slot[i] == OUTSIDE)
            .filter(|&i| {
                self.bodies[p.body[i] as usize]
                    .fracture
                    .is_some_and(|f| length * released[i] >= f.erosion_rate)
            })
            .collect();
        if !joining.is_empty() {
            self.join(&joining, p)?;
        }
        self.times.erode += started.elapsed().as_secs_f64();
        Ok(joining.len())
    }

    /// Adds `joining` (increasing particle indices, none a member yet) to Ω^PD with
    /// their families, and [`Patches::settle`]s their bonds.
    ///
    /// # Errors
    /// [`crate::error::SimError::Refused`] if the neighbour search cannot be built.
    pub(super) fn join(&mut self, joining: &[usize], p: &MpmParticles) -> Result<()> {
        if self.reference.is_none() {
            self.reference = Some(Reference::new(&self.bodies, p)?);
        }
        let families: Vec<Vec<u32>> = joining.par_iter().map(|&i| self.family(i, p)).collect();
        let from = self.members.len();
        for (&i, family) in joining.iter().zip(families) {
            let flows = self.bodies[p.body[i] as usize]
                .bonds
                .map_or(0, |b| b.flows_per_bond());
            self.slot[i] = self.members.len() as u32;
            self.members.push(i as u32);
            self.extensions.push(vec![0.0; flows * family.len()]);
            self.families.push(family);
            self.plastic_inverse.push(None);
        }
        self.settle(from, p);
        Ok(())
    }

    /// The reference family of particle `i` (the search exists).
    fn family(&self, i: usize, p: &MpmParticles) -> Vec<u32> {
        self.reference
            .as_ref()
            .map(|r| r.family(&self.bodies, self.horizon, i, p))
            .unwrap_or_default()
    }
}
