//! Exact signed distance to a closed triangle mesh.
//!
//! The distance is that to the closest point (found with a [`Bvh`]); its sign
//! comes from the angle-weighted pseudonormal of the feature (face, edge or
//! vertex) the closest point lies on (Bærentzen & Aanæs 2005, "Signed distance
//! computation using the angle weighted pseudonormal", Theorem 1): a point `p`
//! with closest point `c` is inside iff `(p − c)·n < 0`. Face pseudonormals are
//! the face normals, edge pseudonormals the sum of the two faces' normals,
//! vertex pseudonormals `Σ αᵢ nᵢ` over the incident faces with `αᵢ` the face's
//! angle at the vertex (their Eq. 2).
//!
//! Its sharp features (for the unstructured mesher) are the mesh's edges whose two
//! faces' normals differ by more than [`MESH_CREASE_ANGLE_DEG`](crate::geometry::sdf::MESH_CREASE_ANGLE_DEG), found once here.

use std::collections::HashMap;

use perifrac_math::{add, cross, dot, normalize, scale, sub};

use super::TriMesh;
use super::bvh::{Bvh, Feature};
use crate::geometry::Sdf;
use crate::geometry::sdf::{Features, mesh_features};

/// The signed distance function of a closed, consistently oriented mesh
/// (as returned by [`TriMesh::load`]): negative inside.
#[derive(Debug, Clone)]
pub struct MeshSdf {
    bvh: Bvh,
    /// Per triangle: pseudonormals of edges 0–2 (edge `i` runs from corner `i`
    /// to corner `i + 1`).
    edge_normals: Vec<[[f64; 3]; 3]>,
    face_normals: Vec<[f64; 3]>,
    vertex_normals: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    lo: [f64; 3],
    hi: [f64; 3],
    /// Corners and creases (edges sharper than [`MESH_CREASE_ANGLE_DEG`](crate::geometry::sdf::MESH_CREASE_ANGLE_DEG)).
    features: Features,
}

impl MeshSdf {
    /// Precomputes the BVH and the pseudonormals of `mesh`.
    pub fn new(mesh: &TriMesh) -> MeshSdf {
        let face_normals: Vec<[f64; 3]> = (0..mesh.triangles.len())
            .map(|t| {
                let [a, b, c] = mesh.corners(t);
                normalize(cross(sub(b, a), sub(c, a)))
            })
            .collect();
        let mut vertex_normals = vec![[0.0; 3]; mesh.vertices.len()];
        let mut by_edge: HashMap<(u32, u32), [f64; 3]> = HashMap::new();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = mesh.corners(t);
            let n = face_normals[t];
            for i in 0..3 {
                let e1 = normalize(sub(p[(i + 1) % 3], p[i]));
                let e2 = normalize(sub(p[(i + 2) % 3], p[i]));
                let angle = dot(e1, e2).clamp(-1.0, 1.0).acos();
                let v = tri[i] as usize;
                vertex_normals[v] = add(vertex_normals[v], scale(n, angle));
                let (a, b) = (tri[i], tri[(i + 1) % 3]);
                let e = by_edge.entry((a.min(b), a.max(b))).or_insert([0.0; 3]);
                *e = add(*e, n);
            }
        }
        let edge_normals = mesh
            .triangles
            .iter()
            .map(|tri| {
                [0, 1, 2].map(|i| {
                    let (a, b) = (tri[i], tri[(i + 1) % 3]);
                    by_edge[&(a.min(b), a.max(b))]
                })
            })
            .collect();
        let (lo, hi) = mesh.bounds();
        let features = mesh_features(&mesh.vertices, &mesh.triangles, &face_normals);
        MeshSdf {
            bvh: Bvh::new((0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect()),
            edge_normals,
            face_normals,
            vertex_normals,
            triangles: mesh.triangles.clone(),
            lo,
            hi,
            features,
        }
    }

    /// The closest point on the surface to `p`.
    pub fn closest_point(&self, p: [f64; 3]) -> [f64; 3] {
        self.bvh.closest(p).map_or(p, |c| c.point)
    }
}

impl Sdf for MeshSdf {
    fn distance(&self, p: [f64; 3]) -> f64 {
        let Some(c) = self.bvh.closest(p) else {
            return f64::INFINITY;
        };
        let normal = match c.feature {
            Feature::Face => self.face_normals[c.triangle],
            Feature::Edge(i) => self.edge_normals[c.triangle][i],
            Feature::Vertex(i) => self.vertex_normals[self.triangles[c.triangle][i] as usize],
        };
        let d = c.distance_squared.sqrt();
        if dot(sub(p, c.point), normal) < 0.0 {
            -d
        } else {
            d
        }
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        (self.lo, self.hi)
    }

    /// Edges whose faces' normals differ by more than [`MESH_CREASE_ANGLE_DEG`](crate::geometry::sdf::MESH_CREASE_ANGLE_DEG), and
    /// the corners where they end or meet; exact, so `resolution` is not used.
    fn features(&self, _resolution: f64) -> Features {
        self.features.clone()
    }
}
