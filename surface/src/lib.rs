//! perifrac's surface stage: frames of particles from the cache (`perifrac-cache`)
//! become surfaces.
//!
//! - [`particles`]: sphere radii from the bodies' mean tet edges, fragments, and the
//!   check that refuses single layers of particles;
//! - [`vdb`] (feature `openvdb`): the `vdb` method, level sets through the system
//!   OpenVDB (`tools::ParticlesToLevelSet`, `tools::LevelSetTracker`,
//!   `tools::LevelSetFilter`, `tools::volumeToMesh`, `tools::csgUnion`), written as
//!   `vdb/NNNN.vdb`;
//! - [`mesh`]: the triangle meshes it returns (the CLI writes them as
//!   `surface/NNNN.glb` with `perifrac-render`);
//! - [`embedded`]: the `embedded` method, the boundary of the split tet mesh
//!   (`tets/NNNN.vtu`, Chen §5.2) with smoothed crack faces (Chen §7);
//! - [`debris`]: fragments too small to surface, as `surface/NNNN_debris.ply` points.
#![warn(missing_docs)]

pub mod debris;
pub mod embedded;
pub mod error;
pub mod mesh;
pub mod particles;
#[cfg(feature = "openvdb")]
pub mod vdb;

pub use error::SurfaceError;
