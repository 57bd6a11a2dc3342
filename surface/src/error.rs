//! The surface stage's error type: every failure names the frame or file it concerns.

use std::path::PathBuf;

use perifrac_cache::CacheError;

/// Everything that can go wrong while surfacing a cache.
#[derive(Debug, thiserror::Error)]
pub enum SurfaceError {
    /// Reading or writing the cache (manifest, frames, surfaces) failed.
    #[error(transparent)]
    Cache(#[from] CacheError),
    /// Writing an output file failed.
    #[error("{path}: {error}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error (in the message, not chained: the OS's words once).
        error: std::io::Error,
    },
    /// The cache cannot be surfaced as asked (no frames, a missing input); the
    /// message names the file.
    #[error("{0}")]
    Input(String),
    /// A surface could not be encoded for its file.
    #[error("{what}: {message}")]
    Encode {
        /// What was being written (`frame 12`, `surface/animated.glb`).
        what: String,
        /// The encoder's error.
        message: String,
    },
    /// A frame's particles cannot be surfaced (none, NaN positions, unknown body).
    #[error("frame {frame}: {message}")]
    Frame {
        /// Frame number (from 1).
        frame: usize,
        /// What is wrong.
        message: String,
    },
    /// A body is a single layer of particles: it has no volume to rasterize.
    #[error(
        "frame {frame}: body '{body}' is a single layer of particles (median local thickness \
         {thickness:.2} particle spacings): the vdb method needs volume to rasterize; use the \
         sheet surface method for membranes and sheets"
    )]
    SingleLayer {
        /// Frame number (from 1).
        frame: usize,
        /// The body's name.
        body: String,
        /// Median thickness of the particles' neighbourhoods, in particle spacings.
        thickness: f64,
    },
    /// OpenVDB failed (its exception text, caught in the shim).
    #[error("frame {frame}: OpenVDB {operation}: {message}")]
    OpenVdb {
        /// Frame number (from 1).
        frame: usize,
        /// What the shim was doing.
        operation: &'static str,
        /// The exception's text.
        message: String,
    },
}

impl SurfaceError {
    /// An I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        SurfaceError::Io {
            path: path.into(),
            error,
        }
    }
}

/// Shorthand for results in this crate.
pub type Result<T, E = SurfaceError> = std::result::Result<T, E>;
