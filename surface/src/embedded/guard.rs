//! The guard of the smoothing: the tets touching movable vertices keep at least
//! [`MIN_VOLUME_FRACTION`] of their volume (so no fragment's surface folds over itself)
//! and their longest edge within [`MAX_EDGE_GROWTH`] times its length before smoothing
//! (so no crack needle).

use perifrac_cache::vtu::TetFrame;
use perifrac_math::{norm, sub};

use super::{MIN_VOLUME_FRACTION, tet_volume};

/// Longest edge a guarded tet may reach in smoothing, over its longest edge before:
/// the split mesh's tets have edges up to about 1.6λ, so smoothing adds no crack edge
/// over 3λ (without this bound the rim moves stretched a few to 4λ in the demo).
const MAX_EDGE_GROWTH: f64 = 1.8;

/// The longest edge of tet `t`.
fn longest_edge(x: &[[f64; 3]], t: [u32; 4]) -> f64 {
    let mut longest = 0.0f64;
    for i in 0..4 {
        for j in i + 1..4 {
            longest = longest.max(norm(sub(x[t[i] as usize], x[t[j] as usize])));
        }
    }
    longest
}

/// The tets a smoothing move must not spoil, with what each must keep.
pub(super) struct Guard<'a> {
    frame: &'a TetFrame,
    movable: &'a [u32],
    /// Index of each vertex in `movable` (`u32::MAX` if it does not move).
    slot: &'a [u32],
    /// The tets touching movable vertices.
    pub(super) tets: Vec<usize>,
    /// Their volumes before smoothing.
    rest: Vec<f64>,
    /// [`MAX_EDGE_GROWTH`] times their longest edges before smoothing.
    reach: Vec<f64>,
}

impl<'a> Guard<'a> {
    /// The guard of the tets of `frame` that touch a vertex of `movable`, at `points`.
    pub(super) fn new(
        frame: &'a TetFrame,
        points: &[[f64; 3]],
        movable: &'a [u32],
        slot: &'a [u32],
    ) -> Self {
        let tets: Vec<usize> = (0..frame.tets.len())
            .filter(|&t| frame.tets[t].iter().any(|&v| slot[v as usize] != u32::MAX))
            .collect();
        let rest = tets
            .iter()
            .map(|&t| tet_volume(points, frame.tets[t]))
            .collect();
        let reach = tets
            .iter()
            .map(|&t| MAX_EDGE_GROWTH * longest_edge(points, frame.tets[t]))
            .collect();
        Guard {
            frame,
            movable,
            slot,
            tets,
            rest,
            reach,
        }
    }

    /// Applies `moves` to the movable vertices, halving (up to four times, then
    /// dropping) the moves of the vertices of any guarded tet that would keep less than
    /// [`MIN_VOLUME_FRACTION`] of its rest volume or have an edge longer than its
    /// `reach` ([`MAX_EDGE_GROWTH`]), until no tet does; returns how many
    /// moves were cut. Dropping moves can leave a tet whose other vertices still move
    /// below the bound, so the drops repeat until none is (each round drops at least
    /// one move, and with every move dropped the tets are where they started).
    pub(super) fn apply(&self, points: &mut [[f64; 3]], mut moves: Vec<[f64; 3]>) -> usize {
        let start: Vec<[f64; 3]> = self.movable.iter().map(|&v| points[v as usize]).collect();
        let mut cut = 0;
        for attempt in 0.. {
            for (i, &v) in self.movable.iter().enumerate() {
                points[v as usize] = [0, 1, 2].map(|a| start[i][a] + moves[i][a]);
            }
            let bad: Vec<usize> = self
                .tets
                .iter()
                .zip(self.rest.iter().zip(&self.reach))
                .filter(|&(&t, (&r, &l))| {
                    tet_volume(points, self.frame.tets[t]) < MIN_VOLUME_FRACTION * r
                        || longest_edge(points, self.frame.tets[t]) > l
                })
                .map(|(&t, _)| t)
                .collect();
            let before = cut;
            for t in bad {
                for &v in &self.frame.tets[t] {
                    let s = self.slot[v as usize];
                    if s != u32::MAX {
                        let m = &mut moves[s as usize];
                        if *m != [0.0; 3] {
                            cut += 1;
                            *m = if attempt < 4 {
                                m.map(|c| c / 2.0)
                            } else {
                                [0.0; 3]
                            };
                        }
                    }
                }
            }
            if cut == before {
                break;
            }
        }
        cut
    }
}
