//! The world's time line: its step, where the current step started, and the frames.

use super::World;
use crate::model::Stepping;

/// The world's time line: the step `dt` since step `steps` at `time`, and frames of
/// `steps_per_frame` steps from frame `frame` on (frame `frame` ends at step `steps`).
/// A run starts on the scene's step from 0; the frame loop starts the clock again from
/// a frame where the frame rate changes (`[output] schedule`) or once only rigid pieces
/// move (with the rigid phase's longer step).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Clock {
    /// Steps at the start of this clock.
    pub steps: u64,
    /// Time at the start of this clock (s).
    pub time: f64,
    /// The frame that ends where this clock starts (0 for the scene's start).
    pub frame: u64,
    /// Steps a frame.
    pub steps_per_frame: u64,
    /// Seconds a frame.
    pub frame_length: f64,
}

impl World {
    /// The time after `steps` steps on the current clock.
    pub fn time_after(&self, steps: u64) -> f64 {
        self.clock.time + (steps - self.clock.steps) as f64 * self.dt
    }

    /// The step at which `frame` ends on the current clock.
    pub fn frame_end(&self, frame: usize) -> u64 {
        let frames = (frame as u64).saturating_sub(1 + self.clock.frame);
        self.clock
            .steps
            .saturating_add(frames.saturating_mul(self.clock.steps_per_frame))
    }

    /// Whether only rigid pieces are left to move: every point of every model is in
    /// a rigid piece (counted, not scanned: this is asked every step).
    pub fn rigid_only(&self) -> bool {
        self.rigid.as_ref().is_some_and(|rigid| {
            let points: usize = self.parts.iter().map(|p| p.model.points().mass.len()).sum();
            rigid.frozen_points() == points
                && self
                    .parts
                    .iter()
                    .all(|p| p.model.stepping() == Stepping::Verlet)
        })
    }

    /// At the end of frame `frame`, before a frame of `frame_length` s: starts the
    /// clock again when the frame rate changes, or when only rigid pieces are left to
    /// move and the rigid phase's longest step allows fewer steps a frame; returns
    /// whether it did. A world part way into a frame (resumed mid-frame) keeps its
    /// clock.
    pub fn start_clock(&mut self, frame: usize, frame_length: f64) -> bool {
        if self.steps != self.frame_end(frame) {
            return false;
        }
        let bound = match &self.rigid {
            Some(rigid) if self.rigid_only() => rigid.longest_step().max(self.step_bound),
            _ => self.step_bound,
        };
        let per_frame = steps_within(frame_length, bound);
        let same = frame_length.to_bits() == self.clock.frame_length.to_bits();
        if same && per_frame >= self.clock.steps_per_frame {
            return false;
        }
        self.restart_clock(frame as u64 - 1, per_frame, frame_length);
        true
    }

    /// Part way through frame `frame`, once only rigid pieces are left to move:
    /// starts the clock again for the rest of the frame, its remaining time over as
    /// few steps as the rigid phase's longest step allows (the frame's end is where
    /// it was, to rounding); the frame's end then starts the frame rate's own clock
    /// ([`World::start_clock`]). Returns whether it did: not when the step would not
    /// grow.
    pub fn start_rigid_clock(&mut self, frame: usize) -> bool {
        let Some(rigid) = &self.rigid else {
            return false;
        };
        let bound = rigid.longest_step().max(self.step_bound);
        if bound <= self.dt || !self.rigid_only() {
            return false;
        }
        self.restart_within_frame(frame, bound)
    }

    /// Part way through frame `frame`, once a rigid piece went back to its model
    /// ([`World::reenter`]) while the step was the rigid phase's: starts the clock
    /// again for the rest of the frame at the deformable bodies' step. Returns whether
    /// it did: not when the step is that already.
    pub fn start_deformable_clock(&mut self, frame: usize) -> bool {
        if self.dt <= self.step_bound || self.rigid_only() {
            return false;
        }
        self.restart_within_frame(frame, self.step_bound)
    }

    /// The rest of frame `frame` over as few steps as `bound` allows, unless that is
    /// as many steps as the clock takes now; returns whether the clock started again.
    fn restart_within_frame(&mut self, frame: usize, bound: f64) -> bool {
        let end = self.frame_end(frame);
        if end <= self.steps {
            return false;
        }
        let remaining = self.time_after(end) - self.time;
        let steps = steps_within(remaining, bound);
        if steps == end - self.steps {
            return false;
        }
        // Frame `frame` ends `steps` steps on: the clock's frame is the one before it
        // less one, as for a clock started at that frame's start.
        self.restart_clock(frame as u64 - 2, steps, remaining);
        true
    }

    /// Starts the clock here, frames of `frame_length` s in `steps_per_frame` steps
    /// from the end of frame `frame` + 1 on.
    fn restart_clock(&mut self, frame: u64, steps_per_frame: u64, frame_length: f64) {
        self.clock = Clock {
            steps: self.steps,
            time: self.time,
            frame,
            steps_per_frame,
            frame_length,
        };
        self.dt = frame_length / steps_per_frame as f64;
    }
}

/// The fewest steps no longer than `bound` that make up `length` s (at least one).
pub fn steps_within(length: f64, bound: f64) -> u64 {
    (length / bound).ceil().max(1.0) as u64
}
