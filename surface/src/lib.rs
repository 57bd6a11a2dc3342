//! perifrac's surface stage: frames from the cache (`perifrac-cache`) become
//! surfaces. Two stages, each a function over a whole cache, which the CLI only
//! dispatches to:
//!
//! - [`embedded::stage`]: the `embedded` method, the boundary of the split tet mesh
//!   (`tets/NNNN.vtu`, Chen §5.2) with smoothed crack faces (Chen §7), as
//!   `surface/NNNN.glb` and `surface/animated.glb`; per frame [`embedded::surface`]
//!   and [`embedded::RenderMesh`];
//! - [`vdb::stage`] (feature `openvdb`): the `vdb` method, level sets through the
//!   system OpenVDB (`tools::ParticlesToLevelSet`, `tools::LevelSetTracker`,
//!   `tools::LevelSetFilter`, `tools::volumeToMesh`, `tools::csgUnion`), written as
//!   `vdb/NNNN.vdb`, debris and `surface/NNNN.glb`; per frame [`vdb::surface_frame`];
//! - [`particles`]: sphere radii from the bodies' mean tet edges, fragments, and the
//!   check that refuses single layers of particles;
//! - [`mesh`]: [`mesh::TriangleMesh`], the mesher's triangles with their measures
//!   (volume, open edges, parts, normals);
//! - [`debris`]: fragments too small to surface, as `surface/NNNN_debris.ply` points;
//! - [`sheet::stage`]: the `sheet` method for membranes, each sheet's intact lattice
//!   triangles (`sheet/NNNN.ply`) thickened into a closed shell, as `surface/NNNN.glb`
//!   and `surface/animated.glb`.
//!
//! Surfaces leave the crate as the cache's one surface type,
//! [`perifrac_cache::mesh::SurfaceMesh`]. The stages write their `.glb` files through a
//! [`perifrac_cache::mesh::SurfaceEncoder`] their caller passes in (the CLI passes
//! `perifrac_render::gltf::Glb`): the stage keeps its frames-in-parallel loop, writes
//! each file as soon as it is made, and still does not depend on the render crate.
//! Errors are [`SurfaceError`].
#![warn(missing_docs)]

pub mod debris;
pub mod embedded;
pub mod error;
pub mod mesh;
pub mod particles;
pub mod sheet;
#[cfg(feature = "openvdb")]
pub mod vdb;

pub use error::SurfaceError;

use std::path::Path;

use perifrac_cache::mesh::EncodeError;

/// Writes what a [`perifrac_cache::mesh::SurfaceEncoder`] made, atomically; `what`
/// names the file in errors.
fn write_encoded(
    path: &Path,
    what: String,
    bytes: std::result::Result<Vec<u8>, EncodeError>,
) -> error::Result<()> {
    let bytes = bytes.map_err(|e| SurfaceError::Encode {
        what,
        message: e.to_string(),
    })?;
    Ok(perifrac_cache::write_atomic(path, &bytes)?)
}

/// The frames a stage works on: `range` checked against the cache's frames, or every
/// frame; an empty cache or a range past its end is an input error naming the
/// manifest.
fn frame_range(
    layout: &perifrac_cache::Layout,
    manifest: &perifrac_cache::manifest::Manifest,
    range: Option<perifrac_cache::frames::FrameRange>,
) -> error::Result<perifrac_cache::frames::FrameRange> {
    let frames = manifest.frame_times.len();
    if frames == 0 {
        return Err(SurfaceError::Input(format!(
            "{}: the cache has no frames to surface",
            layout.manifest().display()
        )));
    }
    let range = range.unwrap_or(perifrac_cache::frames::FrameRange::all(frames));
    range
        .check(frames)
        .map_err(|e| SurfaceError::Input(format!("{}: {e}", layout.manifest().display())))?;
    Ok(range)
}
