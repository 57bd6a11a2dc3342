//! Time stepping of the FEM reference: the same velocity Verlet, anchors, colliders,
//! gravity, air damping and blow-up check as the peridynamic [`crate::step::Simulation`],
//! on the mesh vertices.

use std::time::Instant;

use rayon::prelude::*;

use super::{FemModel, dot3};
use crate::cache::ply::ParticleFrame;
use crate::contact::{self, Anchor, Collider};
use crate::error::{Result, SimError};

/// A FEM simulation: model, colliders, anchors (holding vertices) and the clock.
#[derive(Debug, Clone)]
pub struct FemSimulation {
    /// The FEM model.
    pub model: FemModel,
    /// Rigid colliders.
    pub colliders: Vec<Collider>,
    /// Anchored regions; their `particles` are vertex indices.
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
    /// Whether a vertex is held by an active anchor.
    anchored: Vec<bool>,
    /// Energy scale for blow-up detection (J).
    energy_budget: f64,
    /// Growth factor over the budget that counts as a blow-up.
    energy_growth: f64,
    /// Σ |power| dt of the anchors' forces so far (J).
    pub anchor_work: f64,
    /// Seconds spent computing internal forces.
    pub force_time: f64,
    /// Seconds spent outside the force computation.
    pub other_time: f64,
}

impl FemSimulation {
    /// Assembles a simulation; `dt` must already be chosen. Computes the first forces.
    pub fn new(
        model: FemModel,
        colliders: Vec<Collider>,
        anchors: Vec<Anchor>,
        gravity: [f64; 3],
        dt: f64,
        duration: f64,
        energy_growth: f64,
    ) -> FemSimulation {
        let n = model.len();
        let mut sim = FemSimulation {
            model,
            colliders,
            anchors,
            gravity,
            dt,
            time: 0.0,
            steps: 0,
            acceleration: vec![[0.0; 3]; n],
            anchored: vec![false; n],
            energy_budget: 0.0,
            energy_growth,
            anchor_work: 0.0,
            force_time: 0.0,
            other_time: 0.0,
        };
        sim.apply_anchors();
        sim.model.internal_forces();
        sim.update_acceleration();
        sim.energy_budget = sim.initial_energy_budget(duration);
        sim
    }

    /// Sets every vertex's velocity from its rest position and recomputes the energy
    /// budget of the blow-up check.
    pub fn set_velocity(&mut self, velocity: impl Fn([f64; 3]) -> [f64; 3] + Sync, duration: f64) {
        let x = &self.model.rest;
        self.model
            .velocity
            .par_iter_mut()
            .zip(x.par_iter())
            .for_each(|(v, x)| *v = velocity(*x));
        self.apply_anchors();
        self.energy_budget = self.initial_energy_budget(duration);
    }

    /// The most energy the scene can hold over `duration` (as for peridynamics):
    /// kinetic and strain energy now, free fall, dynamic colliders' kinetic energy,
    /// and what kinematic colliders and anchors can impart.
    fn initial_energy_budget(&self, duration: f64) -> f64 {
        contact::energy_budget(
            self.model.kinetic_energy() + self.model.strain_energy(),
            &self.model.rest,
            &self.model.mass,
            self.gravity,
            duration,
            &self.colliders,
            &self.anchors,
        )
    }

    fn update_acceleration(&mut self) {
        let m = &self.model;
        let g = self.gravity;
        self.acceleration
            .par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, a)| {
                let f = m.force[i];
                let inv = 1.0 / m.mass[i];
                *a = [f[0] * inv + g[0], f[1] * inv + g[1], f[2] * inv + g[2]];
            });
    }

    fn apply_anchors(&mut self) {
        let m = &mut self.model;
        contact::apply_anchors(
            &self.anchors,
            self.time,
            &m.rest,
            &mut m.position,
            &mut m.velocity,
            &mut self.anchored,
        );
    }

    fn account_anchor_work(&mut self) {
        if self.anchors.is_empty() {
            return;
        }
        let power = contact::anchor_power(
            &self.anchored,
            &self.model.mass,
            &self.acceleration,
            &self.model.velocity,
        );
        self.anchor_work += power * self.dt;
    }

    /// One step of velocity Verlet (kick → drift → anchors → forces → kick → anchors →
    /// air damping → contact). Returns 0: nothing breaks in the FEM.
    pub fn step(&mut self) -> Result<usize> {
        let dt = self.dt;
        let t0 = Instant::now();
        {
            let m = &mut self.model;
            let acc = &self.acceleration;
            m.position
                .par_iter_mut()
                .zip(m.velocity.par_iter_mut())
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
        let t1 = Instant::now();
        self.model.internal_forces();
        let t2 = Instant::now();
        self.update_acceleration();
        self.account_anchor_work();
        {
            let m = &mut self.model;
            let acc = &self.acceleration;
            let bodies = &m.bodies;
            let vertex_body = &m.vertex_body;
            let anchored = &self.anchored;
            m.velocity
                .par_iter_mut()
                .zip(acc.par_iter())
                .enumerate()
                .with_min_len(1024)
                .for_each(|(i, (v, a))| {
                    let rate = bodies[vertex_body[i] as usize].material.air_damping;
                    let keep = if anchored[i] {
                        1.0
                    } else {
                        1.0 - (rate * dt).min(1.0)
                    };
                    for k in 0..3 {
                        v[k] = (v[k] + 0.5 * dt * a[k]) * keep;
                    }
                });
        }
        self.apply_anchors();
        let impulses = contact::resolve(
            &self.colliders,
            &mut self.model.position,
            &mut self.model.velocity,
            &self.model.mass,
            &self.anchored,
        );
        contact::advance(&mut self.colliders, &impulses, self.gravity, dt);
        self.steps += 1;
        if self.steps % 16 == 0 {
            self.check_blowup()?;
        }
        self.force_time += (t2 - t1).as_secs_f64();
        self.other_time += (t1 - t0).as_secs_f64() + t2.elapsed().as_secs_f64();
        Ok(0)
    }

    /// Stops the run on non-finite state or kinetic energy far above what the scene
    /// can supply; names the step, the vertex and the output particle of its first tet.
    pub fn check_blowup(&self) -> Result<()> {
        let m = &self.model;
        let bad = (0..m.len()).into_par_iter().find_first(|&i| {
            !(m.position[i].iter().all(|x| x.is_finite())
                && m.velocity[i].iter().all(|x| x.is_finite()))
        });
        if let Some(i) = bad {
            return Err(self.blowup(
                format!("non-finite position or velocity (mesh vertex {i})"),
                i,
            ));
        }
        let kinetic = m.kinetic_energy();
        let budget = self.energy_budget + self.anchor_work;
        if kinetic > self.energy_growth * budget {
            let speed = |i: usize| dot3(m.velocity[i], m.velocity[i]);
            let fastest = (0..m.len())
                .max_by(|&a, &b| speed(a).total_cmp(&speed(b)))
                .unwrap_or(0);
            return Err(self.blowup(
                format!(
                    "kinetic energy {kinetic:.3e} J exceeds {}× the energy the scene can supply ({budget:.3e} J); \
                     fastest mesh vertex {fastest} moves at {:.3e} m/s",
                    self.energy_growth,
                    speed(fastest).sqrt()
                ),
                fastest,
            ));
        }
        Ok(())
    }

    fn blowup(&self, what: String, vertex: usize) -> SimError {
        SimError::BlowUp {
            step: self.steps,
            time: self.time,
            what,
            particle: self.model.particle_of_vertex(vertex),
            position: self.model.position[vertex],
            last_good_frame: 0,
        }
    }

    /// The frame of the current state: tet barycentres in the peridynamic particle
    /// order, damage and plastic strain 0, one fragment per body.
    pub fn frame(&self, frame: usize) -> ParticleFrame {
        let m = &self.model;
        let f32x3 = |v: &[f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32];
        let body: Vec<u32> = m
            .particle_tet
            .iter()
            .map(|&e| m.tet_body[e as usize])
            .collect();
        let mut label = vec![u32::MAX; m.bodies.len()];
        let mut next = 0u32;
        let fragment = body
            .iter()
            .map(|&b| {
                if label[b as usize] == u32::MAX {
                    label[b as usize] = next;
                    next += 1;
                }
                label[b as usize] as f32
            })
            .collect();
        ParticleFrame {
            frame,
            time: self.time,
            position: m.particle_positions().iter().map(f32x3).collect(),
            velocity: m.particle_velocities().iter().map(f32x3).collect(),
            damage: vec![0.0; body.len()],
            plastic: vec![0.0; body.len()],
            material: body.iter().map(|&b| b as f32).collect(),
            fragment,
            extra: Vec::new(),
        }
    }
}
