//! perifrac's simulator: a scene file goes in, frames of particles and split tet
//! meshes go out, into the cache on disk that the surface and render stages read.
//!
//! | module | main items |
//! |---|---|
//! | `scene` | `Scene`: the scene file, its defaults and validation |
//! | [`run`] | [`run::run`], [`run::prepare`], [`run::RunOptions`]: a scene to frames on disk |
//! | [`step`] | [`step::Simulation`]: the time loop, stable step, damping, blow-up detector |
//! | [`pd`] | [`pd::PdModel`], [`pd::Particles`]: Chen et al. 2018 peridynamics |
//! | [`fem`] | [`fem::FemModel`]: the reference FEM solvers (linear, corotated) |
//! | [`family`] | [`family::Bonds`]: neighbour search, CSR bond storage |
//! | [`material`] | [`material::Material`]: parameters and their conversions |
//! | [`geometry`] | [`geometry::TetMesh`], [`geometry::Sdf`], [`geometry::stuff`]: shapes, mesh files, tetrahedralization |
//! | [`embed`] | [`embed::EmbeddedMesh`]: the embedded tet mesh and vertex splitting (Chen §5.2) |
//! | [`contact`] | [`contact::Collider`], [`contact::Anchor`]: colliders, anchors, contact |
//! | `cache` | the frame cache on disk: layout, PLY, VTU, manifest, checkpoints |
//! | [`accuracy`], [`analytic`] | error against a reference run, closed-form solutions |
//! | [`error`] | [`SimError`], the crate's one error type |
//!
//! Shared vector arithmetic, the tet face table, the union-find and the deterministic
//! sum come from `perifrac-math`.
#![warn(missing_docs)]

pub mod accuracy;
pub mod analytic;
pub mod cache;
pub mod contact;
pub mod embed;
pub mod error;
pub mod family;
pub mod fem;
pub mod geometry;
pub mod material;
pub mod pd;
pub mod run;
pub mod scene;
pub mod step;

pub use error::SimError;
