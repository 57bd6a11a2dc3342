//! The world in a checkpoint: what [`World::save`] writes and [`World::restore`]
//! checks and reads back (the container and its header are `perifrac-cache`'s).

use std::collections::BTreeMap;

use super::{Clock, World};
use crate::cache::checkpoint::{Decoder, Encoder};
use crate::contact::{self, ColliderShape};
use crate::error::Result;
use crate::rigid::RigidPhase;

impl World {
    /// Writes the saved state (models, Verlet's accelerations, colliders, anchor
    /// work) into a checkpoint payload; the clock goes in the container's header.
    pub fn save(&self, out: &mut Encoder) {
        out.put_u64(self.parts.len() as u64);
        for part in &self.parts {
            out.put_f64x3_slice(&part.acceleration);
            part.model.save(out);
        }
        out.put_f64(self.anchor_work);
        let colliders: Vec<[f64; 3]> = self
            .colliders
            .iter()
            .flat_map(|c| [c.center, c.velocity])
            .collect();
        out.put_f64x3_slice(&colliders);
        let c = self.clock;
        out.put_u64(c.steps);
        out.put_f64(c.time);
        out.put_u64(c.frame);
        out.put_u64(c.steps_per_frame);
        out.put_f64(self.dt);
        out.put_f64(c.frame_length);
        match &self.rigid {
            Some(rigid) => {
                out.put_u64(1);
                rigid.save(out);
            }
            // Before the first hand-off: the fragments settling, if any.
            None if self.settling.is_empty() => out.put_u64(0),
            None => {
                out.put_u64(2);
                out.put_u64(self.settling.len() as u64);
                for (&(part, point), &since) in &self.settling {
                    out.put_u32(part);
                    out.put_u32(point);
                    out.put_f64(since);
                }
            }
        }
        if let Some(contact) = &self.contact {
            contact.save(out);
        }
    }

    /// Restores what [`World::save`] wrote, at `time` after `steps` steps with
    /// `broken_bonds` bonds broken since the first step (the checkpoint's header):
    /// every value is checked before use, and the bonds the models restore must
    /// have broken exactly `broken_bonds` since set-up.
    pub fn restore(
        &mut self,
        input: &mut Decoder<'_>,
        time: f64,
        steps: u64,
        broken_bonds: u64,
    ) -> Result<()> {
        let models = input.take_u64("models")?;
        if models != self.parts.len() as u64 {
            return Err(input
                .error(
                    "models",
                    format!("{models} where the scene has {}", self.parts.len()),
                )
                .into());
        }
        let cut_at_setup: u64 = self.parts.iter().map(|p| p.model.broken_bonds()).sum();
        for part in &mut self.parts {
            part.acceleration =
                input.take_finite_f64x3_slice("acceleration", part.acceleration.len())?;
            part.model.restore(input)?;
        }
        let broken: u64 = self.parts.iter().map(|p| p.model.broken_bonds()).sum();
        if broken - cut_at_setup != broken_bonds {
            let message = format!(
                "{} bonds broke since the first step, the header says {broken_bonds}",
                broken - cut_at_setup
            );
            return Err(input.error("bonds", message).into());
        }
        self.anchor_work = input.take_finite_f64("anchor work")?;
        let colliders = input.take_finite_f64x3_slice("colliders", 2 * self.colliders.len())?;
        let clock = Clock {
            steps: input.take_u64("clock")?,
            time: input.take_finite_f64("clock")?,
            frame: input.take_u64("clock")?,
            steps_per_frame: input.take_u64("clock")?,
            frame_length: 0.0,
        };
        let dt = input.take_finite_f64("time step")?;
        let frame_length = input.take_finite_f64("clock")?;
        let clock = Clock {
            frame_length,
            ..clock
        };
        if clock.steps > steps || dt <= 0.0 || frame_length < 0.0 {
            return Err(input
                .error(
                    "clock",
                    format!("{clock:?} with a step of {dt:e} s does not fit {steps} steps"),
                )
                .into());
        }
        // The world's time is steps × dt from where its clock started, to the bit, and
        // lies within the scene (which also bounds the collider replay below).
        let reached = clock.time + (steps - clock.steps) as f64 * dt;
        if time.to_bits() != reached.to_bits() || time > self.duration + dt {
            let message = format!(
                "its time {time:e} s is not {steps} steps of {dt:e} s within the scene's {:e} s",
                self.duration
            );
            return Err(input.error("clock", message).into());
        }
        match input.take_u64("rigid phase")? {
            0 => {
                self.rigid = None;
                self.settling.clear();
            }
            2 if self.rigid_settings.is_some() => {
                self.rigid = None;
                self.settling = self.restore_settling(input, time)?;
            }
            1 => {
                let Some(settings) = self.rigid_settings.clone() else {
                    return Err(input
                        .error(
                            "rigid phase",
                            "the scene has no rigid phase ([rigid] enabled = false)",
                        )
                        .into());
                };
                let mut rigid = RigidPhase::new(settings, &self.colliders, BTreeMap::new());
                rigid.restore(input, &mut self.parts)?;
                self.rigid = Some(rigid);
                self.settling.clear();
            }
            other => {
                return Err(input
                    .error(
                        "rigid phase",
                        format!("flag {other}, not 0, 1 or 2 (2 only with [rigid] enabled)"),
                    )
                    .into());
            }
        }
        for (i, (c, cv)) in self
            .colliders
            .iter_mut()
            .zip(colliders.chunks_exact(2))
            .enumerate()
        {
            // A kinematic collider's motion is the scene's: replay it to check.
            if c.mass.is_none() {
                // Exact to the bit on one clock; within rounding over several.
                let mut center = c.center;
                let mut velocity = c.velocity;
                if let ColliderShape::Mesh(_) = c.shape {
                    // A mesh is where its keyframes put it at the checkpoint's time
                    // (not where its first segment's velocity would take it).
                    let mut at = c.clone();
                    at.set_time(time);
                    (center, velocity) = (at.center, at.velocity);
                } else if c.shape != ColliderShape::Ground {
                    if clock.steps == 0 {
                        for _ in 0..steps {
                            for (x, v) in center.iter_mut().zip(c.velocity) {
                                *x += v * self.dt;
                            }
                        }
                    } else {
                        for (x, v) in center.iter_mut().zip(c.velocity) {
                            *x += v * time;
                        }
                    }
                }
                let off = (0..3)
                    .map(|k| (cv[0][k] - center[k]).abs())
                    .fold(0.0, f64::max);
                let scale = (0..3).map(|k| center[k].abs() + (c.velocity[k] * time).abs());
                let tolerance = if clock.steps == 0 {
                    0.0
                } else {
                    1e-9 * scale.fold(1e-3, f64::max)
                };
                if off > tolerance || cv[1] != velocity {
                    let message = format!(
                        "kinematic collider {i} is at {:?} moving at {:?}; after {steps} steps \
                         the scene puts it at {center:?} moving at {velocity:?}",
                        cv[0], cv[1]
                    );
                    return Err(input.error("colliders", message).into());
                }
            }
            (c.center, c.velocity) = (cv[0], cv[1]);
            c.set_time(time);
        }
        self.time = time;
        self.steps = steps;
        self.clock = clock;
        self.dt = dt;
        if let Some(contact) = &mut self.contact {
            contact.restore(input)?;
        }
        for part in &mut self.parts {
            contact::mark_anchored(&part.anchors, time, &mut part.anchored);
        }
        Ok(())
    }

    /// Reads the fragments settling before the first hand-off ([`World::settling`]):
    /// each names a point of a part the scene has and started settling by `time`.
    fn restore_settling(
        &self,
        input: &mut Decoder<'_>,
        time: f64,
    ) -> Result<BTreeMap<(u32, u32), f64>> {
        let n = input.take_u64("fragments settling")?;
        if n.saturating_mul(16) > input.remaining() as u64 {
            return Err(input
                .error(
                    "fragments settling",
                    format!("{n} entries, more than the file holds"),
                )
                .into());
        }
        let mut settling = BTreeMap::new();
        for _ in 0..n {
            let part = input.take_u32("fragments settling")?;
            let point = input.take_u32("fragments settling")?;
            let since = input.take_f64("fragments settling")?;
            let known = self
                .parts
                .get(part as usize)
                .is_some_and(|p| (point as usize) < p.model.points().mass.len());
            if !known || !since.is_finite() || since > time {
                let message = format!(
                    "part {part}, point {point} since {since:e} s: not in the scene by then"
                );
                return Err(input.error("fragments settling", message).into());
            }
            settling.insert((part, point), since);
        }
        Ok(settling)
    }
}
