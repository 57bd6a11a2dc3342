//! `run` and `demo`.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use perifrac_cache::frames::FrameRange;
use perifrac_cache::manifest::Manifest;
use perifrac_cache::scene::{Scene, SurfaceMethod};
use perifrac_cache::{CacheError, Layout};
use perifrac_sim::SimError;
use perifrac_sim::run::{self, Plan, Progress, RunOptions};

use crate::args::RunConfig;
use crate::ranks::Launch;
use crate::signals::{EXIT_INTERRUPTED, Watcher};

/// Exit code of a run that failed (I/O, blow-up) and of `verify` on a failed run.
pub const EXIT_FAILED: u8 = 1;
/// Exit code of bad input: a scene file, flags, a damaged cache or checkpoint, a run
/// that would not fit in memory, an output folder holding another cache.
pub const EXIT_INPUT: u8 = 2;

/// A failed command and its exit code.
pub struct Failure {
    /// What went wrong.
    pub error: anyhow::Error,
    /// [`EXIT_FAILED`], [`EXIT_INPUT`] or [`EXIT_INTERRUPTED`].
    pub code: u8,
}

impl Failure {
    /// Bad input (exit code 2).
    pub fn input(error: anyhow::Error) -> Failure {
        Failure {
            error,
            code: EXIT_INPUT,
        }
    }
}

/// `range` cut to the frames of the cache in `out` ([`FrameRange::within`]), printing
/// the note when frames past the end were left out; a range starting past the end,
/// or a cache without a readable manifest, is bad input.
pub fn frames_within(out: &Path, range: Option<FrameRange>) -> Result<Option<FrameRange>, Failure> {
    let Some(range) = range else {
        return Ok(None);
    };
    let manifest = Layout::new(out).manifest();
    let frames = Manifest::read(&manifest)?.frames();
    let (range, note) = range
        .within(frames)
        .map_err(|e| Failure::input(anyhow::anyhow!("{}: {e}", manifest.display())))?;
    if let Some(note) = note {
        eprintln!("note: {note}");
    }
    Ok(Some(range))
}

impl From<SimError> for Failure {
    fn from(e: SimError) -> Failure {
        let code = match &e {
            SimError::Cache(c) if c.is_bad_input() => EXIT_INPUT,
            SimError::Refused(_) | SimError::Mesh { .. } | SimError::Collider { .. } => EXIT_INPUT,
            SimError::Interrupted { .. } => EXIT_INTERRUPTED,
            _ => EXIT_FAILED,
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
            code: if e.is_bad_input() {
                EXIT_INPUT
            } else {
                EXIT_FAILED
            },
            error: e.into(),
        }
    }
}

impl From<anyhow::Error> for Failure {
    fn from(error: anyhow::Error) -> Failure {
        Failure { error, code: 1 }
    }
}

/// The built-in demo's impact: its first 4 ms (also `assets/scenes/demo.toml`).
pub const DEMO_SCENE: &str = include_str!("../../assets/scenes/demo.toml");

/// The built-in demo as a finished shot: the impact and 5 s of pieces landing (also
/// `assets/scenes/demo-shot.toml`).
pub const DEMO_SHOT_SCENE: &str = include_str!("../../assets/scenes/demo-shot.toml");

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

/// `out/<scene name>`, refused (exit 2) when the name is not a single folder name.
pub fn default_output(scene: &Scene, file: &Path) -> Result<PathBuf, Failure> {
    let name = &scene.scene.name;
    let single = !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains(['/', '\\'])
        && !name.chars().any(char::is_control);
    if !single {
        return Err(Failure::input(anyhow::anyhow!(
            "{}: scene.name = {name:?} cannot name the output folder out/<name>: it must be one \
             folder name (not empty, no '/', '\\' or '..'); rename the scene, or give the \
             output folder with -o",
            file.display()
        )));
    }
    Ok(PathBuf::from("out").join(name))
}

/// `perifrac run SCENE …` as a shell command with `--resume`, to print after a stop.
fn resume_command(config: &RunConfig, out: &Path) -> String {
    let mut words = vec![
        "perifrac".to_string(),
        "run".into(),
        shell_word(&config.scene.to_string_lossy()),
        "-o".into(),
        shell_word(&out.to_string_lossy()),
    ];
    if let Some(n) = config.frames {
        words.push(format!("--frames {n}"));
    }
    if let Some(n) = config.threads {
        words.push(format!("--threads {n}"));
    }
    words.push("--resume".into());
    words.join(" ")
}

/// `word`, quoted for a POSIX shell when it needs to be.
fn shell_word(word: &str) -> String {
    let plain = !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:+,@%".contains(c));
    if plain {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

/// What a command asks of an output folder that may already hold a cache.
pub struct Lifecycle {
    /// Replace an existing cache (`--force`).
    pub force: bool,
    /// The command that continues this run (printed after a stop).
    pub resume_command: String,
}

/// `perifrac run`.
pub fn run(config: &RunConfig, quiet: bool) -> Result<(), Failure> {
    set_threads(config.threads)?;
    let scene = Scene::load(&config.scene)?;
    let out = match &config.out {
        Some(out) => out.clone(),
        None => default_output(&scene, &config.scene)?,
    };
    let lifecycle = Lifecycle {
        force: config.force,
        resume_command: resume_command(config, &out),
    };
    let launch = crate::ranks::launch()?;
    simulate(
        &scene,
        &out,
        &RunOptions {
            frames: config.frames,
            resume: config.resume,
            ..RunOptions::default()
        },
        &lifecycle,
        &launch,
        config.threads,
        quiet,
    )?;
    Ok(())
}

/// `perifrac demo`: the finished shot, or with `impact` its first 4 ms.
pub fn demo(
    out: &Path,
    impact: bool,
    threads: Option<usize>,
    resume: bool,
    force: bool,
    quiet: bool,
) -> Result<(), Failure> {
    set_threads(threads)?;
    let (text, name, flag) = match impact {
        true => (DEMO_SCENE, "demo.toml (built in)", " --impact"),
        false => (DEMO_SHOT_SCENE, "demo-shot.toml (built in)", ""),
    };
    let scene = Scene::parse(text, Path::new(name), Path::new("."))?;
    let lifecycle = Lifecycle {
        force,
        resume_command: format!(
            "perifrac demo -o {}{flag} --resume",
            shell_word(&out.to_string_lossy())
        ),
    };
    let options = RunOptions {
        resume,
        ..RunOptions::default()
    };
    let launch = crate::ranks::launch()?;
    let timing = simulate(&scene, out, &options, &lifecycle, &launch, threads, quiet)?;
    if !launch.leads() {
        return Ok(());
    }
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

/// Makes `out` ready for a run: a folder holding another cache is refused unless the
/// run resumes it or `--force` replaces it (clearing it first). Returns the cache's
/// manifest when `--resume` finds it complete already (nothing to run).
fn prepare_output(
    scene: &Scene,
    layout: &Layout,
    options: &RunOptions,
    lifecycle: &Lifecycle,
    quiet: bool,
) -> Result<Option<Manifest>, Failure> {
    if options.resume {
        return match run::resume_plan(layout, scene, options)? {
            Plan::Complete(manifest) => Ok(Some(*manifest)),
            Plan::Fresh | Plan::Continue(_) => Ok(None),
        };
    }
    if !layout.holds_cache() {
        return Ok(None);
    }
    if lifecycle.force {
        layout.clear()?;
        if !quiet {
            eprintln!(
                "--force: removed the cache that was in {} (frames, previews, surfaces, \
                 checkpoint, manifest)",
                layout.root.display()
            );
        }
        return Ok(None);
    }
    let what = match Manifest::read(&layout.manifest()) {
        Ok(m) => format!(
            "the cache of a run of '{}' ({}, {} frames)",
            m.scene,
            m.status,
            m.frames()
        ),
        Err(e) => format!("a cache (its manifest does not read: {e})"),
    };
    Err(Failure::input(anyhow::anyhow!(
        "{} holds {what}; a run never mixes its frames with another's: continue it with \
         --resume, or replace it with --force (removes its frames, previews, surfaces and \
         checkpoint first), or write to another folder with -o",
        layout.root.display()
    )))
}

/// What to tell the user after the run stopped early.
fn explain_stop(failure: Failure, lifecycle: &Lifecycle, layout: &Layout) -> Failure {
    let resume = &lifecycle.resume_command;
    let error = match failure.code {
        EXIT_INTERRUPTED => {
            anyhow::anyhow!("{:#}; continue with:\n  {resume}", failure.error)
        }
        EXIT_FAILED => match failure.error.downcast_ref::<SimError>() {
            Some(SimError::Cache(c @ (CacheError::Write { .. } | CacheError::Io { .. }))) => {
                let last = Manifest::read(&layout.manifest()).map_or(0, |m| m.frames());
                anyhow::anyhow!(
                    "{c}; the frames up to {last} are on disk and the manifest says so: once \
                     that is fixed, continue from the last checkpoint with:\n  {resume}"
                )
            }
            _ => return failure,
        },
        _ => return failure,
    };
    Failure {
        error,
        code: failure.code,
    }
}

/// Simulates `scene` into `out`, then runs the stages its `[output]` asks for
/// (surfaces, previews). SIGINT, SIGTERM and SIGHUP stop the simulation cleanly (see
/// [`crate::signals`]). Over several ranks (`launch`), every rank simulates and rank
/// 0 alone looks at the output folder, prints, writes and runs the later stages.
pub fn simulate(
    scene: &Scene,
    out: &Path,
    options: &RunOptions,
    lifecycle: &Lifecycle,
    launch: &Launch,
    threads: Option<usize>,
    quiet: bool,
) -> Result<StageSeconds, Failure> {
    let nothing_run = StageSeconds {
        simulation: 0.0,
        preview: None,
        usd: None,
    };
    let layout = Layout::new(out);
    let leads = launch.leads();
    let quiet = quiet || !leads;
    let ready = match leads {
        true => prepare_output(scene, &layout, options, lifecycle, quiet),
        false => Ok(None),
    };
    // The others follow rank 0's look at the folder: refused, or complete already.
    if let Some(ranks) = &launch.ranks
        && ranks.any(!matches!(ready, Ok(None)))
        && !leads
    {
        return Ok(nothing_run);
    }
    if let Some(done) = ready? {
        println!(
            "{}: already complete ({} frames, status {}); nothing to run (perifrac verify {} \
             checks it; --force reruns it)",
            out.display(),
            done.frames(),
            done.status,
            shell_word(&out.to_string_lossy())
        );
        return Ok(nothing_run);
    }
    let options = RunOptions {
        memory_limit: crate::memory::memory_limit(),
        ranks: launch.ranks.clone(),
        ..options.clone()
    };
    let watcher = Watcher::start(options.stop.clone(), out.to_path_buf())
        .map_err(|e| anyhow::anyhow!("cannot watch for SIGINT/SIGTERM/SIGHUP: {e}"))?;
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
    watcher.set_simulating(true);
    let result = run::run(scene, out, &options, &mut report);
    watcher.set_simulating(false);
    bar.finish_and_clear();
    let manifest = result.map_err(|e| {
        let failure = Failure::from(e);
        // A stop is agreed by every rank at one step; anything else may have left
        // the other ranks waiting in a collective.
        match failure.code {
            EXIT_INTERRUPTED => explain_stop(failure, lifecycle, &layout),
            _ => launch.fail(explain_stop(failure, lifecycle, &layout)),
        }
    })?;
    let simulation = start.elapsed().as_secs_f64();
    if !leads {
        return Ok(StageSeconds {
            simulation,
            ..nothing_run
        });
    }
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
        SurfaceMethod::Vdb => crate::surface::stage(out, &scene.output, None, quiet)?,
        SurfaceMethod::Embedded => crate::surface::embedded_stage(out, &scene.output, None, quiet)?,
        SurfaceMethod::Sheet => crate::surface::sheet_stage(out, &scene.output, None, quiet)?,
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
