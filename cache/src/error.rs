//! The cache's error type: every failure names the file it concerns.

use std::path::PathBuf;

/// Everything that can go wrong reading or writing the cache or a scene file.
#[derive(Debug, thiserror::Error)]
pub enum CacheError {
    /// A scene file is malformed or has a value out of range.
    #[error("{file}:{line}:{column}: {key}: {message}")]
    Scene {
        /// The scene file.
        file: PathBuf,
        /// 1-based line of the offending key or value.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The dotted key, e.g. `materials.glass.density`.
        key: String,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// Reading a file (or making a directory) failed.
    #[error("{path}: {error}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error (shown in the message, not chained as its source, so
        /// the OS's words appear once).
        error: std::io::Error,
    },
    /// A file to be read is not there: a scene file given on the command line, or a
    /// file of the cache (its manifest, a frame) that a stage reads. Bad input (exit
    /// code 2).
    #[error("{path}: no such file{hint}")]
    Missing {
        /// The file.
        path: PathBuf,
        /// `; ` and the fix, or empty.
        hint: &'static str,
    },
    /// Writing a cache file failed: names the file (never its temporary name), the
    /// OS's reason once, and what to do about it.
    #[error("could not write {path}: {error}{hint}")]
    Write {
        /// The file being written.
        path: PathBuf,
        /// The underlying error.
        error: std::io::Error,
        /// `; ` and the fix (for a full disk: the free space and what the file needs),
        /// or empty.
        hint: String,
    },
    /// A checkpoint is damaged, of another version, or does not fit the scene: bad
    /// input to `--resume` (exit code 2), never resumed from.
    #[error("{path}: {message}")]
    Checkpoint {
        /// The checkpoint file.
        path: PathBuf,
        /// What is wrong with it and how to rerun.
        message: String,
    },
    /// A cache file does not have the expected layout.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
}

impl CacheError {
    /// An I/O error with the path it concerns ([`CacheError::Missing`] when the file
    /// is not there).
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        let path = path.into();
        if error.kind() == std::io::ErrorKind::NotFound {
            let hint = missing_hint(&path);
            return CacheError::Missing { path, hint };
        }
        CacheError::Io { path, error }
    }

    /// A malformed file.
    pub fn format(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        CacheError::Format {
            path: path.into(),
            message: message.into(),
        }
    }

    /// A checkpoint that cannot be resumed from.
    pub fn checkpoint(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        CacheError::Checkpoint {
            path: path.into(),
            message: message.into(),
        }
    }

    /// Whether the error is bad input (a scene file, a checkpoint given to `--resume`,
    /// or a cache file that is damaged or not what it should be: exit code 2 from
    /// every command), rather than a failed run (I/O).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            CacheError::Scene { .. }
                | CacheError::Format { .. }
                | CacheError::Checkpoint { .. }
                | CacheError::Missing { .. }
        )
    }

    /// Whether the error is a write that failed for lack of space.
    pub fn is_disk_full(&self) -> bool {
        matches!(self, CacheError::Write { error, .. } if is_disk_full(error))
    }
}

/// The fix for a missing file: a cache file (the manifest, the resolved scene, a file
/// in one of the cache's folders) means an incomplete cache; a scene file, a wrong path.
fn missing_hint(path: &std::path::Path) -> &'static str {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    let folder = path
        .parent()
        .and_then(|p| p.file_name())
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    let cache_folders = [
        "particles",
        "tets",
        "surface",
        "vdb",
        "colliders",
        "checkpoint",
    ];
    let in_cache = name == "manifest.json"
        || cache_folders.contains(&folder)
        || path.with_file_name("manifest.json").is_file();
    if in_cache {
        "; the cache is incomplete or not a perifrac cache: give the output folder of a \
         `perifrac run`, or run the scene again into it with --force"
    } else if name.ends_with(".toml") {
        "; give the path of a scene file (assets/scenes/ holds examples)"
    } else {
        ""
    }
}

/// Shorthand for results in this crate.
pub type Result<T, E = CacheError> = std::result::Result<T, E>;

/// Whether `error` says the filesystem (or the file size limit) is full.
pub(crate) fn is_disk_full(error: &std::io::Error) -> bool {
    matches!(
        error.kind(),
        std::io::ErrorKind::StorageFull
            | std::io::ErrorKind::QuotaExceeded
            | std::io::ErrorKind::FileTooLarge
    )
}
