//! Every path of an output directory (ARCHITECTURE.md, "The cache on disk"), and
//! the atomic write every file of it goes through: a temporary name in the same
//! directory, then a rename, so a killed run never leaves a half-written file.
//!
//! Frames are numbered from 1; every file that carries time shows frame k at
//! (k − 1)/`playback_fps` seconds ([`playback_time`]).
//!
//! Frames are numbered from 1 and named with four digits (`NNNN`); turntable views
//! with three (`turntable_NNN.png`).

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{CacheError, Result};

/// Paths inside an output directory. No other code derives a cache path.
#[derive(Debug, Clone)]
pub struct Layout {
    /// The output directory.
    pub root: PathBuf,
}

/// `NNNN.ext`, the file name of frame `frame`.
fn frame_file(frame: usize, extension: &str) -> String {
    format!("{frame:04}.{extension}")
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

    /// `particles/`.
    pub fn particles_dir(&self) -> PathBuf {
        self.root.join("particles")
    }

    /// `particles/NNNN.ply` for frame `frame` (frames start at 1).
    pub fn particles(&self, frame: usize) -> PathBuf {
        self.particles_dir().join(frame_file(frame, "ply"))
    }

    /// `tets/`.
    pub fn tets_dir(&self) -> PathBuf {
        self.root.join("tets")
    }

    /// `tets/NNNN.vtu`, the split tet mesh of frame `frame`.
    pub fn tets(&self, frame: usize) -> PathBuf {
        self.tets_dir().join(frame_file(frame, "vtu"))
    }

    /// `tets/tets.pvd`, the ParaView collection of the tet frames with their times.
    pub fn tets_collection(&self) -> PathBuf {
        self.tets_dir().join("tets.pvd")
    }

    /// `cache.usd`, the USD stage of the whole cache (binary `usdc`).
    pub fn usd(&self) -> PathBuf {
        self.root.join("cache.usd")
    }

    /// `usd/`, the value-clip layers of `cache.usd`.
    pub fn usd_dir(&self) -> PathBuf {
        self.root.join("usd")
    }

    /// `usd/NNNN.usdc`, the value-clip layer of frame `frame`.
    pub fn usd_clip(&self, frame: usize) -> PathBuf {
        self.usd_dir().join(frame_file(frame, "usdc"))
    }

    /// `surface/`.
    pub fn surface_dir(&self) -> PathBuf {
        self.root.join("surface")
    }

    /// `surface/NNNN.glb`, the surfaces of frame `frame`.
    pub fn surface(&self, frame: usize) -> PathBuf {
        self.surface_dir().join(frame_file(frame, "glb"))
    }

    /// `surface/animated.glb`: final topology, one morph target a frame.
    pub fn animated_surface(&self) -> PathBuf {
        self.surface_dir().join("animated.glb")
    }

    /// `surface/NNNN_debris.ply`, the fragments of frame `frame` too small to surface.
    pub fn debris(&self, frame: usize) -> PathBuf {
        self.surface_dir().join(format!("{frame:04}_debris.ply"))
    }

    /// `vdb/`.
    pub fn vdb_dir(&self) -> PathBuf {
        self.root.join("vdb")
    }

    /// `vdb/NNNN.vdb`, the level sets of frame `frame`.
    pub fn vdb(&self, frame: usize) -> PathBuf {
        self.vdb_dir().join(frame_file(frame, "vdb"))
    }

    /// `preview/`.
    pub fn preview_dir(&self) -> PathBuf {
        self.root.join("preview")
    }

    /// `preview/NNNN.png`, the preview image of frame `frame`.
    pub fn preview(&self, frame: usize) -> PathBuf {
        self.preview_dir().join(frame_file(frame, "png"))
    }

    /// `preview/turntable_NNN.png`, turntable view `view` (from 1).
    pub fn turntable(&self, view: usize) -> PathBuf {
        self.preview_dir().join(format!("turntable_{view:03}.png"))
    }

    /// `preview/contact_sheet.png`.
    pub fn contact_sheet(&self) -> PathBuf {
        self.preview_dir().join("contact_sheet.png")
    }

    /// `checkpoint/`.
    pub fn checkpoint_dir(&self) -> PathBuf {
        self.root.join("checkpoint")
    }

    /// `checkpoint/state.bin`, the checkpoint file.
    pub fn checkpoint(&self) -> PathBuf {
        self.checkpoint_dir().join("state.bin")
    }

    /// Frame numbers with a `particles/NNNN.ply`, ascending.
    pub fn particle_frames(&self) -> Vec<usize> {
        frame_numbers(&self.particles_dir(), ".ply")
    }

    /// Frame numbers with a `surface/NNNN.glb`, ascending.
    pub fn surface_frames(&self) -> Vec<usize> {
        frame_numbers(&self.surface_dir(), ".glb")
    }

    /// Creates the directories the simulator writes into.
    pub fn create(&self) -> Result<()> {
        for dir in [
            self.root.clone(),
            self.particles_dir(),
            self.checkpoint_dir(),
        ] {
            std::fs::create_dir_all(&dir).map_err(|e| CacheError::io(&dir, e))?;
        }
        Ok(())
    }
}

/// The playback time (s) of cache frame `frame` (from 1) at `playback_fps`:
/// (frame − 1)/`playback_fps`. The frame's simulation time is in the manifest.
pub fn playback_time(frame: usize, playback_fps: f64) -> f64 {
    (frame as f64 - 1.0) / playback_fps
}

/// Frame numbers of the `NNNN<extension>` files in `dir`, ascending (none if `dir`
/// cannot be read).
fn frame_numbers(dir: &Path, extension: &str) -> Vec<usize> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut frames: Vec<usize> = entries
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            let stem = name.strip_suffix(extension)?;
            (stem.len() == 4).then(|| stem.parse().ok()).flatten()
        })
        .collect();
    frames.sort_unstable();
    frames
}

/// The temporary name beside `path` that a file is written to before it is renamed
/// into place (for writers, like OpenVDB's, that need a path rather than bytes).
pub fn temporary_path(path: &Path) -> PathBuf {
    let dir = path.parent().unwrap_or_else(|| Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dir.join(format!(".{name}.tmp-{}", std::process::id()))
}

/// Writes `bytes` to `path` atomically (temporary file, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temporary_path(path);
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_data()?;
        Ok(())
    };
    write().map_err(|e| CacheError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| CacheError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_and_frame_listing() {
        let dir = tempfile::tempdir().expect("tempdir");
        let layout = Layout::new(dir.path());
        assert!(layout.particles(7).ends_with("particles/0007.ply"));
        assert!(layout.surface(12).ends_with("surface/0012.glb"));
        assert!(layout.debris(3).ends_with("surface/0003_debris.ply"));
        assert!(layout.tets_collection().ends_with("tets/tets.pvd"));
        assert!(layout.usd().ends_with("cache.usd"));
        assert!(layout.usd_clip(5).ends_with("usd/0005.usdc"));
        assert!(layout.turntable(2).ends_with("preview/turntable_002.png"));
        layout.create().expect("create");
        for frame in [3, 1] {
            write_atomic(&layout.particles(frame), b"x").expect("write");
        }
        write_atomic(&layout.particles_dir().join("notes.ply"), b"x").expect("write");
        assert_eq!(layout.particle_frames(), vec![1, 3]);
        assert!(layout.surface_frames().is_empty());
    }
}
