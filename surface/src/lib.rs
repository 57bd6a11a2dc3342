//! perifrac's surface stage: frames from the cache (`perifrac-sim`'s `cache`) become
//! surfaces.
//!
//! | module | main items |
//! |---|---|
//! | [`embedded`] | [`embedded::surface`], [`embedded::EmbeddedSurface`], [`embedded::fragments`]: the `embedded` method, the boundary of the split tet mesh (`tets/NNNN.vtu`, Chen §5.2) with smoothed crack faces (Chen §7) |
//! | `vdb` (feature `openvdb`) | the `vdb` method: level sets through the system OpenVDB, written as `vdb/NNNN.vdb` |
//! | [`particles`] | sphere radii from the bodies' mean tet edges, fragments, the check that refuses single layers of particles |
//! | [`mesh`] | [`mesh::TriangleMesh`]: the meshes both methods return (the CLI writes them as `surface/NNNN.glb` with `perifrac-render`) |
//! | [`debris`] | [`debris::Debris`]: fragments too small to surface, as `surface/NNNN_debris.ply` points |
//! | [`error`] | [`SurfaceError`], the crate's one error type |
#![warn(missing_docs)]

pub mod debris;
pub mod embedded;
pub mod error;
pub mod mesh;
pub mod particles;
#[cfg(feature = "openvdb")]
pub mod vdb;

pub use error::SurfaceError;
