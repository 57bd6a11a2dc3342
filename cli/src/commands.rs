//! `run`, `check` and `demo`.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use perifrac_cache::scene::{Scene, SurfaceMethod};
use perifrac_cache::{CacheError, Layout};
use perifrac_sim::SimError;
use perifrac_sim::family;
use perifrac_sim::geometry::discretize::discretize;
use perifrac_sim::memory::{BYTES_PER_PARTICLE, estimate_memory};
use perifrac_sim::run::{self, Progress, RunOptions};

use crate::args::RunConfig;

/// A failed command and its exit code.
pub struct Failure {
    /// What went wrong.
    pub error: anyhow::Error,
    /// 1 for a failed run, 2 for bad input.
    pub code: u8,
}

impl Failure {
    /// Bad input (exit code 2).
    pub fn input(error: anyhow::Error) -> Failure {
        Failure { error, code: 2 }
    }
}

impl From<SimError> for Failure {
    fn from(e: SimError) -> Failure {
        let code = match &e {
            SimError::Cache(c) if c.is_bad_input() => 2,
            SimError::Refused(_) | SimError::Mesh { .. } => 2,
            _ => 1,
        };
        Failure {
            error: e.into(),
            code,
        }
    }
}

impl From<CacheError> for Failure {
    fn from(e: CacheError) -> Failure {
        Failure {
            code: if e.is_bad_input() { 2 } else { 1 },
            error: e.into(),
        }
    }
}

impl From<anyhow::Error> for Failure {
    fn from(error: anyhow::Error) -> Failure {
        Failure { error, code: 1 }
    }
}

/// The built-in demo scene (also `assets/scenes/demo.toml`).
pub const DEMO_SCENE: &str = include_str!("../../assets/scenes/demo.toml");

/// Sets the worker thread count for the whole process.
pub fn set_threads(threads: Option<usize>) -> Result<(), Failure> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| Failure::input(anyhow::anyhow!("--threads {n}: {e}")))?;
    }
    Ok(())
}

/// Memory the system can still give (MemAvailable of /proc/meminfo), if known: the
/// CLI refuses a scene whose estimate is above it.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Refuses an estimate above the available memory.
pub fn check_memory(estimate: &perifrac_sim::memory::MemoryEstimate) -> Result<(), Failure> {
    match available_memory() {
        Some(limit) => Ok(estimate.refuse_above(limit)?),
        None => Ok(()),
    }
}

/// `perifrac run`.
pub fn run(config: &RunConfig, quiet: bool) -> Result<(), Failure> {
    set_threads(config.threads)?;
    let scene = Scene::load(&config.scene)?;
    let out = config
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&scene.scene.name));
    simulate(
        &scene,
        &out,
        &RunOptions {
            frames: config.frames,
            resume: config.resume,
            ..RunOptions::default()
        },
        config.threads,
        quiet,
    )?;
    Ok(())
}

/// `perifrac demo`.
pub fn demo(out: &Path, threads: Option<usize>, quiet: bool) -> Result<(), Failure> {
    set_threads(threads)?;
    let scene = Scene::parse(
        DEMO_SCENE,
        Path::new("demo.toml (built in)"),
        Path::new("."),
    )?;
    let timing = simulate(&scene, out, &RunOptions::default(), threads, quiet)?;
    if let (false, Some(preview)) = (quiet, timing.preview) {
        eprintln!(
            "demo: simulation {:.1} s, previews {:.1} s ({:.1} % of the simulation)",
            timing.simulation,
            preview,
            100.0 * preview / timing.simulation.max(1e-9)
        );
    }
    if let (false, Some(usd)) = (quiet, timing.usd) {
        eprintln!(
            "demo: cache.usd written in {usd:.2} s ({:.1} % of the simulation)",
            100.0 * usd / timing.simulation.max(1e-9)
        );
    }
    let layout = Layout::new(out);
    println!("demo outputs:");
    println!(
        "  USD stage (all of it, binary):  {}",
        layout.usd().display()
    );
    println!(
        "  particles (PLY, one per frame): {}",
        layout.particles_dir().display()
    );
    println!(
        "  split tet meshes (VTU):         {}",
        layout.tets_dir().display()
    );
    println!(
        "  crack surfaces (glTF, a frame): {}",
        layout.surface_dir().display()
    );
    println!(
        "  animated crack surfaces (glTF): {}",
        layout.animated_surface().display()
    );
    println!(
        "  manifest:                       {}",
        layout.manifest().display()
    );
    println!(
        "  resolved scene:                 {}",
        layout.scene().display()
    );
    if timing.preview.is_some() {
        println!(
            "  previews (PNG, contact sheet):  {}",
            layout.preview_dir().display()
        );
    }
    Ok(())
}

/// Wall-clock seconds of a [`simulate`] call's stages.
pub struct StageSeconds {
    /// The simulation (with its output).
    pub simulation: f64,
    /// The previews, if they were rendered.
    pub preview: Option<f64>,
    /// Writing `cache.usd`, if it was written.
    pub usd: Option<f64>,
}

/// Simulates `scene` into `out`, then runs the stages its `[output]` asks for
/// (surfaces, previews).
pub fn simulate(
    scene: &Scene,
    out: &Path,
    options: &RunOptions,
    threads: Option<usize>,
    quiet: bool,
) -> Result<StageSeconds, Failure> {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(scene.frame_count() as u64 + 1);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:30} frame {pos}/{len} {msg} ETA {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_message("meshing and building bonds");
        bar.enable_steady_tick(Duration::from_millis(200));
        bar
    };
    let start = Instant::now();
    let mut first_step: Option<(Instant, u64)> = None;
    let mut report = |p: Progress| {
        let (t0, s0) = *first_step.get_or_insert((Instant::now(), p.steps));
        let rate = (p.steps - s0) as f64 / t0.elapsed().as_secs_f64().max(1e-9);
        bar.set_length(p.frames as u64);
        bar.set_position(p.frame as u64);
        bar.set_message(format!("{} steps, {:.0} steps/s", p.steps, rate));
    };
    let options = RunOptions {
        memory_limit: available_memory(),
        ..options.clone()
    };
    let result = run::run(scene, out, &options, &mut report);
    bar.finish_and_clear();
    let manifest = result?;
    let simulation = start.elapsed().as_secs_f64();
    if !quiet {
        eprintln!(
            "{}: {} particles, {} bonds, {} steps of {:.3e} s in {:.1} s; output in {}",
            manifest.scene,
            manifest.particles,
            manifest.bonds,
            manifest.steps,
            manifest.dt,
            start.elapsed().as_secs_f64(),
            out.display()
        );
    }
    match scene.output.surface {
        SurfaceMethod::None => {}
        SurfaceMethod::Vdb => crate::surface::stage(out, &scene.output, quiet)?,
        SurfaceMethod::Embedded => crate::surface::embedded_stage(out, &scene.output, quiet)?,
    }
    let usd = if scene.output.usd {
        Some(crate::export::usd(out, quiet)?)
    } else {
        None
    };
    let preview = if scene.output.preview {
        crate::render::stage(out, threads, quiet)
    } else {
        None
    };
    Ok(StageSeconds {
        simulation,
        preview,
        usd,
    })
}

/// `perifrac check`: validates the scene and prints its cost.
pub fn check(path: &Path) -> Result<(), Failure> {
    let scene = Scene::load(path)?;
    let disc = discretize(&scene)?;
    let delta: Vec<f64> = disc
        .body
        .iter()
        .map(|&b| scene.bodies[b as usize].delta())
        .collect();
    let estimate = estimate_memory(&scene, &disc);
    println!("scene {}: {}", scene.scene.name, path.display());
    for (b, spec) in scene.bodies.iter().enumerate() {
        let q = &disc.quality[b];
        let fit = disc.conformity[b].map_or(String::new(), |c| {
            format!(
                ", fit to the mesh {:.3}λ max / {:.3}λ mean ({} vertices snapped)",
                c.max, c.mean, c.snapped
            )
        });
        println!(
            "  body {}: {} particles, mean edge {:.4} m, dihedral angles {:.1}°–{:.1}°{fit}",
            spec.name,
            disc.meshes[b].tets.len(),
            q.mean_edge,
            q.min_dihedral_deg,
            q.max_dihedral_deg
        );
    }
    if run::uses_fem(&scene) {
        return check_fem(&scene, disc);
    }
    check_memory(&estimate)?;
    let bonds = family::count_bonds(&disc.position, &disc.body, &delta)?;
    let particles = disc.position.len();
    let memory = bonds * estimate.bytes_per_bond + particles * BYTES_PER_PARTICLE;
    println!("  particles: {particles}");
    println!(
        "  bonds:     {bonds} directed ({:.1} per particle)",
        bonds as f64 / particles.max(1) as f64
    );
    println!(
        "  memory:    {:.1} MiB ({} bytes a bond)",
        memory as f64 / (1 << 20) as f64,
        estimate.bytes_per_bond
    );
    let mut prepared = run::prepare_discretized(&scene, disc)?;
    let (stable, dt) = (prepared.stable_dt, prepared.world.dt);
    print_cost(&scene, stable, dt, prepared.steps_per_frame, || {
        prepared.world.step()
    })
}

/// The stable step, the step count and the run time estimated from three timed steps.
fn print_cost(
    scene: &Scene,
    stable_dt: (f64, usize),
    dt: f64,
    steps_per_frame: usize,
    mut step: impl FnMut() -> perifrac_sim::error::Result<usize>,
) -> Result<(), Failure> {
    let steps_total = steps_per_frame * scene.frame_count();
    let t = Instant::now();
    let probe = 3;
    for _ in 0..probe {
        step().map_err(Failure::from)?;
    }
    let per_step = t.elapsed().as_secs_f64() / probe as f64;
    println!(
        "  stable dt: {:.3e} s (limited at particle {}); dt used: {:.3e} s",
        stable_dt.0, stable_dt.1, dt
    );
    println!(
        "  steps:     {} frames × {} = {steps_total}",
        scene.frame_count(),
        steps_per_frame
    );
    println!(
        "  estimate:  {:.4} s a step, {:.0} s for the run on {} threads",
        per_step,
        per_step * steps_total as f64,
        rayon::current_num_threads()
    );
    Ok(())
}

/// `perifrac check` of a FEM reference scene: mesh size, stable step and cost.
fn check_fem(
    scene: &Scene,
    disc: perifrac_sim::geometry::discretize::Discretization,
) -> Result<(), Failure> {
    let vertices: usize = disc.meshes.iter().map(|m| m.vertices.len()).sum();
    println!(
        "  FEM reference: {} tets, {vertices} vertices (no bonds)",
        disc.position.len()
    );
    let mut prepared = run::prepare_discretized(scene, disc)?;
    let (stable, dt) = (prepared.stable_dt, prepared.world.dt);
    print_cost(scene, stable, dt, prepared.steps_per_frame, || {
        prepared.world.step()
    })
}
