//! The material point method: MLS-MPM (Lyu 2021 ch. 3; Hu et al. 2018) behind the
//! [`Model`](crate::model::Model) interface, stepping itself
//! ([`Stepping::Own`](crate::model::Stepping::Own)).
//!
//! One step is `sort → stress → p2g → grid_update → g2p → plasticity` on a sparse grid
//! of spacing Δx (the smallest `resolution` of the scene's bodies): see [`grid`] for
//! the blocks and the deterministic scatter, [`constitutive`] for the energies (fixed
//! corotated, Neo-Hookean, stable Neo-Hookean), [`plasticity`] for the plastic flows
//! (J2 with Johnson–Cook hardening and, when its temperature keys are given, its
//! thermal term with adiabatic heating; snow, Drucker–Prager) and the shock model's
//! Mie–Grüneisen pressure. Transfers are APIC with quadratic B-splines by default, a
//! PIC/FLIP blend on request (`[mpm] transfer`); time stepping is explicit.
//!
//! **Shock model** (Lyu §7.2.2): the Cauchy stress is the deviatoric part of the stable
//! Neo-Hookean one plus −p I, with p of Eq. 7.4 from J_p and the particle's internal
//! energy density e_p, which the stress stage integrates by Eq. 7.3 (Δe = Δt sym(C):σ,
//! with the stress and C of the step's start; e⁰ = 0).
//!
//! **Time step.** The world's step is bounded by the elastic wave: Δt ≤
//! [`ELASTIC_COURANT`] Δx / c_p with c_p = √((λ + 2μ)/ρ) of the stiffest material
//! and by the CFL condition v_max Δt ≤ [`CFL`] Δx at the initial velocities (both in
//! [`Model::stable_time_step`](crate::model::Model::stable_time_step)). The step is not adapted during the run (that would
//! hide an elastic instability from the blow-up detector): a scene whose particles
//! end up faster than its fastest initial one (a long fall) sets a smaller
//! `dt_safety` or `dt`.
//!
//! **Data layout** (for models built on it, such as SPB-MPM's bonds on a subset of the
//! particles): particle state is structure-of-arrays in [`MpmParticles`], indexed by
//! particle and never reordered after seeding; the grid keeps its own sorted order,
//! so a later module can hold families over particle indices and add per-particle
//! terms between the transfers without copying them.

pub mod constitutive;
#[cfg(test)]
mod elastic_check_tests;
pub mod grid;
#[cfg(test)]
mod integral_tests;
pub mod johnson_cook;
#[cfg(test)]
mod patch_tests;
pub mod patches;
pub mod plasticity;
#[cfg(test)]
mod plasticity_tests;
mod seed;
pub mod series;
mod setup;
mod solver;
pub mod spectral;
#[cfg(test)]
mod spectral_tests;
mod stages;
#[cfg(test)]
mod tests;

use std::time::Instant;

use rayon::prelude::*;

use crate::error::{Result, SimError};
use crate::scene::MpmElasticity;
use constitutive::{Elastic, IDENTITY, Mat3};
use grid::{Boundary, D_INVERSE_FACTOR, SparseGrid};
use patches::Patches;
use plasticity::{FlowInput, Plasticity};

pub use seed::{PARTICLES_PER_CELL_AXIS, SEED_JITTER};

/// CFL number: the stable step keeps v_max Δt ≤ `CFL` Δx at the initial velocities.
pub const CFL: f64 = 0.3;
/// Elastic Courant number: Δt ≤ `ELASTIC_COURANT` Δx / c_p. Measured on a block on
/// the ground (fixed corotated, 8 particles a cell): c_p Δt/Δx = 0.9 runs 3000 steps,
/// 1.05 grows, 1.2 blows up within 32 steps; so twice this bound is caught.
pub const ELASTIC_COURANT: f64 = 0.6;

/// Particle state, structure-of-arrays, one entry a particle.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MpmParticles {
    /// Positions x_p (m).
    pub position: Vec<[f64; 3]>,
    /// Velocities v_p (m/s).
    pub velocity: Vec<[f64; 3]>,
    /// Positions at seeding (m).
    pub reference: Vec<[f64; 3]>,
    /// Masses m_p (kg).
    pub mass: Vec<f64>,
    /// Initial volumes V_p⁰ (m³).
    pub volume: Vec<f64>,
    /// Scene body of each particle.
    pub body: Vec<u32>,
    /// Deformation gradients F_p.
    pub deformation: Vec<Mat3>,
    /// APIC affine velocity matrices C_p (1/s).
    pub affine: Vec<Mat3>,
    /// Equivalent plastic strain ε^p (0 for elastic materials; for snow and
    /// Drucker–Prager the accumulated plastic Hencky strain, see
    /// [`plasticity::Plasticity::project`]).
    pub plastic: Vec<f64>,
    /// Internal energy density change e_p − e⁰ (J/m³, Eq. 7.3): one entry a particle
    /// when any material uses the shock model, else empty.
    pub internal_energy: Vec<f64>,
    /// Temperature T_p (K) of the thermal Johnson–Cook term: one entry a particle when
    /// any material has it, else empty. It starts at the material's room temperature
    /// (a particle of another material keeps the lowest room temperature of the
    /// thermal ones) and rises by the adiabatic heating of [`plasticity::Thermal`].
    pub temperature: Vec<f64>,
}

impl MpmParticles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }
}

/// A body's material in the MPM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MpmMaterial {
    /// Density ρ⁰ (kg/m³).
    pub density: f64,
    /// Elastic energy and Lamé parameters.
    pub elastic: Elastic,
    /// The shock model's Mie–Grüneisen pressure (Eq. 7.4), replacing the elastic one.
    pub eos: Option<plasticity::MieGruneisen>,
    /// Plastic flow.
    pub plasticity: Plasticity,
    /// The bulk modulus K = λ + 2μ/3 of the volume term of viscous bonds (the
    /// integral-based MPM's, `patches::integral`), 0 without: it adds to the
    /// P-wave modulus where the bonds have not relaxed.
    pub volume_modulus: f64,
}

impl MpmMaterial {
    /// The fastest signal: the P-wave speed √((λ + 2μ)/ρ), or with a Mie–Grüneisen
    /// pressure √(c₀² + 4μ/(3ρ)) if faster (bulk modulus ρ₀c₀² at rest; a strongly
    /// compressed shock material is stiffer still, which `dt_safety` covers); with
    /// viscous bonds' volume term √((λ + 2μ + K)/ρ).
    pub fn wave_speed(&self) -> f64 {
        let elastic = if self.volume_modulus > 0.0 {
            let e = &self.elastic;
            ((e.lambda + 2.0 * e.mu + self.volume_modulus) / self.density).sqrt()
        } else {
            self.elastic.p_wave_speed(self.density)
        };
        match &self.eos {
            Some(eos) => elastic.max(
                (eos.sound_speed * eos.sound_speed + 4.0 * self.elastic.mu / (3.0 * self.density))
                    .sqrt(),
            ),
            None => elastic,
        }
    }

    /// The Kirchhoff stress τ = P Fᵀ = J σ of a particle with deformation gradient `f`
    /// and internal energy density change `energy` (shock model only).
    pub fn kirchhoff(&self, f: &Mat3, energy: f64) -> Mat3 {
        let tau = self.elastic.kirchhoff(f);
        let Some(eos) = &self.eos else {
            return tau;
        };
        let j = constitutive::determinant(f);
        let mut shock = plasticity::deviatoric(&tau);
        let pressure = j * eos.pressure(j, energy);
        for (a, row) in shock.iter_mut().enumerate() {
            row[a] -= pressure;
        }
        shock
    }

    /// Projects a particle's elastic gradient `f` onto the admissible set
    /// ([`Plasticity::project`]), at its plastic strain `plastic`, temperature
    /// `temperature` (K; read by the thermal Johnson–Cook term only) and APIC affine
    /// velocity `affine` (the strain rate, where read). Returns Δε^p and the adiabatic
    /// heating β σ_y(ε^p + Δε^p, ε̇, T) Δε^p/(ρ c) of [`plasticity::Thermal::heating`]
    /// (0 without the thermal term).
    pub fn flow(&self, f: &mut Mat3, plastic: f64, temperature: f64, affine: &Mat3) -> (f64, f64) {
        let mut input = FlowInput {
            mu: self.elastic.mu,
            lambda: self.elastic.lambda,
            rate: 0.0,
            plastic_strain: plastic,
            temperature,
        };
        let increment = if self.plasticity.reads_rate() {
            // The rate only where the particle may yield.
            if self.plasticity.surely_elastic(f, &input) {
                return (0.0, 0.0);
            }
            input.rate = plasticity::equivalent_strain_rate(affine);
            self.plasticity.project_yielding(f, &input)
        } else {
            self.plasticity.project(f, &input)
        };
        let heating = match &self.plasticity {
            Plasticity::JohnsonCook(hardening) if increment > 0.0 => {
                hardening.thermal.as_ref().map_or(0.0, |thermal| {
                    let stress = hardening
                        .at_temperature(temperature)
                        .yield_stress(plastic + increment, input.rate);
                    thermal.heating(stress, increment, self.density)
                })
            }
            _ => 0.0,
        };
        (increment, heating)
    }
}

impl MpmMaterial {
    /// The constitutive model's id in the particle cache's `constitutive` column:
    /// elasticity (0 fixed corotated, 1 Neo-Hookean, 2 stable Neo-Hookean, 3 shock)
    /// plus 10 × plasticity (0 none, 1 J2/Johnson–Cook, 2 snow, 3 Drucker–Prager).
    pub fn id(&self) -> u32 {
        let elastic = match (self.elastic.energy, self.eos.is_some()) {
            (_, true) | (MpmElasticity::Shock, _) => 3,
            (MpmElasticity::FixedCorotated, _) => 0,
            (MpmElasticity::NeoHookean, _) => 1,
            (MpmElasticity::StableNeoHookean, _) => 2,
        };
        let plastic = match self.plasticity {
            Plasticity::None => 0,
            Plasticity::JohnsonCook(_) => 1,
            Plasticity::Snow { .. } => 2,
            Plasticity::DruckerPrager { .. } => 3,
        };
        elastic + 10 * plastic
    }
}

/// How velocities move between particles and grid (`[mpm] transfer`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transfer {
    /// APIC (Jiang et al. 2015): C_p carries the affine velocity.
    Apic,
    /// PIC/FLIP: v_p ← α (v_p + Σ_i w_ip (v_i − v̄_i)) + (1 − α) Σ_i w_ip v_i with v̄_i
    /// the grid velocity before forces; C_p is kept only as the velocity gradient that
    /// grows F.
    PicFlip {
        /// FLIP's share α.
        flip_ratio: f64,
    },
}

/// Wall time of the stages (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct StageTimes {
    sort: f64,
    stress: f64,
    p2g: f64,
    grid: f64,
    g2p: f64,
    plasticity: f64,
}

/// The MLS-MPM model of a scene's bodies on one sparse grid.
#[derive(Debug)]
pub struct Mpm {
    /// The particles.
    pub particles: MpmParticles,
    /// Each body's material.
    pub materials: Vec<MpmMaterial>,
    /// The grid.
    pub grid: SparseGrid,
    /// The velocity transfer.
    pub transfer: Transfer,
    /// SPB-MPM's peridynamic particles, when a material fractures.
    pub patches: Option<Patches>,
    /// Scratch: each particle's affine momentum A_p of [`SparseGrid::p2g`].
    momentum_affine: Vec<Mat3>,
    /// Scratch: the anchored particles of this step and their anchors' velocities.
    held: Vec<(u32, [f64; 3])>,
    /// Scratch: whether each particle is anchored this step (empty when no anchor
    /// is active), for the bond forces ([`Patches::apply`]).
    anchored: Vec<bool>,
    /// Scratch: each particle's mass and velocity in the anchors' P2G (0 and stale
    /// for the particles not held), kept between steps.
    held_p2g: (Vec<f64>, Vec<[f64; 3]>),
    /// Scratch: each particle's eigenerosion history as the stress stage raised it
    /// (empty unless a body erodes).
    raised: Vec<f64>,
    times: StageTimes,
}

impl Mpm {
    /// The model of `particles` (for example seeded by [`Mpm::from_scene`]) on a grid
    /// of spacing `dx`.
    pub fn new(particles: MpmParticles, materials: Vec<MpmMaterial>, dx: f64) -> Mpm {
        let n = particles.len();
        Mpm {
            particles,
            materials,
            grid: SparseGrid::new(dx),
            transfer: Transfer::Apic,
            patches: None,
            momentum_affine: vec![[[0.0; 3]; 3]; n],
            held: Vec::new(),
            anchored: Vec::new(),
            held_p2g: (Vec::new(), Vec::new()),
            raised: Vec::new(),
            times: StageTimes::default(),
        }
    }

    /// The largest speed of any particle (m/s).
    pub fn max_speed(&self) -> f64 {
        self.particles
            .velocity
            .par_iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .reduce(|| 0.0, f64::max)
    }

    /// Sets each anchored particle's velocity target for the step ending at `time`
    /// (the anchor's motion at its seeding position); the step then moves the nodes
    /// the anchored particles hold with them (anchors act on the grid).
    pub fn hold(&mut self, anchors: &[crate::contact::Anchor], time: f64) {
        self.held.clear();
        for anchor in anchors.iter().filter(|a| time <= a.until) {
            for &p in &anchor.particles {
                let p = p as usize;
                let (_, v) = anchor.motion(self.particles.reference[p], time);
                self.held.push((p as u32, v));
            }
        }
        self.anchored.clear();
        if !self.held.is_empty() {
            self.anchored.resize(self.particles.len(), false);
            for &(p, _) in &self.held {
                self.anchored[p as usize] = true;
            }
        }
    }

    /// One explicit MLS-MPM step of length `dt`: `sort → stress → p2g → grid_update →
    /// g2p → plasticity`; with SPB-MPM's patches, their bonds (states, failure, forces)
    /// come first, eigenerosion after the stress, and the bond forces go onto the
    /// velocities before P2G ([`patches`]).
    ///
    /// Returns how many (directed) bonds broke.
    ///
    /// # Errors
    /// [`SimError::Refused`] if the patches' neighbour search cannot be built.
    pub fn step(&mut self, dt: f64, boundary: &Boundary<'_>) -> Result<usize> {
        let broken = match &mut self.patches {
            Some(patches) => patches.prepare(&mut self.particles, &self.materials, dt),
            None => 0,
        };
        let t0 = Instant::now();
        self.grid.rebuild(&self.particles.position);
        if self.held.is_empty() {
            self.grid.release_held();
        } else {
            // A P2G of the anchored particles alone, at their anchors' velocities.
            let p = &self.particles;
            let (mass, velocity) = &mut self.held_p2g;
            mass.resize(p.len(), 0.0);
            velocity.resize(p.len(), [0.0; 3]);
            for &(i, v) in &self.held {
                mass[i as usize] = p.mass[i as usize];
                velocity[i as usize] = v;
            }
            self.grid.p2g_momentum(&p.position, mass, velocity);
            self.grid.keep_held();
            self.held.iter().for_each(|&(i, _)| mass[i as usize] = 0.0);
        }
        let t1 = Instant::now();
        self.stress(dt);
        let t2 = Instant::now();
        if let Some(patches) = self.patches.as_mut().filter(|p| p.erodes()) {
            // Timed by the patches ("spb erosion"), not as a stage of the MPM's own.
            patches.erode(&self.particles, &mut self.grid, &mut self.raised)?;
        }
        let eroded = Instant::now();
        let p = &self.particles;
        let flip = match self.transfer {
            Transfer::Apic => None,
            Transfer::PicFlip { flip_ratio } => {
                // The grid velocity before forces, v̄_i, from a P2G of momentum alone.
                self.grid.p2g_momentum(&p.position, &p.mass, &p.velocity);
                self.grid.keep_velocity();
                Some(flip_ratio)
            }
        };
        if let Some(patches) = &self.patches {
            // The bond forces reach the grid as particle forces do: Δt f_p / m_p on
            // v_p before the transfer (not on anchored particles: their anchors'
            // reactions).
            patches.apply(dt, &self.anchored, &mut self.particles);
        }
        let p = &self.particles;
        self.grid
            .p2g(&p.position, &p.mass, &p.velocity, &self.momentum_affine);
        let t3 = Instant::now();
        self.grid.grid_update(dt, boundary);
        let t4 = Instant::now();
        let p = &mut self.particles;
        self.grid.g2p(
            dt,
            flip,
            &mut p.position,
            &mut p.velocity,
            &mut p.affine,
            &mut p.deformation,
        );
        let t5 = Instant::now();
        self.plasticity();
        let t6 = Instant::now();
        self.times.sort += (t1 - t0).as_secs_f64();
        self.times.stress += (t2 - t1).as_secs_f64();
        self.times.p2g += (t3 - eroded).as_secs_f64();
        self.times.grid += (t4 - t3).as_secs_f64();
        self.times.g2p += (t5 - t4).as_secs_f64();
        self.times.plasticity += (t6 - t5).as_secs_f64();
        Ok(broken)
    }

    /// Total linear momentum Σ m_p v_p (kg m/s), summed in particle order.
    pub fn momentum(&self) -> [f64; 3] {
        let p = &self.particles;
        let mut total = [0.0; 3];
        for (m, v) in p.mass.iter().zip(&p.velocity) {
            for a in 0..3 {
                total[a] += m * v[a];
            }
        }
        total
    }

    /// Total angular momentum about the origin including APIC's affine part (Jiang et
    /// al. 2015): Σ m_p (x_p × v_p + (Δx²/4) ε : C_pᵀ).
    pub fn angular_momentum(&self) -> [f64; 3] {
        let p = &self.particles;
        let d = self.grid.dx * self.grid.dx / D_INVERSE_FACTOR;
        let mut total = [0.0; 3];
        for i in 0..p.len() {
            let (x, v, c, m) = (p.position[i], p.velocity[i], p.affine[i], p.mass[i]);
            let l = [
                x[1] * v[2] - x[2] * v[1] + d * (c[2][1] - c[1][2]),
                x[2] * v[0] - x[0] * v[2] + d * (c[0][2] - c[2][0]),
                x[0] * v[1] - x[1] * v[0] + d * (c[1][0] - c[0][1]),
            ];
            for a in 0..3 {
                total[a] += m * l[a];
            }
        }
        total
    }
}

/// A particle set at rest with F = I and C = 0.
fn at_rest(
    position: Vec<[f64; 3]>,
    volume: Vec<f64>,
    mass: Vec<f64>,
    body: Vec<u32>,
) -> MpmParticles {
    let n = position.len();
    MpmParticles {
        reference: position.clone(),
        position,
        velocity: vec![[0.0; 3]; n],
        mass,
        volume,
        body,
        deformation: vec![IDENTITY; n],
        affine: vec![[[0.0; 3]; 3]; n],
        plastic: vec![0.0; n],
        internal_energy: Vec::new(),
        temperature: Vec::new(),
    }
}

/// The error of a body without particles.
fn empty_body(name: &str) -> SimError {
    SimError::Mesh {
        body: name.to_string(),
        message: "no MPM particle lies inside the shape: use a finer resolution".into(),
    }
}
