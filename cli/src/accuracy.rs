//! `perifrac bench accuracy`: run time against error on the validation scenes of
//! Chen et al. 2018 §6 (Figs. 9–12), for peridynamics (sweeping λ and δ/λ) and both
//! FEM references (sweeping λ), against the converged reference: corotated FEM one
//! step finer than the finest run of the sweep. The error is the paper's position
//! deviation over the bounding-box diagonal (`perifrac_sim::accuracy`), mean over the
//! particles per frame; the tables give its mean and maximum over the frames.

use std::fmt::Write as _;
use std::path::Path;

use perifrac_cache::scene::{LatticeOrientation, ModelKind, Scene};
use perifrac_sim::accuracy::{Recording, deviation, diagonal, record};

use crate::commands::Failure;

/// What one sweep runs.
pub struct Sweep {
    /// Scene files (stems in the scenes directory).
    pub scenes: &'static [&'static str],
    /// λ as multiples of the scene's λ, coarsest first.
    pub resolutions: &'static [f64],
    /// δ/λ of the peridynamic runs (0 stands for the scene's own).
    pub horizons: &'static [f64],
    /// λ of the reference, as a multiple of the scene's λ.
    pub reference: f64,
    /// Simulated seconds (at most the scene's duration).
    pub duration: f64,
}

/// `--quick`: the two scenes of the goal, two resolutions, under five minutes.
pub const QUICK: Sweep = Sweep {
    scenes: &["bar-swing", "bar-twist"],
    resolutions: &[2.0, 1.5],
    horizons: &[0.0],
    reference: 1.0,
    duration: 0.15,
};

/// The full sweep.
pub const FULL: Sweep = Sweep {
    scenes: &[
        "bar-swing",
        "bar-twist",
        "soft-beam-bend",
        "stiff-beam-bend",
        "beam-stretch-nu-0.30",
        "beam-stretch-nu-0.45",
        "beam-stretch-nu-0.46",
    ],
    resolutions: &[3.0, 2.0, 1.5],
    horizons: &[0.0, 2.0],
    reference: 1.0,
    duration: 0.25,
};

/// The analytic figures (issue 6): the first bending frequency of
/// `cantilever-release.toml` against Euler–Bernoulli, and the Poisson ratio measured
/// on the beam-stretch scenes (λ × 2, the first 0.1 s) against the material's;
/// each for peridynamics (the scene's δ/λ), corotated and linear FEM. Returns the
/// "Analytic figures" section of `accuracy.md`.
pub fn analytic(dir: &Path, quiet: bool) -> Result<String, Failure> {
    let methods = [
        (ModelKind::Peridynamics, "PD"),
        (ModelKind::FemCorotated, "FEM corotated"),
        (ModelKind::FemLinear, "FEM linear"),
    ];
    let with_model = |base: &Scene, model: ModelKind| {
        let mut s = base.clone();
        for b in &mut s.bodies {
            b.model = model;
        }
        s
    };
    let mut out = String::from(
        "## Analytic figures\n\n\
         First bending frequency of `cantilever-release.toml` (L = 1 m, h = 0.1 m, \
         λ = 0.025 m; the tip's crossings after the release, smoothed over the second \
         mode's period) against Euler–Bernoulli f₁ = (1.8751²/2π) √(E I / (ρ A L⁴)):\n\n\
         | method | f₁ measured (Hz) | Euler–Bernoulli (Hz) | difference | wall (s) |\n\
         |---|---:|---:|---:|---:|\n",
    );
    let base = Scene::load(&dir.join("cantilever-release.toml"))?;
    for (model, label) in methods {
        let f = perifrac_sim::analytic::first_bending_frequency(&with_model(&base, model))?;
        let (measured, diff) = match f.measured {
            Some(m) => (
                format!("{m:.3}"),
                format!("{:+.2}%", 100.0 * (m / f.euler_bernoulli - 1.0)),
            ),
            None => ("less than a period".into(), "–".into()),
        };
        let line = format!(
            "| {label} | {measured} | {:.3} | {diff} | {:.1} |",
            f.euler_bernoulli, f.wall
        );
        if !quiet {
            eprintln!("cantilever-release {line}");
        }
        let _ = writeln!(out, "{line}");
    }
    out.push_str(
        "\nPoisson ratio ν = −ε_lateral/ε_axial in the middle fifth of the beam-stretch \
         scenes (least-squares strains of the particles there, last frame of the first \
         0.1 s, λ × 2; gravity on, as in the scenes) against the material's:\n\n\
         | scene | material ν | PD | FEM corotated | FEM linear |\n|---|---:|---:|---:|---:|\n",
    );
    for name in [
        "beam-stretch-nu-0.30",
        "beam-stretch-nu-0.45",
        "beam-stretch-nu-0.46",
    ] {
        let mut base = Scene::load(&dir.join(format!("{name}.toml")))?;
        base.scene.duration = base.scene.duration.min(0.1);
        for b in &mut base.bodies {
            b.resolution *= 2.0;
        }
        let material =
            perifrac_sim::material::Material::from_spec(&base.materials[&base.bodies[0].material]);
        let mut line = format!("| {name} | {:.3} |", material.poisson_ratio());
        for (model, _) in methods {
            let rec = record(&with_model(&base, model), base.frame_count())?;
            let last = rec.particles.frames.len() - 1;
            let nu = perifrac_sim::analytic::lateral_contraction(&rec.particles, last, 0);
            let _ = write!(line, " {nu:.3} |");
        }
        if !quiet {
            eprintln!("{line}");
        }
        let _ = writeln!(out, "{line}");
    }
    Ok(out)
}

/// The Kalthoff–Winkler plate's spacings (m) on both meshes and both notch cuts;
/// `--quick` runs the first alone, on the aligned lattice with slotted notches.
const KALTHOFF_WINKLER_LAMBDAS: [f64; 2] = [0.004, 0.003];

/// Finer spacings (m) run with slotted notches only, on both meshes (113 and 307 s on
/// the unstructured mesh, 81 and 207 s on the aligned one, docs/contact.md).
const KALTHOFF_WINKLER_FINE: [f64; 2] = [0.0025, 0.002];

/// The meshes every Kalthoff–Winkler spacing runs on.
const KALTHOFF_WINKLER_MESHES: [LatticeOrientation; 2] = [
    LatticeOrientation::Unstructured,
    LatticeOrientation::Aligned,
];

/// The "Crack angle" section of `accuracy.md` (issue 33, item 7): the
/// Kalthoff–Winkler plate (`kalthoff-winkler.toml`, contact on as shipped) with its
/// notches as slots and as zero-width pre-cuts, on the unstructured and the aligned
/// mesh, at two spacings, and the slotted plate on both at two finer ones; the angle
/// of each notch's crack read from the bonds that broke (`perifrac_sim::crack_angle`)
/// against the experiment's 68–70°.
pub fn crack_angles(dir: &Path, quick: bool, quiet: bool) -> Result<String, Failure> {
    use perifrac_sim::crack_angle::{
        KALTHOFF_WINKLER_NOTCHES, KALTHOFF_WINKLER_REACH, NotchCut, broken_during_run, crack_angle,
        kalthoff_winkler_variant,
    };
    let base = Scene::load(&dir.join("kalthoff-winkler.toml"))?;
    let mut out = String::from(
        "## Crack angle: the Kalthoff–Winkler plate\n\n\
         `kalthoff-winkler.toml` (Silling 2003, after Kalthoff & Winkler 1988; contact on): \
         the angle of each notch's crack from the notch, read from the reference midpoints \
         of the bonds that broke 2δ to 45 mm from its tip: their median polar angle, the \
         medians of the shells 2δ–15, 15–30 and 30–45 mm, and their principal axis. \
         Experiment: 68–70°.\n\n\
         | notches | mesh | λ (mm) | particles | upper: median (shells; axis) | lower: median (shells; axis) | wall (s) |\n\
         |---|---|---:|---:|---|---|---:|\n",
    );
    let runs: Vec<(f64, NotchCut, LatticeOrientation)> = if quick {
        vec![(
            KALTHOFF_WINKLER_LAMBDAS[0],
            NotchCut::Slots,
            LatticeOrientation::Aligned,
        )]
    } else {
        let mut runs = Vec::new();
        for lambda in KALTHOFF_WINKLER_LAMBDAS {
            for cut in [NotchCut::Slots, NotchCut::ZeroWidth] {
                for lattice in KALTHOFF_WINKLER_MESHES {
                    runs.push((lambda, cut, lattice));
                }
            }
        }
        for lambda in KALTHOFF_WINKLER_FINE {
            for lattice in KALTHOFF_WINKLER_MESHES {
                runs.push((lambda, NotchCut::Slots, lattice));
            }
        }
        runs
    };
    for (lambda, cut, lattice) in runs {
        let scene = kalthoff_winkler_variant(&base, lambda, cut, lattice)?;
        let start = std::time::Instant::now();
        let broken = broken_during_run(&scene, |_, _| {})?;
        let wall = start.elapsed().as_secs_f64();
        let angle = |k: usize| {
            let a = crack_angle(&broken, KALTHOFF_WINKLER_NOTCHES[k], KALTHOFF_WINKLER_REACH);
            format!(
                "{:.1}° ({:.1}°, {:.1}°, {:.1}°; {:.1}°)",
                a.median, a.shells[0], a.shells[1], a.shells[2], a.axis
            )
        };
        let cut = match cut {
            NotchCut::Slots => "1.5 mm slots",
            NotchCut::ZeroWidth => "zero-width cuts",
        };
        let lattice = match lattice {
            LatticeOrientation::Aligned => "aligned",
            LatticeOrientation::Rotated => "rotated",
            LatticeOrientation::Unstructured => "unstructured",
        };
        let line = format!(
            "| {cut} | {lattice} | {:.1} | {} | {} | {} | {wall:.0} |",
            lambda * 1e3,
            broken.points,
            angle(0),
            angle(1)
        );
        if !quiet {
            eprintln!("kalthoff-winkler {line}");
        }
        let _ = writeln!(out, "{line}");
    }
    Ok(out)
}

/// One run of the sweep.
#[derive(Debug, Clone)]
pub struct Point {
    /// Scene stem.
    pub scene: String,
    /// "PD δ/λ = …", "FEM linear", "FEM corotated".
    pub method: String,
    /// λ (m).
    pub resolution: f64,
    /// Particles (tets).
    pub particles: usize,
    /// Steps.
    pub steps: u64,
    /// Wall-clock seconds (setup and stepping).
    pub wall: f64,
    /// Mean over frames of the deviation from the reference.
    pub mean: f64,
    /// Max over frames.
    pub max: f64,
}

/// Peridynamics against corotated FEM on the same tets (finest λ of the sweep).
#[derive(Debug, Clone)]
pub struct SameTets {
    /// Scene stem.
    pub scene: String,
    /// Mean over frames of the deviation.
    pub mean: f64,
    /// Max over frames.
    pub max: f64,
}

/// Runs the sweep over the scenes in `dir`; returns the runs and, per scene, the
/// deviation of peridynamics from corotated FEM on the same tets at the finest λ.
pub fn sweep(
    sweep: &Sweep,
    dir: &Path,
    quiet: bool,
) -> Result<(Vec<Point>, Vec<SameTets>), Failure> {
    let mut points = Vec::new();
    let mut same_tets = Vec::new();
    for name in sweep.scenes {
        let path = dir.join(format!("{name}.toml"));
        let base = Scene::load(&path)?;
        let variant = |model: ModelKind, factor: f64, horizon: f64| {
            let mut s = base.clone();
            s.scene.duration = s.scene.duration.min(sweep.duration);
            for b in &mut s.bodies {
                b.model = model;
                b.resolution *= factor;
                if horizon > 0.0 {
                    b.horizon = horizon;
                }
            }
            s
        };
        let frames = variant(ModelKind::FemCorotated, 1.0, 0.0).frame_count();
        let reference = record(
            &variant(ModelKind::FemCorotated, sweep.reference, 0.0),
            frames,
        )?;
        let Some(field) = reference.vertices.as_ref() else {
            return Err(anyhow::anyhow!("{name}: the reference run kept no mesh").into());
        };
        let d = diagonal(&reference.particles.rest);
        if !quiet {
            eprintln!(
                "{name}: reference corotated FEM, {} tets, {} steps, {:.1} s",
                reference.particles.rest.len(),
                reference.steps,
                reference.wall
            );
        }
        let mut measure = |method: String, rec: &Recording, factor: f64| {
            let r = field.sample(&rec.particles.rest, &rec.particles.times);
            let dev = deviation(&rec.particles, &r, d);
            let p = Point {
                scene: name.to_string(),
                method,
                resolution: base.bodies[0].resolution * factor,
                particles: rec.particles.rest.len(),
                steps: rec.steps,
                wall: rec.wall,
                mean: dev.mean,
                max: dev.max,
            };
            if !quiet {
                eprintln!(
                    "  {:<18} λ = {:.4} m: {:>6} particles, {:>6} steps, {:>7.2} s, error mean {:.3e} max {:.3e}",
                    p.method, p.resolution, p.particles, p.steps, p.wall, p.mean, p.max
                );
            }
            points.push(p);
        };
        let finest = *sweep.resolutions.last().unwrap_or(&1.0);
        let mut finest_runs: (Option<Recording>, Option<Recording>) = (None, None);
        for &factor in sweep.resolutions {
            for (kind, label) in [
                (ModelKind::FemLinear, "FEM linear"),
                (ModelKind::FemCorotated, "FEM corotated"),
            ] {
                let rec = record(&variant(kind, factor, 0.0), frames)?;
                measure(label.to_string(), &rec, factor);
                if factor == finest && kind == ModelKind::FemCorotated {
                    finest_runs.1 = Some(rec);
                }
            }
            for &h in sweep.horizons {
                let s = variant(ModelKind::Peridynamics, factor, h);
                let rec = record(&s, frames)?;
                measure(format!("PD δ/λ = {:.2}", s.bodies[0].horizon), &rec, factor);
                if factor == finest && h == sweep.horizons[0] {
                    finest_runs.0 = Some(rec);
                }
            }
        }
        if let (Some(pd), Some(fem)) = finest_runs {
            let dev = deviation(&pd.particles, &fem.particles, diagonal(&fem.particles.rest));
            same_tets.push(SameTets {
                scene: name.to_string(),
                mean: dev.mean,
                max: dev.max,
            });
        }
    }
    Ok((points, same_tets))
}

/// Corotated FEM's error at wall time `wall` from its runs (wall, error; sorted by
/// wall): log–log interpolation within their range; beyond it, the best error of a
/// run that took no longer; `None` if every run took longer.
fn error_at(curve: &[(f64, f64)], wall: f64) -> Option<f64> {
    let inside = curve.windows(2).find_map(|w| {
        let ((t0, e0), (t1, e1)) = (w[0], w[1]);
        (t0 <= wall && wall <= t1 && t1 > t0).then(|| {
            let s = (wall.ln() - t0.ln()) / (t1.ln() - t0.ln());
            (e0.ln() + s * (e1.ln() - e0.ln())).exp()
        })
    });
    inside.or_else(|| {
        curve
            .iter()
            .filter(|(t, _)| *t <= wall)
            .map(|(_, e)| *e)
            .min_by(f64::total_cmp)
    })
}

/// The report: the table of runs, PD against corotated FEM on the same tets, and
/// PD's error over corotated FEM's at equal wall time.
pub fn report(points: &[Point], same_tets: &[SameTets], sweep: &Sweep, threads: usize) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Accuracy: run time against error\n\n\
         Validation scenes of Chen et al. 2018 §6 (`assets/scenes`), the first {} s of each, {threads} threads. \
         Error: position deviation over the bounding-box diagonal (Chen §6), mean over the particles per frame, \
         against corotated FEM at λ × {} (the converged reference); `mean` and `max` over the frames. \
         Wall time: setup (meshing, families, stable step) and stepping.\n",
        sweep.duration, sweep.reference
    );
    let _ = writeln!(
        s,
        "| scene | method | λ (m) | particles | steps | wall (s) | error mean | error max |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for p in points {
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {} | {} | {:.2} | {:.2e} | {:.2e} |",
            p.scene, p.method, p.resolution, p.particles, p.steps, p.wall, p.mean, p.max
        );
    }
    let _ = writeln!(
        s,
        "\n## Peridynamics against corotated FEM on the same tets, finest λ of the sweep\n\n\
         | scene | deviation mean | deviation max | under 3%? |\n|---|---|---|---|"
    );
    for t in same_tets {
        let _ = writeln!(
            s,
            "| {} | {:.2}% | {:.2}% | {} |",
            t.scene,
            100.0 * t.mean,
            100.0 * t.max,
            if t.max < 0.03 { "yes" } else { "no" }
        );
    }
    let _ = writeln!(
        s,
        "\n## Peridynamics' error over corotated FEM's at equal wall time\n\n\
         Corotated FEM's error at each PD run's wall time: its runs' errors interpolated (log–log), or beyond \
         its slowest run the best error of a FEM run that took no longer (– : every FEM run took longer).\n\n\
         | scene | PD run | wall (s) | PD error | FEM corotated error | ratio | ≤ 1.5? |\n|---|---|---|---|---|---|---|"
    );
    let mut scenes: Vec<&str> = points.iter().map(|p| p.scene.as_str()).collect();
    scenes.dedup();
    for scene in scenes {
        let mut fem: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.scene == scene && p.method == "FEM corotated")
            .map(|p| (p.wall, p.mean))
            .collect();
        fem.sort_by(|a, b| a.0.total_cmp(&b.0));
        for p in points
            .iter()
            .filter(|p| p.scene == scene && p.method.starts_with("PD"))
        {
            let (fem_error, ratio) = match error_at(&fem, p.wall) {
                Some(e) => (format!("{e:.2e}"), format!("{:.2}", p.mean / e)),
                None => ("–".into(), "–".into()),
            };
            let ok = match error_at(&fem, p.wall) {
                Some(e) if p.mean / e <= 1.5 => "yes",
                Some(_) => "no",
                None => "–",
            };
            let _ = writeln!(
                s,
                "| {scene} | {} λ = {:.4} | {:.2} | {:.2e} | {fem_error} | {ratio} | {ok} |",
                p.method, p.resolution, p.wall, p.mean
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_in_log_log() {
        let curve = [(1.0, 1e-1), (100.0, 1e-3)];
        let e = error_at(&curve, 10.0).expect("in range");
        assert!((e - 1e-2).abs() < 1e-12);
        assert_eq!(error_at(&curve, 1000.0), Some(1e-3));
        assert!(error_at(&curve, 0.5).is_none());
    }
}
