//! The simulator's error type: every failure names what it was working on.

use std::path::PathBuf;

/// Everything that can go wrong in the simulator, with enough context to fix it.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// Reading or writing a file failed.
    #[error("{path}: {error}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error (in the message, not chained, so it reads once).
        error: std::io::Error,
    },
    /// A scene file is bad, or a cache file (frames, manifest, checkpoint) could not
    /// be read or written.
    #[error(transparent)]
    Cache(#[from] perifrac_cache::CacheError),
    /// A body could not be discretized.
    #[error("body '{body}': {message}")]
    Mesh {
        /// The body's name.
        body: String,
        /// What went wrong.
        message: String,
    },
    /// A collider could not be built (its mesh or transforms file).
    #[error("collider {index}: {message}")]
    Collider {
        /// The collider's index in the scene (`[[collider]]` order, from 0).
        index: usize,
        /// What went wrong, with the file and line.
        message: String,
    },
    /// The run would not fit in memory or is otherwise not runnable as asked.
    #[error("{0}")]
    Refused(String),
    /// The run was asked to stop (a signal, through [`crate::run::StopRequest`]): it
    /// finished the step it was on and checkpointed the world there.
    #[error("interrupted by {reason}: frames to {frame} written, checkpointed at step {step}")]
    Interrupted {
        /// Who asked (e.g. `SIGTERM`).
        reason: String,
        /// The last frame written, and the checkpoint's frame.
        frame: usize,
        /// The step the checkpoint holds.
        step: u64,
    },
    /// The simulation became unstable.
    #[error(
        "blow-up at step {step} (t = {time:.6e} s): {what} at particle {particle} \
         (position {position:?}); last good frame {last_good_frame} is on disk"
    )]
    BlowUp {
        /// Step at which it was detected.
        step: u64,
        /// Simulation time.
        time: f64,
        /// What was detected (non-finite value, energy growth).
        what: String,
        /// The particle where it was seen first.
        particle: usize,
        /// That particle's position.
        position: [f64; 3],
        /// The last frame written before the blow-up.
        last_good_frame: usize,
    },
}

impl SimError {
    /// An I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        SimError::Io {
            path: path.into(),
            error,
        }
    }
}

/// Shorthand for results in this crate.
pub type Result<T, E = SimError> = std::result::Result<T, E>;
