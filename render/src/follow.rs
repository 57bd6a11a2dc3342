//! The cameras that move with a shot: the one that follows it
//! ([`crate::preview::CameraMotion::Follow`]: frame k framed on the frames 1 to k
//! pooled), whether a shot spreads enough that the automatic camera follows it, and
//! the one on each frame's largest piece ([`crate::preview::CameraMotion::Largest`]).

use crate::cache::{FRAMING_TAIL, FramePoints, Framing, percentile_bounds};
use crate::camera::{Bounds, Camera, Subject};

/// See [`crate::preview::CameraMotion::Auto`]: how many times the first frame's size the robust
/// subject of the whole shot must reach for the camera to follow it.
pub const FOLLOW_GROWTH: f32 = 3.0;

/// Most points a following camera fits (the pool of the frames so far, decimated).
pub const FOLLOW_POOL: usize = 32_768;

/// Most points each frame's colliders add to a following camera's subject: a few, so
/// that a projectile flying on is left out as far debris is, while one beside the
/// bodies is kept.
pub const COLLIDER_SAMPLES: usize = 8;

/// The points a following camera frames, pooled over the frames so far: every
/// `stride`-th point offered, the stride doubling (and every other point kept
/// dropped) whenever the pool reaches twice [`FOLLOW_POOL`], so it stays an even
/// stride of everything offered whatever the shot's length.
#[derive(Debug, Clone)]
struct Pool {
    points: Vec<[f32; 3]>,
    stride: usize,
    offered: usize,
}

impl Pool {
    fn new() -> Pool {
        Pool {
            points: Vec::new(),
            stride: 1,
            offered: 0,
        }
    }

    /// Offers frame `f`'s points: its samples, and its colliders' vertices thinned to
    /// at most [`COLLIDER_SAMPLES`].
    fn offer(&mut self, f: &FramePoints) {
        let thin = f.colliders.len().div_ceil(COLLIDER_SAMPLES).max(1);
        for &p in f.samples.iter().chain(f.colliders.iter().step_by(thin)) {
            if self.offered % self.stride == 0 {
                self.points.push(p);
            }
            self.offered += 1;
            if self.points.len() >= 2 * FOLLOW_POOL {
                self.points = self.points.iter().step_by(2).copied().collect();
                self.stride *= 2;
            }
        }
    }
}

/// The cameras of [`crate::preview::CameraMotion::Follow`], one a frame of `framing` with the bounds
/// its shadow and clip planes cover: frame k's is [`Camera::fit`] on the subject of
/// frames 1 to k pooled (each frame's samples, and its colliders as a few
/// samples, so a projectile flying on is left out as far debris is), without far
/// outliers as the fixed camera's; its bounds are the pool's percentile bounds. The
/// pool only grows, so the camera pulls back as the debris spreads and does not jump
/// in again.
pub fn follow_cameras(framing: &Framing, aspect: f32, azimuth: f32) -> Vec<(Camera, Bounds)> {
    let pad = framing.subject.pad;
    let mut pool = Pool::new();
    framing
        .frames
        .iter()
        .map(|f| {
            pool.offer(f);
            let subject = Subject {
                samples: pool.points.clone(),
                pad,
                tail: FRAMING_TAIL,
                whole: Vec::new(),
            };
            let bounds = percentile_bounds(&pool.points, FRAMING_TAIL, pad);
            (Camera::fit(&subject, &bounds, aspect, azimuth), bounds)
        })
        .collect()
}

/// How much of the ground around its largest piece [`largest_piece_view`] shows: the
/// camera frames the box reaching this many of the piece's radii from its centre.
pub const AROUND_LARGEST: f32 = 0.8;

/// The camera of [`crate::preview::CameraMotion::Largest`] for one frame, with the
/// bounds its shadow and clip planes cover: framed on the frame's largest fragment,
/// whose bounds are `piece` ([`FramePoints::largest`]), the box [`AROUND_LARGEST`] of
/// its radii (at least `pad`) from its centre. `None` when the frame has no particles.
/// For a still of the end of a shot whose pieces lie metres apart: on the largest
/// piece where it came to rest among the chips around it, not on all the ground the
/// debris crossed.
pub fn largest_piece_view(
    piece: &Bounds,
    pad: f32,
    aspect: f32,
    azimuth: f32,
) -> Option<(Camera, Bounds)> {
    if piece.is_empty() {
        return None;
    }
    let (center, reach) = (piece.center(), AROUND_LARGEST * piece.radius().max(pad));
    let mut around = Bounds::EMPTY;
    for corner in [-reach, reach] {
        around.add(center.map(|c| c + corner));
    }
    let mut bounds = *piece;
    bounds.add(around.min);
    bounds.add(around.max);
    Some((Camera::framing(&around, aspect, azimuth), bounds))
}

/// Whether the action spreads: the robust bounds of the whole shot's pool (as the
/// following camera pools it) over [`FOLLOW_GROWTH`] times the first frame's, by
/// radius ([`crate::preview::CameraMotion::Auto`]).
pub fn spreads(framing: &Framing) -> bool {
    let pad = framing.subject.pad;
    let Some(first) = framing.frames.first() else {
        return false;
    };
    let mut pool = Pool::new();
    pool.offer(first);
    let start = percentile_bounds(&pool.points, FRAMING_TAIL, pad);
    for f in &framing.frames[1..] {
        pool.offer(f);
    }
    let end = percentile_bounds(&pool.points, FRAMING_TAIL, pad);
    !start.is_empty() && !end.is_empty() && end.radius() > FOLLOW_GROWTH * start.radius()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cache::Ranges;
    use perifrac_cache::ply::ParticleFrame;

    /// A shot of 40 frames: a 0.4 m slab of 4,000 points whose points fly apart at up to
    /// `spread` m a frame from frame 2 on, and a ball beside it that flies on at 2 m a
    /// frame.
    fn shot(spread: f32) -> Framing {
        let slab: Vec<[f32; 3]> = (0..4000)
            .map(|i| {
                let (a, b, c) = (i % 20, (i / 20) % 20, i / 400);
                [a as f32 * 0.02 - 0.2, b as f32 * 0.02, c as f32 * 0.005]
            })
            .collect();
        let frames = (0..40)
            .map(|k| {
                let t = k as f32;
                let samples = slab
                    .iter()
                    .enumerate()
                    .map(|(i, p)| {
                        // Each point's own direction, from its index.
                        let u = (i as f32 * 0.618_034).fract() - 0.5;
                        let w = (i as f32 * 0.414_214).fract() - 0.5;
                        [p[0] + spread * t * u, p[1], p[2] + spread * t * w]
                    })
                    .collect();
                let ball = [0.0, 0.2, -0.1 + 2.0 * t];
                let colliders = (0..200)
                    .map(|j| {
                        let a = j as f32 * 0.1;
                        [ball[0] + 0.05 * a.cos(), ball[1] + 0.05 * a.sin(), ball[2]]
                    })
                    .collect();
                FramePoints {
                    colliders,
                    samples,
                    largest: Bounds::EMPTY,
                }
            })
            .collect::<Vec<_>>();
        let mut samples = Vec::new();
        let mut whole = Vec::new();
        for f in &frames {
            samples.extend_from_slice(&f.samples);
            whole.extend_from_slice(&f.colliders);
        }
        let mut bounds = percentile_bounds(&samples, FRAMING_TAIL, 0.01);
        for &p in &whole {
            bounds.add(p);
        }
        Framing {
            subject: Subject {
                samples,
                pad: 0.01,
                tail: FRAMING_TAIL,
                whole,
            },
            bounds,
            ranges: Ranges::default(),
            frames,
        }
    }

    /// A shot whose last frame holds a 0.4 m slab of 1,000 particles (fragment 7) 5 m
    /// from the origin and 200 grains (fragments 1000–1199) spread 40 m: the framing
    /// finds the slab as the largest piece, and its camera looks at the slab, close
    /// enough that it fills a good part of the picture; a frame without particles has
    /// none.
    #[test]
    fn the_largest_piece_camera_frames_the_largest_piece() {
        let mut frame = ParticleFrame::default();
        for i in 0..1000 {
            let (a, b, c) = (i % 10, (i / 10) % 10, i / 100);
            frame
                .position
                .push([5.0 + a as f32 * 0.04, c as f32 * 0.005, b as f32 * 0.04]);
            frame.fragment.push(7.0);
        }
        for i in 0..200 {
            let t = i as f32 * 0.2;
            frame.position.push([-20.0 + t, 0.0, 20.0 - t]);
            frame.fragment.push(1000.0 + i as f32);
        }
        let (_, piece) = crate::cache::pieces(&frame);
        let (camera, bounds) = largest_piece_view(&piece, 0.01, 16.0 / 9.0, 0.6).expect("a camera");
        let slab = Bounds {
            min: [5.0, 0.0, 0.0],
            max: [5.36, 0.045, 0.36],
        };
        assert!(
            distance(&camera) < 3.0
                && (0..3).all(|k| (camera.target[k] - slab.center()[k]).abs() < 0.01),
            "{camera:?}"
        );
        assert!((0..3).all(|k| bounds.min[k] <= slab.min[k] && bounds.max[k] >= slab.max[k]));
        assert!(largest_piece_view(&Bounds::EMPTY, 0.01, 1.0, 0.0).is_none());
    }

    fn distance(c: &Camera) -> f32 {
        (0..3)
            .map(|k| (c.eye[k] - c.target[k]).powi(2))
            .sum::<f32>()
            .sqrt()
    }

    #[test]
    fn a_following_camera_starts_close_pulls_back_and_leaves_the_ball_out() {
        let framing = shot(0.25);
        assert!(spreads(&framing), "debris flying 10 m from a 0.4 m slab");
        let cameras = follow_cameras(&framing, 16.0 / 9.0, 0.6);
        assert_eq!(cameras.len(), 40);
        let d: Vec<f32> = cameras.iter().map(|(c, _)| distance(c)).collect();
        // Close on the slab at first: as the fixed camera would frame frame 1 alone.
        let first = Subject {
            samples: framing.frames[0].samples.clone(),
            pad: 0.01,
            tail: FRAMING_TAIL,
            whole: Vec::new(),
        };
        let b = percentile_bounds(&first.samples, FRAMING_TAIL, 0.01);
        let alone = distance(&Camera::fit(&first, &b, 16.0 / 9.0, 0.6));
        assert!(
            (d[0] - alone).abs() < 0.1 * alone,
            "{} against {alone}",
            d[0]
        );
        // Pulling back as the debris spreads, never in by more than a few per cent.
        for k in 1..40 {
            assert!(
                d[k] > 0.97 * d[k - 1],
                "frame {k}: {} after {}",
                d[k],
                d[k - 1]
            );
        }
        assert!(d[39] > 10.0 * d[0], "{} against {}", d[39], d[0]);
        // The ball, 78 m off by the end, is not what the camera frames: the fixed
        // camera (the colliders whole) is much further out.
        let (last, bounds) = cameras[39];
        assert!(bounds.max[2] < 20.0, "{bounds:?}");
        let fixed = Camera::fit(&framing.subject, &framing.bounds, 16.0 / 9.0, 0.6);
        assert!(distance(&fixed) > 3.0 * distance(&last));
    }

    #[test]
    fn a_shot_that_stays_in_place_keeps_one_camera() {
        // Points that drift a little (5 cm over the shot) and the ball flying on: the
        // automatic camera stays fixed.
        assert!(!spreads(&shot(0.0013)));
    }
}
