//! A model in the world with its anchors, and velocity Verlet's kick and drift.

use rayon::prelude::*;

use crate::contact::{self, Anchor};
use crate::model::Model;

/// A model in the world with its anchors and the integrator's per-point state.
#[derive(Debug)]
pub struct Part {
    /// The model.
    pub model: Box<dyn Model>,
    /// Anchored regions; their `particles` index the model's points.
    pub anchors: Vec<Anchor>,
    /// Verlet's acceleration at the current positions (saved in checkpoints: after a
    /// step's contact projection it is not the acceleration of the new positions).
    pub(super) acceleration: Vec<[f64; 3]>,
    /// Whether a point is held by an active anchor.
    pub(super) anchored: Vec<bool>,
}

impl Part {
    /// A model with its anchors.
    pub fn new(model: Box<dyn Model>, anchors: Vec<Anchor>) -> Part {
        let n = model.points().position.len();
        Part {
            model,
            anchors,
            acceleration: vec![[0.0; 3]; n],
            anchored: vec![false; n],
        }
    }

    pub(super) fn apply_anchors(&mut self, time: f64) {
        let p = self.model.points_mut();
        contact::apply_anchors(
            &self.anchors,
            time,
            p.reference,
            p.position,
            p.velocity,
            &mut self.anchored,
        );
    }

    /// The accelerations at the current state: internal forces over mass plus
    /// gravity, the forces on the clamps' ghosts carried to their sources.
    pub(super) fn accelerations(&mut self, time: f64, gravity: [f64; 3]) {
        self.model.accelerations(gravity, &mut self.acceleration);
        contact::carry_clamp_forces(
            &self.anchors,
            time,
            self.model.points().mass,
            gravity,
            &mut self.acceleration,
        );
    }

    /// Holds the anchored points at `time` (placing the clamps' ghosts) and computes
    /// the accelerations at the current positions, as a step does between its drift
    /// and its second kick; returns them (measurements of the stiffness: tests and
    /// docs/lattice.md, "Bending").
    pub fn accelerations_at(&mut self, time: f64, gravity: [f64; 3]) -> &[[f64; 3]] {
        self.apply_anchors(time);
        self.model.internal_forces();
        self.accelerations(time, gravity);
        &self.acceleration
    }

    /// Whether point `i` is held by an active anchor.
    pub fn is_anchored(&self, i: usize) -> bool {
        self.anchored.get(i).copied().unwrap_or(false)
    }

    /// |m a · v| summed over the anchored points: the anchors' power.
    pub(super) fn anchor_power(&self) -> f64 {
        if self.anchors.is_empty() {
            return 0.0;
        }
        let p = self.model.points();
        contact::anchor_power(&self.anchored, p.mass, &self.acceleration, p.velocity)
    }
}

/// Velocity Verlet's half kick v ← v + ½Δt a, with the drift y ← y + Δt v after it
/// when `drift`.
pub(super) fn kick(part: &mut Part, dt: f64, drift: bool) {
    let p = part.model.points_mut();
    let acc = &part.acceleration;
    if drift {
        p.position
            .par_iter_mut()
            .zip(p.velocity.par_iter_mut())
            .zip(acc.par_iter())
            .with_min_len(8192)
            .for_each(|((y, v), a)| {
                for k in 0..3 {
                    v[k] += 0.5 * dt * a[k];
                    y[k] += dt * v[k];
                }
            });
    } else {
        p.velocity
            .par_iter_mut()
            .zip(acc.par_iter())
            .with_min_len(8192)
            .for_each(|(v, a)| {
                for k in 0..3 {
                    v[k] += 0.5 * dt * a[k];
                }
            });
    }
}
