//! perifrac's cache on disk, the contract between the stages (ARCHITECTURE.md, "The
//! cache on disk"). It depends on nothing of the solver: the simulator writes it, the
//! surface and render stages read it, and each reads and writes it only through the
//! types here.
//!
//! | type | what it is |
//! |---|---|
//! | [`Layout`] | every path of an output directory (`manifest.json`, `scene.toml`, `particles/NNNN.ply`, `tets/NNNN.vtu`, `tets/tets.pvd`, `colliders/mesh_N.ply`, `cache.usd`, `usd/NNNN.usdc`, `surface/NNNN.glb`, `surface/animated.glb`, `surface/NNNN_debris.ply`, `vdb/NNNN.vdb`, `preview/…`, `checkpoint/state.bin`) |
//! | [`write_atomic`] | the one way a cache file is written (temporary name, [`temporary_file`], then rename); [`stop_writes`] before an exit at once |
//! | [`scene::Scene`] | the scene file format, its defaults and validation; [`scene::Scene::load`] also reads the resolved `OUT/scene.toml` |
//! | [`ply::ParticleFrame`] | a particle frame (float PLY: standard columns, then a model's extra columns); [`ply::encode_points`] / [`ply::FloatPly`] for other point files |
//! | [`vtu::TetFrame`] | the split tet mesh of a frame (VTK XML); [`vtu::write_collection`] the ParaView `.pvd` that gives the frames their times |
//! | [`manifest::Manifest`] | `manifest.json`: what a run produced and what it cost; [`Layout::update_manifest`] changes it under a lock, so stages running side by side on one cache keep each other's records |
//! | [`frames::FrameRange`] | the frames a stage works on (`--frames 10..20`), for a farm's array jobs |
//! | [`checkpoint::Checkpoint`] | the versioned, checksummed checkpoint container; a model writes its state into the payload with [`checkpoint::Encoder`] and reads it with [`checkpoint::Decoder`] |
//! | [`collider::ColliderMesh`] | a mesh collider's triangles in its own frame (`colliders/mesh_N.ply`), written once by the run; [`collider::mesh_colliders`] reads them with their poses per frame for the previews, `cache.usd` and `animated.glb` |
//! | [`mesh::SurfaceMesh`] | a surface as the surface stage makes it and the glTF writer writes it; [`mesh::SurfaceEncoder`] is how the surface stage has it encoded |
//! | [`verify::verify`] | a cache checked against its manifest: frames present, sizes and checksums as written, finite positions |
//! | [`CacheError`] | every failure, naming the file (and, for scenes, line, column and key) |
#![warn(missing_docs)]

pub mod checkpoint;
pub mod collider;
pub mod error;
pub mod frames;
mod layout;
pub mod manifest;
pub mod mesh;
pub mod ply;
pub mod scene;
pub mod sheet;
pub mod verify;
pub mod vtu;

pub use error::{CacheError, Result};
pub use layout::{
    Layout, TemporaryFile, free_space, human_bytes, playback_time, stop_writes, temporary_file,
    write_atomic, write_error,
};
