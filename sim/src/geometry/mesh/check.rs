//! Checks that a welded triangle mesh bounds a solid: no degenerate faces, every
//! edge shared by exactly two faces, consistent winding, no self-intersection; and
//! that an open one is a surface a membrane can be made of (`check_surface`).

use std::path::Path;

use perifrac_math::{cross, dot, norm, sub};
use rayon::prelude::*;

use super::bvh::Bvh;
use super::{MeshFileError, TriMesh};

/// A face is of zero area when its area is below this times the squared
/// bounding-box diagonal.
const ZERO_AREA: f64 = 1e-14;

/// A segment crosses a face's plane only if both ends are farther than this
/// times the bounding-box diagonal from it: coplanar neighbours (a flat region
/// of a rotated mesh, with rounding in every coordinate) are not crossings.
const PLANE_TOLERANCE: f64 = 1e-9;

/// Runs every check in order (degenerate, closed, oriented, self-intersecting)
/// and returns the first failure.
pub(super) fn check(mesh: &TriMesh, path: &Path) -> Result<(), MeshFileError> {
    degenerate(mesh, path)?;
    let path = || path.to_path_buf();
    let (lo, hi) = mesh.bounds();
    let diagonal2 = dot(sub(hi, lo), sub(hi, lo));
    let edges = edge_counts(mesh);
    if edges.boundary + edges.non_manifold > 0 {
        return Err(MeshFileError::NotClosed {
            path: path(),
            boundary: edges.boundary,
            non_manifold: edges.non_manifold,
            edges: edges.unique,
        });
    }
    if edges.flipped > 0 {
        return Err(MeshFileError::InconsistentOrientation {
            path: path(),
            edges: edges.flipped,
        });
    }

    let (pairs, first_pair) = intersecting_pairs(mesh, PLANE_TOLERANCE * diagonal2.sqrt());
    if pairs > 0 {
        return Err(MeshFileError::SelfIntersecting {
            path: path(),
            pairs,
            first_pair: first_pair.unwrap_or((0, 0)),
        });
    }
    Ok(())
}

/// The checks of a surface that may be open (a membrane's sheet): no degenerate
/// face, no edge of more than two faces and no vertex where two sheets touch (a
/// manifold with boundary), consistent winding.
pub(super) fn check_surface(mesh: &TriMesh, path: &Path) -> Result<(), MeshFileError> {
    degenerate(mesh, path)?;
    let edges = edge_counts(mesh);
    // A vertex of a manifold surface with boundary has no or two boundary edges.
    let mut boundary_edges = vec![0u32; mesh.vertices.len()];
    for &(a, b) in &edges.boundary_edges {
        boundary_edges[a as usize] += 1;
        boundary_edges[b as usize] += 1;
    }
    let pinched = boundary_edges.iter().filter(|&&n| n > 2).count();
    if edges.non_manifold + pinched > 0 {
        return Err(MeshFileError::NotManifold {
            path: path.to_path_buf(),
            edges: edges.non_manifold,
            vertices: pinched,
        });
    }
    if edges.flipped > 0 {
        return Err(MeshFileError::InconsistentOrientation {
            path: path.to_path_buf(),
            edges: edges.flipped,
        });
    }
    Ok(())
}

/// How the undirected edges of a mesh are used.
struct EdgeCounts {
    /// Edges.
    unique: usize,
    /// Edges of one face.
    boundary: usize,
    /// The boundary edges (smaller vertex first).
    boundary_edges: Vec<(u32, u32)>,
    /// Edges of three or more faces.
    non_manifold: usize,
    /// Edges of two faces that run them the same way.
    flipped: usize,
}

fn edge_counts(mesh: &TriMesh) -> EdgeCounts {
    // Directed edges sorted by their undirected key.
    let mut edges: Vec<(u32, u32, bool)> = mesh
        .triangles
        .iter()
        .flat_map(|t| {
            [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(a, b)| (a.min(b), a.max(b), a < b))
        })
        .collect();
    edges.par_sort_unstable();
    let mut counts = EdgeCounts {
        unique: 0,
        boundary: 0,
        boundary_edges: Vec::new(),
        non_manifold: 0,
        flipped: 0,
    };
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
            j += 1;
        }
        counts.unique += 1;
        match j - i {
            1 => {
                counts.boundary += 1;
                counts.boundary_edges.push((edges[i].0, edges[i].1));
            }
            2 => counts.flipped += usize::from(edges[i].2 == edges[i + 1].2),
            _ => counts.non_manifold += 1,
        }
        i = j;
    }
    counts
}

/// Fails on faces with a repeated vertex or of (near) zero area.
fn degenerate(mesh: &TriMesh, path: &Path) -> Result<(), MeshFileError> {
    let path = || path.to_path_buf();
    let (lo, hi) = mesh.bounds();
    let diagonal2 = dot(sub(hi, lo), sub(hi, lo));
    let (mut repeated, mut zero_area, mut first) = (0, 0, None);
    for (f, t) in mesh.triangles.iter().enumerate() {
        let bad = if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            repeated += 1;
            true
        } else {
            let [a, b, c] = mesh.corners(f);
            let area = 0.5 * norm(cross(sub(b, a), sub(c, a)));
            // NaN areas count as zero.
            let zero = area.is_nan() || area <= ZERO_AREA * diagonal2;
            zero_area += usize::from(zero);
            zero
        };
        if bad && first.is_none() {
            first = Some(f);
        }
    }
    if let Some(first) = first {
        return Err(MeshFileError::Degenerate {
            path: path(),
            count: repeated + zero_area,
            repeated,
            zero_area,
            faces: mesh.triangles.len(),
            first,
        });
    }
    Ok(())
}

/// Number of pairs of faces that intersect other than in shared vertices or a
/// shared edge, and the first such pair (lowest indices).
fn intersecting_pairs(mesh: &TriMesh, tolerance: f64) -> (usize, Option<(usize, usize)>) {
    let bvh = Bvh::new((0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect());
    let per_face: Vec<(usize, Option<usize>)> = (0..mesh.triangles.len())
        .into_par_iter()
        .map(|f| {
            let tri = mesh.corners(f);
            let lo = [0, 1, 2].map(|k| tri[0][k].min(tri[1][k]).min(tri[2][k]));
            let hi = [0, 1, 2].map(|k| tri[0][k].max(tri[1][k]).max(tri[2][k]));
            let (mut count, mut first) = (0, None::<usize>);
            bvh.overlapping(lo, hi, |g| {
                if g > f && faces_intersect(mesh, f, g, tolerance) {
                    count += 1;
                    first = Some(first.map_or(g, |x| x.min(g)));
                }
            });
            (count, first)
        })
        .collect();
    let pairs = per_face.iter().map(|p| p.0).sum();
    let first = per_face
        .iter()
        .enumerate()
        .find_map(|(f, p)| p.1.map(|g| (f, g)));
    (pairs, first)
}

/// Whether faces `f` and `g` cross. Faces sharing an edge are taken as not
/// crossing (a fold onto itself would already break the orientation check);
/// faces sharing one vertex cross when the edge of either opposite the shared
/// vertex passes through the other; otherwise when any edge of one passes
/// through the other.
fn faces_intersect(mesh: &TriMesh, f: usize, g: usize, tolerance: f64) -> bool {
    let (tf, tg) = (mesh.triangles[f], mesh.triangles[g]);
    let shared: Vec<u32> = tf.iter().copied().filter(|v| tg.contains(v)).collect();
    let (pf, pg) = (mesh.corners(f), mesh.corners(g));
    match shared.len() {
        0 => {
            (0..3).any(|i| segment_crosses(pf[i], pf[(i + 1) % 3], pg, tolerance))
                || (0..3).any(|i| segment_crosses(pg[i], pg[(i + 1) % 3], pf, tolerance))
        }
        1 => {
            let s = shared[0];
            let opposite = |t: [u32; 3], p: [[f64; 3]; 3]| {
                let k = t.iter().position(|&v| v == s).unwrap_or(0);
                (p[(k + 1) % 3], p[(k + 2) % 3])
            };
            let (a, b) = opposite(tf, pf);
            let (c, d) = opposite(tg, pg);
            segment_crosses(a, b, pg, tolerance) || segment_crosses(c, d, pf, tolerance)
        }
        _ => false,
    }
}

/// Six times the signed volume of `abcd`.
fn orient(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    dot(sub(b, a), cross(sub(c, a), sub(d, a)))
}

/// Whether the segment `pq` passes through the triangle `t`: its ends lie on
/// both sides of the plane, each farther than `tolerance` from it, and the
/// crossing point inside the triangle (or on its border). Coplanar overlaps are
/// not detected.
fn segment_crosses(p: [f64; 3], q: [f64; 3], [a, b, c]: [[f64; 3]; 3], tolerance: f64) -> bool {
    let area2 = norm(cross(sub(b, a), sub(c, a)));
    // Signed distances from the plane.
    let sp = orient(a, b, c, p) / area2;
    let sq = orient(a, b, c, q) / area2;
    if !(sp > tolerance && sq < -tolerance || sp < -tolerance && sq > tolerance) {
        return false;
    }
    let u = orient(p, q, a, b);
    let v = orient(p, q, b, c);
    let w = orient(p, q, c, a);
    (u >= 0.0 && v >= 0.0 && w >= 0.0) || (u <= 0.0 && v <= 0.0 && w <= 0.0)
}
