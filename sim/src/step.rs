//! Time stepping: velocity Verlet with contact, anchors and damping; the stable time
//! step; blow-up detection.
//!
//! One step is the list of stages `kick → drift → anchors → dilatation (+ plasticity) →
//! forces (+ fracture) → kick → damping → contact`, each timed.

use std::time::Instant;

use rayon::prelude::*;

use crate::contact::{self, Anchor, Collider};
use crate::error::{Result, SimError};
use crate::family::{BROKEN, INDEX};
use crate::pd::{PdModel, StageTimes, family_volume};

/// The simulation: model, colliders, anchors and the clock.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The peridynamic model.
    pub model: PdModel,
    /// Rigid colliders.
    pub colliders: Vec<Collider>,
    /// Anchored regions.
    pub anchors: Vec<Anchor>,
    /// Gravity (m/s²).
    pub gravity: [f64; 3],
    /// Time step (s).
    pub dt: f64,
    /// Current time (s).
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Acceleration at the current positions (Verlet).
    acceleration: Vec<[f64; 3]>,
    /// Particle masses (kg).
    mass: Vec<f64>,
    /// Whether a particle is held by an active anchor.
    anchored: Vec<bool>,
    /// Energy scale for blow-up detection (J).
    energy_budget: f64,
    /// Growth factor over the budget that counts as a blow-up.
    energy_growth: f64,
    /// Σ |power| dt of the anchors' forces so far (J): work they may have put in.
    pub anchor_work: f64,
    /// Seconds spent outside the model's stages (integration, contact, damping).
    pub other_time: f64,
}

/// Σ over the times of the stages, for reports.
pub fn total_time(t: &StageTimes) -> f64 {
    t.dilatation + t.forces
}

impl Simulation {
    /// Assembles a simulation; `dt` must already be chosen. Computes the first forces.
    pub fn new(
        model: PdModel,
        colliders: Vec<Collider>,
        anchors: Vec<Anchor>,
        gravity: [f64; 3],
        dt: f64,
        duration: f64,
        energy_growth: f64,
    ) -> Simulation {
        let n = model.len();
        let mass: Vec<f64> = (0..n).map(|i| model.mass(i)).collect();
        let mut sim = Simulation {
            model,
            colliders,
            anchors,
            gravity,
            dt,
            time: 0.0,
            steps: 0,
            acceleration: vec![[0.0; 3]; n],
            mass,
            anchored: vec![false; n],
            energy_budget: 0.0,
            energy_growth,
            anchor_work: 0.0,
            other_time: 0.0,
        };
        sim.apply_anchors();
        sim.model.internal_forces();
        sim.update_acceleration();
        sim.energy_budget = sim.initial_energy_budget(duration);
        sim
    }

    /// Sets every particle's velocity from its reference position (initial conditions
    /// given in code) and recomputes the energy budget of the blow-up check.
    pub fn set_velocity(&mut self, velocity: impl Fn([f64; 3]) -> [f64; 3] + Sync, duration: f64) {
        let x = &self.model.reference.position;
        self.model
            .particles
            .velocity
            .par_iter_mut()
            .zip(x.par_iter())
            .for_each(|(v, x)| *v = velocity(*x));
        self.apply_anchors();
        self.energy_budget = self.initial_energy_budget(duration);
    }

    /// The most energy the scene can hold over `duration`: kinetic and strain energy
    /// now, free fall, dynamic colliders' kinetic energy, and what kinematic colliders
    /// and anchors can impart (twice their speed to every particle).
    fn initial_energy_budget(&self, duration: f64) -> f64 {
        contact::energy_budget(
            self.model.kinetic_energy() + self.model.strain_energy(),
            &self.model.reference.position,
            &self.mass,
            self.gravity,
            duration,
            &self.colliders,
            &self.anchors,
        )
    }

    /// Verlet's acceleration at the current positions (saved in checkpoints: after a
    /// step's contact projection it is not the acceleration of the new positions).
    pub fn acceleration(&self) -> &[[f64; 3]] {
        &self.acceleration
    }

    /// Replaces the saved state's acceleration (restoring a checkpoint).
    pub fn restore_acceleration(&mut self, acceleration: Vec<[f64; 3]>) {
        self.acceleration = acceleration;
        self.anchored.iter_mut().for_each(|a| *a = false);
        let t = self.time;
        for anchor in &self.anchors {
            if t <= anchor.until {
                for &p in &anchor.particles {
                    self.anchored[p as usize] = true;
                }
            }
        }
    }

    fn update_acceleration(&mut self) {
        let m = &self.model;
        let g = self.gravity;
        self.acceleration
            .par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, a)| {
                let rho = m.bodies[m.reference.body[i] as usize].material.density;
                let f = m.force[i];
                *a = [f[0] / rho + g[0], f[1] / rho + g[1], f[2] / rho + g[2]];
            });
    }

    /// Adds the anchors' work this step: an anchor cancels the free acceleration of
    /// the particles it holds, so it acts with −m a and its power is −m a·v.
    fn account_anchor_work(&mut self) {
        if self.anchors.is_empty() {
            return;
        }
        let power = contact::anchor_power(
            &self.anchored,
            &self.mass,
            &self.acceleration,
            &self.model.particles.velocity,
        );
        self.anchor_work += power * self.dt;
    }

    fn apply_anchors(&mut self) {
        let p = &mut self.model.particles;
        contact::apply_anchors(
            &self.anchors,
            self.time,
            &self.model.reference.position,
            &mut p.position,
            &mut p.velocity,
            &mut self.anchored,
        );
    }

    /// One step of velocity Verlet; returns the number of bonds broken.
    pub fn step(&mut self) -> Result<usize> {
        let dt = self.dt;
        let t0 = Instant::now();
        {
            let p = &mut self.model.particles;
            let acc = &self.acceleration;
            p.position
                .par_iter_mut()
                .zip(p.velocity.par_iter_mut())
                .zip(acc.par_iter())
                .with_min_len(1024)
                .for_each(|((y, v), a)| {
                    for k in 0..3 {
                        v[k] += 0.5 * dt * a[k];
                        y[k] += dt * v[k];
                    }
                });
        }
        self.time = (self.steps + 1) as f64 * dt;
        self.apply_anchors();
        self.other_time += t0.elapsed().as_secs_f64();
        let broken = self.model.internal_forces();
        let t1 = Instant::now();
        self.update_acceleration();
        self.account_anchor_work();
        {
            let p = &mut self.model.particles;
            let acc = &self.acceleration;
            p.velocity
                .par_iter_mut()
                .zip(acc.par_iter())
                .with_min_len(1024)
                .for_each(|(v, a)| {
                    for k in 0..3 {
                        v[k] += 0.5 * dt * a[k];
                    }
                });
        }
        self.apply_anchors();
        self.damping();
        let impulses = contact::resolve(
            &self.colliders,
            &mut self.model.particles.position,
            &mut self.model.particles.velocity,
            &self.mass,
            &self.anchored,
        );
        contact::advance(&mut self.colliders, &impulses, self.gravity, dt);
        self.steps += 1;
        if self.steps % 16 == 0 {
            self.check_blowup()?;
        }
        self.other_time += t1.elapsed().as_secs_f64();
        Ok(broken)
    }

    /// Air damping v ← (1 − λa) v and Laplacian smoothing v ← v + λl L(v) over
    /// intact bonds, L(v)_i = Σ_j V_j (v_j − v_i) / Σ_j V_j (Chen §6), with the
    /// per-step coefficients λ = rate·Δt.
    fn damping(&mut self) {
        let dt = self.dt;
        let m = &self.model;
        let any_air = m.bodies.iter().any(|b| b.material.air_damping > 0.0);
        let any_laplace = m.bodies.iter().any(|b| b.material.laplacian_damping > 0.0);
        if !any_air && !any_laplace {
            return;
        }
        let old = &m.particles.velocity;
        let bonds = &m.bonds;
        let volume = &m.reference.volume;
        let anchored = &self.anchored;
        let new: Vec<[f64; 3]> = (0..m.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let mat = &m.bodies[m.reference.body[i] as usize].material;
                let mut v = old[i];
                if anchored[i] {
                    return v;
                }
                let lambda_l = (mat.laplacian_damping * dt).min(1.0);
                if lambda_l > 0.0 {
                    let mut sum = [0.0; 3];
                    let mut w = 0.0;
                    for k in bonds.range(i) {
                        let nb = bonds.neighbours[k];
                        if nb & BROKEN != 0 {
                            continue;
                        }
                        let j = (nb & INDEX) as usize;
                        for a in 0..3 {
                            sum[a] += volume[j] * (old[j][a] - old[i][a]);
                        }
                        w += volume[j];
                    }
                    if w > 0.0 {
                        for a in 0..3 {
                            v[a] += lambda_l * sum[a] / w;
                        }
                    }
                }
                let keep = 1.0 - (mat.air_damping * dt).min(1.0);
                [v[0] * keep, v[1] * keep, v[2] * keep]
            })
            .collect();
        self.model.particles.velocity = new;
    }

    /// Stops the run on non-finite state or kinetic energy far above what the scene
    /// can supply.
    pub fn check_blowup(&self) -> Result<()> {
        let p = &self.model.particles;
        let bad = (0..self.model.len()).into_par_iter().find_first(|&i| {
            !(p.position[i].iter().all(|x| x.is_finite())
                && p.velocity[i].iter().all(|x| x.is_finite()))
        });
        if let Some(i) = bad {
            return Err(self.blowup("non-finite position or velocity".into(), i));
        }
        let kinetic = self.model.kinetic_energy();
        let budget = self.energy_budget + self.anchor_work;
        if kinetic > self.energy_growth * budget {
            let fastest = (0..self.model.len())
                .max_by(|&a, &b| norm(p.velocity[a]).total_cmp(&norm(p.velocity[b])))
                .unwrap_or(0);
            return Err(self.blowup(
                format!(
                    "kinetic energy {kinetic:.3e} J exceeds {}× the energy the scene can supply ({:.3e} J); \
                     fastest particle moves at {:.3e} m/s",
                    self.energy_growth,
                    budget,
                    norm(p.velocity[fastest])
                ),
                fastest,
            ));
        }
        Ok(())
    }

    fn blowup(&self, what: String, particle: usize) -> SimError {
        SimError::BlowUp {
            step: self.steps,
            time: self.time,
            what,
            particle,
            position: self.model.particles.position[particle],
            last_good_frame: 0,
        }
    }

    /// Total mass of the particles.
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// Particle masses (kg).
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The stable time step of velocity Verlet for the linearized model, 2/√λ_max with
/// λ_max ≤ max_i R_i/ρ_i by Gershgorin's theorem. R_i bounds the row sum of the
/// stiffness of particle i (force density per unit displacement):
///
/// ```text
/// R_i = 4 Σ_j ω b (p_ij + p_ji) V_j + 4 h_i Σ_j ω |a'| q_ij V_j + 4 Σ_j ω |a'| q_ji V_j h_j
/// h_i = Σ_j 3 ω q_ij V_j / (δ V_H∞)   (the sensitivity of θ_i)
/// ```
///
/// For a bond-based model this reduces to the Silling–Askari bound
/// Δt < √(2ρ / Σ_j V_j c_ij/|ξ_ij|). Returns the time step and the particle that
/// limits it.
pub fn stable_time_step(m: &PdModel) -> (f64, usize) {
    let n = m.len();
    let bonds = &m.bonds;
    let h: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| {
            let delta = m.bodies[m.reference.body[i] as usize].constants.delta;
            let s: f64 = bonds
                .range(i)
                .map(|k| {
                    m.coef.dil[k] as f64
                        * m.reference.volume[(bonds.neighbours[k] & INDEX) as usize]
                })
                .sum();
            3.0 * s / (delta * family_volume(delta))
        })
        .collect();
    let rate: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| {
            let body = &m.bodies[m.reference.body[i] as usize];
            let ap = body.a_prime.abs();
            let (mut dev, mut dil_i, mut dil_j) = (0.0, 0.0, 0.0);
            for k in bonds.range(i) {
                let j = (bonds.neighbours[k] & INDEX) as usize;
                let v = m.reference.volume[j];
                dev += v * (m.coef.dev[k] + m.coef.dev_rev[k]) as f64;
                dil_i += v * ap * m.coef.dil[k] as f64;
                dil_j += v * ap * m.coef.dil_rev[k] as f64 * h[j];
            }
            4.0 * (dev + h[i] * dil_i + dil_j) / body.material.density
        })
        .collect();
    let (worst, lambda) =
        rate.iter().copied().enumerate().fold(
            (0, 0.0f64),
            |(bi, bl), (i, l)| if l > bl { (i, l) } else { (bi, bl) },
        );
    if lambda <= 0.0 {
        return (f64::INFINITY, worst);
    }
    (2.0 / lambda.sqrt(), worst)
}
