//! SIGINT, SIGTERM and SIGHUP while `perifrac run` (or `demo`) works on a cache.
//!
//! A thread waits for the signals (signal-hook's iterator: the handler only wakes it,
//! everything else runs on an ordinary thread). The first signal during the simulation
//! asks the run to stop through its [`StopRequest`]: the run finishes the step it is on
//! (or the frame it is writing), writes a checkpoint there, marks the manifest
//! interrupted and returns, and the command exits with [`EXIT_INTERRUPTED`] and the
//! command that resumes. A second signal, or one outside the simulation (meshing,
//! surfaces, previews: nothing there to checkpoint), waits for the file writes in
//! flight to land (each a write and a rename, never a frame's work), removes this
//! process's temporary files and exits at once with 128 + the signal number (130 for Ctrl-C), as a shell
//! reports a process killed by it.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use perifrac_cache::Layout;
use perifrac_sim::run::StopRequest;
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use signal_hook::iterator::{Handle, Signals};

/// Exit code of a run stopped cleanly by a signal, resumable with `--resume`.
pub const EXIT_INTERRUPTED: u8 = 3;

/// The signal's name, for messages and the manifest.
fn name(signal: i32) -> &'static str {
    match signal {
        SIGINT => "SIGINT (Ctrl-C)",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    }
}

/// Watches for the signals while it lives.
pub struct Watcher {
    handle: Handle,
    thread: Option<std::thread::JoinHandle<()>>,
    simulating: Arc<AtomicBool>,
}

impl Watcher {
    /// Starts watching; `stop` is the run's stop request and `out` the cache whose
    /// temporary files an immediate exit removes.
    pub fn start(stop: StopRequest, out: PathBuf) -> std::io::Result<Watcher> {
        let mut signals = Signals::new([SIGINT, SIGTERM, SIGHUP])?;
        let handle = signals.handle();
        let simulating = Arc::new(AtomicBool::new(false));
        let active = Arc::clone(&simulating);
        let thread = std::thread::spawn(move || {
            for signal in signals.forever() {
                if active.load(Ordering::SeqCst) && stop.reason().is_none() {
                    stop.request(name(signal));
                    eprintln!(
                        "\n{}: finishing the step in progress, then writing a checkpoint \
                         (send it again, or press Ctrl-C again, to quit at once)",
                        name(signal)
                    );
                    continue;
                }
                perifrac_cache::stop_writes();
                let removed = Layout::new(&out).remove_temporary_files().len();
                eprintln!(
                    "\n{}: quitting at once{}; the frames and the last checkpoint on disk stay",
                    name(signal),
                    match removed {
                        0 => String::new(),
                        n => format!(" (removed {n} temporary file{})", plural(n)),
                    }
                );
                std::process::exit(128 + signal);
            }
        });
        Ok(Watcher {
            handle,
            thread: Some(thread),
            simulating,
        })
    }

    /// Whether a signal now asks the run to stop after the step it is on (true) or
    /// exits at once (false).
    pub fn set_simulating(&self, simulating: bool) {
        self.simulating.store(simulating, Ordering::SeqCst);
    }
}

impl Drop for Watcher {
    fn drop(&mut self) {
        self.handle.close();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}
