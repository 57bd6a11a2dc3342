//! Closed triangle meshes as body shapes (issue 3, item 1), and open ones as
//! membranes' sheets (module `remesh`, issue 14).
//!
//! A mesh file (OBJ, PLY or glTF/GLB, module `read`) is read into a [`TriMesh`], its
//! duplicate vertices welded, placed in the scene by a [`Placement`]
//! (scale, rotation, translation), checked to be a closed, consistently oriented,
//! non-degenerate, non-self-intersecting surface (module `check`) and turned into an
//! exact signed distance function ([`MeshSdf`], BVH + angle-weighted
//! pseudonormals, Bærentzen & Aanæs 2005) that the isosurface-stuffing mesher
//! fills with tetrahedra; [`conformity`] measures how closely the tet mesh's
//! boundary follows the surface and snaps it closer.

mod bvh;
mod check;
pub mod conformity;
mod distance;
mod read;
pub mod remesh;

use std::path::{Path, PathBuf};

use perifrac_math::{cross, dist, dot, norm, sub};

pub use self::bvh::Bvh;
pub use self::conformity::{Conformity, conform};
pub use self::distance::MeshSdf;

/// Why a mesh file cannot be used as a body's shape. Every variant names the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshFileError {
    /// The file could not be read or parsed.
    #[error("{path}: cannot read the mesh: {reason}")]
    Unreadable {
        /// The mesh file.
        path: PathBuf,
        /// What the reader reported.
        reason: String,
    },
    /// The file's extension is not one the loader knows.
    #[error("{path}: unsupported mesh format '{extension}': use .obj, .ply, .gltf or .glb")]
    UnsupportedExtension {
        /// The mesh file.
        path: PathBuf,
        /// The extension found (empty if none).
        extension: String,
    },
    /// The file holds no triangles.
    #[error(
        "{path}: the mesh has no triangles ({vertices} vertices): export the surface as triangles"
    )]
    Empty {
        /// The mesh file.
        path: PathBuf,
        /// Number of vertices read.
        vertices: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("{path}: face {face} refers to vertex {index} but the mesh has {vertices} vertices")]
    IndexOutOfRange {
        /// The mesh file.
        path: PathBuf,
        /// The face (0-based, in file order).
        face: usize,
        /// The offending vertex index.
        index: u64,
        /// Number of vertices.
        vertices: usize,
    },
    /// Some vertex coordinates are NaN or infinite (in the file or after placement).
    #[error(
        "{path}: {count} vertices have non-finite coordinates (first: {first:?}); fix the file or the scale/rotation/translation"
    )]
    NonFinite {
        /// The mesh file.
        path: PathBuf,
        /// Number of such vertices.
        count: usize,
        /// The first one's coordinates.
        first: [f64; 3],
    },
    /// Faces with (near) zero area or a repeated vertex.
    #[error(
        "{path}: {count} of {faces} faces are degenerate ({repeated} with a repeated vertex after welding, {zero_area} of zero area; first: face {first}); remove them or remesh"
    )]
    Degenerate {
        /// The mesh file.
        path: PathBuf,
        /// Number of degenerate faces.
        count: usize,
        /// Of those, faces using a vertex twice.
        repeated: usize,
        /// Of those, faces of zero area.
        zero_area: usize,
        /// Total number of faces.
        faces: usize,
        /// The first degenerate face.
        first: usize,
    },
    /// Some edges belong to one face (holes) or to more than two (non-manifold).
    #[error(
        "{path}: the mesh is not closed: {boundary} boundary edges (used by one face) and {non_manifold} non-manifold edges (used by more than two faces) of {edges}; close the holes or split the shells"
    )]
    NotClosed {
        /// The mesh file.
        path: PathBuf,
        /// Edges used by exactly one face.
        boundary: usize,
        /// Edges used by three or more faces.
        non_manifold: usize,
        /// Total number of edges.
        edges: usize,
    },
    /// An open surface (a membrane's sheet) that is not a manifold with boundary.
    #[error(
        "{path}: the sheet is not a surface: {edges} edges are shared by more than two faces and at {vertices} vertices two sheets touch at one point; a membrane's mesh must be one sheet whose every edge has one or two faces: split it into separate bodies or remesh"
    )]
    NotManifold {
        /// The mesh file.
        path: PathBuf,
        /// Edges used by three or more faces.
        edges: usize,
        /// Vertices with more than two boundary edges.
        vertices: usize,
    },
    /// Neighbouring faces are wound in opposite directions.
    #[error(
        "{path}: inconsistent orientation: {edges} edges are traversed in the same direction by both of their faces (some faces are flipped); recompute the normals consistently"
    )]
    InconsistentOrientation {
        /// The mesh file.
        path: PathBuf,
        /// Edges whose two faces disagree.
        edges: usize,
    },
    /// Faces cross each other.
    #[error(
        "{path}: the mesh intersects itself: {pairs} pairs of faces intersect (first: faces {first_pair:?}); union the parts or remesh"
    )]
    SelfIntersecting {
        /// The mesh file.
        path: PathBuf,
        /// Number of intersecting face pairs.
        pairs: usize,
        /// The first pair found (smallest indices).
        first_pair: (usize, usize),
    },
}

/// A triangle soup with shared vertices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as three vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// How a mesh file is placed in the scene: `p ↦ R (s ⊙ p) + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Scale factor along each axis of the file (applied first).
    pub scale: [f64; 3],
    /// Rotation in degrees about x, then y, then z (fixed axes): R = Rz Ry Rx.
    pub rotation_deg: [f64; 3],
    /// Translation (applied last).
    pub translation: [f64; 3],
}

impl Default for Placement {
    fn default() -> Self {
        Placement {
            scale: [1.0; 3],
            rotation_deg: [0.0; 3],
            translation: [0.0; 3],
        }
    }
}

impl Placement {
    /// The 3×3 matrix R·diag(s) (rows).
    fn linear(&self) -> [[f64; 3]; 3] {
        let [ax, ay, az] = self.rotation_deg.map(f64::to_radians);
        let (sx, cx) = ax.sin_cos();
        let (sy, cy) = ay.sin_cos();
        let (sz, cz) = az.sin_cos();
        let rx = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]];
        let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
        let rz = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]];
        let r = matmul(rz, matmul(ry, rx));
        [0, 1, 2].map(|i| [0, 1, 2].map(|j| r[i][j] * self.scale[j]))
    }

    /// Where the point `p` of the file goes.
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let m = self.linear();
        [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + self.translation[i])
    }

    /// Whether the placement mirrors (an odd number of negative scale factors).
    pub fn mirrors(&self) -> bool {
        self.scale.iter().filter(|s| **s < 0.0).count() % 2 == 1
    }
}

fn matmul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// Fails if some vertex has a NaN or infinite coordinate.
fn non_finite(mesh: &TriMesh, path: &Path) -> Result<(), MeshFileError> {
    let mut bad = mesh
        .vertices
        .iter()
        .filter(|v| !v.iter().all(|x| x.is_finite()));
    match bad.next() {
        Some(&first) => Err(MeshFileError::NonFinite {
            path: path.to_path_buf(),
            count: 1 + bad.count(),
            first,
        }),
        None => Ok(()),
    }
}

/// Welding tolerance relative to the bounding-box diagonal: vertices closer than
/// this (on a grid of this cell size) are merged.
const WELD_TOLERANCE: f64 = 1e-9;

impl TriMesh {
    /// Reads a mesh file (`.obj`, `.ply`, `.gltf`, `.glb`, by extension),
    /// welds duplicate vertices, places it and checks that it bounds a solid;
    /// a mesh wound inside-out is turned the right way.
    ///
    /// # Errors
    /// Every [`MeshFileError`] kind, naming `path`.
    pub fn load(path: &Path, placement: &Placement) -> Result<TriMesh, MeshFileError> {
        let mut mesh = TriMesh::read_placed(path, placement)?;
        check::check(&mesh, path)?;
        if mesh.enclosed_volume() < 0.0 {
            mesh.flip();
        }
        Ok(mesh)
    }

    /// Reads a mesh file of a surface that may be open (a membrane's sheet), welds
    /// duplicate vertices, places it and checks that it is a manifold with boundary,
    /// consistently wound and without degenerate faces.
    ///
    /// # Errors
    /// [`MeshFileError`]: unreadable, empty, non-finite, degenerate, not manifold,
    /// inconsistent orientation — each naming `path`.
    pub fn load_surface(path: &Path, placement: &Placement) -> Result<TriMesh, MeshFileError> {
        let mesh = TriMesh::read_placed(path, placement)?;
        check::check_surface(&mesh, path)?;
        Ok(mesh)
    }

    /// What [`TriMesh::load`] and [`TriMesh::load_surface`] share: the file read,
    /// finite, welded, placed, and turned back the right way if the placement mirrors.
    fn read_placed(path: &Path, placement: &Placement) -> Result<TriMesh, MeshFileError> {
        let mut mesh = read::read(path)?;
        non_finite(&mesh, path)?;
        mesh.weld();
        for v in &mut mesh.vertices {
            *v = placement.apply(*v);
        }
        non_finite(&mesh, path)?;
        if placement.mirrors() {
            mesh.flip();
        }
        Ok(mesh)
    }

    /// Merges vertices that coincide (to `WELD_TOLERANCE` = 10⁻⁹ of the bounding-box
    /// diagonal) and drops unused ones; the first occurrence's position is kept.
    pub fn weld(&mut self) {
        let (lo, hi) = self.bounds();
        let diagonal = dist(lo, hi);
        let cell = if diagonal > 0.0 {
            WELD_TOLERANCE * diagonal
        } else {
            1.0
        };
        let mut used = vec![false; self.vertices.len()];
        for t in &self.triangles {
            for &v in t {
                used[v as usize] = true;
            }
        }
        let mut index = std::collections::HashMap::new();
        let mut remap = vec![u32::MAX; self.vertices.len()];
        let mut vertices = Vec::new();
        for (v, p) in self.vertices.iter().enumerate() {
            if !used[v] {
                continue;
            }
            let key = [0, 1, 2].map(|k| ((p[k] - lo[k]) / cell).round() as i64);
            let id = *index.entry(key).or_insert_with(|| {
                vertices.push(*p);
                (vertices.len() - 1) as u32
            });
            remap[v] = id;
        }
        for t in &mut self.triangles {
            *t = t.map(|v| remap[v as usize]);
        }
        self.vertices = vertices;
    }

    /// Reverses the winding of every triangle.
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
    }

    /// Axis-aligned bounds (min, max) of the vertices.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in &self.vertices {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        (lo, hi)
    }

    /// The three corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [[f64; 3]; 3] {
        self.triangles[t].map(|v| self.vertices[v as usize])
    }

    /// Volume enclosed by a closed surface (divergence theorem; negative when
    /// the triangles are wound inward).
    pub fn enclosed_volume(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                dot(a, cross(b, c)) / 6.0
            })
            .sum()
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                0.5 * norm(cross(sub(b, a), sub(c, a)))
            })
            .sum()
    }
}

#[cfg(test)]
mod tests;
