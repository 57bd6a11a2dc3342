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
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
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
    /// An I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        CacheError::Io {
            path: path.into(),
            source,
        }
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

    /// Whether the error is bad input from the user (a scene file, a checkpoint given
    /// to `--resume`), rather than a failed run or a damaged cache.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            CacheError::Scene { .. } | CacheError::Checkpoint { .. }
        )
    }
}

/// Shorthand for results in this crate.
pub type Result<T, E = CacheError> = std::result::Result<T, E>;
