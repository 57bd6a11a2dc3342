//! The cache on disk, the contract between the stages (ARCHITECTURE.md):
//! `manifest.json`, `scene.toml`, `particles/NNNN.ply`, `tets/NNNN.vtu`, `checkpoint/`.
//!
//! Every file is written to a temporary name in the same directory and renamed into
//! place, so a killed run never leaves a half-written file.

pub mod checkpoint;
pub mod manifest;
pub mod ply;
pub mod vtu;

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Result, SimError};

/// Paths inside an output directory.
#[derive(Debug, Clone)]
pub struct Layout {
    /// The output directory.
    pub root: PathBuf,
}

impl Layout {
    /// The layout under `root`.
    pub fn new(root: impl Into<PathBuf>) -> Layout {
        Layout { root: root.into() }
    }

    /// `manifest.json`.
    pub fn manifest(&self) -> PathBuf {
        self.root.join("manifest.json")
    }

    /// `scene.toml` (the resolved scene).
    pub fn scene(&self) -> PathBuf {
        self.root.join("scene.toml")
    }

    /// `particles/NNNN.ply` for frame `frame` (frames start at 1).
    pub fn particles(&self, frame: usize) -> PathBuf {
        self.root.join("particles").join(format!("{frame:04}.ply"))
    }

    /// `tets/NNNN.vtu`, the split tet mesh of frame `frame`.
    pub fn tets(&self, frame: usize) -> PathBuf {
        self.root.join("tets").join(format!("{frame:04}.vtu"))
    }

    /// The checkpoint file.
    pub fn checkpoint(&self) -> PathBuf {
        self.root.join("checkpoint").join("state.bin")
    }

    /// Creates the directories the simulator writes into.
    pub fn create(&self) -> Result<()> {
        for dir in [
            self.root.clone(),
            self.root.join("particles"),
            self.root.join("checkpoint"),
        ] {
            std::fs::create_dir_all(&dir).map_err(|e| SimError::io(&dir, e))?;
        }
        Ok(())
    }
}

/// Writes `bytes` to `path` atomically (temporary file, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path.parent().unwrap_or_else(|| Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_data()?;
        Ok(())
    };
    write().map_err(|e| SimError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| SimError::io(path, e))
}
