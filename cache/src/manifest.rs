//! `manifest.json`: what a run produced and what it cost.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{CacheError, Result};

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
    /// Particles of the body (one per tet for the tet-mesh models).
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
    /// The model's stages by name (for the peridynamic model `dilatation` and
    /// `forces`), filled in by the simulator.
    pub stages: BTreeMap<String, f64>,
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
        crate::write_atomic(path, self.to_json().as_bytes())
    }

    /// Reads a manifest.
    pub fn read(path: &Path) -> Result<Manifest> {
        let text = std::fs::read_to_string(path).map_err(|e| CacheError::io(path, e))?;
        serde_json::from_str(&text).map_err(|e| CacheError::Format {
            path: path.to_path_buf(),
            message: format!("not a perifrac manifest: {e}"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn awkward_floats_read_back_to_the_same_bits() {
        let awkward = [
            0.1 + 0.2,
            1.0 / 3.0,
            7.3e-5 * 3.0,
            2.0f64.sqrt() * 1e-300,
            1e308,
        ];
        let manifest = Manifest {
            scene: "floats".into(),
            dt: awkward[2],
            stable_dt: awkward[3],
            fps: 24.0,
            frame_times: awkward.to_vec(),
            collider_centers: vec![vec![[awkward[0], awkward[1], awkward[4]]]],
            timings: Timings {
                stages: [
                    ("dilatation".to_string(), awkward[1]),
                    ("forces".into(), 0.7),
                ]
                .into_iter()
                .collect(),
                total: awkward[0],
                ..Timings::default()
            },
            ..Manifest::default()
        };
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("manifest.json");
        manifest.write(&path).expect("write");
        let back = Manifest::read(&path).expect("read");
        let bits = |m: &Manifest| -> Vec<u64> {
            let mut v: Vec<f64> = vec![m.dt, m.stable_dt, m.timings.total];
            v.extend(&m.frame_times);
            v.extend(m.collider_centers.iter().flatten().flatten());
            v.extend(m.timings.stages.values());
            v.into_iter().map(f64::to_bits).collect()
        };
        assert_eq!(bits(&back), bits(&manifest));
        assert_eq!(back, manifest);
        let json = manifest.to_json();
        assert!(
            json.contains("\"stages\": {\n      \"dilatation\": 0.3333333333333333,\n      \"forces\": 0.7\n    }"),
            "{json}"
        );
    }
}
