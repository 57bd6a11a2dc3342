//! `manifest.json`: what a run produced and what it cost.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Result, SimError};
use crate::pd::StageTimes;

/// The manifest of an output directory.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Scene name.
    pub scene: String,
    /// Units of every quantity in the cache.
    pub units: String,
    /// perifrac version that wrote it.
    pub tool_version: String,
    /// Time step (s).
    pub dt: f64,
    /// Stable time step bound (s).
    pub stable_dt: f64,
    /// Output frame rate.
    pub fps: f64,
    /// Time of each written frame (s); frame k (from 1) is `frame_times[k - 1]`.
    pub frame_times: Vec<f64>,
    /// Centre of each collider (scene order) at each written frame; frame k (from 1)
    /// is `collider_centers[k - 1]`. The previews draw dynamic colliders from it.
    #[serde(default)]
    pub collider_centers: Vec<Vec<[f64; 3]>>,
    /// Particles.
    pub particles: usize,
    /// Directed bonds.
    pub bonds: usize,
    /// Bodies.
    pub bodies: Vec<BodyInfo>,
    /// Steps taken.
    pub steps: u64,
    /// Bonds broken so far (directed).
    pub broken_bonds: u64,
    /// How the run ended: `"complete"`, `"running"` or the blow-up message.
    pub status: String,
    /// Wall-clock seconds in each stage (not part of the deterministic output:
    /// excluded by [`Manifest::deterministic_json`]).
    pub timings: Timings,
}

/// One body's discretization.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BodyInfo {
    /// Name.
    pub name: String,
    /// Material name.
    pub material: String,
    /// Particles (tets).
    pub particles: usize,
    /// Mesh vertices.
    pub vertices: usize,
    /// Smallest dihedral angle of the tet mesh (degrees).
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle (degrees).
    pub max_dihedral_deg: f64,
    /// Mean tet edge length (m).
    pub mean_edge: f64,
}

/// Wall-clock seconds.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// Meshing and placing particles.
    pub discretize: f64,
    /// Neighbour search and bond setup.
    pub families: f64,
    /// The model's stages.
    pub stages: StageTimes,
    /// Integration, anchors, damping, contact.
    pub integrate_contact: f64,
    /// Writing frames.
    pub output: f64,
    /// The embedded mesh at frame output (Chen §5.2): crack-face set, vertex
    /// splitting and vertex positions (`tets = true`).
    #[serde(default)]
    pub split: f64,
    /// Surface extraction of the `embedded` method over all frames (boundary,
    /// smoothing, normals; not the writing of .glb files), set by the surface stage.
    #[serde(default)]
    pub surface: f64,
    /// Whole run.
    pub total: f64,
}

impl Manifest {
    /// Pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// JSON without the wall-clock timings (identical across runs of one scene).
    pub fn deterministic_json(&self) -> String {
        let mut m = self.clone();
        m.timings = Timings::default();
        m.to_json()
    }

    /// Writes it atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        super::write_atomic(path, self.to_json().as_bytes())
    }

    /// Reads a manifest.
    pub fn read(path: &Path) -> Result<Manifest> {
        let text = std::fs::read_to_string(path).map_err(|e| SimError::io(path, e))?;
        serde_json::from_str(&text).map_err(|e| SimError::Cache {
            path: path.to_path_buf(),
            message: format!("not a perifrac manifest: {e}"),
        })
    }
}
