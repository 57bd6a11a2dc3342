//! Fitting a background tetrahedralization to the surface: the warp and the stencils
//! of isosurface stuffing (Labelle & Shewchuk 2007, §3) generalized to tetrahedra of
//! any shape. Where stuffing's BCC stencils choose the diagonals of quadrilateral
//! faces by the lattice's parity, here every quadrilateral is split by the diagonal
//! through its vertex of smallest index, and a prism by the rule of Dompierre et al.
//! (1999), "How to subdivide pyramids, prisms and hexahedra into tetrahedra", which
//! follows that diagonal on each of its three quadrilaterals: two tetrahedra sharing
//! a face split it alike, so the mesh stays conforming.
//!
//! Stuffing's lattice is finer than any gap it meets; these background points are only
//! r apart, so a gap thinner than r (a slot, as the Kalthoff–Winkler notches at
//! λ = 3 mm) can pass between two inside points. Three tests keep such a gap open:
//! a tetrahedron with no vertex outside is kept only where its middle is inside, an
//! edge is cut at the zero nearest its inside end ([`first_zero`]), and a piece of a
//! cut tetrahedron whose middle lies more than [`GAP_MIDDLE`] r outside is dropped.
//! A convex shape is meshed as without them.

use std::collections::HashMap;

use rayon::prelude::*;

use perifrac_math::{dist, lerp, signed_volume};

use super::super::sdf::Sdf;
use super::super::{MeshError, TetMesh};
use super::delaunay::orient;
use super::{ALPHA, MIN_VOLUME, ROOT_TOLERANCE, find_zero};

/// Warping threshold for the neighbours of points on sharp features (see [`warp`]):
/// only a vertex this close to the surface, as a fraction of its edge, moves onto it
/// (one 1.6e-4 r under a box's face, left in place, was a boundary vertex off the
/// surface at seed 1 of `a_slotted_box_keeps_its_creases`).
const PROTECTED_ALPHA: f64 = 0.02;

/// A piece of a cut tetrahedron whose middle lies farther than this many r outside the
/// shape is not emitted: it spans a gap. Not 0, since on a concave surface a piece's
/// faces are chords that lie a little outside. With the two other tests of the module
/// doc, no shipped scene's mesh changed but the slotted Kalthoff–Winkler plate's (−459
/// of 79,212 particles at 3 mm), the figure's (−2 of 21,104) and the vases' (−1).
const GAP_MIDDLE: f64 = 0.1;

/// Most rounds of [`unpinch`].
const UNPINCH_ROUNDS: usize = 8;

fn opposite_signs(a: f64, b: f64) -> bool {
    (a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0)
}

/// The mesh of the inside of `sdf` cut from the background tetrahedra `tets` on
/// `points`, whose signed distances are `values`: `points` and `values` are warped
/// in place. `r` is the background's sampling radius; the first `features` points lie
/// on the shape's sharp features (value 0).
pub(super) fn cleave(
    sdf: &dyn Sdf,
    points: &mut [[f64; 3]],
    values: &mut [f64],
    tets: &[[u32; 4]],
    r: f64,
    features: usize,
) -> Result<TetMesh, MeshError> {
    let edges = cut_edges(tets, values);
    let tol = ROOT_TOLERANCE * r;
    let cuts: Vec<[f64; 3]> = edges
        .par_iter()
        .map(|&(u, v)| {
            let (a, b) = (points[u as usize], points[v as usize]);
            first_zero(sdf, a, values[u as usize], b, values[v as usize], tol)
                .map(|t| lerp(a, b, t))
        })
        .collect::<Result<_, _>>()?;
    warp(points, values, tets, &edges, &cuts, r, features);
    // Cut points that survive the warp (both ends still off the surface) become
    // vertices after the background's points, in edge order.
    let mut vertices = points.to_vec();
    let mut cut_vertex = HashMap::with_capacity(edges.len());
    for (&(u, v), &c) in edges.iter().zip(&cuts) {
        if opposite_signs(values[u as usize], values[v as usize]) {
            cut_vertex.insert((u, v), vertices.len() as u32);
            vertices.push(c);
        }
    }
    let cut = |a: u32, b: u32| cut_vertex[&(a.min(b), a.max(b))];
    let min_volume = MIN_VOLUME * r.powi(3);
    let mut out = Vec::with_capacity(tets.len());
    let values: &[f64] = values;
    let mut emit = |mut t: [u32; 4]| {
        let [a, b, c, d] = t.map(|v| vertices[v as usize]);
        let volume = signed_volume(a, b, c, d);
        // A piece of a cut tetrahedron (one with a cut point) whose middle lies well
        // outside spans a gap (a slot thinner than r, between two inside vertices on
        // its two faces). Whole tetrahedra had their middles tested below.
        let piece = t.iter().any(|&v| v as usize >= values.len());
        if piece && middle_distance(sdf, &vertices, values, t, GAP_MIDDLE * r) > GAP_MIDDLE * r {
            return;
        }
        if volume.abs() > min_volume {
            if volume < 0.0 {
                t.swap(0, 1);
            }
            out.push(t);
        }
    };
    for tet in tets {
        let sign = |v: u32| {
            let value = values[v as usize];
            if value < 0.0 {
                -1
            } else if value > 0.0 {
                1
            } else {
                0
            }
        };
        let with = |s: i8| {
            tet.iter()
                .copied()
                .filter(|&v| sign(v) == s)
                .collect::<Vec<u32>>()
        };
        let (neg, zero, pos) = (with(-1), with(0), with(1));
        match (neg.len(), zero.len(), pos.len()) {
            (0, 4, 0) | (1.., _, 0) => {
                // No vertex outside, but the points are r apart: a gap thinner than
                // that (a slot) can pass between them. Kept where its middle is inside
                // (strictly, when all four are on the surface: such a tetrahedron spans
                // a crease or a thin part, and the body would pinch without it).
                let value = middle_distance(sdf, &vertices, values, *tet, 0.0);
                if value.is_nan() {
                    return Err(MeshError::NonFiniteDistance {
                        point: middle(&vertices, *tet),
                    });
                }
                if value < 0.0 || (value == 0.0 && zero.len() < 4) {
                    emit(*tet);
                }
            }
            (0, _, _) => {}
            (1, _, _) => {
                // One inside vertex: a corner tetrahedron on the zeros and cut points.
                let n = neg[0];
                emit(tet.map(|v| if sign(v) > 0 { cut(n, v) } else { v }));
            }
            (2, 1, 1) => {
                // A pyramid on the quadrilateral n1 n2 c2 c1 with apex at the zero.
                let (n1, n2, p) = (neg[0], neg[1], pos[0]);
                pyramid(zero[0], [n1, n2, cut(n2, p), cut(n1, p)], &mut emit);
            }
            (2, 0, 2) => {
                let (n1, n2, p1, p2) = (neg[0], neg[1], pos[0], pos[1]);
                prism(
                    [n1, cut(n1, p1), cut(n1, p2)],
                    [n2, cut(n2, p1), cut(n2, p2)],
                    &mut emit,
                );
            }
            _ => {
                // Three inside vertices and one outside: a prism under the cut triangle.
                let p = pos[0];
                prism(
                    [neg[0], neg[1], neg[2]],
                    [cut(neg[0], p), cut(neg[1], p), cut(neg[2], p)],
                    &mut emit,
                );
            }
        }
    }
    unpinch(&vertices, &mut out);
    Ok(compact(vertices, out))
}

/// The mean of tetrahedron `t`'s four vertices.
fn middle(vertices: &[[f64; 3]], t: [u32; 4]) -> [f64; 3] {
    let [a, b, c, d] = t.map(|v| vertices[v as usize]);
    [0, 1, 2].map(|k| 0.25 * (a[k] + b[k] + c[k] + d[k]))
}

/// The signed distance at the [`middle`] of tetrahedron `t` of `vertices` (the first
/// `values.len()` of them with their signed distances, the rest cut points on the
/// surface), or a bound of it at or below `limit` where a vertex gives one: the
/// signed distance is 1-Lipschitz, so f(m) ≤ f(v) + |m − v|. Inside a body every
/// tetrahedron is settled by its vertices, without evaluating `sdf`.
fn middle_distance(
    sdf: &dyn Sdf,
    vertices: &[[f64; 3]],
    values: &[f64],
    t: [u32; 4],
    limit: f64,
) -> f64 {
    let m = middle(vertices, t);
    let bound = t
        .iter()
        .map(|&v| values.get(v as usize).copied().unwrap_or(0.0) + dist(m, vertices[v as usize]))
        .fold(f64::INFINITY, f64::min);
    if bound <= limit {
        bound
    } else {
        sdf.distance(m)
    }
}

/// Most sphere-tracing steps of [`first_zero`]; an edge not traced to its root in
/// these keeps the root [`find_zero`] brackets.
const TRACE_STEPS: usize = 64;

/// A trace of [`first_zero`] that comes this close (a fraction of the edge) to the
/// root [`find_zero`] gave has reached it: the zero it would cross there is that root,
/// found to `tol` in value rather than in position where the edge grazes the surface.
const SAME_ZERO: f64 = 1e-3;

/// The zero of `sdf` on the segment a–b (signed distances `fa`, `fb` of opposite signs)
/// nearest its inside end, as a fraction of the way from a. The background points are
/// r apart, so an edge can cross a gap thinner than that (a slot) and the surface
/// three times; a bracketing root-finder returns any of the zeros, and a corner
/// tetrahedron cut at the far face of the slot spans it. So the root [`find_zero`]
/// gives is checked by sphere tracing from the inside end (steps of |f|, which never
/// cross the surface of a signed distance or of a CSG bound of one): where the trace
/// reaches it, it is the first zero and is returned as it is, so an edge crossing the
/// surface once is cut where it always was; where the trace crosses the surface
/// first, the zero it crossed is refined and returned.
fn first_zero(
    sdf: &dyn Sdf,
    a: [f64; 3],
    fa: f64,
    b: [f64; 3],
    fb: f64,
    tol: f64,
) -> Result<f64, MeshError> {
    let root = find_zero(sdf, a, fa, b, fb, tol)?;
    let (from, f_from, to, end, flip) = if fa < 0.0 {
        (a, fa, b, root, false)
    } else {
        (b, fb, a, 1.0 - root, true)
    };
    let len = dist(from, to);
    if len == 0.0 {
        return Ok(root);
    }
    let (mut s, mut f) = (0.0, f_from);
    for _ in 0..TRACE_STEPS {
        let next = s + f.abs().max(tol) / len;
        if next >= end - SAME_ZERO {
            break;
        }
        let p = lerp(from, to, next);
        let g = sdf.distance(p);
        if g.is_nan() {
            return Err(MeshError::NonFiniteDistance { point: p });
        }
        if g >= 0.0 {
            let t = s + find_zero(sdf, lerp(from, to, s), f, p, g, tol)? * (next - s);
            return Ok(if flip { 1.0 - t } else { t });
        }
        (s, f) = (next, g);
    }
    Ok(root)
}

/// Where a crease of the surface passes between two background vertices, the inside
/// can meet itself along a single edge: a vertex in the corner the chord cuts off
/// keeps a fan of tetrahedra of its own around the edge, and the boundary is not a
/// manifold there (four boundary faces on one edge). Each such edge keeps its
/// largest fan by volume; the corner's slivers go. Repeated until no edge is pinched
/// (removing a fan can pinch a neighbouring edge), at most [`UNPINCH_ROUNDS`] times.
fn unpinch(vertices: &[[f64; 3]], tets: &mut Vec<[u32; 4]>) {
    for _ in 0..UNPINCH_ROUNDS {
        let mut faces: HashMap<[u32; 3], (u32, u32)> = HashMap::with_capacity(tets.len() * 2);
        for (t, tet) in tets.iter().enumerate() {
            for skip in 0..4 {
                let mut face = [0; 3];
                let mut n = 0;
                for (k, &v) in tet.iter().enumerate() {
                    if k != skip {
                        face[n] = v;
                        n += 1;
                    }
                }
                face.sort_unstable();
                faces.entry(face).or_insert((t as u32, 0)).1 += 1;
            }
        }
        let mut on_edge: HashMap<(u32, u32), usize> = HashMap::new();
        for (face, &(_, count)) in &faces {
            if count == 1 {
                for (a, b) in [(0, 1), (0, 2), (1, 2)] {
                    *on_edge.entry((face[a], face[b])).or_default() += 1;
                }
            }
        }
        let mut pinched: Vec<(u32, u32)> = on_edge
            .into_iter()
            .filter(|&(_, count)| count > 2)
            .map(|(edge, _)| edge)
            .collect();
        if pinched.is_empty() {
            return;
        }
        pinched.sort_unstable();
        let mut removed = vec![false; tets.len()];
        let incident = incidence(tets, vertices.len());
        for (u, v) in pinched {
            let around: Vec<usize> = incident[u as usize]
                .iter()
                .map(|&t| t as usize)
                .filter(|&t| !removed[t] && tets[t].contains(&v))
                .collect();
            // Fans: tetrahedra around the edge joined through faces holding it.
            let mut fan = vec![usize::MAX; around.len()];
            let mut fans = 0;
            for start in 0..around.len() {
                if fan[start] != usize::MAX {
                    continue;
                }
                fan[start] = fans;
                let mut stack = vec![start];
                while let Some(i) = stack.pop() {
                    for j in 0..around.len() {
                        let shared = tets[around[i]]
                            .iter()
                            .filter(|w| tets[around[j]].contains(w))
                            .count();
                        if fan[j] == usize::MAX && shared == 3 {
                            fan[j] = fans;
                            stack.push(j);
                        }
                    }
                }
                fans += 1;
            }
            let mut volume = vec![0.0; fans];
            for (i, &t) in around.iter().enumerate() {
                let [a, b, c, d] = tets[t].map(|w| vertices[w as usize]);
                volume[fan[i]] += signed_volume(a, b, c, d);
            }
            let keep = (0..fans)
                .max_by(|&x, &y| volume[x].total_cmp(&volume[y]))
                .unwrap_or(0);
            for (i, &t) in around.iter().enumerate() {
                if fan[i] != keep {
                    removed[t] = true;
                }
            }
        }
        let mut t = 0;
        tets.retain(|_| {
            t += 1;
            !removed[t - 1]
        });
    }
}

/// The background edges whose ends have opposite signs, as sorted pairs, sorted.
fn cut_edges(tets: &[[u32; 4]], values: &[f64]) -> Vec<(u32, u32)> {
    let mut edges: Vec<(u32, u32)> = tets
        .iter()
        .flat_map(|t| {
            [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
                .map(|(i, j)| (t[i].min(t[j]), t[i].max(t[j])))
        })
        .filter(|&(u, v)| opposite_signs(values[u as usize], values[v as usize]))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Labelle & Shewchuk's warp: a vertex with a cut point closer than [`ALPHA`] of its
/// edge's length moves onto its closest such cut point and its value becomes zero
/// (the cuts on its other edges vanish). Violations are taken closest first, so the
/// result does not depend on the order of the vertices; a move that would invert or
/// flatten a tetrahedron around the vertex is not made (the cut stays, and the
/// stencils fill the tetrahedron instead). The first `features` points (placed for
/// corners and creases, and the points beside them) and the inside vertices next to a
/// corner or crease point are warped only by cuts closer than [`PROTECTED_ALPHA`] of
/// their edge: warped onto a face, the only inside vertex near a corner left no
/// tetrahedron there to keep, and the corner was cut off (at seed 0 of
/// `a_box_keeps_its_corners_and_edges`; warping them freely gave 0.58λ deviations from
/// the box's creases and lost corners). Outside vertices warp as before (on a face they
/// keep the crease); holding them too gave the glass block of `tests/lattice.rs` 15% more
/// tetrahedra (10,900 against 9,449).
fn warp(
    points: &mut [[f64; 3]],
    values: &mut [f64],
    tets: &[[u32; 4]],
    edges: &[(u32, u32)],
    cuts: &[[f64; 3]],
    r: f64,
    features: usize,
) {
    let mut protected: Vec<bool> = (0..points.len()).map(|v| v < features).collect();
    for tet in tets {
        if tet
            .iter()
            .any(|&v| (v as usize) < features && values[v as usize] == 0.0)
        {
            for &v in tet {
                protected[v as usize] |= values[v as usize] < 0.0;
            }
        }
    }
    let mut violations = Vec::new();
    for (e, (&(u, v), &c)) in edges.iter().zip(cuts).enumerate() {
        let (a, b) = (points[u as usize], points[v as usize]);
        let length = dist(a, b);
        for (vertex, other, gap) in [(u, v, dist(a, c)), (v, u, dist(b, c))] {
            if gap < ALPHA * length {
                // Distances in units of 1e-9 r, so that mirror-image ties stay ties.
                let close = gap < PROTECTED_ALPHA * length;
                violations.push(((gap / r * 1e9).round() as u64, vertex, other, e, close));
            }
        }
    }
    violations.sort_unstable();
    let around = incidence(tets, points.len());
    let mut warped = vec![false; points.len()];
    for (_, vertex, other, e, close) in violations {
        if warped[vertex as usize] || warped[other as usize] {
            continue;
        }
        if protected[vertex as usize] && !close {
            continue;
        }
        let to = cuts[e];
        let keeps_orientation = around[vertex as usize].iter().all(|&t| {
            let corners =
                tets[t as usize].map(|w| if w == vertex { to } else { points[w as usize] });
            orient(corners[0], corners[1], corners[2], corners[3]) > 0.0
        });
        if keeps_orientation {
            points[vertex as usize] = to;
            values[vertex as usize] = 0.0;
            warped[vertex as usize] = true;
        }
    }
}

/// The tetrahedra around each vertex.
fn incidence(tets: &[[u32; 4]], vertices: usize) -> Vec<Vec<u32>> {
    let mut around = vec![Vec::new(); vertices];
    for (t, tet) in tets.iter().enumerate() {
        for &v in tet {
            around[v as usize].push(t as u32);
        }
    }
    around
}

/// The two tetrahedra of a pyramid with apex `apex` over the quadrilateral `quad`
/// (cyclic), split by the quadrilateral's diagonal through its smallest index.
fn pyramid(apex: u32, quad: [u32; 4], emit: &mut impl FnMut([u32; 4])) {
    let [q0, q1, q2, q3] = quad;
    if q0.min(q2) < q1.min(q3) {
        emit([apex, q0, q1, q2]);
        emit([apex, q0, q2, q3]);
    } else {
        emit([apex, q1, q2, q3]);
        emit([apex, q1, q3, q0]);
    }
}

/// The three tetrahedra of the prism between triangles `a` and `b` (a[i]–b[i] its
/// lateral edges), after Dompierre et al. (1999): the tetrahedron joining the
/// smallest index to the opposite triangle, and the pyramid left over.
fn prism(a: [u32; 3], b: [u32; 3], emit: &mut impl FnMut([u32; 4])) {
    let six = [a[0], a[1], a[2], b[0], b[1], b[2]];
    let smallest = (0..6).min_by_key(|&i| six[i]).expect("six vertices");
    let (near, far) = if smallest < 3 { (a, b) } else { (b, a) };
    let k = smallest % 3;
    let (n0, n1, n2) = (near[k], near[(k + 1) % 3], near[(k + 2) % 3]);
    let (f0, f1, f2) = (far[k], far[(k + 1) % 3], far[(k + 2) % 3]);
    emit([n0, f0, f1, f2]);
    pyramid(n0, [n1, n2, f2, f1], emit);
}

/// The mesh of the used vertices, renumbered in order of index.
fn compact(vertices: Vec<[f64; 3]>, mut tets: Vec<[u32; 4]>) -> TetMesh {
    let mut new_index = vec![u32::MAX; vertices.len()];
    for t in &tets {
        for &v in t {
            new_index[v as usize] = 0;
        }
    }
    let mut kept = Vec::new();
    for (v, p) in vertices.into_iter().enumerate() {
        if new_index[v] == 0 {
            new_index[v] = kept.len() as u32;
            kept.push(p);
        }
    }
    for t in &mut tets {
        *t = t.map(|v| new_index[v as usize]);
    }
    TetMesh {
        vertices: kept,
        tets,
    }
}
