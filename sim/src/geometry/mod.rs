//! Geometry for building bodies to simulate: solid shapes described by
//! signed distance functions ([`sdf`]), the isosurface-stuffing tetrahedral
//! mesher that fills them ([`stuffing`]), and the [`TetMesh`] it produces.

pub mod discretize;
pub mod mesh;
#[cfg(test)]
mod mesh_check;
pub mod sdf;
pub mod shape;
pub mod stuffing;
pub mod unstructured;

use std::fmt;

use perifrac_math::{TET_FACES, cross, dist, dot, norm, signed_volume, sub};

pub use self::sdf::{Ball, Cuboid, Cylinder, Difference, Sdf, Union};
pub use self::stuffing::{random_rotation, stuff, stuff_rotated};

/// Why a shape could not be meshed.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshError {
    /// The target edge length was zero, negative, infinite, NaN, or too large
    /// to place a lattice in floating point.
    InvalidEdgeLength(f64),
    /// The shape's bounds are not finite, or enclose nothing (`min >= max` on some axis).
    InvalidBounds {
        /// Lower corner reported by the shape.
        min: [f64; 3],
        /// Upper corner reported by the shape.
        max: [f64; 3],
    },
    /// The lattice needed at this edge length has too many points.
    LatticeTooLarge {
        /// Number of lattice points that would be needed.
        points: u64,
        /// Largest number of lattice points allowed.
        limit: u64,
        /// The edge length that was asked for.
        edge_length: f64,
        /// An edge length that keeps the lattice within the limit.
        suggested_edge_length: f64,
    },
    /// The signed distance function returned NaN.
    NonFiniteDistance {
        /// Where it was evaluated.
        point: [f64; 3],
    },
    /// No tetrahedra were produced: the shape is thinner than the lattice resolves.
    EmptyMesh {
        /// The edge length that was asked for.
        edge_length: f64,
        /// A smaller edge length that should resolve the shape.
        suggested_edge_length: f64,
    },
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidEdgeLength(l) => {
                write!(
                    f,
                    "edge length must be a finite, positive, representable size, got {l}"
                )
            }
            Self::InvalidBounds { min, max } => write!(
                f,
                "shape bounds must be finite and non-empty, got min {min:?} and max {max:?}"
            ),
            Self::LatticeTooLarge {
                points,
                limit,
                edge_length,
                suggested_edge_length,
            } => write!(
                f,
                "edge length {edge_length} needs a lattice of {points} points, more than the \
                 limit of {limit}; use an edge length of at least {suggested_edge_length:.3e}"
            ),
            Self::NonFiniteDistance { point } => {
                write!(f, "signed distance function returned NaN at {point:?}")
            }
            Self::EmptyMesh {
                edge_length,
                suggested_edge_length,
            } => write!(
                f,
                "meshing at edge length {edge_length} produced no tetrahedra: the shape is \
                 thinner than the lattice resolves; use a smaller edge length, such as \
                 {suggested_edge_length:.3e}"
            ),
        }
    }
}

impl std::error::Error for MeshError {}

/// The bounds of `sdf`, after checking them and `edge_length` (both meshers).
fn checked_bounds(sdf: &dyn sdf::Sdf, edge_length: f64) -> Result<([f64; 3], [f64; 3]), MeshError> {
    if !(edge_length.is_finite() && edge_length > 0.0) {
        return Err(MeshError::InvalidEdgeLength(edge_length));
    }
    let (min, max) = sdf.bounds();
    let finite = (0..3).all(|k| (max[k] - min[k]).is_finite());
    if !finite || (0..3).any(|k| min[k] >= max[k]) {
        return Err(MeshError::InvalidBounds { min, max });
    }
    Ok((min, max))
}

/// The error for a shape meshed at `edge_length` into no tetrahedra, with an edge
/// length that resolves its thinnest side.
fn empty_mesh(min: [f64; 3], max: [f64; 3], edge_length: f64) -> MeshError {
    let thinnest = (0..3)
        .map(|k| max[k] - min[k])
        .fold(f64::INFINITY, f64::min);
    MeshError::EmptyMesh {
        edge_length,
        suggested_edge_length: (0.25 * thinnest).min(0.5 * edge_length),
    }
}

/// A tetrahedral mesh: shared vertices and tetrahedra indexing them.
///
/// Meshes made by [`stuff`] have every tetrahedron positively oriented
/// (signed volume > 0) and are conforming (two tetrahedra meet in a whole
/// shared face, edge or vertex, or not at all).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TetMesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Tetrahedra as four indices into `vertices`.
    pub tets: Vec<[u32; 4]>,
}

/// Shape and size statistics of a [`TetMesh`], from [`TetMesh::quality`].
///
/// Edge statistics run over the six edges of every tetrahedron, so an edge
/// shared by several tetrahedra counts once per tetrahedron. An empty mesh
/// reports zeros.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshQuality {
    /// Smallest dihedral angle of any tetrahedron, in degrees.
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle of any tetrahedron, in degrees.
    pub max_dihedral_deg: f64,
    /// Shortest edge length.
    pub min_edge: f64,
    /// Mean edge length.
    pub mean_edge: f64,
    /// Longest edge length.
    pub max_edge: f64,
    /// Number of tetrahedra.
    pub tets: usize,
}

/// Pairs of local vertex indices forming the six edges of a tetrahedron.
const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

impl TetMesh {
    fn corners(&self, t: usize) -> [[f64; 3]; 4] {
        self.tets[t].map(|v| self.vertices[v as usize])
    }

    /// Signed volume of tetrahedron `t` (positive when positively oriented).
    ///
    /// # Panics
    /// If `t` or one of its vertex indices is out of range.
    pub fn volume(&self, t: usize) -> f64 {
        let [a, b, c, d] = self.corners(t);
        signed_volume(a, b, c, d)
    }

    /// Barycentre (vertex average) of tetrahedron `t`.
    ///
    /// # Panics
    /// If `t` or one of its vertex indices is out of range.
    pub fn barycentre(&self, t: usize) -> [f64; 3] {
        let p = self.corners(t);
        [0, 1, 2].map(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]))
    }

    /// Sum of the signed volumes of all tetrahedra.
    ///
    /// # Panics
    /// If a vertex index is out of range.
    pub fn total_volume(&self) -> f64 {
        (0..self.tets.len()).map(|t| self.volume(t)).sum()
    }

    /// Mean length of the six edges of every tetrahedron (an edge counts once
    /// per tetrahedron using it); 0 for an empty mesh.
    ///
    /// # Panics
    /// If a vertex index is out of range.
    pub fn mean_edge_length(&self) -> f64 {
        if self.tets.is_empty() {
            return 0.0;
        }
        let sum: f64 = (0..self.tets.len())
            .map(|t| {
                let p = self.corners(t);
                EDGES.iter().map(|&[i, j]| dist(p[i], p[j])).sum::<f64>()
            })
            .sum();
        sum / (6 * self.tets.len()) as f64
    }

    /// Dihedral angle and edge length statistics over all tetrahedra.
    ///
    /// # Panics
    /// If a vertex index is out of range.
    pub fn quality(&self) -> MeshQuality {
        if self.tets.is_empty() {
            return MeshQuality {
                min_dihedral_deg: 0.0,
                max_dihedral_deg: 0.0,
                min_edge: 0.0,
                mean_edge: 0.0,
                max_edge: 0.0,
                tets: 0,
            };
        }
        let mut q = MeshQuality {
            min_dihedral_deg: f64::INFINITY,
            max_dihedral_deg: f64::NEG_INFINITY,
            min_edge: f64::INFINITY,
            mean_edge: 0.0,
            max_edge: f64::NEG_INFINITY,
            tets: self.tets.len(),
        };
        let mut edge_sum = 0.0;
        for t in 0..self.tets.len() {
            let p = self.corners(t);
            for &[i, j] in &EDGES {
                let l = dist(p[i], p[j]);
                edge_sum += l;
                q.min_edge = q.min_edge.min(l);
                q.max_edge = q.max_edge.max(l);
            }
            let (lo, hi) = dihedral_range(p);
            q.min_dihedral_deg = q.min_dihedral_deg.min(lo);
            q.max_dihedral_deg = q.max_dihedral_deg.max(hi);
        }
        q.mean_edge = edge_sum / (6 * self.tets.len()) as f64;
        q
    }

    /// Faces used by exactly one tetrahedron, wound so that their right-hand
    /// normals point out of the tetrahedron owning them.
    ///
    /// # Panics
    /// If a vertex index is out of range.
    pub fn boundary_faces(&self) -> Vec<[u32; 3]> {
        // Bucket every face by its smallest vertex (a counting sort), then
        // sort each small bucket by the other two vertices to find repeats.
        let n = self.vertices.len();
        let mut start = vec![0usize; n + 1];
        for tet in &self.tets {
            for face in TET_FACES {
                let m = face.iter().map(|&i| tet[i]).min().unwrap_or(0);
                start[m as usize + 1] += 1;
            }
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut entries = vec![(0u32, 0u32, 0usize); 4 * self.tets.len()];
        for (t, tet) in self.tets.iter().enumerate() {
            for (f, face) in TET_FACES.iter().enumerate() {
                let mut key = face.map(|i| tet[i]);
                key.sort_unstable();
                let slot = &mut fill[key[0] as usize];
                entries[*slot] = (key[1], key[2], 4 * t + f);
                *slot += 1;
            }
        }
        let mut faces = Vec::new();
        for v in 0..n {
            let bucket = &mut entries[start[v]..start[v + 1]];
            bucket.sort_unstable();
            let mut i = 0;
            while i < bucket.len() {
                let mut j = i + 1;
                while j < bucket.len() && bucket[j].0 == bucket[i].0 && bucket[j].1 == bucket[i].1 {
                    j += 1;
                }
                if j == i + 1 {
                    let (t, f) = (bucket[i].2 / 4, bucket[i].2 % 4);
                    let tet = self.tets[t];
                    let [a, b, c] = TET_FACES[f].map(|k| tet[k]);
                    faces.push(if self.volume(t) < 0.0 {
                        [a, c, b]
                    } else {
                        [a, b, c]
                    });
                }
                i = j;
            }
        }
        faces
    }
}

/// Smallest and largest dihedral angle (degrees) of the tetrahedron `p`.
pub(crate) fn dihedral_range(p: [[f64; 3]; 4]) -> (f64, f64) {
    // Unit normals of the faces opposite each vertex, pointing away from it.
    let normals = [0, 1, 2, 3].map(|v| {
        let [a, b, c] = TET_FACES[v].map(|k| p[k]);
        let n = cross(sub(b, a), sub(c, a));
        let s = if dot(n, sub(p[v], a)) > 0.0 {
            -1.0
        } else {
            1.0
        };
        let len = norm(n);
        if len > 0.0 {
            n.map(|x| s * x / len)
        } else {
            [0.0; 3]
        }
    });
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..4 {
        for j in i + 1..4 {
            let c = dot(normals[i], normals[j]).clamp(-1.0, 1.0);
            let angle = 180.0 - c.acos().to_degrees();
            lo = lo.min(angle);
            hi = hi.max(angle);
        }
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn regular_tet() -> TetMesh {
        TetMesh {
            vertices: vec![
                [1.0, 1.0, 1.0],
                [1.0, -1.0, -1.0],
                [-1.0, 1.0, -1.0],
                [-1.0, -1.0, 1.0],
            ],
            tets: vec![[0, 1, 2, 3]],
        }
    }

    #[test]
    fn regular_tet_measures() {
        let mut m = regular_tet();
        if m.volume(0) < 0.0 {
            m.tets[0].swap(0, 1);
        }
        assert!((m.volume(0) - 8.0 / 3.0).abs() < 1e-12);
        assert!((m.total_volume() - 8.0 / 3.0).abs() < 1e-12);
        assert_eq!(m.barycentre(0), [0.0, 0.0, 0.0]);
        let q = m.quality();
        let expected = (1.0f64 / 3.0).acos().to_degrees();
        assert!((q.min_dihedral_deg - expected).abs() < 1e-9);
        assert!((q.max_dihedral_deg - expected).abs() < 1e-9);
        assert!((q.mean_edge - 8f64.sqrt()).abs() < 1e-12);
        assert!((m.mean_edge_length() - 8f64.sqrt()).abs() < 1e-12);
        assert_eq!(q.tets, 1);
    }

    #[test]
    fn right_corner_tet_has_right_dihedrals() {
        let m = TetMesh {
            vertices: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            tets: vec![[0, 1, 2, 3]],
        };
        assert!((m.volume(0) - 1.0 / 6.0).abs() < 1e-15);
        let q = m.quality();
        assert!((q.max_dihedral_deg - 90.0).abs() < 1e-9);
        assert!((q.min_dihedral_deg - 54.735_610_317_245_35).abs() < 1e-9);
        assert!((q.min_edge - 1.0).abs() < 1e-15);
        assert!((q.max_edge - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn boundary_faces_of_two_tets_point_outward() {
        let m = TetMesh {
            vertices: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
            ],
            tets: vec![[0, 1, 2, 3], [1, 2, 3, 4]],
        };
        let mut m = m;
        for t in 0..2 {
            if m.volume(t) < 0.0 {
                m.tets[t].swap(0, 1);
            }
        }
        let faces = m.boundary_faces();
        assert_eq!(faces.len(), 6);
        assert!(!faces.iter().any(|f| {
            let mut k = *f;
            k.sort_unstable();
            k == [1, 2, 3]
        }));
        // Closed surface: area vectors sum to zero; each points away from the
        // centroid of the union.
        let centre = [0.4, 0.4, 0.4];
        let mut total = [0.0; 3];
        for f in &faces {
            let [a, b, c] = f.map(|i| m.vertices[i as usize]);
            let n = cross(sub(b, a), sub(c, a));
            total = [0, 1, 2].map(|k| total[k] + n[k]);
            assert!(dot(n, sub(a, centre)) > 0.0, "face {f:?} points inward");
        }
        assert!(norm(total) < 1e-12);
    }

    #[test]
    fn empty_mesh_statistics_are_zero() {
        let m = TetMesh::default();
        assert_eq!(m.total_volume(), 0.0);
        assert_eq!(m.mean_edge_length(), 0.0);
        assert_eq!(m.quality().tets, 0);
        assert!(m.boundary_faces().is_empty());
    }

    #[test]
    fn errors_display_their_numbers() {
        let e = MeshError::LatticeTooLarge {
            points: 300_000_000,
            limit: 200_000_000,
            edge_length: 0.001,
            suggested_edge_length: 0.0012,
        };
        let s = e.to_string();
        assert!(s.contains("300000000") && s.contains("1.200e-3"), "{s}");
        let e = MeshError::EmptyMesh {
            edge_length: 0.1,
            suggested_edge_length: 5e-5,
        };
        assert!(e.to_string().contains("smaller edge length"));
    }
}
