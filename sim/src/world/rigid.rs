//! The world's side of the rigid phase ([`crate::rigid`]): pieces going back to their
//! models, the stop points that keep rapier's resumes exact, and the step once only
//! rigid pieces move.

use std::time::Instant;

use super::World;
use crate::contact;
use crate::error::Result;
#[cfg(doc)]
use crate::rigid::RigidPhase;

impl World {
    /// Before a step: gives back to their models the rigid pieces that the step would
    /// bring into a hard hit ([`RigidPhase::reenter`]); returns whether any went. Their
    /// points start the step with the rigid phase's last accelerations of them, or,
    /// after steps in which only rigid pieces moved (no forces were computed), with
    /// gravity's: the piece was calm when it went rigid, so its bonds pull on it
    /// next to nothing.
    pub fn reenter(&mut self) -> bool {
        let rigid_only = self.rigid_only();
        let Some(rigid) = &mut self.rigid else {
            return false;
        };
        let thawed = rigid.reenter(self.dt, self.time, &mut self.parts, &self.colliders);
        if rigid_only {
            for t in &thawed {
                for &i in &t.points {
                    self.parts[t.part].acceleration[i as usize] = self.gravity;
                }
            }
        }
        !thawed.is_empty()
    }

    /// Whether a run may stop (and checkpoint) here: always without a rigid phase;
    /// with one, only every `check_every` steps and at frame ends
    /// ([`World::end_frame`]), where every run resets rapier's unsaved workspaces
    /// ([`RigidPhase::reset_workspaces`]), so that a run resumed there continues as
    /// one that never stopped.
    pub fn at_stop_point(&self) -> bool {
        match (&self.rigid, &self.rigid_settings) {
            (Some(_), Some(settings)) => self.steps % settings.check_every as u64 == 0,
            _ => true,
        }
    }

    /// At a frame's end (a stop point whatever the step): resets rapier's unsaved
    /// workspaces, unless the frame's last step ended at a stop point and did.
    pub fn end_frame(&mut self) {
        if !self.at_stop_point()
            && let Some(rigid) = &mut self.rigid
        {
            rigid.reset_workspaces();
        }
    }

    /// After a step: at a stop point, resets rapier's unsaved workspaces.
    pub(super) fn reset_at_stop_point(&mut self) {
        if self.at_stop_point()
            && let Some(rigid) = &mut self.rigid
        {
            rigid.reset_workspaces();
        }
    }

    /// A step when only rigid pieces move: rapier's, the other colliders moved as the
    /// scene says; no model, particle contact or particle–collider contact is left to
    /// compute.
    pub(super) fn rigid_step(&mut self, time: f64) -> Result<usize> {
        let t0 = Instant::now();
        let dt = self.dt;
        if let Some(rigid) = &mut self.rigid {
            rigid.step(dt, self.gravity, &mut self.parts, &mut self.colliders);
            let moved: Vec<bool> = (0..self.colliders.len())
                .map(|i| rigid.moves_collider(i, &self.colliders))
                .collect();
            let none = vec![[0.0; 3]; self.colliders.len()];
            contact::advance_except(&mut self.colliders, &none, self.gravity, dt, time, &moved);
        }
        self.time = time;
        self.steps += 1;
        if self.steps % 16 == 0 {
            self.check_blowup()?;
        }
        self.reset_at_stop_point();
        self.other_time += t0.elapsed().as_secs_f64();
        Ok(0)
    }
}
