//! The one integrator: a world of models on one time line, stepped by velocity Verlet
//! with anchors, rigid colliders, damping and the blow-up detector, written once over
//! [`Model`].
//!
//! One step is the list of stages `kick → drift → anchors → forces → particle contact →
//! kick → anchors → damping → collider contact`, the forces on a clamp's ghosts
//! carried back to their sources after the forces ([`crate::clamp`]), each model's
//! forces timed by the model, particle contact ([`ParticleContact`], when the scene
//! has it) and the rest by the world.
//! Every model shares the world's time step: the smallest of their stable steps.

use std::any::Any;
use std::collections::BTreeMap;
use std::time::Instant;

use perifrac_math::dot;
use rayon::prelude::*;

use crate::contact::{self, Anchor, Collider};
use crate::error::{Result, SimError};
use crate::model::{Environment, Model, ParticleColumns, Stepping};
use crate::particle_contact::ParticleContact;
use crate::rigid::RigidPhase;
use crate::scene::RigidSpec;

mod checkpoint;
mod clock;
mod rigid;
pub use clock::steps_within;
mod part;

pub use clock::Clock;
pub use part::Part;
use part::kick;

/// Settings of a world that do not change during a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldSettings {
    /// Gravity (m/s²).
    pub gravity: [f64; 3],
    /// Time step (s).
    pub dt: f64,
    /// Duration of the run (s), for the blow-up detector's energy budget.
    pub duration: f64,
    /// Growth over the energy budget that counts as a blow-up.
    pub energy_growth: f64,
}

/// Every model of a scene, the colliders and the clock.
#[derive(Debug)]
pub struct World {
    /// The models, in the order their particles go to the cache.
    pub parts: Vec<Part>,
    /// Rigid colliders.
    pub colliders: Vec<Collider>,
    /// Gravity (m/s²).
    pub gravity: [f64; 3],
    /// Time step (s).
    pub dt: f64,
    /// The longest step the scene's models allow (s): the frame loop makes each
    /// frame's step the frame's length over the fewest whole steps within it.
    pub step_bound: f64,
    /// Where the current time step started.
    pub clock: Clock,
    /// Current time (s).
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Σ |power| dt of the anchors' forces so far (J): work they may have put in.
    pub anchor_work: f64,
    /// Seconds spent outside the models' stages (integration, anchors, contact,
    /// damping).
    pub other_time: f64,
    /// Contact between the models' particles, when the scene has it.
    pub contact: Option<ParticleContact>,
    /// When fragments may go rigid (a breaking body and `[rigid] enabled`).
    pub rigid_settings: Option<RigidSpec>,
    /// The rigid phase, from the first hand-off on.
    pub rigid: Option<RigidPhase>,
    /// Before the first hand-off, the fragments settling ([`RigidPhase::take_calm`]):
    /// their `settle_time` runs on across the looks.
    pub settling: BTreeMap<(u32, u32), f64>,
    /// The scene's length (s): a checkpoint's clock lies within it.
    duration: f64,
    /// Energy scale for blow-up detection (J).
    energy_budget: f64,
    /// Growth factor over the budget that counts as a blow-up.
    energy_growth: f64,
}

impl World {
    /// Assembles a world; `settings.dt` must already be chosen. Holds the anchored
    /// points and computes the first forces.
    pub fn new(parts: Vec<Part>, colliders: Vec<Collider>, settings: WorldSettings) -> World {
        let mut world = World {
            parts,
            colliders,
            gravity: settings.gravity,
            dt: settings.dt,
            step_bound: settings.dt,
            clock: Clock::default(),
            time: 0.0,
            steps: 0,
            anchor_work: 0.0,
            other_time: 0.0,
            contact: None,
            rigid_settings: None,
            rigid: None,
            settling: BTreeMap::new(),
            duration: settings.duration,
            energy_budget: 0.0,
            energy_growth: settings.energy_growth,
        };
        let gravity = world.gravity;
        for part in &mut world.parts {
            part.accelerations_at(0.0, gravity);
        }
        world.energy_budget = world.initial_energy_budget(settings.duration);
        world
    }

    /// Sets every point's velocity from its reference position (initial conditions
    /// given in code) and recomputes the energy budget of the blow-up check.
    pub fn set_velocity(&mut self, velocity: impl Fn([f64; 3]) -> [f64; 3] + Sync, duration: f64) {
        let time = self.time;
        for part in &mut self.parts {
            let p = part.model.points_mut();
            p.velocity
                .par_iter_mut()
                .zip(p.reference.par_iter())
                .for_each(|(v, x)| *v = velocity(*x));
            part.apply_anchors(time);
        }
        self.energy_budget = self.initial_energy_budget(duration);
    }

    /// The most energy the scene can hold over `duration` (see
    /// [`contact::energy_budget`]).
    fn initial_energy_budget(&self, duration: f64) -> f64 {
        let initial: f64 = self
            .parts
            .iter()
            .map(|p| p.model.kinetic_energy() + p.model.strain_energy())
            .sum();
        let points: Vec<_> = self.parts.iter().map(|p| p.model.points()).collect();
        let anchors: Vec<&Anchor> = self.parts.iter().flat_map(|p| &p.anchors).collect();
        contact::energy_budget(
            initial,
            &points,
            self.gravity,
            duration,
            &self.colliders,
            &anchors,
        )
    }

    /// One step of every model; returns the number of bonds broken.
    pub fn step(&mut self) -> Result<usize> {
        let dt = self.dt;
        let t0 = Instant::now();
        let time = self.time_after(self.steps + 1);
        if self.rigid_only() {
            return self.rigid_step(time);
        }
        let mut broken = 0;
        let mut model_time = 0.0;
        for part in &mut self.parts {
            if part.model.stepping() == Stepping::Verlet {
                kick(part, dt, true);
            }
        }
        if let Some(rigid) = &mut self.rigid {
            rigid.half_kick(dt, &mut self.parts);
            rigid.step(dt, self.gravity, &mut self.parts, &mut self.colliders);
        }
        for part in &mut self.parts {
            match part.model.stepping() {
                Stepping::Verlet => {
                    part.apply_anchors(time);
                    let t = Instant::now();
                    broken += part.model.internal_forces();
                    model_time += t.elapsed().as_secs_f64();
                    part.accelerations(time, self.gravity);
                }
                Stepping::Own => {
                    let t = Instant::now();
                    let environment = Environment {
                        gravity: self.gravity,
                        colliders: &self.colliders,
                        anchors: &part.anchors,
                        time,
                    };
                    broken += part.model.advance(dt, &environment)?;
                    model_time += t.elapsed().as_secs_f64();
                    part.apply_anchors(time);
                }
            }
        }
        let contact_time = self.particle_contact();
        for part in &mut self.parts {
            if part.model.stepping() == Stepping::Verlet {
                self.anchor_work += part.anchor_power() * dt;
                kick(part, dt, false);
                part.apply_anchors(time);
                part.model.damp(dt, &part.anchored);
            }
        }
        if let Some(rigid) = &mut self.rigid {
            rigid.half_kick(dt, &mut self.parts);
        }
        self.time = time;
        let mut impulses = vec![[0.0; 3]; self.colliders.len()];
        for part in &mut self.parts {
            // Rigid pieces meet the colliders in the rigid solver.
            let held: Option<Vec<bool>> = part.model.frozen().map(|frozen| {
                frozen
                    .iter()
                    .zip(&part.anchored)
                    .map(|(&f, &a)| f || a)
                    .collect()
            });
            let p = part.model.points_mut();
            let j = contact::resolve(
                &self.colliders,
                p.position,
                p.velocity,
                p.mass,
                held.as_deref().unwrap_or(&part.anchored),
            );
            for (total, j) in impulses.iter_mut().zip(j) {
                for a in 0..3 {
                    total[a] += j[a];
                }
            }
        }
        match &mut self.rigid {
            Some(rigid) => {
                // Rapier moves the dynamic colliders: they take the particles'
                // impulses there, and the others move as the scene says.
                for (i, j) in impulses.iter_mut().enumerate() {
                    if rigid.moves_collider(i, &self.colliders) {
                        rigid.push_collider(i, *j);
                        let c = &mut self.colliders[i];
                        let m = c.mass.unwrap_or(1.0);
                        for (v, j) in c.velocity.iter_mut().zip(j.iter()) {
                            *v += j / m;
                        }
                        *j = [0.0; 3];
                    }
                }
                let moved: Vec<bool> = (0..self.colliders.len())
                    .map(|i| rigid.moves_collider(i, &self.colliders))
                    .collect();
                contact::advance_except(
                    &mut self.colliders,
                    &impulses,
                    self.gravity,
                    dt,
                    time,
                    &moved,
                );
            }
            None => contact::advance(&mut self.colliders, &impulses, self.gravity, dt, time),
        }
        if let Some(settings) = &self.rigid_settings
            && (self.steps + 1) % settings.check_every as u64 == 0
        {
            let rigid = self.rigid.get_or_insert_with(|| {
                let calm = std::mem::take(&mut self.settling);
                RigidPhase::new(settings.clone(), &self.colliders, calm)
            });
            let handed = rigid.look(&mut self.parts, time);
            if handed > 0
                && let Some(contact) = &self.contact
            {
                rigid.gather_contact(&self.parts, |p| contact.force(p));
            }
            if rigid.pieces() == 0 {
                // Nothing went rigid yet: the world stays as it was without it, but
                // for the fragments settling.
                self.settling = rigid.take_calm();
                self.rigid = None;
            }
        }
        self.steps += 1;
        if self.steps % 16 == 0 {
            self.check_blowup()?;
        }
        self.reset_at_stop_point();
        self.other_time += t0.elapsed().as_secs_f64() - model_time - contact_time;
        Ok(broken)
    }

    /// Adds the particle-contact forces (if the scene has particle contact) to the
    /// Verlet parts' accelerations, a += F/m, then keeps the pairs that touch at least
    /// their limit apart with pairwise impulses on the half-step velocities
    /// ([`crate::particle_contact::apart`]; anchored points act as infinitely heavy);
    /// returns the seconds it took.
    fn particle_contact(&mut self) -> f64 {
        let Some(contact) = &mut self.contact else {
            return 0.0;
        };
        let t = Instant::now();
        let models: Vec<&dyn Model> = self.parts.iter().map(|p| p.model.as_ref()).collect();
        contact.compute(&models);
        if let Some(rigid) = &mut self.rigid {
            rigid.gather_contact(&self.parts, |p| contact.force(p));
        }
        for (p, part) in self.parts.iter_mut().enumerate() {
            if part.model.stepping() != Stepping::Verlet {
                continue;
            }
            let force = contact.force(p);
            if force.is_empty() {
                continue;
            }
            let mass = part.model.points().mass;
            part.acceleration
                .par_iter_mut()
                .zip(force.par_iter())
                .zip(mass.par_iter())
                .with_min_len(1024)
                .for_each(|((a, f), m)| {
                    for k in 0..3 {
                        a[k] += f[k] / m;
                    }
                });
        }
        let acceleration: Vec<&[[f64; 3]]> = self
            .parts
            .iter()
            .map(|part| part.acceleration.as_slice())
            .collect();
        // Rigid pieces' points take no kick (their body moves them): as anchored ones.
        let rigid_held: Vec<Option<Vec<bool>>> = self
            .parts
            .iter()
            .map(|p| {
                let frozen = p.model.frozen()?;
                Some(
                    frozen
                        .iter()
                        .zip(&p.anchored)
                        .map(|(&f, &a)| f || a)
                        .collect(),
                )
            })
            .collect();
        let held: Vec<&[bool]> = self
            .parts
            .iter()
            .zip(&rigid_held)
            .map(|(p, r)| r.as_deref().unwrap_or(p.anchored.as_slice()))
            .collect();
        let models: Vec<&dyn Model> = self.parts.iter().map(|p| p.model.as_ref()).collect();
        let kicks = contact.separate(&models, self.dt, &acceleration, &held);
        for (p, k, dv) in kicks {
            let v = &mut self.parts[p].model.points_mut().velocity[k];
            for a in 0..3 {
                v[a] += dv[a];
            }
        }
        let elapsed = t.elapsed().as_secs_f64();
        contact.time += elapsed;
        elapsed
    }

    /// Turns particle contact on: its forces at the current state join the
    /// accelerations of the first half kick.
    pub fn set_particle_contact(&mut self, contact: ParticleContact) {
        self.contact = Some(contact);
        self.particle_contact();
    }

    /// The first model of type `T`, for measurements and tests that read a model's own
    /// state (the loop itself never asks).
    pub fn model<T: Model>(&self) -> Option<&T> {
        self.parts
            .iter()
            .find_map(|p| (p.model.as_ref() as &dyn Any).downcast_ref())
    }

    /// The first model of type `T`, writable.
    pub fn model_mut<T: Model>(&mut self) -> Option<&mut T> {
        self.parts
            .iter_mut()
            .find_map(|p| (p.model.as_mut() as &mut dyn Any).downcast_mut())
    }

    /// Kinetic energy of every model (J).
    pub fn kinetic_energy(&self) -> f64 {
        self.parts.iter().map(|p| p.model.kinetic_energy()).sum()
    }

    /// Stops the run on non-finite state or kinetic energy far above what the scene
    /// can supply; names the step, the point and its cache particle.
    pub fn check_blowup(&self) -> Result<()> {
        for part in &self.parts {
            let p = part.model.points();
            let bad = (0..p.position.len()).into_par_iter().find_first(|&i| {
                !(p.position[i].iter().all(|x| x.is_finite())
                    && p.velocity[i].iter().all(|x| x.is_finite()))
            });
            if let Some(i) = bad {
                let what = match part.model.point_kind() {
                    "particle" => "non-finite position or velocity".to_string(),
                    kind => format!("non-finite position or velocity ({kind} {i})"),
                };
                return Err(self.blowup(part, what, i));
            }
        }
        let kinetic = self.kinetic_energy();
        let budget = self.energy_budget + self.anchor_work;
        if kinetic <= self.energy_growth * budget {
            return Ok(());
        }
        let fastest = self
            .parts
            .iter()
            .flat_map(|part| {
                let v = part.model.points().velocity;
                (0..v.len()).map(move |i| (part, i, dot(v[i], v[i])))
            })
            .max_by(|a, b| a.2.total_cmp(&b.2));
        let Some((part, point, speed)) = fastest else {
            return Ok(());
        };
        let who = match part.model.point_kind() {
            "particle" => "particle".to_string(),
            kind => format!("{kind} {point}"),
        };
        Err(self.blowup(
            part,
            format!(
                "kinetic energy {kinetic:.3e} J exceeds {}× the energy the scene can supply ({budget:.3e} J); \
                 fastest {who} moves at {:.3e} m/s",
                self.energy_growth,
                speed.sqrt()
            ),
            point,
        ))
    }

    fn blowup(&self, part: &Part, what: String, point: usize) -> SimError {
        let offset: usize = self
            .parts
            .iter()
            .take_while(|p| !std::ptr::eq(*p, part))
            .map(|p| p.model.particles().position.len())
            .sum();
        SimError::BlowUp {
            step: self.steps,
            time: self.time,
            what,
            particle: offset + part.model.particle_of_point(point),
            position: part.model.points().position[point],
            last_good_frame: 0,
        }
    }

    /// The particles of every model, in part order, with fragment ids made unique
    /// across models; a model's extra column is 0 on the other models' particles.
    pub fn particles(&self) -> ParticleColumns {
        let columns: Vec<ParticleColumns> =
            self.parts.iter().map(|p| p.model.particles()).collect();
        let mut names: Vec<&str> = Vec::new();
        for (name, _) in columns.iter().flat_map(|c| &c.extra) {
            if !names.contains(&name.as_str()) {
                names.push(name);
            }
        }
        let mut all = ParticleColumns {
            extra: names.iter().map(|n| (n.to_string(), Vec::new())).collect(),
            ..ParticleColumns::default()
        };
        let mut fragment_base = 0u32;
        for c in &columns {
            let n = c.position.len();
            for (name, values) in &mut all.extra {
                match c.extra.iter().find(|(own, _)| own == name) {
                    Some((_, own)) => values.extend(own),
                    None => values.extend(std::iter::repeat_n(0.0, n)),
                }
            }
            let next = c.fragment.iter().map(|&f| f + 1).max().unwrap_or(0);
            all.position.extend(&c.position);
            all.velocity.extend(&c.velocity);
            all.damage.extend(&c.damage);
            all.plastic.extend(&c.plastic);
            all.body.extend(&c.body);
            all.fragment
                .extend(c.fragment.iter().map(|f| f + fragment_base));
            fragment_base += next;
        }
        all
    }

    /// Total mass of every point (kg).
    pub fn total_mass(&self) -> f64 {
        self.parts
            .iter()
            .map(|p| p.model.points().mass.iter().sum::<f64>())
            .sum()
    }

    /// Bonds of every model (directed).
    pub fn bonds(&self) -> usize {
        self.parts.iter().map(|p| p.model.bonds()).sum()
    }

    /// Wall time of the models' stages by name, summed over the models.
    pub fn stage_times(&self) -> Vec<(&'static str, f64)> {
        let mut out: Vec<(&'static str, f64)> = Vec::new();
        for part in &self.parts {
            for (name, t) in part.model.stage_times() {
                match out.iter_mut().find(|(n, _)| *n == name) {
                    Some(slot) => slot.1 += t,
                    None => out.push((name, t)),
                }
            }
        }
        if let Some(contact) = &self.contact {
            out.push(("particle contact", contact.time));
        }
        if let Some(rigid) = &self.rigid {
            out.push(("rigid bodies", rigid.time));
        }
        out
    }

    /// Sets every stage timer back to zero (benchmarks).
    pub fn reset_times(&mut self) {
        self.other_time = 0.0;
        if let Some(contact) = &mut self.contact {
            contact.time = 0.0;
        }
        for part in &mut self.parts {
            part.model.reset_stage_times();
        }
    }
}
