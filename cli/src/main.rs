//! The `perifrac` command: runs scenes through the pipeline. No physics here.
//!
//! | module | what it holds |
//! |---|---|
//! | [`args`] | the clap arguments ([`args::Cli`], [`args::Command`]) and their validated configs ([`args::RunConfig`], [`args::SurfaceConfig`], …) |
//! | [`commands`] | `run`, `demo`, `check`; [`commands::Failure`] and its exit code |
//! | [`memory`] | the memory a run may use (available, `ulimit -v`, cgroup limits) |
//! | [`signals`] | SIGINT/SIGTERM/SIGHUP during a run: a clean stop with a checkpoint |
//! | [`verify`] | `perifrac verify`, and the warnings `render` and `surface` print first |
//! | `surface`, [`render`], `export` | the surface and render stages and the USD export as commands |
//! | [`bench`](mod@bench), [`bench_render`], [`accuracy`], [`stability`], [`plot`] | `perifrac bench …`: throughput, accuracy against a reference, stability, plots |
//!
//! Exit codes: 0 success; 1 a run failed (I/O, blow-up); 2 bad input (scene, flags, a
//! damaged cache or checkpoint, an output folder holding another cache); 3 a run
//! stopped by SIGINT/SIGTERM/SIGHUP after a checkpoint (the message gives the command
//! that resumes it); 128 + N when a second signal N ends it at once (130 for Ctrl-C).
//! `perifrac verify`: 0 clean and complete, 1 the run failed, 2 damaged or missing
//! files, 3 unfinished.

mod accuracy;
mod args;
mod bench;
mod bench_render;
mod check;
mod commands;
mod export;
mod memory;
mod plot;
mod ranks;
mod render;
mod signals;
mod stability;
mod surface;
mod verify;

use std::process::ExitCode;

use clap::Parser;

use args::{Cli, Command};

fn main() -> ExitCode {
    restore_sigpipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(run) => match args::RunConfig::try_from(run) {
            Ok(config) => commands::run(&config, cli.quiet),
            Err(message) => Err(commands::Failure::input(anyhow::anyhow!(message))),
        },
        Command::Surface(args) => match args::SurfaceConfig::try_from(args) {
            Ok(config) => surface::command(&config, cli.quiet),
            Err(message) => Err(commands::Failure::input(anyhow::anyhow!(message))),
        },
        Command::Render(args) => match args::RenderConfig::try_from(args) {
            Ok(config) => render::command(&config, cli.quiet),
            Err(message) => Err(commands::Failure::input(anyhow::anyhow!(message))),
        },
        Command::Check { scene } => check::command(&scene),
        Command::Verify { out } => verify::command(&out),
        Command::Demo {
            out,
            impact,
            threads,
            resume,
            force,
        } => commands::demo(&out, impact, threads, resume, force, cli.quiet),
        Command::Bench { which } => bench::run(which, cli.quiet),
        Command::Export {
            format: args::ExportFormat::Usd { out },
        } => export::usd(&out, cli.quiet).map(|_| ()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let label = match failure.code {
                signals::EXIT_INTERRUPTED => "stopped",
                _ => "error",
            };
            eprintln!("{label}: {:#}", failure.error);
            ExitCode::from(failure.code)
        }
    }
}

/// Output piped into a reader that stops early (`perifrac check … | head`) ends the
/// process quietly, as it does every Unix tool: Rust ignores SIGPIPE, and a write to the
/// closed pipe would then panic in `println!`.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: sets the disposition of one signal to its default before any thread is
    // started; no handler of ours is replaced.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
