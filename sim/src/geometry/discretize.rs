//! Bodies to particles (Chen §5.2): each body is tetrahedralized to edge length ≈ λ
//! (a breaking body without a lattice, as Chen et al. mesh theirs with TetGen; others on
//! a lattice centred on the body: see the body's `lattice` key and `docs/lattice.md`)
//! and one particle is placed at each tet's barycentre with the tet's volume; a
//! membrane body gets the particles of its sheet instead ([`crate::membrane::sheet`],
//! an empty tet mesh). All particles are then sorted along a Morton curve so that
//! families sit close in memory.

use rayon::prelude::*;

use super::mesh::{Conformity, MeshSdf, TriMesh, conform};
use super::sdf::Sdf;
use super::shape::{placement, to_sdf};
use super::stuffing::{random_rotation, stuff, stuff_rotated};
use super::unstructured::{mesh_seed, mesh_unstructured};
use super::{MeshQuality, TetMesh};
use crate::error::{Result, SimError};
use crate::membrane::sheet::{self, Sheet};
use crate::scene::{LatticeOrientation, ModelKind, Scene, ShapeSpec};

/// The particles of all bodies, sorted spatially.
#[derive(Debug, Clone, Default)]
pub struct Discretization {
    /// Barycentres x.
    pub position: Vec<[f64; 3]>,
    /// Tet volumes V.
    pub volume: Vec<f64>,
    /// Body index of each particle.
    pub body: Vec<u32>,
    /// Index of each particle's tet in its body's mesh.
    pub tet: Vec<u32>,
    /// Each body's tet mesh.
    pub meshes: Vec<TetMesh>,
    /// Each body's mesh quality.
    pub quality: Vec<MeshQuality>,
    /// For bodies given by a mesh file: how closely the tet mesh's boundary
    /// follows the file's surface (`None` for primitive shapes, whose boundary
    /// vertices lie on the exact surface).
    pub conformity: Vec<Option<Conformity>>,
    /// The triangles of the membranes given by a mesh (their remeshed sheets), as
    /// indices of the sorted particles; a lattice sheet's are found from its bonds.
    pub sheet_triangles: Vec<[u32; 3]>,
}

/// Meshes every body of the scene and places the particles.
pub fn discretize(scene: &Scene) -> Result<Discretization> {
    let bodies: Vec<(TetMesh, Option<Conformity>)> = scene
        .bodies
        .par_iter()
        .enumerate()
        .map(|(index, b)| {
            let error = |message: String| SimError::Mesh {
                body: b.name.clone(),
                message,
            };
            // A breaking body gets no lattice at all unless it asks for one (issue 13:
            // an aligned lattice's weak planes showed as axis-aligned cracks, a turned
            // one's as cracks along its own axes); others stay aligned and centred, so
            // symmetric shapes get symmetric particles.
            let lattice = scene
                .materials
                .get(&b.material)
                .map_or(LatticeOrientation::Aligned, |m| b.lattice(m));
            let tet_mesh = |sdf: &dyn Sdf, lambda: f64| match lattice {
                LatticeOrientation::Rotated => {
                    stuff_rotated(sdf, lambda, random_rotation(scene.scene.seed, index as u64))
                }
                LatticeOrientation::Unstructured => {
                    mesh_unstructured(sdf, lambda, mesh_seed(scene.scene.seed, index as u64))
                }
                LatticeOrientation::Aligned => stuff(sdf, lambda),
            };
            match (&b.shape, placement(&b.shape)) {
                // Membranes sample their sheet; MPM bodies seed their own particles.
                _ if matches!(b.model, ModelKind::Membrane | ModelKind::Mpm) => {
                    Ok((TetMesh::default(), None))
                }
                (ShapeSpec::Mesh { path, .. }, Some(placement)) => {
                    let surface = TriMesh::load(&scene.base_dir.join(path), &placement)
                        .map_err(|e| error(e.to_string()))?;
                    let sdf = MeshSdf::new(&surface);
                    let mut tets =
                        tet_mesh(&sdf, b.resolution).map_err(|e| error(e.to_string()))?;
                    let fit = conform(&mut tets, &surface, &sdf, b.resolution);
                    Ok((tets, Some(fit)))
                }
                (shape, _) => {
                    let sdf = to_sdf(shape, &scene.base_dir).map_err(error)?;
                    let tets =
                        tet_mesh(sdf.as_ref(), b.resolution).map_err(|e| error(e.to_string()))?;
                    Ok((tets, None))
                }
            }
        })
        .collect::<Result<_>>()?;
    let (meshes, conformity): (Vec<TetMesh>, Vec<Option<Conformity>>) = bodies.into_iter().unzip();
    let sheets: Vec<Option<Sheet>> = scene
        .bodies
        .iter()
        .map(|b| {
            (b.model == ModelKind::Membrane)
                .then(|| {
                    sheet::sample(b, &scene.base_dir).map_err(|message| SimError::Mesh {
                        body: b.name.clone(),
                        message,
                    })
                })
                .transpose()
        })
        .collect::<Result<_>>()?;
    let mut items: Vec<(u64, [f64; 3], f64, u32, u32)> = Vec::new();
    let (lo, hi) = bounds(
        meshes
            .iter()
            .flat_map(|m| m.vertices.iter())
            .chain(sheets.iter().flatten().flat_map(|s| s.position.iter())),
    );
    for (b, sheet) in sheets.iter().enumerate() {
        // A membrane's particles are its sheet's (Han §6), each with volume A h.
        if let Some(s) = sheet {
            for (t, (&x, &area)) in s.position.iter().zip(&s.area).enumerate() {
                items.push((morton(x, lo, hi), x, area * s.thickness, b as u32, t as u32));
            }
        }
    }
    for (b, mesh) in meshes.iter().enumerate() {
        for t in 0..mesh.tets.len() {
            let c = mesh.barycentre(t);
            items.push((morton(c, lo, hi), c, mesh.volume(t), b as u32, t as u32));
        }
    }
    items.par_sort_unstable_by_key(|it| (it.0, it.3, it.4));
    let quality = meshes.iter().map(TetMesh::quality).collect();
    // Where each sheet particle (body, index in its sheet) went in the sorted order.
    let mut sorted: Vec<Vec<u32>> = sheets
        .iter()
        .map(|s| vec![0; s.as_ref().map_or(0, |s| s.position.len())])
        .collect();
    for (i, it) in items.iter().enumerate() {
        if let Some(slot) = sorted[it.3 as usize].get_mut(it.4 as usize) {
            *slot = i as u32;
        }
    }
    let sheet_triangles = sheets
        .iter()
        .enumerate()
        .flat_map(|(b, s)| {
            let sorted = &sorted[b];
            s.iter()
                .flat_map(|s| s.triangles.iter())
                .map(move |t| t.map(|v| sorted[v as usize]))
        })
        .collect();
    Ok(Discretization {
        position: items.iter().map(|it| it.1).collect(),
        volume: items.iter().map(|it| it.2).collect(),
        body: items.iter().map(|it| it.3).collect(),
        tet: items.iter().map(|it| it.4).collect(),
        meshes,
        quality,
        conformity,
        sheet_triangles,
    })
}

/// The bounding box of `points`.
pub(super) fn bounds<'a>(points: impl Iterator<Item = &'a [f64; 3]>) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for v in points {
        for a in 0..3 {
            lo[a] = lo[a].min(v[a]);
            hi[a] = hi[a].max(v[a]);
        }
    }
    (lo, hi)
}

/// 63-bit Morton code of `p` in the box [lo, hi].
pub(super) fn morton(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> u64 {
    let mut code = 0u64;
    let q: Vec<u64> = (0..3)
        .map(|a| {
            let span = (hi[a] - lo[a]).max(1e-30);
            (((p[a] - lo[a]) / span).clamp(0.0, 1.0) * ((1u64 << 21) - 1) as f64) as u64
        })
        .collect();
    for bit in (0..21).rev() {
        for &c in &q {
            code = (code << 1) | ((c >> bit) & 1);
        }
    }
    code
}
