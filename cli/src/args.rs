//! Command-line arguments: parsed raw by clap, then validated into configs.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use perifrac_cache::frames::FrameRange;

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
    /// Run the built-in demo: a steel ball through a glass wall, and the 5 s after it
    /// with the pieces landing (a finished shot).
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
    /// both FEM references against the converged corotated FEM; the analytic figures;
    /// the Kalthoff–Winkler plate's crack angle; writes `accuracy.md` and
    /// `accuracy.png`.
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
    /// Render only this frame, as `preview/frame_NNNN.png` (default: every frame, and
    /// the contact sheet).
    #[arg(long, conflicts_with = "frames")]
    pub frame: Option<String>,
    /// Render only the sequence's frames FIRST..LAST (both included) as
    /// `preview/NNNN.png`, each through the camera of a render of every frame, so
    /// that ranges run side by side on a farm fill one sequence; `--join` makes the
    /// contact sheet and the movies once all are there.
    #[arg(long, conflicts_with_all = ["turntable", "movie"])]
    pub frames: Option<String>,
    /// Render nothing: make the contact sheet (and with `--movie` the movies) from the
    /// frames `preview/NNNN.png` that `--frames` ranges rendered.
    #[arg(long, conflicts_with_all = ["frame", "frames", "turntable", "color_by", "azimuth", "overlay"])]
    pub join: bool,
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
    /// framed on the shot so far, pulling back as debris spreads), `auto` (follow
    /// when the action spreads over more than 3 times the first frame's size) or
    /// `largest` (each frame framed on its largest piece and the particles within
    /// three of its radii: a still of the end of a shot whose pieces lie metres apart).
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
    /// Each frame framed on its largest piece and what lies around it (a still of
    /// the end of a shot).
    Largest,
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
    /// Only these frames of the sequence.
    pub frames: Option<FrameRange>,
    /// Join the rendered frames into the contact sheet and movies.
    pub join: bool,
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

/// Parses `--frames FIRST..LAST`, if given.
fn frame_range(text: Option<&str>) -> Result<Option<FrameRange>, String> {
    text.map(|t| FrameRange::parse("--frames", t)).transpose()
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
            frames: frame_range(a.frames.as_deref())?,
            join: a.join,
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
    /// Surface only frames FIRST..LAST (both included), writing only their files, so
    /// that ranges run side by side on a farm fill one cache; the whole-shot
    /// `surface/animated.glb` of the embedded and sheet methods needs every frame.
    #[arg(long)]
    pub frames: Option<String>,
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
    /// Only these frames.
    pub frames: Option<FrameRange>,
    /// Thread count.
    pub threads: Option<usize>,
}

impl TryFrom<SurfaceArgs> for SurfaceConfig {
    type Error = String;

    fn try_from(a: SurfaceArgs) -> Result<Self, Self::Error> {
        Ok(SurfaceConfig {
            threads: positive("--threads", a.threads.as_deref())?,
            frames: frame_range(a.frames.as_deref())?,
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
mod tests;
