//! The material point method: MLS-MPM (Lyu 2021 ch. 3; Hu et al. 2018) behind the
//! [`Model`] interface, stepping itself ([`Stepping::Own`]).
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
//! [`Model::stable_time_step`]). The step is not adapted during the run (that would
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
pub mod grid;
pub mod johnson_cook;
#[cfg(test)]
mod patch_tests;
pub mod patches;
pub mod plasticity;
mod seed;
pub mod spectral;
#[cfg(test)]
mod spectral_tests;
#[cfg(test)]
mod tests;

use std::time::Instant;

use rayon::prelude::*;

use crate::cache::checkpoint::{Decoder, Encoder};
use crate::cache::ply::VOLUME;
use crate::error::{Result, SimError};
use crate::model::{Environment, Model, ParticleColumns, Points, PointsMut, Stepping};
use crate::scene::Scene;
use crate::scene::{MpmElasticity, MpmPlasticity, MpmTransfer};
use constitutive::{Elastic, IDENTITY, Mat3};
use grid::{Boundary, D_INVERSE_FACTOR, SparseGrid};
use patches::{Fracture, Measure, PatchBody, Patches};
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
}

impl MpmMaterial {
    /// The fastest signal: the P-wave speed √((λ + 2μ)/ρ), or with a Mie–Grüneisen
    /// pressure √(c₀² + 4μ/(3ρ)) if faster (bulk modulus ρ₀c₀² at rest; a strongly
    /// compressed shock material is stiffer still, which `dt_safety` covers).
    pub fn wave_speed(&self) -> f64 {
        let elastic = self.elastic.p_wave_speed(self.density);
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
            times: StageTimes::default(),
        }
    }

    /// The model of a scene whose bodies all use `model = "mpm"`: particles seeded
    /// from each body's shape with the scene's seed, each body's angular velocity in
    /// C (the velocities are the caller's).
    pub fn from_scene(scene: &Scene) -> Result<Mpm> {
        let mut particles = seed::seed(scene)?;
        let materials: Vec<MpmMaterial> = scene
            .bodies
            .iter()
            .map(|b| {
                let spec = &scene.materials[&b.material];
                let m = crate::material::Material::from_spec(spec);
                let mpm = spec.mpm.clone().unwrap_or_default();
                MpmMaterial {
                    density: spec.density,
                    elastic: Elastic::from_young(
                        mpm.elasticity,
                        m.youngs_modulus(),
                        m.poisson_ratio(),
                    ),
                    eos: mpm.bulk_sound_speed.map(|c| plasticity::MieGruneisen {
                        density: spec.density,
                        sound_speed: c,
                        slope: mpm.shock_slope,
                        gamma: mpm.gruneisen,
                    }),
                    plasticity: match mpm.plasticity {
                        MpmPlasticity::None => Plasticity::None,
                        MpmPlasticity::JohnsonCook {
                            yield_stress,
                            hardening,
                            exponent,
                            rate_coefficient,
                            reference_rate,
                            melting_temperature,
                            room_temperature,
                            thermal_exponent,
                            specific_heat,
                            taylor_quinney,
                        } => Plasticity::JohnsonCook(plasticity::JohnsonCook {
                            a: yield_stress,
                            b: hardening,
                            n: exponent,
                            c: rate_coefficient,
                            reference_rate,
                            // The scene's checks make the four keys all or none.
                            thermal: match (
                                melting_temperature,
                                room_temperature,
                                thermal_exponent,
                                specific_heat,
                            ) {
                                (Some(melt), Some(room), Some(m), Some(c)) => {
                                    Some(plasticity::Thermal {
                                        melting_temperature: melt,
                                        room_temperature: room,
                                        exponent: m,
                                        specific_heat: c,
                                        taylor_quinney: taylor_quinney
                                            .unwrap_or(plasticity::TAYLOR_QUINNEY),
                                    })
                                }
                                _ => None,
                            },
                        }),
                        MpmPlasticity::Snow {
                            critical_compression,
                            critical_stretch,
                        } => Plasticity::Snow {
                            critical_compression,
                            critical_stretch,
                        },
                        MpmPlasticity::DruckerPrager { friction_angle } => {
                            Plasticity::drucker_prager(friction_angle)
                        }
                    },
                }
            })
            .collect();
        if materials.iter().any(|m| m.eos.is_some()) {
            particles.internal_energy = vec![0.0; particles.len()];
        }
        let room = |m: &MpmMaterial| match m.plasticity {
            Plasticity::JohnsonCook(plasticity::JohnsonCook {
                thermal: Some(t), ..
            }) => Some(t.room_temperature),
            _ => None,
        };
        if let Some(lowest) = materials.iter().filter_map(room).reduce(f64::min) {
            particles.temperature = particles
                .body
                .iter()
                .map(|&b| room(&materials[b as usize]).unwrap_or(lowest))
                .collect();
        }
        let dx = scene
            .bodies
            .iter()
            .map(|b| b.resolution)
            .fold(f64::INFINITY, f64::min);
        let mut model = Mpm::new(particles, materials, dx);
        let shapes = crate::geometry::shape::bond_shapes(scene)?;
        let bodies = scene
            .bodies
            .iter()
            .zip(shapes)
            .zip(&model.materials)
            .map(|((b, shape), material)| {
                let spec = scene.materials[&b.material].mpm.clone().unwrap_or_default();
                PatchBody {
                    fracture: spec.energy_release_rate.map(|g| Fracture {
                        release_rate: g,
                        erosion_rate: spec.erosion_release_rate.unwrap_or(g),
                        young: material.elastic.young(),
                    }),
                    shape,
                    resolution: b.resolution,
                }
            })
            .collect();
        model.patches = Patches::new(bodies, model.particles.len(), dx);
        let settings = scene.mpm.unwrap_or_default();
        model.transfer = match settings.transfer {
            MpmTransfer::Apic => Transfer::Apic,
            MpmTransfer::PicFlip => Transfer::PicFlip {
                flip_ratio: settings.flip_ratio,
            },
        };
        for (p, c) in model.particles.affine.iter_mut().enumerate() {
            let w = scene.bodies[model.particles.body[p] as usize].angular_velocity;
            *c = [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]];
        }
        Ok(model)
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
            Some(patches) => patches.prepare(&self.particles, &self.materials),
            None => 0,
        };
        let t0 = Instant::now();
        self.grid.rebuild(&self.particles.position);
        if self.held.is_empty() {
            self.grid.release_held();
        } else {
            // A P2G of the anchored particles alone, at their anchors' velocities.
            let p = &self.particles;
            let mut mass = vec![0.0; p.len()];
            let mut velocity = vec![[0.0; 3]; p.len()];
            for &(i, v) in &self.held {
                mass[i as usize] = p.mass[i as usize];
                velocity[i as usize] = v;
            }
            let zero = vec![[[0.0; 3]; 3]; p.len()];
            self.grid.p2g(&p.position, &mass, &velocity, &zero);
            self.grid.keep_held();
        }
        let t1 = Instant::now();
        self.stress(dt);
        let t2 = Instant::now();
        if let Some(patches) = &mut self.patches {
            // Timed by the patches ("spb erosion"), not as a stage of the MPM's own.
            patches.erode(&self.particles, &self.materials, &mut self.grid)?;
        }
        let eroded = Instant::now();
        let p = &self.particles;
        let flip = match self.transfer {
            Transfer::Apic => None,
            Transfer::PicFlip { flip_ratio } => {
                // The grid velocity before forces, v̄_i, from a P2G of momentum alone.
                let zero = vec![[[0.0; 3]; 3]; p.len()];
                self.grid.p2g(&p.position, &p.mass, &p.velocity, &zero);
                self.grid.keep_velocity();
                Some(flip_ratio)
            }
        };
        if let Some(patches) = &self.patches {
            // The bond forces reach the grid as particle forces do: Δt f_p / m_p on
            // v_p before the transfer.
            patches.apply(dt, &mut self.particles);
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

    /// Each particle's affine momentum A_p = m_p C_p − Δt V_p⁰ D⁻¹ τ_p (MLS-MPM, Hu et
    /// al. 2018 Eq. 16–17; τ = P Fᵀ), without m_p C_p under PIC/FLIP; the shock
    /// model's internal energy advances by Eq. 7.3 with the same stress.
    fn stress(&mut self, dt: f64) {
        let p = &mut self.particles;
        let d_inv = D_INVERSE_FACTOR / (self.grid.dx * self.grid.dx);
        let materials = &self.materials;
        let affine_share = match self.transfer {
            Transfer::Apic => 1.0,
            Transfer::PicFlip { .. } => 0.0,
        };
        let (deformation, volume, mass, affine, body) =
            (&p.deformation, &p.volume, &p.mass, &p.affine, &p.body);
        let patches = self.patches.as_ref();
        let kernel = |i: usize, a: &mut Mat3, e: Option<&mut f64>| {
            let material = &materials[body[i] as usize];
            // A peridynamic particle's forces come from its bonds, not the grid; its
            // stress (for the shock model's Eq. 7.3) is σ(F^PD).
            let (f, member) = match patches.and_then(|patches| patches.measure(i)) {
                Some(Measure::Bonds(f)) => (Some(f), true),
                Some(Measure::Free) => (None, true),
                Some(Measure::Material) => (Some(deformation[i]), true),
                None => (Some(deformation[i]), false),
            };
            let energy = e.as_deref().copied().unwrap_or(0.0);
            // A member's stress is needed only for its internal energy.
            let wanted = !member || e.is_some();
            let stress = f
                .filter(|_| wanted)
                .map(|f| (material.kirchhoff(&f, energy), f));
            if let (Some(e), Some((tau, f))) = (e, &stress) {
                let j = constitutive::determinant(f);
                let sigma = tau.map(|row| row.map(|x| x / j));
                *e += plasticity::internal_energy_increment(dt, &affine[i], &sigma);
            }
            let tau = match stress {
                Some((tau, _)) if !member => tau,
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
        if p.internal_energy.is_empty() {
            self.momentum_affine
                .par_iter_mut()
                .enumerate()
                .with_min_len(256)
                .for_each(|(i, a)| kernel(i, a, None));
        } else {
            self.momentum_affine
                .par_iter_mut()
                .zip(p.internal_energy.par_iter_mut())
                .enumerate()
                .with_min_len(256)
                .for_each(|(i, (a, e))| kernel(i, a, Some(e)));
        }
    }

    /// Projects each plastic particle's grown deformation gradient onto its material's
    /// admissible set and accumulates ε^p ([`Plasticity::project`]); a thermal
    /// Johnson–Cook particle, returned at its temperature T of the step's start, is
    /// heated by β σ_y(ε^p + Δε^p, ε̇, T) Δε^p/(ρ c) ([`plasticity::Thermal::heating`]).
    fn plasticity(&mut self) {
        if self
            .materials
            .iter()
            .all(|m| m.plasticity == Plasticity::None)
        {
            return;
        }
        let p = &mut self.particles;
        let materials = &self.materials;
        let (body, affine) = (&p.body, &p.affine);
        let kernel = |i: usize, f: &mut Mat3, plastic: &mut f64, temperature: Option<&mut f64>| {
            let material = &materials[body[i] as usize];
            if material.plasticity == Plasticity::None {
                return;
            }
            let mut input = FlowInput {
                mu: material.elastic.mu,
                lambda: material.elastic.lambda,
                rate: 0.0,
                plastic_strain: *plastic,
                temperature: temperature.as_deref().copied().unwrap_or(0.0),
            };
            if material.plasticity.surely_elastic(f, &input) {
                return;
            }
            if material.plasticity.reads_rate() {
                input.rate = plasticity::equivalent_strain_rate(&affine[i]);
            }
            let increment = material.plasticity.project_yielding(f, &input);
            *plastic += increment;
            if let Some(temperature) = temperature
                && let Plasticity::JohnsonCook(hardening) = &material.plasticity
                && let Some(thermal) = &hardening.thermal
                && increment > 0.0
            {
                let stress = hardening
                    .at_temperature(input.temperature)
                    .yield_stress(*plastic, input.rate);
                *temperature += thermal.heating(stress, increment, material.density);
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

fn flatten(m: &[Mat3]) -> Vec<f64> {
    m.iter().flat_map(|r| r.iter().flatten().copied()).collect()
}

fn unflatten(values: &[f64], out: &mut [Mat3]) {
    for (m, chunk) in out.iter_mut().zip(values.chunks_exact(9)) {
        for (r, row) in m.iter_mut().enumerate() {
            row.copy_from_slice(&chunk[3 * r..3 * r + 3]);
        }
    }
}

impl Model for Mpm {
    fn name(&self) -> &'static str {
        "mpm"
    }

    fn points(&self) -> Points<'_> {
        Points {
            position: &self.particles.position,
            velocity: &self.particles.velocity,
            reference: &self.particles.reference,
            mass: &self.particles.mass,
        }
    }

    fn points_mut(&mut self) -> PointsMut<'_> {
        PointsMut {
            position: &mut self.particles.position,
            velocity: &mut self.particles.velocity,
            reference: &self.particles.reference,
            mass: &self.particles.mass,
        }
    }

    fn point_bodies(&self) -> &[u32] {
        &self.particles.body
    }

    fn stepping(&self) -> Stepping {
        Stepping::Own
    }

    /// Forces live on the grid: nothing to compute at the world's request.
    fn internal_forces(&mut self) -> usize {
        0
    }

    /// Gravity only: the MPM's accelerations come from its grid inside
    /// [`Model::advance`].
    fn accelerations(&self, gravity: [f64; 3], out: &mut [[f64; 3]]) {
        out.iter_mut().for_each(|a| *a = gravity);
    }

    fn damp(&mut self, _dt: f64, _anchored: &[bool]) {}

    fn advance(&mut self, dt: f64, environment: &Environment<'_>) -> Result<usize> {
        let boundary = Boundary {
            gravity: environment.gravity,
            colliders: environment.colliders,
        };
        self.hold(environment.anchors, environment.time);
        self.step(dt, &boundary)
    }

    /// min(ELASTIC_COURANT Δx / c_p, CFL Δx / v_max); the limiting particle is the
    /// fastest one when the CFL bound is the smaller, else the first particle of the
    /// stiffest body.
    fn stable_time_step(&self) -> (f64, usize) {
        let p = &self.particles;
        let dx = self.grid.dx;
        let (elastic, stiffest) = (0..p.len())
            .map(|i| {
                let m = &self.materials[p.body[i] as usize];
                (ELASTIC_COURANT * dx / m.wave_speed(), i)
            })
            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
        let (speed, fastest) = (0..p.len())
            .map(|i| {
                let v = p.velocity[i];
                ((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt(), i)
            })
            .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
        let cfl = CFL * dx / speed;
        if cfl < elastic {
            (cfl, fastest)
        } else {
            (elastic, stiffest)
        }
    }

    fn kinetic_energy(&self) -> f64 {
        let p = &self.particles;
        p.mass
            .iter()
            .zip(&p.velocity)
            .map(|(m, v)| 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
            .sum()
    }

    /// Σ_p V_p⁰ ψ(F_p) of the elastic part; a shock material counts its stable
    /// Neo-Hookean energy plus the work it took in, J_p V_p⁰ (e_p − e⁰).
    fn strain_energy(&self) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .map(|i| {
                let material = &self.materials[p.body[i] as usize];
                let f = &p.deformation[i];
                let taken = match material.eos {
                    Some(_) => constitutive::determinant(f) * p.internal_energy[i],
                    None => 0.0,
                };
                p.volume[i] * (material.elastic.energy_density(f) + taken)
            })
            .sum()
    }

    fn particles(&self) -> ParticleColumns {
        let p = &self.particles;
        let f32x3 = |v: &[f64; 3]| v.map(|x| x as f32);
        // The search behind the fragments was built when the first particle joined.
        let fragment = self
            .patches
            .as_ref()
            .and_then(|patches| patches.fragments(p).ok())
            .unwrap_or_else(|| p.body.clone());
        ParticleColumns {
            position: p.position.iter().map(f32x3).collect(),
            velocity: p.velocity.iter().map(f32x3).collect(),
            damage: self
                .patches
                .as_ref()
                .map_or_else(|| vec![0.0; p.len()], Patches::damage),
            plastic: p.plastic.iter().map(|&e| e as f32).collect(),
            body: p.body.clone(),
            fragment,
            extra: vec![
                // The current volume V_p = J_p V_p⁰.
                (
                    VOLUME.to_string(),
                    (0..p.len())
                        .map(|i| {
                            (constitutive::determinant(&p.deformation[i]) * p.volume[i]) as f32
                        })
                        .collect(),
                ),
                (
                    "J".to_string(),
                    p.deformation
                        .iter()
                        .map(|f| constitutive::determinant(f) as f32)
                        .collect(),
                ),
                (
                    "constitutive".to_string(),
                    p.body
                        .iter()
                        .map(|&b| self.materials[b as usize].id() as f32)
                        .collect(),
                ),
            ]
            .into_iter()
            .chain((!p.temperature.is_empty()).then(|| {
                (
                    "temperature".to_string(),
                    p.temperature.iter().map(|&t| t as f32).collect(),
                )
            }))
            .chain(self.patches.as_ref().map(|patches| {
                // SPB-MPM's region: 0 a material point, 1 a peridynamic particle.
                (
                    "region".to_string(),
                    (0..p.len())
                        .map(|i| f32::from(u8::from(patches.is_member(i))))
                        .collect(),
                )
            }))
            .collect(),
        }
    }

    fn save(&self, out: &mut Encoder) {
        let p = &self.particles;
        out.put_f64x3_slice(&p.position);
        out.put_f64x3_slice(&p.velocity);
        out.put_f64_slice(&flatten(&p.deformation));
        out.put_f64_slice(&flatten(&p.affine));
        out.put_f64_slice(&p.plastic);
        out.put_f64_slice(&p.internal_energy);
        out.put_f64_slice(&p.temperature);
        if let Some(patches) = &self.patches {
            patches.save(out);
        }
    }

    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let p = &mut self.particles;
        let n = p.len();
        p.position = input.take_finite_f64x3_slice("MPM positions", n)?;
        p.velocity = input.take_finite_f64x3_slice("MPM velocities", n)?;
        let f = input.take_finite_f64_slice("MPM deformation gradients", 9 * n)?;
        unflatten(&f, &mut p.deformation);
        let c = input.take_finite_f64_slice("MPM affine matrices", 9 * n)?;
        unflatten(&c, &mut p.affine);
        p.plastic = input.take_finite_f64_slice("MPM plastic strains", n)?;
        if let Some(i) = p.plastic.iter().position(|&e| e < 0.0) {
            let message = format!("particle {i} has a negative plastic strain");
            return Err(input.error("MPM plastic strains", message).into());
        }
        let energies = p.internal_energy.len();
        p.internal_energy = input.take_finite_f64_slice("MPM internal energies", energies)?;
        let temperatures = p.temperature.len();
        p.temperature = input.take_finite_f64_slice("MPM temperatures", temperatures)?;
        if let Some(i) = p.temperature.iter().position(|&t| t <= 0.0) {
            let message = format!("particle {i} has a temperature at or below 0 K");
            return Err(input.error("MPM temperatures", message).into());
        }
        if let Some(patches) = &mut self.patches {
            patches.restore(input, &self.particles)?;
        }
        Ok(())
    }

    /// SPB-MPM's bonds (both directions), built as particles turn peridynamic.
    fn bonds(&self) -> usize {
        self.patches.as_ref().map_or(0, Patches::bonds)
    }

    fn broken_bonds(&self) -> u64 {
        self.patches
            .as_ref()
            .map_or(0, |patches| patches.broken_bonds() as u64)
    }

    fn stage_times(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("mpm sort", self.times.sort),
            ("stress", self.times.stress),
            ("p2g", self.times.p2g),
            ("grid", self.times.grid),
            ("g2p", self.times.g2p),
            ("plasticity", self.times.plasticity),
        ]
        .into_iter()
        .chain(self.patches.iter().flat_map(|patches| {
            [
                ("spb erosion", patches.times.erode),
                ("spb bonds", patches.times.evolve),
            ]
        }))
        .collect()
    }

    fn reset_stage_times(&mut self) {
        self.times = StageTimes::default();
        if let Some(patches) = &mut self.patches {
            patches.times = patches::PatchTimes::default();
        }
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
