//! How the rim vertices of a crack (where it meets the original surface) may move, and
//! their smoothing move: see the module doc of [`super`].

use perifrac_math::{add, cross, dot, norm, sub};

use super::plane::plane_normal;
use super::{Constraint, PLANE_COS, STEP, area_vector};

/// The smoothing move of a rim vertex at `x` with constraint `c`, whose ring on the
/// crack surface (neighbours and theirs) is `ring` with centroid `mean`: half way,
/// within the constraint, to the plane fitted through the ring (through `mean`, its
/// normal the direction of least spread of the ring's points), and no further than
/// half the distance to `mean` nor out of the ball around `mean` through the ring's
/// farthest point. On a planar crack the move is nil wherever the ring
/// lies, so a rim vertex at a box edge, whose ring lies on the inner side of the
/// edge, is not pulled off the crack's plane as a move towards `mean` would pull it.
/// (The neighbours alone were measured too few: fitted to a zig-zag, their plane
/// tilted and carried rim vertices 0.7λ off the tilted cut.)
pub(super) fn rim_move(
    c: Constraint,
    x: [f64; 3],
    mean: [f64; 3],
    ring: impl Iterator<Item = [f64; 3]> + Clone,
) -> [f64; 3] {
    let radius = ring
        .clone()
        .map(|p| norm(sub(p, mean)))
        .fold(0.0f64, f64::max);
    let Some(n) = plane_normal(mean, ring) else {
        return [0.0; 3];
    };
    let d = c.project(n);
    let dd = dot(d, d);
    if dd <= 1e-12 {
        return [0.0; 3];
    }
    let offset = sub(mean, x);
    let mut m = d.map(|e| STEP * dot(n, offset) * e / dd);
    let cap = STEP * norm(offset);
    let l = norm(m);
    if l > cap {
        m = m.map(|e| e * cap / l);
    }
    // The vertex stays within the ball of the ring around its centroid: a move along
    // the constraint nearly parallel to the fitted plane would otherwise carry it
    // away from its ring, pass after pass.
    for _ in 0..4 {
        if norm(sub(add(x, m), mean)) <= radius {
            return m;
        }
        m = m.map(|e| e / 2.0);
    }
    [0.0; 3]
}

/// The original (not crack) triangles around each vertex: its own, and those around
/// the vertex it was split from (its root, in every fragment), with unit normals and
/// areas.
struct OriginalSurface<'a> {
    triangles: &'a [[u32; 3]],
    root: Vec<u32>,
    /// Unit normal and area of each boundary triangle (`None` for crack or degenerate
    /// ones).
    normal: Vec<Option<([f64; 3], f64)>>,
    /// Original triangles of each vertex.
    own: Vec<Vec<u32>>,
    /// Original triangles of each root vertex, over all its copies.
    star: Vec<Vec<u32>>,
}

impl OriginalSurface<'_> {
    /// Whether two of `v`'s own original triangles lie in one plane.
    fn on_flat_face(&self, v: u32) -> bool {
        let normals: Vec<[f64; 3]> = self.own[v as usize]
            .iter()
            .filter_map(|&i| self.normal[i as usize].map(|(n, _)| n))
            .collect();
        normals
            .iter()
            .enumerate()
            .any(|(k, n)| normals[k + 1..].iter().any(|m| dot(*n, *m) > PLANE_COS))
    }
}

/// How each vertex may move (`None`: it stays put). Vertices off the crack, or on an
/// edge not shared by exactly two boundary faces, stay put; crack vertices inside the
/// body are free; rim vertices (on crack and original faces) are classified by the
/// planes of their own original triangles (normals within [`PLANE_COS`] count as one),
/// a plane being a *flat face* when two or more of them lie in it:
///
/// - one plane: they slide within it;
/// - exactly one flat face and other planes that only tilt a little along some
///   direction within the face: they slide along that direction, the *edge axis*
///   ([`edge_axis`]). This is where a crack meets a box's edge, which the stuffing
///   turns into a band of tilted triangles between the two faces (no vertex lies on
///   the edge itself);
/// - otherwise two planes: they slide along the planes' intersection;
/// - otherwise (a corner, or three or more planes of a curved surface) they stay put.
///
/// In every case a vertex stays in the plane of each of its flat faces. A vertex of
/// curved surface whose own triangles span one or two planes slides in them, leaving
/// the curved surface (by up to 0.07λ on a ball: docs/embedded.md).
pub(super) fn constraints(
    points: &[[f64; 3]],
    parent: &[i32],
    triangles: &[[u32; 3]],
    crack: &[bool],
    on_crack: &[bool],
    fixed: &[bool],
) -> Vec<Option<Constraint>> {
    let nv = points.len();
    let mut root: Vec<u32> = Vec::with_capacity(nv);
    for (v, &p) in parent.iter().enumerate().take(nv) {
        root.push(if p < 0 { v as u32 } else { root[p as usize] });
    }
    let normal: Vec<Option<([f64; 3], f64)>> = triangles
        .iter()
        .zip(crack)
        .map(|(f, &c)| {
            let n = area_vector(points, *f);
            let l = norm(n);
            (!c && l > 0.0).then(|| (n.map(|x| x / l), l / 2.0))
        })
        .collect();
    let mut own: Vec<Vec<u32>> = vec![Vec::new(); nv];
    let mut star: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (i, f) in triangles.iter().enumerate() {
        if !crack[i] {
            for &v in f {
                own[v as usize].push(i as u32);
                star[root[v as usize] as usize].push(i as u32);
            }
        }
    }
    let surface = OriginalSurface {
        triangles,
        root,
        normal,
        own,
        star,
    };
    (0..nv)
        .map(|v| {
            if !on_crack[v] || fixed[v] {
                return None;
            }
            if surface.own[v].is_empty() {
                return Some(Constraint::Free);
            }
            let mut planes: Vec<[f64; 3]> = Vec::new();
            for &i in &surface.own[v] {
                if let Some((n, _)) = surface.normal[i as usize]
                    && !planes.iter().any(|m| dot(*m, n) > PLANE_COS)
                {
                    planes.push(n);
                }
            }
            let faces: Vec<[f64; 3]> = planes
                .iter()
                .copied()
                .filter(|&n| {
                    surface.own[v]
                        .iter()
                        .filter(|&&i| {
                            surface.normal[i as usize].is_some_and(|(m, _)| dot(m, n) > PLANE_COS)
                        })
                        .count()
                        >= 2
                })
                .collect();
            let line = |d: [f64; 3]| {
                let l = norm(d);
                (l > 0.0).then(|| Constraint::Line(d.map(|c| c / l)))
            };
            let two_planes = || match planes.as_slice() {
                [p, q] => line(cross(*p, *q)),
                _ => None,
            };
            match (planes.as_slice(), faces.as_slice()) {
                ([], _) => None,
                ([p], _) => Some(Constraint::Plane(*p)),
                (_, [face]) => edge_axis(v, *face, &surface)
                    .and_then(line)
                    .or_else(two_planes),
                _ => two_planes(),
            }
        })
        .collect()
}

/// Largest sine of the angle between the edge axis and the plane of an original
/// triangle at the vertex that is not in its flat face (15°): sliding along the axis
/// tilts such a triangle. The band a stuffed box edge becomes tilts by up to 8° along
/// the edge (sine 0.14, measured on the test block), while a box corner's third face
/// (90°) must keep its vertex put.
const MAX_AXIS_SINE: f64 = 0.26;

/// The direction within the flat face of normal `face` at vertex `v` most nearly
/// parallel to the original triangles around it (the least-squares null direction of
/// the area-weighted normals, projected into the face, of the triangles around `v`'s
/// root and its neighbours' roots, in all fragments), if every original triangle of
/// `v` outside the face is within [`MAX_AXIS_SINE`] of it and has two vertices on flat
/// faces (so it belongs to a band between flat faces: on a curved surface, which has
/// no flat faces, vertices stay put).
fn edge_axis(v: usize, face: [f64; 3], surface: &OriginalSurface) -> Option<[f64; 3]> {
    let helper = if face[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = cross(face, helper);
    let u = u.map(|c| c / norm(u));
    let w = cross(face, u);
    let star = |x: u32| surface.star[surface.root[x as usize] as usize].iter();
    let mut ring: Vec<u32> = star(v as u32)
        .flat_map(|&i| surface.triangles[i as usize])
        .flat_map(|x| star(x).copied())
        .collect();
    ring.sort_unstable();
    ring.dedup();
    let (mut p, mut q, mut r) = (0.0, 0.0, 0.0);
    for &i in &ring {
        if let Some((n, a)) = surface.normal[i as usize] {
            let (x, y) = (dot(n, u), dot(n, w));
            p += a * x * x;
            q += a * x * y;
            r += a * y * y;
        }
    }
    // Eigenvector of [[p, q], [q, r]] for its smaller eigenvalue.
    let smaller = 0.5 * (p + r) - (0.25 * (p - r) * (p - r) + q * q).sqrt();
    let (a, b) = if q.abs() > 1e-12 * (p + r) {
        (q, smaller - p)
    } else if p <= r {
        (1.0, 0.0)
    } else {
        (0.0, 1.0)
    };
    let axis = [0, 1, 2].map(|k| a * u[k] + b * w[k]);
    let axis = axis.map(|c| c / norm(axis));
    surface.own[v]
        .iter()
        .filter_map(|&i| surface.normal[i as usize].map(|(n, _)| (i, n)))
        .filter(|(_, n)| dot(*n, face) <= PLANE_COS)
        .all(|(i, n)| {
            dot(n, axis).abs() <= MAX_AXIS_SINE
                && surface.triangles[i as usize]
                    .iter()
                    .filter(|&&x| surface.on_flat_face(x))
                    .count()
                    >= 2
        })
        .then_some(axis)
}
