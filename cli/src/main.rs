//! The `perifrac` command: runs scenes through the pipeline. No physics here.
//!
//! | module | what it holds |
//! |---|---|
//! | [`args`] | the clap arguments ([`args::Cli`], [`args::Command`]) and their validated configs ([`args::RunConfig`], [`args::SurfaceConfig`], …) |
//! | [`commands`] | `run`, `demo`, `check`; [`commands::Failure`] and its exit code |
//! | `surface`, [`render`], `export` | the surface and render stages and the USD export as commands |
//! | [`bench`](mod@bench), [`bench_render`], [`accuracy`], [`stability`], [`plot`] | `perifrac bench …`: throughput, accuracy against a reference, stability, plots |
//!
//! Exit codes: 0 success, 1 a run failed (I/O, blow-up), 2 bad input (scene, flags).

mod accuracy;
mod args;
mod bench;
mod bench_render;
mod commands;
mod export;
mod plot;
mod render;
mod stability;
mod surface;

use std::process::ExitCode;

use clap::Parser;

use args::{Cli, Command};

fn main() -> ExitCode {
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
        Command::Check { scene } => commands::check(&scene),
        Command::Demo { out, threads } => commands::demo(&out, threads, cli.quiet),
        Command::Bench { which } => bench::run(which, cli.quiet),
        Command::Export {
            format: args::ExportFormat::Usd { out },
        } => export::usd(&out, cli.quiet).map(|_| ()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("error: {:#}", failure.error);
            ExitCode::from(failure.code)
        }
    }
}
