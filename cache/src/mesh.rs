//! Surfaces as the surface stage makes them and the render stage writes them
//! (`surface/NNNN.glb`, `surface/animated.glb`): one type on both sides, and the
//! interface through which the surface stage has its files encoded without
//! depending on the glTF writer.

use crate::collider::MovingCollider;

/// A triangle surface: shared vertex arrays, the original surface's triangles and the
/// crack faces' triangles (counter-clockwise seen from outside).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Name of the mesh (and its node) in the files that carry one; may be empty.
    pub name: String,
    /// Vertex positions (m).
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Damage φ in [0, 1] per vertex (the `vdb` method's: the nearest particle's);
    /// empty when the surface carries none.
    pub damage: Vec<f32>,
    /// The diffused quantity θ per vertex (a membrane's sheet, Han Eq. 25); empty
    /// when the surface carries none.
    pub quantity: Vec<f32>,
    /// The θ at the two ends of the colour map of `quantity`, [θ_lo, θ_hi]: fixed for
    /// a whole run (the sheet method takes the range over all its frames), so a colour
    /// means the same θ in every frame. Unused when `quantity` is empty.
    pub quantity_range: [f32; 2],
    /// Three vertex indices a triangle of the original surface.
    pub surface_indices: Vec<u32>,
    /// Three vertex indices a triangle of the crack surfaces (the inside of the
    /// object).
    pub crack_indices: Vec<u32>,
}

impl SurfaceMesh {
    /// Number of triangles, original and crack.
    pub fn triangle_count(&self) -> usize {
        (self.surface_indices.len() + self.crack_indices.len()) / 3
    }
}

/// An error of a [`SurfaceEncoder`].
pub type EncodeError = Box<dyn std::error::Error + Send + Sync>;

/// Turns surfaces into the bytes of a surface file. perifrac-render's glTF writer
/// implements it; the surface stage receives it from its caller, so the surface crate
/// does not depend on the render crate.
pub trait SurfaceEncoder: Sync {
    /// A fractured surface of one frame (original and crack triangles apart).
    fn fractured(&self, mesh: &SurfaceMesh) -> Result<Vec<u8>, EncodeError>;

    /// A fractured surface animated over frames: `frames[k]` are the positions of
    /// `mesh`'s vertices in cache frame k + 1, at simulation time `times[k]` (s), and,
    /// when `mesh` carries a quantity, `quantities[k]` its θ there (else `quantities`
    /// is empty); the encoder keys frame k + 1 on timeline frame k + 1, at (k +
    /// 1)/playback_fps s (glTF's time as Blender's importer maps it to frames). The
    /// scene's mesh `colliders` go beside it, each moved rigidly to its pose of each
    /// frame.
    fn animated(
        &self,
        mesh: &SurfaceMesh,
        times: &[f32],
        frames: &[Vec<[f32; 3]>],
        quantities: &[Vec<f32>],
        colliders: &[MovingCollider],
    ) -> Result<Vec<u8>, EncodeError>;

    /// Plain meshes of one frame (e.g. one a fragment), each with its own name.
    fn meshes(&self, meshes: &[SurfaceMesh]) -> Result<Vec<u8>, EncodeError>;
}
