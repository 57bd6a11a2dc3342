//! Sharp features of a shape's surface (corners and creases), which the unstructured
//! mesher places vertices on before it fills the rest with blue noise, so that a box's
//! edges and corners come out sharp instead of bevelled at random depths (issue 13).
//!
//! Primitives know theirs exactly; a [`Union`](super::Union) or a
//! [`Difference`](super::Difference) keeps the parts of its children's features that lie
//! on its own surface (each crease cut where it enters another child, the cut points
//! becoming corners) and adds the creases where a planar face of one child meets a
//! planar face of another (a slot's walls meeting the top of the box it is cut into).
//! A mesh file's creases are its edges whose faces' normals differ by more than
//! [`MESH_CREASE_ANGLE_DEG`].

use perifrac_math::{add, cross, dist, dot, lerp, norm, normalize, scale, sub};

/// The sharp features of a shape's surface.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Features {
    /// Points where creases meet or end (a box's 8 corners).
    pub corners: Vec<[f64; 3]>,
    /// Creases as polylines whose vertices lie on the crease; a curved crease's
    /// vertices are no further apart than the resolution asked for; a closed crease's
    /// last point repeats its first.
    pub creases: Vec<Vec<[f64; 3]>>,
    /// Planar faces as convex polygons (vertices in order around the face), for the
    /// creases where two shapes' faces meet in a union or a difference. Only
    /// primitives report faces; a union's or difference's faces are not passed on.
    pub faces: Vec<Vec<[f64; 3]>>,
}

/// A mesh file's edge is a crease when the normals of its two faces differ by more
/// than this (the surface turns by more than 30° across it); a vertex is a corner where
/// one crease ends, where three or more meet, or where a crease turns by more than this.
pub const MESH_CREASE_ANGLE_DEG: f64 = 30.0;

/// Sphere-tracing steps along a crease are at least the resolution over this: zeros
/// of the other shapes' distances closer together than that may be missed.
const MIN_STEP_PER_RESOLUTION: f64 = 8.0;

/// Bisection steps refining where a crease leaves the other shapes' outside.
const BISECTIONS: usize = 60;

/// A box's features: 8 corners, 12 edges, 6 faces.
pub(super) fn cuboid(center: [f64; 3], half: [f64; 3]) -> Features {
    let corner =
        |i: usize| [0, 1, 2].map(|k| center[k] + if i >> k & 1 == 1 { half[k] } else { -half[k] });
    let corners: Vec<[f64; 3]> = (0..8).map(corner).collect();
    let mut creases = Vec::with_capacity(12);
    for i in 0..8 {
        for k in 0..3 {
            if i >> k & 1 == 0 {
                creases.push(vec![corner(i), corner(i | 1 << k)]);
            }
        }
    }
    let mut faces = Vec::with_capacity(6);
    for k in 0..3 {
        let (u, v) = (1 << ((k + 1) % 3), 1 << ((k + 2) % 3));
        // Counter-clockwise seen from outside: the far face (u, v) turns about +k.
        faces.push(vec![corner(0), corner(v), corner(u | v), corner(u)]);
        let far = 1 << k;
        faces.push(vec![
            corner(far),
            corner(far | u),
            corner(far | u | v),
            corner(far | v),
        ]);
    }
    Features {
        corners,
        creases,
        faces,
    }
}

/// A capped cylinder's features: its two rim circles (closed polylines, vertices on
/// the circles at most `resolution` apart, at least 16 a rim) and its two caps (as
/// the polygons of those vertices).
pub(super) fn cylinder(
    center: [f64; 3],
    axis: usize,
    (u, v): (usize, usize),
    radius: f64,
    half_height: f64,
    resolution: f64,
) -> Features {
    let around = std::f64::consts::TAU * radius;
    let segments = (around / resolution).ceil().clamp(16.0, 1e6) as usize;
    let mut features = Features::default();
    for side in [-1.0, 1.0] {
        let rim: Vec<[f64; 3]> = (0..=segments)
            .map(|s| {
                let angle = std::f64::consts::TAU * (s % segments) as f64 / segments as f64;
                let mut p = center;
                p[axis] += side * half_height;
                p[u] += radius * angle.cos();
                p[v] += radius * angle.sin();
                p
            })
            .collect();
        features.faces.push(rim[..segments].to_vec());
        features.creases.push(rim);
    }
    features
}

/// The parts of `child`'s features where `keep` (a distance bound, |grad| ≤ 1) is not
/// negative, added to `out`: corners where it holds, creases cut into pieces where it
/// changes sign (the cut points are corners of the result). Faces are not passed on.
pub(super) fn restrict(
    child: &Features,
    keep: &dyn Fn([f64; 3]) -> f64,
    resolution: f64,
    out: &mut Features,
) {
    out.corners
        .extend(child.corners.iter().copied().filter(|&c| keep(c) >= 0.0));
    for crease in &child.creases {
        pieces(crease, keep, resolution, out);
    }
}

/// The creases where a planar face of one shape meets a planar face of another,
/// where `keep` is not negative, added to `out` with their ends as corners.
pub(super) fn meeting_faces(
    a: &Features,
    b: &Features,
    keep: &dyn Fn([f64; 3]) -> f64,
    resolution: f64,
    out: &mut Features,
) {
    for fa in &a.faces {
        for fb in &b.faces {
            if let Some((p, q)) = face_meet(fa, fb) {
                out.corners
                    .extend([p, q].into_iter().filter(|&c| keep(c) >= 0.0));
                pieces(&[p, q], keep, resolution, out);
            }
        }
    }
}

/// The pieces of polyline `crease` on which `keep ≥ 0`, appended to `out.creases`, the
/// points where `keep` changes sign appended to `out.corners`. Each segment is walked by
/// sphere tracing (no zero of a 1-Lipschitz `keep` lies within |keep(p)| of p; steps of
/// at least `resolution` / [`MIN_STEP_PER_RESOLUTION`]) and each sign change refined
/// by bisection.
fn pieces(
    crease: &[[f64; 3]],
    keep: &dyn Fn([f64; 3]) -> f64,
    resolution: f64,
    out: &mut Features,
) {
    let min_step = resolution / MIN_STEP_PER_RESOLUTION;
    let mut piece: Vec<[f64; 3]> = Vec::new();
    let finish = |piece: &mut Vec<[f64; 3]>, out: &mut Features| {
        if piece.len() >= 2 {
            out.creases.push(std::mem::take(piece));
        }
        piece.clear();
    };
    for segment in crease.windows(2) {
        let (a, b) = (segment[0], segment[1]);
        let length = dist(a, b);
        let mut t = 0.0;
        let mut value = keep(a);
        if value >= 0.0 && piece.is_empty() {
            piece.push(a);
        }
        while t < 1.0 {
            let step = if length > 0.0 {
                value.abs().max(min_step) / length
            } else {
                1.0
            };
            let next = (t + step).min(1.0);
            let next_value = keep(lerp(a, b, next));
            if (value >= 0.0) != (next_value >= 0.0) {
                let (mut lo, mut hi) = (t, next);
                for _ in 0..BISECTIONS {
                    let mid = 0.5 * (lo + hi);
                    if (keep(lerp(a, b, mid)) >= 0.0) == (value >= 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                // The kept side's end of the bracket, so the cut point keeps `keep ≥ 0`.
                let cut = lerp(a, b, if value >= 0.0 { lo } else { hi });
                out.corners.push(cut);
                piece.push(cut);
                if value >= 0.0 {
                    finish(&mut piece, out);
                }
            }
            (t, value) = (next, next_value);
        }
        if value >= 0.0 {
            piece.push(b);
        }
    }
    finish(&mut piece, out);
}

/// Newell's normal of a polygon (not normalized; its length is twice the area).
fn polygon_normal(polygon: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    for (i, &p) in polygon.iter().enumerate() {
        n = add(n, cross(p, polygon[(i + 1) % polygon.len()]));
    }
    n
}

/// The segment where two convex planar polygons meet, or `None` if they do not (or
/// are parallel): the line where their planes meet, clipped by both polygons.
fn face_meet(a: &[[f64; 3]], b: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let (na, nb) = (normalize(polygon_normal(a)), normalize(polygon_normal(b)));
    let direction = cross(na, nb);
    let length = norm(direction);
    if length < 1e-9 || a.len() < 3 || b.len() < 3 {
        return None;
    }
    let (da, db) = (dot(na, a[0]), dot(nb, b[0]));
    // The point of both planes closest to the origin.
    let origin = scale(
        add(
            scale(cross(nb, direction), da),
            scale(cross(direction, na), db),
        ),
        1.0 / (length * length),
    );
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for (polygon, normal) in [(a, na), (b, nb)] {
        for (i, &p) in polygon.iter().enumerate() {
            // Inward normal of edge i in the polygon's plane (Newell's normal turns
            // the polygon counter-clockwise).
            let inward = cross(normal, sub(polygon[(i + 1) % polygon.len()], p));
            let (at, rate) = (dot(inward, sub(origin, p)), dot(inward, direction));
            if rate.abs() < 1e-300 {
                if at < 0.0 {
                    return None;
                }
            } else if rate > 0.0 {
                lo = lo.max(-at / rate);
            } else {
                hi = hi.min(-at / rate);
            }
        }
    }
    let scale_of = a.iter().chain(b).map(|&p| norm(p)).fold(1e-300, f64::max);
    if hi - lo <= 1e-12 * scale_of {
        return None;
    }
    Some((
        add(origin, scale(direction, lo)),
        add(origin, scale(direction, hi)),
    ))
}

/// A closed triangle mesh's creases (edges whose two faces' normals differ by more
/// than [`MESH_CREASE_ANGLE_DEG`]) chained into polylines between corners (vertices
/// where one crease ends, three or more meet, or a crease turns by more than that
/// angle), and closed loops of creases without corners.
pub(crate) fn mesh(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    normals: &[[f64; 3]],
) -> Features {
    let cos_limit = MESH_CREASE_ANGLE_DEG.to_radians().cos();
    let mut by_edge: std::collections::BTreeMap<(u32, u32), Vec<usize>> = Default::default();
    for (t, tri) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); vertices.len()];
    for (&(a, b), faces) in &by_edge {
        let sharp = match faces[..] {
            [f, g] => dot(normals[f], normals[g]) < cos_limit,
            _ => false,
        };
        if sharp {
            around[a as usize].push(b);
            around[b as usize].push(a);
        }
    }
    let turns = |v: usize| {
        let [p, q] = [around[v][0], around[v][1]].map(|w| vertices[w as usize]);
        let (d1, d2) = (
            normalize(sub(vertices[v], p)),
            normalize(sub(q, vertices[v])),
        );
        dot(d1, d2) < cos_limit
    };
    let is_corner: Vec<bool> = (0..vertices.len())
        .map(|v| !around[v].is_empty() && (around[v].len() != 2 || turns(v)))
        .collect();
    let mut features = Features {
        corners: (0..vertices.len())
            .filter(|&v| is_corner[v])
            .map(|v| vertices[v])
            .collect(),
        ..Features::default()
    };
    let mut used: std::collections::HashSet<(u32, u32)> = Default::default();
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    // Walks from `start` through `next` until a corner or back at `start`.
    let walk = |start: u32, next: u32, used: &mut std::collections::HashSet<(u32, u32)>| {
        let mut line = vec![vertices[start as usize]];
        let (mut prev, mut at) = (start, next);
        used.insert(key(prev, at));
        loop {
            line.push(vertices[at as usize]);
            if is_corner[at as usize] || at == start {
                break;
            }
            let Some(&step) = around[at as usize]
                .iter()
                .find(|&&w| w != prev && !used.contains(&key(at, w)))
            else {
                break;
            };
            used.insert(key(at, step));
            (prev, at) = (at, step);
        }
        line
    };
    for (v, neighbours) in around.iter().enumerate() {
        if is_corner[v] {
            for &w in neighbours {
                if !used.contains(&key(v as u32, w)) {
                    let line = walk(v as u32, w, &mut used);
                    features.creases.push(line);
                }
            }
        }
    }
    for (v, neighbours) in around.iter().enumerate() {
        for &w in neighbours {
            if !used.contains(&key(v as u32, w)) {
                let line = walk(v as u32, w, &mut used);
                features.creases.push(line);
            }
        }
    }
    features
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_has_eight_corners_twelve_edges_and_six_faces() {
        let f = cuboid([0.0; 3], [1.0, 2.0, 3.0]);
        assert_eq!(
            (f.corners.len(), f.creases.len(), f.faces.len()),
            (8, 12, 6)
        );
        let length: f64 = f.creases.iter().map(|c| dist(c[0], c[1])).sum();
        assert!((length - 4.0 * (2.0 + 4.0 + 6.0)).abs() < 1e-12);
        // Every face's Newell normal points outward.
        for face in &f.faces {
            let n = polygon_normal(face);
            let middle = face.iter().fold([0.0; 3], |m, &p| add(m, scale(p, 0.25)));
            assert!(dot(n, middle) > 0.0);
        }
    }

    #[test]
    fn two_faces_meet_along_the_segment_in_both() {
        let big = cuboid([0.0; 3], [1.0; 3]);
        let slab = cuboid([0.0, 1.0, 0.0], [0.5, 0.5, 2.0]);
        // The slab's face x = 0.5 meets the big box's top y = 1 along z in [-1, 1].
        let (p, q) = face_meet(&slab.faces[1], &big.faces[3]).expect("they meet");
        let (p, q) = if p[2] < q[2] { (p, q) } else { (q, p) };
        for (got, want) in [(p, [0.5, 1.0, -1.0]), (q, [0.5, 1.0, 1.0])] {
            assert!(dist(got, want) < 1e-12, "{got:?} vs {want:?}");
        }
        assert!(
            face_meet(&big.faces[0], &big.faces[1]).is_none(),
            "parallel"
        );
    }

    #[test]
    fn a_crease_is_cut_where_the_kept_region_ends() {
        let mut out = Features::default();
        // Keep |x| ≥ 0.5 along the x axis from −2 to 2: two pieces, two cut points.
        pieces(
            &[[-2.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
            &|p| p[0].abs() - 0.5,
            0.1,
            &mut out,
        );
        assert_eq!(out.creases.len(), 2);
        assert_eq!(out.corners.len(), 2);
        assert!((out.creases[0][1][0] + 0.5).abs() < 1e-12);
        assert!((out.creases[1][0][0] - 0.5).abs() < 1e-12);
    }
}
