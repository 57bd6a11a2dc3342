//! How closely a tet mesh's boundary follows the input surface, and snapping
//! that brings it closer where the lattice mesher bevelled a feature.
//!
//! Isosurface stuffing puts every boundary vertex on the zero set of the
//! signed distance, but a feature of the surface (a crease, a tip) finer than
//! the lattice is cut off: the boundary triangles span across it. [`conform`]
//! moves, for every surface vertex and every sample (λ/4 apart) along a crease
//! ([`CREASE_ANGLE_DEG`]) farther than [`SNAP_THRESHOLD`]·λ from the tet
//! boundary, the nearest boundary vertex onto the feature (in a few passes),
//! and projects every other
//! boundary vertex onto its closest surface point; each move is kept only if
//! every tet around the vertex stays positive and within the dihedral bounds
//! ([`MIN_DIHEDRAL_DEG`], [`MAX_DIHEDRAL_DEG`], or no worse than before),
//! otherwise the vertex goes back. It then measures the two-sided Hausdorff
//! distance between the boundary and the surface.

use perifrac_math::{cross, dist, dot, normalize, signed_volume, sub};
use rayon::prelude::*;

use super::bvh::Bvh;
use super::{MeshSdf, TriMesh};
use crate::geometry::{TetMesh, dihedral_range};

/// Surface vertices farther than this (in λ) from the tet boundary pull the
/// nearest boundary vertex onto them.
pub const SNAP_THRESHOLD: f64 = 0.05;

/// A snapped vertex's tets keep dihedral angles of at least this (degrees),
/// unless they had smaller ones before.
pub const MIN_DIHEDRAL_DEG: f64 = 10.0;

/// A snapped vertex's tets keep dihedral angles of at most this (degrees),
/// unless they had larger ones before.
pub const MAX_DIHEDRAL_DEG: f64 = 165.0;

/// Passes of feature snapping.
const SNAP_PASSES: usize = 3;

/// Sample spacing on the surfaces when measuring, in λ.
const SAMPLE_SPACING: f64 = 0.1;

/// The fit of a tet mesh to the surface it fills, in units of the resolution λ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conformity {
    /// Two-sided Hausdorff distance: the larger of the farthest boundary point
    /// from the surface and the farthest surface point from the boundary (in λ).
    pub max: f64,
    /// Mean distance over all samples of both sides (in λ).
    pub mean: f64,
    /// Where the largest distance was found (a sample point on the boundary or
    /// on the surface).
    pub worst_point: [f64; 3],
    /// Boundary vertices moved by snapping.
    pub snapped: usize,
}

/// Snaps the boundary of `tets` (meshed from `surface` at resolution
/// `lambda`) onto `surface` where that keeps the tets valid, then measures the
/// fit (see the module documentation).
pub fn conform(tets: &mut TetMesh, surface: &TriMesh, sdf: &MeshSdf, lambda: f64) -> Conformity {
    let incident = incident_tets(tets);
    let boundary = tets.boundary_faces();
    let mut on_boundary = vec![false; tets.vertices.len()];
    for f in &boundary {
        for &v in f {
            on_boundary[v as usize] = true;
        }
    }
    // (b) Features (surface vertices, then crease samples): each far from the
    // boundary pulls the nearest unmoved vertex of the closest boundary face
    // onto it. Moved vertices stay put; a few passes, each with the boundary
    // as moved so far. (Pulling vertices to face centroids as well was tried
    // and made the fit worse: a vertex slid along a curved surface leaves
    // longer chords behind.)
    let features = feature_points(surface, lambda);
    let mut snapped = vec![false; tets.vertices.len()];
    for _ in 0..SNAP_PASSES {
        let boundary_bvh = face_bvh(tets, &boundary);
        let pulls: Vec<Option<(u32, [f64; 3])>> = features
            .par_iter()
            .map(|feature| {
                let p = feature.point;
                let c = boundary_bvh.closest(p)?;
                if c.distance_squared.sqrt() <= SNAP_THRESHOLD * lambda {
                    return None;
                }
                let v = boundary[c.triangle]
                    .into_iter()
                    .filter(|&v| !snapped[v as usize])
                    .min_by(|&a, &b| {
                        dist(tets.vertices[a as usize], p)
                            .total_cmp(&dist(tets.vertices[b as usize], p))
                            .then(a.cmp(&b))
                    })?;
                Some((v, feature.target(tets.vertices[v as usize])))
            })
            .collect();
        let mut moved = false;
        for (v, target) in pulls.into_iter().flatten() {
            if !snapped[v as usize] && try_move(tets, &incident, v, target) {
                snapped[v as usize] = true;
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
    // (a) Every other boundary vertex onto its closest surface point.
    let targets: Vec<Option<[f64; 3]>> = (0..tets.vertices.len())
        .into_par_iter()
        .map(|v| {
            if !on_boundary[v] || snapped[v] {
                return None;
            }
            let p = tets.vertices[v];
            let c = sdf.closest_point(p);
            (dist(c, p) > 1e-9 * lambda).then_some(c)
        })
        .collect();
    for (v, target) in targets.into_iter().enumerate() {
        if let Some(target) = target
            && try_move(tets, &incident, v as u32, target)
        {
            snapped[v] = true;
        }
    }
    let (max, mean, worst_point) = hausdorff(tets, &boundary, surface, sdf, lambda);
    Conformity {
        max,
        mean,
        worst_point,
        snapped: snapped.iter().filter(|&&s| s).count(),
    }
}

/// Faces meeting at an edge at a dihedral angle sharper than this (the angle
/// between their normals, degrees) make it a crease.
pub const CREASE_ANGLE_DEG: f64 = 30.0;

/// A point of a surface feature: a vertex, or a sample on a crease segment.
struct FeaturePoint {
    point: [f64; 3],
    /// The crease segment the point samples, if any.
    segment: Option<([f64; 3], [f64; 3])>,
}

impl FeaturePoint {
    /// Where a boundary vertex at `p` pulled by this feature goes: the feature
    /// vertex, or the closest point of the crease segment.
    fn target(&self, p: [f64; 3]) -> [f64; 3] {
        match self.segment {
            None => self.point,
            Some((a, b)) => {
                let ab = [0, 1, 2].map(|k| b[k] - a[k]);
                let ap = [0, 1, 2].map(|k| p[k] - a[k]);
                let len2: f64 = ab.iter().map(|x| x * x).sum();
                let t = ((0..3).map(|k| ab[k] * ap[k]).sum::<f64>() / len2).clamp(0.0, 1.0);
                [0, 1, 2].map(|k| a[k] + t * ab[k])
            }
        }
    }
}

/// The surface's vertices, then samples every λ/4 along its creases.
fn feature_points(surface: &TriMesh, lambda: f64) -> Vec<FeaturePoint> {
    let mut points: Vec<FeaturePoint> = surface
        .vertices
        .iter()
        .map(|&point| FeaturePoint {
            point,
            segment: None,
        })
        .collect();
    let normals: Vec<[f64; 3]> = (0..surface.triangles.len())
        .map(|t| {
            let [a, b, c] = surface.corners(t);
            normalize(cross(sub(b, a), sub(c, a)))
        })
        .collect();
    let mut edges: Vec<(u32, u32, usize)> = surface
        .triangles
        .iter()
        .enumerate()
        .flat_map(|(t, tri)| {
            [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])]
                .map(|(a, b)| (a.min(b), a.max(b), t))
        })
        .collect();
    edges.sort_unstable();
    let cos_crease = CREASE_ANGLE_DEG.to_radians().cos();
    for pair in edges.chunks_exact(2) {
        let ((a, b, f), (_, _, g)) = (pair[0], pair[1]);
        if dot(normals[f], normals[g]) >= cos_crease {
            continue;
        }
        let (pa, pb) = (surface.vertices[a as usize], surface.vertices[b as usize]);
        let n = (dist(pa, pb) / (0.25 * lambda)).ceil() as usize;
        for i in 1..n {
            let t = i as f64 / n as f64;
            points.push(FeaturePoint {
                point: [0, 1, 2].map(|k| pa[k] + t * (pb[k] - pa[k])),
                segment: Some((pa, pb)),
            });
        }
    }
    points
}

/// Two-sided Hausdorff distance and mean distance (in λ) between the boundary
/// faces of `tets` and `surface`, sampled at `SAMPLE_SPACING` = 0.1 λ, and the
/// sample point where the largest distance was found.
pub fn hausdorff(
    tets: &TetMesh,
    boundary: &[[u32; 3]],
    surface: &TriMesh,
    sdf: &MeshSdf,
    lambda: f64,
) -> (f64, f64, [f64; 3]) {
    let boundary_bvh = face_bvh(tets, boundary);
    let spacing = SAMPLE_SPACING * lambda;
    let to_surface: Vec<Samples> = boundary
        .par_iter()
        .map(|f| {
            let tri = f.map(|v| tets.vertices[v as usize]);
            sample(tri, spacing, |p| dist(sdf.closest_point(p), p))
        })
        .collect();
    let from_surface: Vec<Samples> = (0..surface.triangles.len())
        .into_par_iter()
        .map(|t| {
            sample(surface.corners(t), spacing, |p| {
                boundary_bvh
                    .closest(p)
                    .map_or(f64::INFINITY, |c| c.distance_squared.sqrt())
            })
        })
        .collect();
    let mut all = Samples::default();
    for s in to_surface.into_iter().chain(from_surface) {
        all.merge(s);
    }
    (
        all.max / lambda,
        all.sum / all.count.max(1) as f64 / lambda,
        all.worst,
    )
}

/// Distance statistics over sample points.
#[derive(Default)]
struct Samples {
    max: f64,
    worst: [f64; 3],
    sum: f64,
    count: usize,
}

impl Samples {
    fn add(&mut self, p: [f64; 3], d: f64) {
        if d > self.max {
            self.max = d;
            self.worst = p;
        }
        self.sum += d;
        self.count += 1;
    }

    fn merge(&mut self, other: Samples) {
        if other.max > self.max {
            self.max = other.max;
            self.worst = other.worst;
        }
        self.sum += other.sum;
        self.count += other.count;
    }
}

/// `distance` over points of triangle `tri` on a barycentric grid fine enough
/// for `spacing`.
fn sample(tri: [[f64; 3]; 3], spacing: f64, distance: impl Fn([f64; 3]) -> f64) -> Samples {
    let longest = dist(tri[0], tri[1])
        .max(dist(tri[1], tri[2]))
        .max(dist(tri[2], tri[0]));
    let n = ((longest / spacing).ceil() as usize).clamp(1, 1000);
    let mut samples = Samples::default();
    for i in 0..=n {
        for j in 0..=n - i {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let w = 1.0 - u - v;
            let p = [0, 1, 2].map(|k| w * tri[0][k] + u * tri[1][k] + v * tri[2][k]);
            samples.add(p, distance(p));
        }
    }
    samples
}

fn face_bvh(tets: &TetMesh, faces: &[[u32; 3]]) -> Bvh {
    Bvh::new(
        faces
            .iter()
            .map(|f| f.map(|v| tets.vertices[v as usize]))
            .collect(),
    )
}

/// Tets around each vertex (CSR: offsets, tet indices).
fn incident_tets(tets: &TetMesh) -> (Vec<usize>, Vec<u32>) {
    let mut offsets = vec![0usize; tets.vertices.len() + 1];
    for t in &tets.tets {
        for &v in t {
            offsets[v as usize + 1] += 1;
        }
    }
    for v in 0..tets.vertices.len() {
        offsets[v + 1] += offsets[v];
    }
    let mut fill = offsets.clone();
    let mut list = vec![0u32; offsets[tets.vertices.len()]];
    for (t, tet) in tets.tets.iter().enumerate() {
        for &v in tet {
            list[fill[v as usize]] = t as u32;
            fill[v as usize] += 1;
        }
    }
    (offsets, list)
}

/// Moves vertex `v` to `target` if every tet around it stays positive and
/// within the dihedral bounds (or no worse than before); reverts it otherwise.
fn try_move(
    tets: &mut TetMesh,
    (offsets, list): &(Vec<usize>, Vec<u32>),
    v: u32,
    target: [f64; 3],
) -> bool {
    let around = &list[offsets[v as usize]..offsets[v as usize + 1]];
    let range = |m: &TetMesh| {
        around.iter().fold(
            (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY),
            |acc, &t| {
                let p = m.tets[t as usize].map(|i| m.vertices[i as usize]);
                let (lo, hi) = dihedral_range(p);
                let volume = signed_volume(p[0], p[1], p[2], p[3]);
                (acc.0.min(lo), acc.1.max(hi), acc.2.min(volume))
            },
        )
    };
    let (lo0, hi0, _) = range(tets);
    let old = tets.vertices[v as usize];
    tets.vertices[v as usize] = target;
    let (lo, hi, volume) = range(tets);
    let ok = volume > 0.0 && lo >= MIN_DIHEDRAL_DEG.min(lo0) && hi <= MAX_DIHEDRAL_DEG.max(hi0);
    if !ok {
        tets.vertices[v as usize] = old;
    }
    ok
}
