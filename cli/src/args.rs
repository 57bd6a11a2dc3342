//! Command-line arguments: parsed raw by clap, then validated into configs.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// Exit codes, shown under `perifrac --help`.
const EXIT_CODES: &str = "Exit codes: 0 success; 1 the run failed (I/O, full disk, blow-up); \
2 bad input (scene, flags, a damaged cache or checkpoint, an output folder holding another \
cache); 3 stopped by SIGINT/SIGTERM/SIGHUP after a checkpoint (resume with --resume); \
128+N a second signal N ended it at once (130: Ctrl-C). verify: 0 clean and complete, \
1 the run failed, 2 damaged or missing files, 3 unfinished.";

/// perifrac: fracture animation for visual effects.
#[derive(Debug, Parser)]
#[command(name = "perifrac", version, about, long_about = None, after_help = EXIT_CODES)]
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
    /// Render preview images of a cache: `preview/NNNN.png`, turntables, a contact
    /// sheet.
    Render(RenderArgs),
    /// Check a cache against its manifest: every frame there, each file's size and
    /// checksum as written, finite positions, the checkpoint readable. Exit 0 when
    /// clean and complete, 1 when the run failed, 2 when something is damaged or
    /// missing, 3 when the run is unfinished (running or interrupted).
    Verify {
        /// The output directory of a `perifrac run`.
        out: PathBuf,
    },
    /// Validate a scene and print what it would cost.
    Check {
        /// The scene file.
        scene: PathBuf,
    },
    /// Run the built-in demo: a steel ball through a glass wall, and the 2 s after it
    /// with every piece landing (a finished shot).
    Demo {
        /// Output directory.
        #[arg(short, long, default_value = "out/demo")]
        out: PathBuf,
        /// Only the impact: the first 4 ms, every piece deformable (the scene of the
        /// physics checks, assets/scenes/demo.toml).
        #[arg(long)]
        impact: bool,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Continue an interrupted demo from its checkpoint.
        #[arg(long, conflicts_with = "force")]
        resume: bool,
        /// Replace a cache already in the output directory.
        #[arg(long)]
        force: bool,
    },
    /// Benchmarks.
    Bench {
        /// Which benchmark.
        #[command(subcommand)]
        which: BenchCommand,
    },
    /// Write an existing cache in another format.
    Export {
        /// The format.
        #[command(subcommand)]
        format: ExportFormat,
    },
}

/// Formats `perifrac export` writes.
#[derive(Debug, Subcommand)]
pub enum ExportFormat {
    /// The whole cache as one USD stage, `OUT/cache.usd` (binary usdc): particles,
    /// surfaces, volumes and colliders, frame k at time code k, played at
    /// `[output] playback_fps`.
    Usd {
        /// The output directory of a `perifrac run`.
        out: PathBuf,
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
    /// Render time of a 1280×720 frame of a 200k-triangle mesh and of 3×10^5
    /// particles (warm, per pass), and the demo's preview time against its simulation
    /// time.
    Render {
        /// Image size, WIDTHxHEIGHT.
        #[arg(long, default_value = "1280x720")]
        size: String,
        /// Triangles of the mesh.
        #[arg(long, default_value_t = 200_000)]
        triangles: usize,
        /// Particles.
        #[arg(long, default_value_t = 300_000)]
        particles: usize,
        /// Timed frames of each (after one warm-up frame).
        #[arg(long, default_value_t = 5)]
        frames: usize,
        /// Also run the demo and time its previews against its simulation.
        #[arg(long)]
        demo: bool,
        /// Where to write `render.md` (and the demo's cache).
        #[arg(short, long, default_value = "bench")]
        out: PathBuf,
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

/// What the particles (and meshes, for damage) are coloured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorByArg {
    /// Each body in its material's colour (`color` in the scene, else a default
    /// palette), crack faces apart (the default).
    Material,
    /// Damage, blue intact → red broken (Chen et al. 2018, Fig. 6).
    Damage,
    /// Fragment id.
    Fragment,
    /// Plastic strain.
    Plastic,
    /// Temperature (scenes with heat diffusion, or MPM with thermal Johnson–Cook).
    Temperature,
    /// A membrane's diffused quantity θ (sheet surfaces, else particles).
    Quantity,
}

/// `perifrac render` as typed.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The output directory of a `perifrac run`.
    pub out: PathBuf,
    /// Also render N turntable views (`preview/turntable_NNN.png`) of `--frame` or of
    /// the last frame.
    #[arg(long)]
    pub turntable: Option<String>,
    /// Render only this frame (default: every frame, and the contact sheet).
    #[arg(long)]
    pub frame: Option<String>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "960x540")]
    pub size: String,
    /// Colouring (default: material, crack faces apart).
    #[arg(long, value_enum)]
    pub color_by: Option<ColorByArg>,
    /// Worker threads, each with its own GL context (default: all cores).
    #[arg(long)]
    pub threads: Option<String>,
    /// Camera azimuth in degrees about the vertical axis (0 looks from +z, 90 from +x).
    /// Default: 35° off the projectile's path on the side it comes from (its impact
    /// face in view), else 35.
    #[arg(long, allow_hyphen_values = true)]
    pub azimuth: Option<String>,
    /// Also write the frames as a movie at the playback rate: `preview/movie.png`
    /// (animated PNG), `preview/movie.mp4` when ffmpeg is installed, and
    /// `preview/turntable.png` with `--turntable`.
    #[arg(long)]
    pub movie: bool,
    /// Draw the frame number, simulation time and playback time in the bottom-left
    /// corner of each frame (for reviews).
    #[arg(long)]
    pub overlay: bool,
    /// The sequence's camera: `fixed` (framed on the whole shot), `follow` (each frame
    /// framed on the shot so far, pulling back as debris spreads) or `auto` (follow
    /// when the action spreads over more than 3 times the first frame's size).
    #[arg(long, value_enum, default_value = "auto")]
    pub camera: CameraArg,
}

/// `--camera`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CameraArg {
    /// Follow when the action spreads far beyond its start.
    Auto,
    /// One camera on the whole shot.
    Fixed,
    /// Each frame framed on the shot so far.
    Follow,
}

/// A validated `perifrac render`.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderConfig {
    /// The cache.
    pub out: PathBuf,
    /// Turntable views (0: none).
    pub turntable: usize,
    /// Only this frame.
    pub frame: Option<usize>,
    /// Width and height in pixels.
    pub size: (u32, u32),
    /// Colouring.
    pub color_by: Option<ColorByArg>,
    /// Worker threads.
    pub threads: Option<usize>,
    /// Camera azimuth (degrees), if given.
    pub azimuth: Option<f32>,
    /// Also write the movies.
    pub movie: bool,
    /// Draw the review overlay.
    pub overlay: bool,
    /// The sequence's camera.
    pub camera: CameraArg,
}

/// Parses `WIDTHxHEIGHT` (each 1–8192).
pub fn parse_size(flag: &str, value: &str) -> Result<(u32, u32), String> {
    let bad = || {
        format!("{flag} takes WIDTHxHEIGHT in pixels (each 1–8192), e.g. 1280x720; got '{value}'")
    };
    let (w, h) = value.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(1..=8192).contains(&w) || !(1..=8192).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

impl TryFrom<RenderArgs> for RenderConfig {
    type Error = String;

    fn try_from(a: RenderArgs) -> Result<Self, Self::Error> {
        Ok(RenderConfig {
            turntable: positive("--turntable", a.turntable.as_deref())?.unwrap_or(0),
            frame: positive("--frame", a.frame.as_deref())?,
            size: parse_size("--size", &a.size)?,
            color_by: a.color_by,
            threads: positive("--threads", a.threads.as_deref())?,
            azimuth: a
                .azimuth
                .as_deref()
                .map(|text| {
                    text.parse::<f32>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| format!("--azimuth takes degrees, e.g. 35; got '{text}'"))
                })
                .transpose()?,
            movie: a.movie,
            overlay: a.overlay,
            camera: a.camera,
            out: a.out,
        })
    }
}

/// `perifrac run` as typed.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Output directory (default: `out/<scene name>`).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Simulate this many frames after the initial one, then stop (--resume continues):
    /// frame 0001 is the scene at t = 0, so N + 1 frame files.
    #[arg(long)]
    pub frames: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<String>,
    /// Continue an interrupted run from its checkpoint.
    #[arg(long, conflicts_with = "force")]
    pub resume: bool,
    /// Replace the cache already in the output directory (its frames, previews,
    /// surfaces and checkpoint are removed first).
    #[arg(long)]
    pub force: bool,
}

/// A surface method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SurfaceMethodArg {
    /// OpenVDB level sets per fragment: `vdb/NNNN.vdb`, `surface/NNNN.glb`.
    Vdb,
    /// The split tet mesh's boundary with smoothed crack faces (needs `tets/`):
    /// `surface/NNNN.glb` and `surface/animated.glb`.
    Embedded,
    /// Membranes: each sheet's intact triangles offset to its thickness (needs
    /// `sheet/`): `surface/NNNN.glb` and `surface/animated.glb`.
    Sheet,
}

/// `perifrac surface` as typed.
#[derive(Debug, clap::Args)]
pub struct SurfaceArgs {
    /// The output directory of a `perifrac run` (its settings come from the scene
    /// there, `[output.vdb]` or `[output.embedded]`).
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
    /// Replace an existing cache.
    pub force: bool,
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
            force: a.force,
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
        assert!(c.resume && !c.force);
        assert!(
            parse(&["perifrac", "run", "a.toml", "--force"])
                .unwrap()
                .force
        );
        assert!(
            parse(&["perifrac", "run", "a.toml", "--force", "--resume"])
                .unwrap_err()
                .contains("cannot be used with")
        );
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
    fn render_flags() {
        let parse = |args: &[&str]| -> Result<RenderConfig, String> {
            let cli = Cli::try_parse_from(args).map_err(|e| e.to_string())?;
            match cli.command {
                Command::Render(r) => RenderConfig::try_from(r),
                other => Err(format!("not render: {other:?}")),
            }
        };
        let c = parse(&[
            "perifrac",
            "render",
            "out/x",
            "--turntable",
            "12",
            "--frame",
            "7",
            "--size",
            "320x200",
            "--color-by",
            "fragment",
        ])
        .unwrap();
        assert_eq!(c.turntable, 12);
        assert_eq!(c.frame, Some(7));
        assert_eq!(c.size, (320, 200));
        assert_eq!(c.color_by, Some(ColorByArg::Fragment));
        let q = parse(&["perifrac", "render", "o", "--color-by", "quantity"]).unwrap();
        assert_eq!(q.color_by, Some(ColorByArg::Quantity));
        let d = parse(&["perifrac", "render", "o"]).unwrap();
        assert_eq!(
            (d.turntable, d.frame, d.size, d.color_by, d.movie),
            (0, None, (960, 540), None, false)
        );
        let m = parse(&[
            "perifrac",
            "render",
            "o",
            "--movie",
            "--color-by",
            "material",
        ])
        .unwrap();
        assert_eq!((m.movie, m.color_by), (true, Some(ColorByArg::Material)));
        assert!(
            !m.overlay
                && parse(&["perifrac", "render", "o", "--overlay"])
                    .unwrap()
                    .overlay
        );
        for bad in ["0x10", "10", "axb", "9000x10"] {
            assert!(
                parse(&["perifrac", "render", "o", "--size", bad])
                    .unwrap_err()
                    .contains("--size"),
                "{bad}"
            );
        }
        assert!(
            parse(&["perifrac", "render", "o", "--frame", "0"])
                .unwrap_err()
                .contains("--frame")
        );
        assert!(parse(&["perifrac", "render", "o", "--color-by", "heat"]).is_err());
        assert_eq!(
            parse(&["perifrac", "render", "o", "--azimuth", "-90"])
                .unwrap()
                .azimuth,
            Some(-90.0)
        );
        assert_eq!(
            d.azimuth, None,
            "the azimuth follows the projectile unless given"
        );
        assert!(
            parse(&["perifrac", "render", "o", "--azimuth", "left"])
                .unwrap_err()
                .contains("--azimuth")
        );
    }

    #[test]
    fn quiet_is_global() {
        let cli = Cli::try_parse_from(["perifrac", "check", "a.toml", "--quiet"]).unwrap();
        assert!(cli.quiet);
    }
}
