//! `manifest.json`: what a run produced and what it cost.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{CacheError, Result};
use crate::frames::{FrameRange, frame_of_file};

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
    /// Rotation of each collider (scene order) at each written frame, a unit
    /// quaternion [x, y, z, w] (identity for all but moving mesh colliders), written
    /// when the scene has a mesh collider: a mesh collider is its placed mesh moved to
    /// x ↦ centre + R (x − pivot), with the pivot of the scene.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub collider_rotations: Vec<Vec<[f64; 4]>>,
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
    /// How the run stands: running, complete, interrupted or failed.
    pub status: Status,
    /// Why the run was interrupted (a signal, `--frames`) or what made it fail (the
    /// blow-up, the I/O error); empty while running and when complete.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub message: String,
    /// Size and CRC-32 of every file the run wrote, by path relative to the output
    /// directory (`particles/0001. py`, …), recorded at write time: `perifrac verify`
    /// checks the cache against them.
    #[serde(default)]
    pub files: BTreeMap<String, FileRecord>,
    /// Wall-clock seconds in each stage (not part of the deterministic output:
    /// excluded by [`Manifest::deterministic_json`]).
    pub timings: Timings,
}

/// How a run stands, in `manifest.json` as a lowercase word.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Being written (or the process was killed: nothing else marks it).
    #[default]
    Running,
    /// Every frame of the scene is written.
    Complete,
    /// Stopped before the end, with a checkpoint to continue from (`--resume`): a
    /// signal, or `--frames`; [`Manifest::message`] says which.
    Interrupted,
    /// Stopped by an error (a blow-up, a write that failed); [`Manifest::message`]
    /// holds it.
    Failed,
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Status::Running => "running",
            Status::Complete => "complete",
            Status::Interrupted => "interrupted",
            Status::Failed => "failed",
        })
    }
}

/// A file as it was written: what `perifrac verify` checks it against.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileRecord {
    /// Length in bytes.
    pub bytes: u64,
    /// CRC-32 (IEEE) of its bytes.
    pub crc32: u32,
}

impl FileRecord {
    /// The record of `bytes`.
    pub fn of(bytes: &[u8]) -> FileRecord {
        FileRecord {
            bytes: bytes.len() as u64,
            crc32: crc32fast::hash(bytes),
        }
    }
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
    /// Spacing of the body's particles (m) where the model places them itself (an
    /// MPM body: its grid spacing over the particles per cell axis; a membrane: its
    /// lattice spacing); 0 for a tet-mesh body, whose spacing follows from
    /// `mean_edge`, and in caches written before it existed.
    #[serde(default)]
    pub particle_spacing: f64,
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
        let bytes = std::fs::read(path).map_err(|e| CacheError::io(path, e))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            CacheError::format(
                path,
                format!(
                    "not a perifrac manifest: not UTF-8 (byte {})",
                    e.utf8_error().valid_up_to()
                ),
            )
        })?;
        serde_json::from_str(&text).map_err(|e| {
            CacheError::format(path, format!("not a perifrac manifest (damaged?): {e}"))
        })
    }

    /// Records what was written to `path` (a file under `root`), for
    /// `perifrac verify`.
    pub fn record(&mut self, root: &Path, path: &Path, record: FileRecord) {
        let key = path.strip_prefix(root).unwrap_or(path);
        self.files
            .insert(key.to_string_lossy().replace('\\', "/"), record);
    }

    /// Records every file in each of `folders` (written after the run by a stage:
    /// surfaces, volumes, previews), dropping first the records of files that were
    /// under them, so that `perifrac verify` checks what the stage left. The files are
    /// read back for their checksums; temporary files (`.NAME.tmp-PID`) are skipped.
    pub fn record_folders(&mut self, root: &Path, folders: &[PathBuf]) -> Result<()> {
        self.record_in(root, folders, |_| false, |name| !name.starts_with('.'))
    }

    /// Records the files of frames `range` in each of `folders` (`NNNN.ext`,
    /// `NNNN_what.ext`), dropping first the records of those frames' files there (and
    /// of files there that are gone: a contact sheet the range made stale) and
    /// leaving every other record: what a stage run over a frame range left
    /// ([`record_folders`](Self::record_folders) for a whole shot).
    pub fn record_frames(
        &mut self,
        root: &Path,
        folders: &[PathBuf],
        range: FrameRange,
    ) -> Result<()> {
        let ours = |name: &str| frame_of_file(name).is_some_and(|k| range.contains(k));
        self.record_in(
            root,
            folders,
            |name| !ours(name) && root.join(name).is_file(),
            ours,
        )
    }

    /// In each of `folders`: keeps the records of files under it for which `keep`
    /// (given the record's name) holds and drops the others, then records the files
    /// there whose name `take` accepts, read back for their checksums.
    fn record_in(
        &mut self,
        root: &Path,
        folders: &[PathBuf],
        keep: impl Fn(&str) -> bool,
        take: impl Fn(&str) -> bool,
    ) -> Result<()> {
        for dir in folders {
            let prefix = dir.strip_prefix(root).unwrap_or(dir);
            let prefix = format!("{}/", prefix.to_string_lossy().replace('\\', "/"));
            self.files
                .retain(|name, _| !name.starts_with(&prefix) || keep(name));
            let Ok(entries) = std::fs::read_dir(dir) else {
                continue;
            };
            let mut paths: Vec<PathBuf> = entries
                .flatten()
                .filter(|e| e.file_name().to_str().is_some_and(&take))
                .map(|e| e.path())
                .filter(|p| p.is_file())
                .collect();
            paths.sort();
            for path in paths {
                let bytes = std::fs::read(&path).map_err(|e| CacheError::io(&path, e))?;
                self.record(root, &path, FileRecord::of(&bytes));
            }
        }
        Ok(())
    }

    /// Frames written (`frame_times` has one entry a frame).
    pub fn frames(&self) -> usize {
        self.frame_times.len()
    }

    /// Keeps what describes frames 1 to `frame` (their times, collider centres and
    /// file records) and forgets later ones: what a resume from a checkpoint at
    /// `frame` starts from.
    pub fn truncate_to_frame(&mut self, frame: usize) {
        self.frame_times.truncate(frame);
        self.collider_centers.truncate(frame);
        self.collider_rotations.truncate(frame);
        self.files.retain(|name, _| match frame_of(name) {
            Some(k) => k <= frame,
            None => true,
        });
    }
}

/// The frame number of a per-frame file name (`particles/0007.ply` → 7).
pub fn frame_of(name: &str) -> Option<usize> {
    let file = name.rsplit('/').next()?;
    let stem = file.split('.').next()?;
    (stem.len() == 4 && stem.bytes().all(|b| b.is_ascii_digit()))
        .then(|| stem.parse().ok())
        .flatten()
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
