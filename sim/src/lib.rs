//! perifrac's simulator: a scene file goes in, frames of particles go out.
//!
//! The physics is the state-based peridynamic elastoplastic fracture model of
//! Chen et al. 2018 (`pd`), on particles placed at the barycentres of a tetrahedral
//! mesh of each body (`geometry`), with rigid colliders and anchors (`contact`),
//! explicit velocity-Verlet time stepping (`step`) and a frame cache on disk (`cache`,
//! the `perifrac-cache` crate, re-exported with its `scene` format) that the surface
//! and render stages read.
#![warn(missing_docs)]

pub mod accuracy;
pub mod analytic;
pub mod checkpoint_state;
pub mod contact;
pub mod embed;
pub mod error;
pub mod family;
pub mod fem;
pub mod geometry;
pub mod material;
pub mod pd;
pub mod run;
pub mod step;

pub use error::SimError;
pub use perifrac_cache as cache;
pub use perifrac_cache::scene;
