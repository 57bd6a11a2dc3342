//! perifrac's simulator: a scene file goes in, frames of particles and split tet
//! meshes go out, into the cache on disk that the surface and render stages read.
//!
//! Main types, by module:
//! - [`model::Model`]: the interface every solver implements (points, forces or an
//!   own sub-step, stable step, energies, cache columns, checkpoint state, timings).
//! - [`world::World`] of [`world::Part`]s: the one integrator (velocity Verlet), with
//!   anchors, colliders, damping and the blow-up detector, over every model of a scene.
//! - [`run::run`] / [`run::prepare`]: scene → world ([`run::Prepared`]) → frames on
//!   disk, checkpoints and resume.
//! - [`pd::Peridynamics`] (Chen et al. 2018 state-based peridynamics, [`pd::PdModel`])
//!   and [`fem::Fem`] (the linear and corotated FEM references, [`fem::FemModel`]);
//!   [`membrane::Membrane`] (Han et al. 2021 thin membranes, [`membrane::MembraneModel`]).
//! - [`geometry::discretize::Discretization`]: bodies meshed into tets, particles at
//!   their barycentres; [`family::Bonds`]: families in CSR arrays.
//! - [`contact::Collider`], [`contact::Anchor`]; [`embed::EmbeddedMesh`] (Chen §5.2);
//!   [`memory::MemoryEstimate`]; [`SimError`].
//! - [`cache`] and [`scene`]: the cache layout and the scene format (re-exported from
//!   the ground crate the other stages read).
//!
//! Shared vector arithmetic, the tet face table, the union-find and the deterministic
//! sum come from `perifrac-math`.
#![warn(missing_docs)]

pub mod accuracy;
pub mod analytic;
pub mod clamp;
pub mod contact;
pub mod crack_angle;
pub mod embed;
pub mod error;
pub mod family;
pub mod fem;
pub mod geometry;
pub mod material;
pub mod membrane;
pub mod memory;
pub mod model;
pub mod mpm;
pub mod particle_contact;
pub mod pd;
pub mod ranks;
pub mod rigid;
pub mod run;
pub mod world;

pub use error::SimError;
pub use perifrac_cache as cache;
pub use perifrac_cache::scene;
