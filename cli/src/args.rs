//! Command-line arguments: parsed raw by clap, then validated into configs.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// perifrac: fracture animation for visual effects.
#[derive(Debug, Parser)]
#[command(name = "perifrac", version, about, long_about = None)]
pub struct Cli {
    /// No progress bar.
    #[arg(long, global = true)]
    pub quiet: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a scene and write its cache.
    Run(RunArgs),
    /// Surface a cache's particle frames (level sets, .vdb files and meshes).
    Surface(SurfaceArgs),
    /// Validate a scene and print what it would cost.
    Check {
        /// The scene file.
        scene: PathBuf,
    },
    /// Run the built-in demo scene (a sphere through a glass wall).
    Demo {
        /// Output directory.
        #[arg(short, long, default_value = "out/demo")]
        out: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Benchmarks.
    Bench {
        /// Which benchmark.
        #[command(subcommand)]
        which: BenchCommand,
    },
}

/// Benchmarks.
#[derive(Debug, Subcommand)]
pub enum BenchCommand {
    /// Bond-updates per second for an elastic, a plastic and a fracturing wall.
    Throughput {
        /// Target particle count of each wall.
        #[arg(long, default_value_t = 300_000)]
        particles: usize,
        /// Steps to time (after one warm-up step).
        #[arg(long, default_value_t = 10)]
        steps: usize,
        /// Also time the scenes of Chen Table 1 (`assets/scenes` files) rescaled to
        /// the paper's particle counts, where memory allows (`throughput-table1.md`).
        #[arg(long)]
        table1: Option<PathBuf>,
        /// Where to write `throughput.md`.
        #[arg(short, long, default_value = "bench")]
        out: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Edge cases (time step past the stable bound, ν = 0.45, stiffness ratio 10^6,
    /// a 500 m/s projectile, a single layer of particles, a shattered body): each
    /// stays finite and bounded or is caught; writes `stability.md`.
    Stability {
        /// Where to write the report.
        #[arg(short, long, default_value = "bench")]
        out: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Run time against error on the validation scenes (Chen §6): peridynamics and
    /// both FEM references against the converged corotated FEM; writes
    /// `accuracy.md` and `accuracy.png`.
    Accuracy {
        /// Two scenes, two resolutions, a short run (under five minutes).
        #[arg(long)]
        quick: bool,
        /// Directory of the validation scene files.
        #[arg(long, default_value = "assets/scenes")]
        scenes: PathBuf,
        /// Where to write the report and the plot.
        #[arg(short, long, default_value = "bench")]
        out: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
}

/// `perifrac run` as typed.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Output directory (default: `out/<scene name>`).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Stop after this many frames.
    #[arg(long)]
    pub frames: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<String>,
    /// Continue an interrupted run from its checkpoint.
    #[arg(long)]
    pub resume: bool,
}

/// A surface method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SurfaceMethodArg {
    /// OpenVDB level sets per fragment: `vdb/NNNN.vdb`, `surface/NNNN.glb`.
    Vdb,
}

/// `perifrac surface` as typed.
#[derive(Debug, clap::Args)]
pub struct SurfaceArgs {
    /// The output directory of a `perifrac run` (its settings come from the scene
    /// there, `[output.vdb]`).
    pub out: PathBuf,
    /// The surface method.
    #[arg(long, value_enum, default_value_t = SurfaceMethodArg::Vdb)]
    pub method: SurfaceMethodArg,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<String>,
}

/// A validated `perifrac surface`.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceConfig {
    /// The cache to surface.
    pub out: PathBuf,
    /// The method.
    pub method: SurfaceMethodArg,
    /// Thread count.
    pub threads: Option<usize>,
}

impl TryFrom<SurfaceArgs> for SurfaceConfig {
    type Error = String;

    fn try_from(a: SurfaceArgs) -> Result<Self, Self::Error> {
        Ok(SurfaceConfig {
            threads: positive("--threads", a.threads.as_deref())?,
            out: a.out,
            method: a.method,
        })
    }
}

/// A validated `perifrac run`.
#[derive(Debug, Clone, PartialEq)]
pub struct RunConfig {
    /// The scene file.
    pub scene: PathBuf,
    /// Output directory, if given.
    pub out: Option<PathBuf>,
    /// Frame limit.
    pub frames: Option<usize>,
    /// Thread count.
    pub threads: Option<usize>,
    /// Resume from a checkpoint.
    pub resume: bool,
}

fn positive(flag: &str, value: Option<&str>) -> Result<Option<usize>, String> {
    value
        .map(|v| match v.parse::<usize>() {
            Ok(n) if n > 0 => Ok(n),
            _ => Err(format!("{flag} takes a whole number ≥ 1, got '{v}'")),
        })
        .transpose()
}

impl TryFrom<RunArgs> for RunConfig {
    type Error = String;

    fn try_from(a: RunArgs) -> Result<Self, Self::Error> {
        Ok(RunConfig {
            frames: positive("--frames", a.frames.as_deref())?,
            threads: positive("--threads", a.threads.as_deref())?,
            scene: a.scene,
            out: a.out,
            resume: a.resume,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<RunConfig, String> {
        let cli = Cli::try_parse_from(args).map_err(|e| e.to_string())?;
        match cli.command {
            Command::Run(r) => RunConfig::try_from(r),
            other => Err(format!("not run: {other:?}")),
        }
    }

    #[test]
    fn run_flags() {
        let c = parse(&[
            "perifrac",
            "run",
            "a.toml",
            "-o",
            "x",
            "--frames",
            "3",
            "--threads",
            "2",
            "--resume",
        ])
        .unwrap();
        assert_eq!(c.frames, Some(3));
        assert_eq!(c.threads, Some(2));
        assert_eq!(c.out, Some(PathBuf::from("x")));
        assert!(c.resume);
    }

    #[test]
    fn bad_numbers_are_refused() {
        assert!(
            parse(&["perifrac", "run", "a.toml", "--frames", "0"])
                .unwrap_err()
                .contains("--frames")
        );
        assert!(
            parse(&["perifrac", "run", "a.toml", "--threads", "two"])
                .unwrap_err()
                .contains("--threads")
        );
        assert!(parse(&["perifrac", "run"]).is_err());
    }

    #[test]
    fn surface_flags() {
        let parse = |args: &[&str]| -> Result<SurfaceConfig, String> {
            let cli = Cli::try_parse_from(args).map_err(|e| e.to_string())?;
            match cli.command {
                Command::Surface(s) => SurfaceConfig::try_from(s),
                other => Err(format!("not surface: {other:?}")),
            }
        };
        let c = parse(&[
            "perifrac",
            "surface",
            "out/x",
            "--method",
            "vdb",
            "--threads",
            "2",
        ])
        .unwrap();
        assert_eq!(c.out, PathBuf::from("out/x"));
        assert_eq!(c.method, SurfaceMethodArg::Vdb);
        assert_eq!(c.threads, Some(2));
        assert_eq!(
            parse(&["perifrac", "surface", "o"]).unwrap().method,
            SurfaceMethodArg::Vdb
        );
        assert!(parse(&["perifrac", "surface", "o", "--method", "marching"]).is_err());
        assert!(
            parse(&["perifrac", "surface", "o", "--threads", "0"])
                .unwrap_err()
                .contains("--threads")
        );
    }

    #[test]
    fn quiet_is_global() {
        let cli = Cli::try_parse_from(["perifrac", "check", "a.toml", "--quiet"]).unwrap();
        assert!(cli.quiet);
    }
}
