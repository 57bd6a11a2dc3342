//! perifrac's simulator: a scene file goes in, frames of particles go out.
//!
//! The physics is the state-based peridynamic elastoplastic fracture model of
//! Chen et al. 2018 (`pd`), on particles placed at the barycentres of a tetrahedral
//! mesh of each body (`geometry`), with rigid colliders and anchors (`contact`),
//! explicit velocity-Verlet time stepping (`step`) and a frame cache on disk (`cache`)
//! that the surface and render stages read.
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
pub mod memory;
pub mod model;
pub mod pd;
pub mod run;
pub mod scene;
pub mod world;

pub use error::SimError;
