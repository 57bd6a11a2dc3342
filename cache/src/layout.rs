//! Every path of an output directory (ARCHITECTURE.md, "The cache on disk"), and
//! the atomic write every file of it goes through: a temporary name in the same
//! directory, then a rename, so a killed run never leaves a half-written file.
//!
//! Frames are numbered from 1; every file that carries time shows frame k on
//! timeline frame k, (k − 1)/`playback_fps` seconds after frame 1 ([`playback_time`];
//! `animated.glb` keys it at k/`playback_fps` s, where Blender's glTF importer puts
//! frame k).
//!
//! Frames are numbered from 1 and named with four digits (`NNNN`); turntable views
//! with three (`turntable_NNN.png`).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{PoisonError, RwLock, RwLockReadGuard};

use crate::error::{CacheError, Result};
use crate::frames::FrameRange;
use crate::manifest::Manifest;

/// Paths inside an output directory. No other code derives a cache path.
#[derive(Debug, Clone)]
pub struct Layout {
    /// The output directory.
    pub root: PathBuf,
}

/// Waits for an exclusive advisory lock on `file` (flock(2); std's `File::lock` is
/// newer than the workspace's rust-version), released when the file closes.
fn lock_exclusive(file: &std::fs::File) -> std::io::Result<()> {
    use rustix::fs::{FlockOperation, flock};
    loop {
        match flock(file, FlockOperation::LockExclusive) {
            Err(rustix::io::Errno::INTR) => continue,
            result => return result.map_err(std::io::Error::from),
        }
    }
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

    /// Records in the manifest every file the stages after the run left in `folders`
    /// ([`Manifest::record_folders`]) and writes it; a cache whose manifest does not
    /// read is left as it is (`perifrac verify` reports that).
    pub fn record_outputs(&self, folders: &[PathBuf]) -> Result<()> {
        self.update_manifest(|m| m.record_folders(&self.root, folders))
    }

    /// Records in the manifest the files of frames `range` the stages left in
    /// `folders` ([`Manifest::record_frames`]), keeping every other record: what a
    /// stage over a frame range does, side by side with others on the same cache.
    pub fn record_frame_outputs(&self, folders: &[PathBuf], range: FrameRange) -> Result<()> {
        self.update_manifest(|m| m.record_frames(&self.root, folders, range))
    }

    /// Reads the manifest, changes it with `change` and writes it back, holding an
    /// exclusive lock on `.manifest.lock` throughout, so that stages updating it side
    /// by side (frame ranges of a farm writing into one cache) never lose each other's
    /// changes. A manifest that does not read is left as it is (`perifrac verify`
    /// reports that).
    pub fn update_manifest(&self, change: impl FnOnce(&mut Manifest) -> Result<()>) -> Result<()> {
        let path = self.manifest_lock();
        let lock = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| CacheError::io(&path, e))?;
        lock_exclusive(&lock).map_err(|e| CacheError::io(&path, e))?;
        let Ok(mut manifest) = Manifest::read(&self.manifest()) else {
            return Ok(());
        };
        change(&mut manifest)?;
        manifest.write(&self.manifest())
        // The lock goes with the file handle.
    }

    /// `manifest.json`.
    pub fn manifest(&self) -> PathBuf {
        self.root.join("manifest.json")
    }

    /// `.manifest.lock`, the lock [`update_manifest`](Self::update_manifest) holds.
    pub fn manifest_lock(&self) -> PathBuf {
        self.root.join(".manifest.lock")
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

    /// `sheet/`.
    pub fn sheet_dir(&self) -> PathBuf {
        self.root.join("sheet")
    }

    /// `sheet/NNNN.ply`, a membrane's sheet (particles and intact triangles) at frame
    /// `frame`.
    pub fn sheet(&self, frame: usize) -> PathBuf {
        self.sheet_dir().join(frame_file(frame, "ply"))
    }

    /// `tets/tets.pvd`, the ParaView collection of the tet frames with their times.
    pub fn tets_collection(&self) -> PathBuf {
        self.tets_dir().join("tets.pvd")
    }

    /// `colliders/`.
    pub fn colliders_dir(&self) -> PathBuf {
        self.root.join("colliders")
    }

    /// `colliders/mesh_N.ply`, the geometry of mesh collider `index` (its place in the
    /// scene's `[[collider]]` list, from 0) in its own frame.
    pub fn collider_mesh(&self, index: usize) -> PathBuf {
        self.colliders_dir()
            .join(format!("{}.ply", crate::collider::mesh_name(index)))
    }

    /// `cache.usd`, the USD stage of the whole cache (binary `usdc`).
    pub fn usd(&self) -> PathBuf {
        self.root.join("cache.usd")
    }

    /// `usd/`, the value clips of `cache.usd`: one layer a frame and the clip manifest.
    pub fn usd_dir(&self) -> PathBuf {
        self.root.join("usd")
    }

    /// `usd/NNNN.usdc`, the value clip of `cache.usd` holding frame `frame`'s time
    /// samples.
    pub fn usd_clip(&self, frame: usize) -> PathBuf {
        self.usd_dir().join(frame_file(frame, "usdc"))
    }

    /// `usd/manifest.usdc`, the clip manifest of `cache.usd` (the attributes its value
    /// clips give).
    pub fn usd_clip_manifest(&self) -> PathBuf {
        self.usd_dir().join("manifest.usdc")
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

    /// `preview/frame_NNNN.png`, a single frame rendered on its own (`perifrac render
    /// --frame`), apart from the sequence's `preview/NNNN.png` so it never replaces one.
    pub fn single_preview(&self, frame: usize) -> PathBuf {
        self.preview_dir().join(format!("frame_{frame:04}.png"))
    }

    /// `preview/turntable_NNN.png`, turntable view `view` (from 1).
    pub fn turntable(&self, view: usize) -> PathBuf {
        self.preview_dir().join(format!("turntable_{view:03}.png"))
    }

    /// `preview/movie.png`, the preview frames as an animated PNG at the playback rate.
    pub fn movie(&self) -> PathBuf {
        self.preview_dir().join("movie.png")
    }

    /// `preview/movie.mp4`, the preview frames as an H.264 MP4 (written when ffmpeg is
    /// on the machine).
    pub fn movie_mp4(&self) -> PathBuf {
        self.preview_dir().join("movie.mp4")
    }

    /// `preview/turntable.png`, the turntable views as an animated PNG.
    pub fn turntable_movie(&self) -> PathBuf {
        self.preview_dir().join("turntable.png")
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

    /// Whether the directory holds a cache (a manifest, particle frames or a
    /// checkpoint): a new run into it must resume it or replace it, never mix with it.
    pub fn holds_cache(&self) -> bool {
        self.manifest().exists() || !self.particle_frames().is_empty() || self.checkpoint().exists()
    }

    /// Removes the cache in the directory: the manifest (and its lock), the resolved scene, `cache.usd`
    /// (whose clips are in `usd/`) and the
    /// `particles/`, `tets/`, `sheet/`, `colliders/`, `surface/`, `vdb/`, `preview/`,
    /// `checkpoint/` and `usd/` directories (nothing else). `perifrac run --force` calls it before
    /// a new run.
    pub fn clear(&self) -> Result<()> {
        for dir in self.directories() {
            match std::fs::remove_dir_all(&dir) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(CacheError::io(&dir, e));
                }
                _ => {}
            }
        }
        for file in [
            self.manifest(),
            self.manifest_lock(),
            self.scene(),
            self.usd(),
        ] {
            match std::fs::remove_file(&file) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(CacheError::io(&file, e));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Every directory of the layout below the root.
    fn directories(&self) -> [PathBuf; 9] {
        [
            self.particles_dir(),
            self.tets_dir(),
            self.sheet_dir(),
            self.colliders_dir(),
            self.surface_dir(),
            self.vdb_dir(),
            self.preview_dir(),
            self.checkpoint_dir(),
            self.usd_dir(),
        ]
    }

    /// Removes the temporary files ([`temporary_file`]) a killed or failed writer
    /// left in the cache: those of this process and of processes no longer running
    /// (a live process's are its writes in flight). Returns the files removed.
    pub fn remove_temporary_files(&self) -> Vec<PathBuf> {
        let own = std::process::id();
        let mut removed = Vec::new();
        let dirs = std::iter::once(self.root.clone()).chain(self.directories());
        for dir in dirs {
            let Ok(entries) = std::fs::read_dir(&dir) else {
                continue;
            };
            for entry in entries.flatten() {
                let name = entry.file_name();
                let Some(pid) = name.to_str().and_then(temporary_owner) else {
                    continue;
                };
                if (pid == own || !process_is_running(pid))
                    && std::fs::remove_file(entry.path()).is_ok()
                {
                    removed.push(entry.path());
                }
            }
        }
        removed.sort();
        removed
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

/// Held shared by every temporary file of this process while it exists and taken
/// for good by [`stop_writes`], so an exit at once can leave none behind.
static WRITES: RwLock<()> = RwLock::new(());

/// The temporary name `.NAME.tmp-PID` beside `path` that a file is written to
/// before it is renamed into place.
fn temporary_path(path: &Path) -> PathBuf {
    let dir = path.parent().unwrap_or_else(|| Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dir.join(format!(".{name}.tmp-{}", std::process::id()))
}

/// A file's temporary name while it is written (for writers, like OpenVDB's, that
/// need a path rather than bytes; [`write_atomic`] for the others): the writer
/// creates it, renames it into place or removes it, then drops this.
/// [`stop_writes`] waits until every one alive is dropped.
pub struct TemporaryFile {
    /// Where the file is written before the rename.
    pub path: PathBuf,
    _writing: RwLockReadGuard<'static, ()>,
}

/// The temporary file for `path`; blocks for good once [`stop_writes`] was called.
pub fn temporary_file(path: &Path) -> TemporaryFile {
    TemporaryFile {
        _writing: WRITES.read().unwrap_or_else(PoisonError::into_inner),
        path: temporary_path(path),
    }
}

/// Waits for the writes in flight to rename or remove their temporary files and
/// blocks every later one, for the rest of the process: what an exit at once calls
/// before it removes what is left ([`Layout::remove_temporary_files`]) and exits.
pub fn stop_writes() {
    std::mem::forget(WRITES.write().unwrap_or_else(PoisonError::into_inner));
}

/// The process id in a temporary file name `.NAME.tmp-PID`, if it is one.
fn temporary_owner(name: &str) -> Option<u32> {
    let (stem, pid) = name.rsplit_once(".tmp-")?;
    (stem.starts_with('.') && stem.len() > 1 && !pid.is_empty())
        .then(|| pid.parse().ok())
        .flatten()
}

/// Whether process `pid` is running (Linux: `/proc/PID` exists; elsewhere every
/// other process counts as gone).
fn process_is_running(pid: u32) -> bool {
    Path::new("/proc").join(pid.to_string()).exists()
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, then a rename.
/// On failure the temporary file is removed and the error names `path`, the OS's
/// reason and the fix (for a full disk, the free space and the bytes needed).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_file(path, |f| f.write_all(bytes), || bytes.len() as u64)
}

/// Writes the file `path` atomically as [`write_atomic`] does, its bytes passed by
/// `write` through a buffer instead of held whole (`needed`, their length, goes in
/// a full disk's message). Returns the file's record (length and CRC-32).
pub fn write_atomic_with(
    path: &Path,
    needed: u64,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<crate::manifest::FileRecord> {
    write_atomic_file(
        path,
        |file| {
            let mut out = Recorded {
                inner: std::io::BufWriter::with_capacity(1 << 20, file),
                crc: crc32fast::Hasher::new(),
                bytes: 0,
            };
            write(&mut out)?;
            out.inner.flush()?;
            Ok(crate::manifest::FileRecord {
                bytes: out.bytes,
                crc32: out.crc.finalize(),
            })
        },
        || needed,
    )
}

/// Writes the file `path` atomically: `write` fills the temporary file beside it,
/// which is synced and renamed into place. On failure the temporary file is removed
/// and the error names `path`, the OS's reason and the fix (for a full disk, the free
/// space and the `needed` bytes).
pub fn write_atomic_file<T>(
    path: &Path,
    write: impl FnOnce(&mut std::fs::File) -> std::io::Result<T>,
    needed: impl FnOnce() -> u64,
) -> Result<T> {
    let tmp = temporary_file(path);
    let written = || -> std::io::Result<T> {
        let mut file = std::fs::File::create(&tmp.path)?;
        let value = write(&mut file)?;
        file.sync_data()?;
        drop(file);
        std::fs::rename(&tmp.path, path)?;
        Ok(value)
    };
    written().map_err(|error| {
        // The partial file would keep a full disk full.
        let _ = std::fs::remove_file(&tmp.path);
        write_error(path, error, needed())
    })
}

/// A writer that keeps the length and CRC-32 of what went through it.
struct Recorded<W> {
    inner: W,
    crc: crc32fast::Hasher,
    bytes: u64,
}

impl<W: Write> Write for Recorded<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.crc.update(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// The error of a failed write of `needed` bytes to `path`, with the fix.
pub fn write_error(path: &Path, error: std::io::Error, needed: u64) -> CacheError {
    use std::io::ErrorKind;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let hint = match error.kind() {
        ErrorKind::StorageFull | ErrorKind::QuotaExceeded => {
            let free = free_space(dir).map_or_else(
                || "an unknown amount of space".to_string(),
                |b| format!("{} free", human_bytes(b)),
            );
            format!(
                "; the filesystem of {} has {free} and this file needs {}: free some \
                 space, or write the cache to another disk (-o)",
                dir.display(),
                human_bytes(needed)
            )
        }
        ErrorKind::FileTooLarge => format!(
            "; the file ({}) is above this process's file size limit (`ulimit -f`): raise it",
            human_bytes(needed)
        ),
        ErrorKind::PermissionDenied => {
            format!("; check that {} is writable by this user", dir.display())
        }
        ErrorKind::ReadOnlyFilesystem => {
            "; the filesystem is read-only: write the cache elsewhere (-o)".to_string()
        }
        ErrorKind::NotFound => format!(
            "; the directory {} is gone (removed while the run was writing?)",
            dir.display()
        ),
        _ => String::new(),
    };
    CacheError::Write {
        path: path.to_path_buf(),
        error,
        hint,
    }
}

/// Bytes the filesystem holding `path` gives an unprivileged user, if known.
pub fn free_space(path: &Path) -> Option<u64> {
    let stat = rustix::fs::statvfs(path).ok()?;
    Some(stat.f_bavail.saturating_mul(stat.f_frsize))
}

/// `1.5 MiB`, `820 B`: a byte count for messages.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["KiB", "MiB", "GiB", "TiB", "PiB"];
    if bytes < 1024 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

#[cfg(test)]
mod tests;
