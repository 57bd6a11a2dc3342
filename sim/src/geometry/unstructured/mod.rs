//! An unstructured tetrahedral mesh of a signed-distance shape, for bodies whose
//! cracks must not follow a lattice (issue 13; `lattice = "unstructured"`).
//!
//! Chen et al. (2018, §5.2) mesh their bodies with TetGen, so their cracks have no
//! preferred directions; a BCC lattice, even turned, has weak planes that cracks
//! follow. Here the body is filled with blue-noise points (Poisson-disk samples,
//! seeded), the points are tetrahedralized (Delaunay, `delaunay.rs`), and the
//! tetrahedra are fitted to the surface as isosurface stuffing fits its lattice's
//! (Labelle & Shewchuk 2007; "lattice cleaving" of an arbitrary background mesh,
//! Bronson, Levine & Whitaker 2012): vertices close to the surface are warped onto it,
//! and a tetrahedron the surface cuts is replaced by the tetrahedra filling its inside
//! part. Boundary vertices lie on the zero set; every tetrahedron is positively
//! oriented. Unlike stuffing's, the dihedral angles are not bounded: Delaunay
//! tetrahedralizations of random points hold slivers, which the peridynamic model
//! takes as particles of small volume (forces weigh the neighbour's volume, not the
//! particle's own).
//!
//! Sharp features are sampled first (feature-aware sampling: Delaunay meshers of
//! piecewise-smooth shapes protect the sharp features with balls before they place
//! anything else, Cheng, Dey & Levine 2007, "A practical Delaunay meshing algorithm for
//! a large class of domains", as CGAL's Mesh_3 does): the shape's corners
//! ([`Sdf::features`]), then points along its creases and a point in each narrow wedge
//! beside them (`features.rs`); the darts keep r away from all of them. The surface
//! then runs through the creases instead of bevelling them at random depths.

mod cleave;
mod delaunay;
mod features;

use std::collections::HashMap;

use rayon::prelude::*;

use perifrac_math::{SplitMix64, dist};

use super::sdf::Sdf;
use super::stuffing::{MIN_VOLUME, ROOT_TOLERANCE, find_zero};
use super::{MeshError, TetMesh, checked_bounds, empty_mesh};

/// Poisson-disk radius over the target mean edge length: the mean edge of the
/// Delaunay tetrahedralization of the samples is then about the asked edge length (measured
/// by `a_ball_gets_a_conforming_mesh_of_its_volume_and_edge_length`: 1.04λ).
const RADIUS_PER_EDGE: f64 = 0.78;

/// Candidates tried in each background cell before it is left empty.
const CANDIDATES: usize = 24;

/// Samples are kept up to this many radii outside the surface, so that the
/// tetrahedra around the surface have outside vertices to cut against.
const OUTSIDE_MARGIN: f64 = 1.5;

/// Warping threshold: a vertex whose edge is cut closer than this fraction of the
/// edge's length moves onto the cut point (stuffing uses 0.25 and 0.41 on the BCC
/// lattice's two kinds of edge).
const ALPHA: f64 = 0.3;

/// Largest number of background cells the sampler will visit.
const MAX_CELLS: u64 = 100_000_000;

/// The seed of body `stream`'s points from the scene's `seed`.
pub fn mesh_seed(seed: u64, stream: u64) -> u64 {
    seed ^ stream.wrapping_mul(0x9e37_79b9_7f4a_7c15)
}

/// Meshes `sdf` with tetrahedra of mean edge length ≈ `edge_length` on blue-noise
/// points drawn from `seed` (the same seed gives the same mesh).
///
/// # Errors
/// [`MeshError::InvalidEdgeLength`], [`MeshError::InvalidBounds`],
/// [`MeshError::LatticeTooLarge`] (too many background cells),
/// [`MeshError::NonFiniteDistance`], or [`MeshError::EmptyMesh`] for a shape
/// thinner than the points resolve.
pub fn mesh_unstructured(sdf: &dyn Sdf, edge_length: f64, seed: u64) -> Result<TetMesh, MeshError> {
    let (min, max) = checked_bounds(sdf, edge_length)?;
    let r = RADIUS_PER_EDGE * edge_length;
    let Samples {
        mut points,
        mut values,
        features,
    } = sample(sdf, min, max, r, seed, edge_length)?;
    let tets = delaunay::tetrahedralize(&points);
    let mesh = cleave::cleave(sdf, &mut points, &mut values, &tets, r, features)?;
    if mesh.tets.is_empty() {
        return Err(empty_mesh(min, max, edge_length));
    }
    Ok(mesh)
}

/// The sampler's points with their signed distances; the first `features` were placed
/// for the shape's sharp features.
struct Samples {
    points: Vec<[f64; 3]>,
    values: Vec<f64>,
    features: usize,
}

/// Poisson-disk samples of radius `r` (no two closer than r) in the shape and up to
/// [`OUTSIDE_MARGIN`] r outside it, with their signed distances: first the points
/// placed for its sharp features ([`features::feature_points`]), then dart throwing in a
/// background grid of cells of side r/√3 (at most one dart a cell, none within r of a
/// feature point), the cells visited in a random order drawn from `seed`,
/// [`CANDIDATES`] darts a cell.
fn sample(
    sdf: &dyn Sdf,
    min: [f64; 3],
    max: [f64; 3],
    r: f64,
    seed: u64,
    edge_length: f64,
) -> Result<Samples, MeshError> {
    let cell = r / 3f64.sqrt();
    let pad = 2.0 * r;
    let origin = min.map(|m| m - pad);
    let dims = [0, 1, 2].map(|k| ((max[k] - min[k] + 2.0 * pad) / cell).ceil().max(1.0));
    let cells = dims.iter().product::<f64>();
    if cells > MAX_CELLS as f64 {
        let grow = (cells / MAX_CELLS as f64).cbrt();
        return Err(MeshError::LatticeTooLarge {
            points: cells as u64,
            limit: MAX_CELLS,
            edge_length,
            suggested_edge_length: edge_length * grow * 1.01,
        });
    }
    let [nx, ny, nz] = dims.map(|d| d as usize);
    let total = nx * ny * nz;
    // The signed distance at each cell's centre decides which cells are worth darts;
    // evaluated in parallel, in cell order.
    let centres: Vec<f64> = (0..total)
        .into_par_iter()
        .map(|c| {
            let (i, j, k) = (c % nx, c / nx % ny, c / (nx * ny));
            sdf.distance([
                origin[0] + (i as f64 + 0.5) * cell,
                origin[1] + (j as f64 + 0.5) * cell,
                origin[2] + (k as f64 + 0.5) * cell,
            ])
        })
        .collect();
    if let Some(c) = centres.iter().position(|d| d.is_nan()) {
        let (i, j, k) = (c % nx, c / nx % ny, c / (nx * ny));
        let point = [i, j, k].map(|n| n as f64 + 0.5);
        return Err(MeshError::NonFiniteDistance {
            point: [0, 1, 2].map(|a| origin[a] + point[a] * cell),
        });
    }
    // A cell can hold a kept sample if its centre is within half its diagonal (r/2)
    // of the kept region.
    let reach = OUTSIDE_MARGIN * r + 0.5 * r;
    let mut order: Vec<u32> = (0..total as u32)
        .filter(|&c| centres[c as usize] <= reach)
        .collect();
    let mut rng = SplitMix64::new(seed);
    for i in (1..order.len()).rev() {
        order.swap(i, rng.below(i + 1));
    }
    let mut grid = vec![u32::MAX; total];
    let on_features = features::feature_points(sdf, r, seed)?;
    // Feature points may be closer than r to each other, so a cell can hold several.
    let mut feature_cells: HashMap<usize, Vec<u32>> = HashMap::new();
    let mut has_features = vec![false; total];
    let (mut points, mut values) = (Vec::new(), Vec::new());
    for (p, value) in on_features {
        let index = [0, 1, 2].map(|k| ((p[k] - origin[k]) / cell).floor());
        if (0..3).any(|k| !(index[k] >= 0.0 && index[k] < dims[k])) {
            continue;
        }
        let c = index[0] as usize + nx * (index[1] as usize + ny * index[2] as usize);
        has_features[c] = true;
        feature_cells
            .entry(c)
            .or_default()
            .push(points.len() as u32);
        points.push(p);
        values.push(value);
    }
    let features = points.len();
    for c in order {
        let c = c as usize;
        let (i, j, k) = (c % nx, c / nx % ny, c / (nx * ny));
        for _ in 0..CANDIDATES {
            let p = [
                origin[0] + (i as f64 + rng.next_f64()) * cell,
                origin[1] + (j as f64 + rng.next_f64()) * cell,
                origin[2] + (k as f64 + rng.next_f64()) * cell,
            ];
            let crowded = (k.saturating_sub(2)..(k + 3).min(nz)).any(|c2| {
                (j.saturating_sub(2)..(j + 3).min(ny)).any(|c1| {
                    (i.saturating_sub(2)..(i + 3).min(nx)).any(|c0| {
                        let near = c0 + nx * (c1 + ny * c2);
                        let q = grid[near];
                        (q != u32::MAX && dist(points[q as usize], p) < r)
                            || (has_features[near]
                                && feature_cells[&near]
                                    .iter()
                                    .any(|&q| dist(points[q as usize], p) < r))
                    })
                })
            });
            if crowded {
                continue;
            }
            let value = sdf.distance(p);
            if value.is_nan() {
                return Err(MeshError::NonFiniteDistance { point: p });
            }
            if value <= OUTSIDE_MARGIN * r {
                grid[c] = points.len() as u32;
                points.push(p);
                values.push(value);
                break;
            }
        }
    }
    Ok(Samples {
        points,
        values,
        features,
    })
}

#[cfg(test)]
mod tests;
