//! The points the unstructured mesher places for a shape's sharp features before its
//! darts (feature-aware sampling, issue 13): the corners, points along the creases
//! (value 0: they are on the surface), and beside each segment between consecutive
//! crease points a point in each wedge narrower than a half-turn that the crease's two
//! faces bound.
//!
//! Along a crease, consecutive points are at most [`CREASE_STEP`] r apart, below √2 r:
//! every point of the ball on the segment between two of them lies within r of one of
//! them, where no dart lands, so the segment is a Gabriel edge and hence an edge of the
//! Delaunay tetrahedralization. Around such an edge each tetrahedron is cut by the plane
//! through the edge and a cut point on one of the two faces, so the surface runs
//! through the crease. That needs a vertex on each side in the wedges: with none,
//! Delaunay joined two points just outside the two faces across the inside wedge of a
//! box's edge, and the wedge's material was lost (0.36λ deep at seed 0 of
//! `a_box_keeps_its_corners_and_edges`). So each segment (length s ≤ 1.3r) gets a point
//! at depth d ≤ 0.75r below its middle along the wedge's bisector: the sphere through
//! the segment's ends and two points a, b out along the faces (at least r from the
//! ends, so a² ≥ r² − s²/4) holds it when d² − √2 d (c_a + c_b) < s²/4 with
//! c_a = (a² − s²/4)/2a, which the worst case (s = 1.3r, a = b = 0.76r) meets up to
//! d = 0.81r; Delaunay then puts the point in the edge's link. (Placed beside the crease
//! points at r instead, it missed such spheres: their cross-section there is small.)
//! The wedge points are jittered (depth 0.6r to 0.75r, angle within a sixth of the
//! wedge's width of its bisector, drawn from the mesh's seed): placed exactly, a box's
//! symmetry made four of them nearly coplanar with two crease points near a corner, and
//! the sliver between them (under 1e-12 r³) was dropped, which pinched the boundary.
//! This follows the protecting balls of Delaunay meshers of piecewise-smooth shapes
//! (Cheng, Dey & Levine 2007, "A practical Delaunay meshing algorithm for a large
//! class of domains"; CGAL's Mesh_3), which sample the sharp features first and keep
//! every other point out of balls around them.

use std::collections::HashMap;

use perifrac_math::{SplitMix64, cross, dist, lerp, normalize, sub};

use super::super::sdf::Sdf;
use super::MeshError;

/// Longest step between consecutive points on a crease, in radii (below √2). Steps are
/// equal along a crease (its length over ⌈length / 1.3r⌉), so between 0.65r and 1.3r
/// on creases longer than 1.3r.
const CREASE_STEP: f64 = 1.3;

/// A point closer than this many radii to one placed before it (a crease's end at a
/// corner, two shapes' creases crossing, wedge points near a corner) is not placed.
const FEATURE_GAP: f64 = 0.6;

/// Curved creases are asked for as polylines with vertices this many radii apart, so
/// the points placed on their chords sit within (0.05r)²/8R of a curve of radius R.
const FEATURE_RESOLUTION: f64 = 0.05;

/// Depths of the wedge points below their segments' middles, in radii (drawn between).
const WEDGE_DEPTH: [f64; 2] = [0.6, 0.75];

/// Directions probed around a crease point (every 5°) to find the wedges beside it.
const WEDGE_DIRECTIONS: usize = 72;

/// Wedges of at most this many probed directions (170°) get a point; wider ones
/// (a flat surface, the outside of a convex crease) cannot be spanned by one
/// tetrahedron.
const NARROW_WEDGE: usize = 34;

/// The points placed so far, hashed in cells of side `gap` to find close ones.
struct Placed {
    gap: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
    points: Vec<([f64; 3], f64)>,
}

impl Placed {
    fn cell(&self, p: [f64; 3]) -> [i64; 3] {
        p.map(|x| (x / self.gap).floor() as i64)
    }

    /// Places `p` with signed distance `value` unless it is not finite or within `gap`
    /// of a point already placed; whether it was placed.
    fn place(&mut self, p: [f64; 3], value: f64) -> bool {
        if p.iter().any(|x| !x.is_finite()) {
            return false;
        }
        let c = self.cell(p);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                    if self.cells.get(&key).is_some_and(|near| {
                        near.iter()
                            .any(|&q| dist(self.points[q as usize].0, p) < self.gap)
                    }) {
                        return false;
                    }
                }
            }
        }
        self.cells
            .entry(c)
            .or_default()
            .push(self.points.len() as u32);
        self.points.push((p, value));
        true
    }
}

/// The points placed for `sdf`'s sharp features ([`Sdf::features`]) with their signed
/// distances, at sampling radius `r`: corners first, then each crease's points at
/// equal steps of arc length (value 0), then the wedge points beside the segments
/// between them (see the module's comment, jittered from `seed`); each left out if closer than
/// [`FEATURE_GAP`] r to one placed before it.
///
/// # Errors
/// [`MeshError::NonFiniteDistance`] where a wedge probe's distance is NaN.
pub(super) fn feature_points(
    sdf: &dyn Sdf,
    r: f64,
    seed: u64,
) -> Result<Vec<([f64; 3], f64)>, MeshError> {
    let features = sdf.features(FEATURE_RESOLUTION * r);
    let mut placed = Placed {
        gap: FEATURE_GAP * r,
        cells: HashMap::new(),
        points: Vec::new(),
    };
    for &corner in &features.corners {
        placed.place(corner, 0.0);
    }
    // The middles of the segments between consecutive crease points, with their
    // directions.
    let mut middles = Vec::new();
    for crease in &features.creases {
        let lengths: Vec<f64> = crease.windows(2).map(|s| dist(s[0], s[1])).collect();
        let length: f64 = lengths.iter().sum();
        if lengths.is_empty() || !length.is_finite() || length <= 0.0 {
            continue;
        }
        let closed = crease.first() == crease.last();
        let steps = (length / (CREASE_STEP * r)).ceil().max(1.0) as usize;
        let step = length / steps as f64;
        let (mut segment, mut start) = (0, 0.0);
        let mut previous: Option<[f64; 3]> = None;
        for k in 0..=steps {
            let at = k as f64 * step;
            while segment + 1 < lengths.len() && start + lengths[segment] < at {
                start += lengths[segment];
                segment += 1;
            }
            let t = if lengths[segment] > 0.0 {
                ((at - start) / lengths[segment]).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let p = lerp(crease[segment], crease[segment + 1], t);
            if k < steps || !closed {
                placed.place(p, 0.0);
            }
            if let Some(q) = previous {
                middles.push((lerp(q, p, 0.5), normalize(sub(p, q))));
            }
            previous = Some(p);
        }
    }
    let mut rng = SplitMix64::new(seed);
    for (p, tangent) in middles {
        for (q, value) in wedge_points(sdf, p, tangent, r, &mut rng)? {
            placed.place(q, value);
        }
    }
    Ok(placed.points)
}

/// A point [`WEDGE_DEPTH`] from `p` (a segment's middle on a crease) near the bisector
/// of each wedge narrower than [`NARROW_WEDGE`] probes (the runs of one sign among
/// [`WEDGE_DIRECTIONS`] probes on the circle of radius r about `p` across the crease's
/// direction `tangent`), jittered by `rng`, with its signed distance.
fn wedge_points(
    sdf: &dyn Sdf,
    p: [f64; 3],
    tangent: [f64; 3],
    r: f64,
    rng: &mut SplitMix64,
) -> Result<Vec<([f64; 3], f64)>, MeshError> {
    let helper = if tangent[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = normalize(cross(tangent, helper));
    let v = cross(tangent, u);
    let at = |angle: f64, reach: f64| {
        [0, 1, 2].map(|k| p[k] + reach * (angle.cos() * u[k] + angle.sin() * v[k]))
    };
    let step = std::f64::consts::TAU / WEDGE_DIRECTIONS as f64;
    let mut inside = [false; WEDGE_DIRECTIONS];
    for (k, side) in inside.iter_mut().enumerate() {
        let q = at(k as f64 * step, r);
        let value = sdf.distance(q);
        if value.is_nan() {
            return Err(MeshError::NonFiniteDistance { point: q });
        }
        *side = value < 0.0;
    }
    // Runs of one side, from a probe whose predecessor is on the other side.
    let Some(first) = (0..WEDGE_DIRECTIONS)
        .find(|&k| inside[k] != inside[(k + WEDGE_DIRECTIONS - 1) % WEDGE_DIRECTIONS])
    else {
        return Ok(Vec::new());
    };
    let mut wedges = Vec::new();
    let mut k = 0;
    while k < WEDGE_DIRECTIONS {
        let begin = (first + k) % WEDGE_DIRECTIONS;
        let mut length = 1;
        while length < WEDGE_DIRECTIONS
            && inside[(begin + length) % WEDGE_DIRECTIONS] == inside[begin]
        {
            length += 1;
        }
        if length <= NARROW_WEDGE {
            let middle = begin as f64 + 0.5 * (length - 1) as f64;
            let turn = (rng.next_f64() - 0.5) * length as f64 / 3.0;
            let reach = r * (WEDGE_DEPTH[0] + (WEDGE_DEPTH[1] - WEDGE_DEPTH[0]) * rng.next_f64());
            let q = at((middle + turn) * step, reach);
            let value = sdf.distance(q);
            if value.is_nan() {
                return Err(MeshError::NonFiniteDistance { point: q });
            }
            // A probe between two sign changes can still hit the surface (a thin part).
            if value != 0.0 {
                wedges.push((q, value));
            }
        }
        k += length;
    }
    Ok(wedges)
}
