//! Framing a whole shot: what the camera looks at over every frame of a sequence
//! ([`Cache::sequence_framing`]), each frame's own points for a camera that follows,
//! and the robust bounds (percentiles, grains left out) both are built from.

use std::collections::BTreeMap;

use perifrac_cache::ply::ParticleFrame;
use rayon::prelude::*;

use super::{Cache, ColorBy, NO_RANGE, Ranges, quantity, temperature, widen};
use crate::RenderError;
use crate::camera::{Bounds, Subject};
use crate::geometry::{self, FrameGeometry};
use crate::gltf::read_glb;

impl Cache {
    /// What the camera frames, its bounds, and the sequence's value ranges for
    /// `color_by`.
    ///
    /// The subject is robust, to frame the action and not the far debris: the particles
    /// in pieces of every frame (leaving out grains, fragments of at most
    /// [`GRAIN_PARTICLES`] particles, while they are under half the particles), or the
    /// surface's vertices where a frame has no particles, up
    /// to [`SAMPLES_PER_FRAME`] of each, evenly strided, pooled over the whole shot,
    /// grown by half a particle, without far outliers (beyond the [`FRAMING_TAIL`]
    /// quantile along an edge by more than a quarter of the spread: `Subject::support`); the colliders (the projectile) of every frame are framed whole. The
    /// bounds (for the shadow and the clip planes) are the samples' 1st to 99th
    /// percentile on each axis and the colliders.
    ///
    /// With them, each frame's own points ([`FramePoints`]), for a camera that follows
    /// the shot.
    pub fn sequence_framing(&self, color_by: ColorBy) -> Result<Framing, RenderError> {
        // Every frame's result is kept and the first error in frame order reported, so
        // the message does not depend on which thread failed first.
        type FrameBounds = (Vec<[f32; 3]>, Vec<[f32; 3]>, Bounds, Ranges);
        let per_frame: Vec<Result<FrameBounds, RenderError>> = self
            .frames
            .par_iter()
            .map(|&frame| -> Result<FrameBounds, RenderError> {
                let mut ranges = Ranges {
                    plastic_max: 0.0,
                    temperature: (f32::INFINITY, f32::NEG_INFINITY),
                    quantity: NO_RANGE,
                };
                let mut g = FrameGeometry::default();
                self.push_colliders(frame, &mut g);
                let colliders = strided(&mesh_positions(&g));
                let mut samples = Vec::new();
                let mut largest = Bounds::EMPTY;
                if self.uses_surface(frame, color_by) {
                    let mut s = FrameGeometry::default();
                    ranges.quantity =
                        read_glb(&self.layout.surface(frame), color_by, &ranges, &mut s)?;
                    if !self.layout.particles(frame).is_file() {
                        samples = strided(&mesh_positions(&s));
                    }
                }
                if self.layout.particles(frame).is_file() {
                    let path = self.layout.particles(frame);
                    let p = ParticleFrame::read(&path)?;
                    let (kept, piece) = pieces(&p);
                    samples = strided(&kept);
                    largest = piece;
                    ranges.plastic_max = p
                        .plastic
                        .iter()
                        .copied()
                        .filter(|v| v.is_finite())
                        .fold(0.0, f32::max);
                    if color_by == ColorBy::Temperature {
                        for &v in temperature(&p, &path)? {
                            if v.is_finite() {
                                ranges.temperature.0 = ranges.temperature.0.min(v);
                                ranges.temperature.1 = ranges.temperature.1.max(v);
                            }
                        }
                    }
                    if color_by == ColorBy::Quantity && !self.uses_surface(frame, color_by) {
                        ranges.quantity = widen(NO_RANGE, quantity(&p, &path)?);
                    }
                }
                Ok((colliders, samples, largest, ranges))
            })
            .collect();
        let per_frame: Vec<FrameBounds> = per_frame.into_iter().collect::<Result<_, _>>()?;
        let mut whole = Vec::new();
        let mut samples = Vec::new();
        let mut frames = Vec::with_capacity(per_frame.len());
        let mut ranges = Ranges {
            plastic_max: 0.0,
            temperature: (f32::INFINITY, f32::NEG_INFINITY),
            quantity: NO_RANGE,
        };
        for (c, s, largest, r) in per_frame {
            whole.extend_from_slice(&c);
            samples.extend_from_slice(&s);
            frames.push(FramePoints {
                colliders: c,
                samples: s,
                largest,
            });
            ranges.plastic_max = ranges.plastic_max.max(r.plastic_max);
            ranges.temperature.0 = ranges.temperature.0.min(r.temperature.0);
            ranges.temperature.1 = ranges.temperature.1.max(r.temperature.1);
            ranges.quantity = widen(ranges.quantity, &r.quantity);
        }
        let pad = self.radius(0.0);
        let mut bounds = percentile_bounds(&samples, FRAMING_TAIL, pad);
        for &p in &whole {
            bounds.add(p);
        }
        let subject = Subject {
            samples,
            pad,
            tail: FRAMING_TAIL,
            whole,
        };
        if !ranges.temperature.0.is_finite() {
            ranges.temperature = (0.0, 1.0);
        }
        if ranges.quantity[0] > ranges.quantity[1] {
            ranges.quantity = [0.0, 0.0];
        }
        Ok(Framing {
            subject,
            bounds,
            ranges,
            frames,
        })
    }
}

/// What [`Cache::sequence_framing`] finds: the whole shot's subject and bounds, its
/// value ranges, and each frame's own points.
#[derive(Debug, Clone)]
pub struct Framing {
    /// The subject over the whole shot (the colliders whole).
    pub subject: Subject,
    /// Its bounds (shadow and clip planes).
    pub bounds: Bounds,
    /// The sequence's value ranges.
    pub ranges: Ranges,
    /// Each frame's points, in frame order.
    pub frames: Vec<FramePoints>,
}

/// One frame's points for the framing.
#[derive(Debug, Clone)]
pub struct FramePoints {
    /// The colliders' vertices (strided).
    pub colliders: Vec<[f32; 3]>,
    /// The bodies' samples: up to [`SAMPLES_PER_FRAME`] particles or surface vertices.
    pub samples: Vec<[f32; 3]>,
    /// The bounds of the frame's largest fragment (most particles, the lowest id of
    /// equals; all its particles without a fragment column), empty without particles.
    pub largest: Bounds,
}

/// Points of one frame that the framing looks at, at most (a stride through the
/// particles keeps the pooled sample of a long shot small).
pub const SAMPLES_PER_FRAME: usize = 4096;

/// The fraction of the pooled sample the framing may leave outside each edge of the
/// image (and the bounds leave out on each side of each axis): 1 %.
pub const FRAMING_TAIL: f32 = 0.01;

/// The positions of the mesh vertices of `g`.
fn mesh_positions(g: &FrameGeometry) -> Vec<[f32; 3]> {
    g.mesh_vertices
        .chunks_exact(geometry::MESH_STRIDE)
        .map(|v| [v[0], v[1], v[2]])
        .collect()
}

/// The positions of the particles in pieces: of fragments of more than
/// [`GRAIN_PARTICLES`] particles, when they are at least half of the particles (else
/// all). A shattered body throws thousands of single grains, a tenth of its particles,
/// far and wide; the camera frames the pieces, and the grains in view with them. With
/// them, the bounds of the largest fragment ([`FramePoints::largest`]).
pub(crate) fn pieces(p: &ParticleFrame) -> (Vec<[f32; 3]>, Bounds) {
    let whole = |points: &[[f32; 3]]| {
        let mut b = Bounds::EMPTY;
        points.iter().for_each(|&x| b.add(x));
        b
    };
    if p.fragment.len() != p.position.len() {
        return (p.position.clone(), whole(&p.position));
    }
    let mut size: BTreeMap<u32, usize> = BTreeMap::new();
    for &f in &p.fragment {
        *size.entry(f as u32).or_default() += 1;
    }
    let mut largest = Bounds::EMPTY;
    if let Some((&id, _)) = size
        .iter()
        .max_by_key(|&(f, n)| (*n, std::cmp::Reverse(*f)))
    {
        for (x, _) in p
            .position
            .iter()
            .zip(&p.fragment)
            .filter(|(_, f)| **f as u32 == id)
        {
            largest.add(*x);
        }
    }
    let kept: Vec<[f32; 3]> = p
        .position
        .iter()
        .zip(&p.fragment)
        .filter(|(_, f)| size[&(**f as u32)] > GRAIN_PARTICLES)
        .map(|(x, _)| *x)
        .collect();
    if 2 * kept.len() >= p.position.len() {
        (kept, largest)
    } else {
        (p.position.clone(), largest)
    }
}

/// Fragments of at most this many particles are grains, which the framing leaves to
/// fall where they may ([`Cache::sequence_framing`]).
pub const GRAIN_PARTICLES: usize = 8;

/// At most [`SAMPLES_PER_FRAME`] of `points`, evenly strided from the first.
fn strided(points: &[[f32; 3]]) -> Vec<[f32; 3]> {
    let stride = points.len().div_ceil(SAMPLES_PER_FRAME).max(1);
    points.iter().step_by(stride).copied().collect()
}

/// Bounds of the finite `points` without the fraction `tail` of them on each side of
/// each axis, grown by `radius`.
pub fn percentile_bounds(points: &[[f32; 3]], tail: f32, radius: f32) -> Bounds {
    let finite: Vec<[f32; 3]> = points
        .iter()
        .copied()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .collect();
    if finite.is_empty() {
        return Bounds::EMPTY;
    }
    let cut = ((finite.len() as f32 * tail) as usize).min((finite.len() - 1) / 2);
    let mut b = Bounds::EMPTY;
    for k in 0..3 {
        let mut values: Vec<f32> = finite.iter().map(|p| p[k]).collect();
        let hi = values.len() - 1 - cut;
        let (_, &mut lo_v, _) = values.select_nth_unstable_by(cut, f32::total_cmp);
        let (_, &mut hi_v, _) = values.select_nth_unstable_by(hi, f32::total_cmp);
        b.min[k] = lo_v - radius;
        b.max[k] = hi_v + radius;
    }
    b
}
