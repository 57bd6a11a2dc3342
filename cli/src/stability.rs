//! `perifrac bench stability`: scenes with parameters pushed to their edges, each
//! reported as having stayed finite with bounded energy, or as caught by the
//! simulator's blow-up detector (what and where).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use perifrac_cache::scene::Scene;
use perifrac_sim::SimError;
use perifrac_sim::run;

use crate::commands::Failure;

const SOFT: &str = "density = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.25";

/// A spinning, drifting soft block with the time step at `factor` × the stable
/// bound (`force_dt` lets it past the refusal above 1).
fn time_step_case(factor: f64, stable: f64, model: &str) -> String {
    format!(
        "[scene]\nname = \"dt\"\ngravity = [0, 0, 0]\nduration = 0.05\nfps = 100\ndt = {}\nforce_dt = true\n\
         [materials.m]\n{SOFT}\n\
         [[body]]\nmaterial = \"m\"\nmodel = \"{model}\"\nresolution = 0.0125\nvelocity = [0.1, 0, 0]\nangular_velocity = [0, 0, 5]\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [0.1, 0.05, 0.05] }}\n",
        factor * stable
    )
}

/// The cases: name, what is pushed, scene text (the time-step cases are filled in
/// once the stable step is known).
fn cases() -> Vec<(&'static str, String)> {
    vec![
        (
            "Poisson ratio 0.45, cantilever under gravity",
            "[scene]\nname = \"nu\"\nduration = 0.1\nfps = 50\n\
             [materials.m]\ndensity = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.45\n\
             [[body]]\nmaterial = \"m\"\nresolution = 0.02\n\
             shape = { type = \"box\", center = [0, 0, 0], size = [0.4, 0.08, 0.08] }\n\
             [[body.anchor]]\nregion = { type = \"box\", center = [-0.2, 0, 0], size = [0.06, 0.2, 0.2] }\n"
                .into(),
        ),
        (
            "stiffness ratio 10^6 (E = 1e4 Pa and 1e10 Pa bodies, one time step)",
            "[scene]\nname = \"ratio\"\nduration = 0.02\nfps = 100\n\
             [materials.soft]\ndensity = 1000.0\nyoungs_modulus = 1.0e4\npoisson_ratio = 0.25\n\
             [materials.stiff]\ndensity = 1000.0\nyoungs_modulus = 1.0e10\npoisson_ratio = 0.25\n\
             [[body]]\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [0, -1, 0]\n\
             shape = { type = \"box\", center = [0, 0.2, 0], size = [0.1, 0.1, 0.1] }\n\
             [[body]]\nmaterial = \"stiff\"\nresolution = 0.02\nvelocity = [0, -1, 0]\n\
             shape = { type = \"box\", center = [0, 0.06, 0], size = [0.1, 0.1, 0.1] }\n\
             [[collider]]\ntype = \"ground\"\n"
                .into(),
        ),
        (
            "projectile at 500 m/s into a glass plate",
            "[scene]\nname = \"projectile\"\ngravity = [0, 0, 0]\nduration = 0.001\nfps = 10000\n\
             [materials.glass]\ndensity = 2200.0\nbulk_modulus = 3.3e10\nshear_modulus = 2.0e10\ncritical_stretch = 0.0005\n\
             [[body]]\nmaterial = \"glass\"\nresolution = 0.01\n\
             shape = { type = \"box\", center = [0, 0, 0], size = [0.2, 0.2, 0.03] }\n\
             [[collider]]\ntype = \"sphere\"\ncenter = [0, 0, 0.04]\nradius = 0.02\nvelocity = [0, 0, -500]\nmass = 0.1\ngravity = false\n"
                .into(),
        ),
        (
            "thinnest body the tet mesher makes (slab 1.5 λ thick) falling on the ground",
            "[scene]\nname = \"layer\"\nduration = 0.2\nfps = 50\n\
             [materials.m]\ndensity = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.25\n\
             [[body]]\nmaterial = \"m\"\nresolution = 0.01\nvelocity = [0, -2, 0]\n\
             shape = { type = \"slab\", center = [0, 0.05, 0], size = [0.3, 0.015, 0.3] }\n\
             [[collider]]\ntype = \"ground\"\n"
                .into(),
        ),
        (
            "fully shattered body (critical stretch 1e-6) hit at 50 m/s",
            "[scene]\nname = \"shatter\"\ngravity = [0, 0, 0]\nduration = 0.01\nfps = 1000\n\
             [materials.m]\ndensity = 1000.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.25\ncritical_stretch = 1.0e-6\n\
             [[body]]\nmaterial = \"m\"\nresolution = 0.01\n\
             shape = { type = \"box\", center = [0, 0, 0], size = [0.1, 0.1, 0.1] }\n\
             [[collider]]\ntype = \"sphere\"\ncenter = [0, 0, 0.08]\nradius = 0.03\nvelocity = [0, 0, -50]\n"
                .into(),
        ),
    ]
}

/// Runs one case through `perifrac run`'s code path into a scratch directory;
/// returns the table row.
fn run_case(name: &str, text: &str, scratch: &Path, quiet: bool) -> Result<String, Failure> {
    let scene = Scene::parse(
        text,
        Path::new(&format!("stability: {name}")),
        Path::new("."),
    )?;
    let dir = scratch.join(&scene.scene.name);
    let t = Instant::now();
    let result = run::run(&scene, &dir, &run::RunOptions::default(), &mut |_| {});
    let wall = t.elapsed().as_secs_f64();
    let (outcome, m) = match result {
        Ok(m) => (
            format!(
                "stayed finite, kinetic energy within {}× the energy the scene can supply",
                scene.scene.blowup_energy_growth
            ),
            m,
        ),
        Err(e @ SimError::BlowUp { .. }) => {
            let m = perifrac_cache::manifest::Manifest::read(&dir.join("manifest.json"))?;
            (format!("caught: {e}"), m)
        }
        Err(e) => return Err(e.into()),
    };
    let (steps, particles) = (m.steps, m.particles);
    let broken = if m.bonds > 0 {
        format!("{:.1}%", 100.0 * m.broken_bonds as f64 / m.bonds as f64)
    } else {
        "–".into()
    };
    if !quiet {
        eprintln!("{name}: {outcome} ({steps} steps, {wall:.1} s)");
    }
    Ok(format!(
        "| {name} | {particles} | {steps} | {broken} | {wall:.1} | {outcome} |"
    ))
}

/// Runs every case and writes `stability.md`.
pub fn stability(out: &Path, quiet: bool) -> Result<(), Failure> {
    let scratch = std::env::temp_dir().join(format!("perifrac-stability-{}", std::process::id()));
    let mut rows = Vec::new();
    for (model, label) in [
        ("peridynamics", "peridynamics"),
        ("fem-corotated", "corotated FEM"),
    ] {
        let probe = Scene::parse(
            &time_step_case(1.0, 1e-5, model),
            Path::new("stability: time step"),
            Path::new("."),
        )?;
        let stable = run::prepare(&probe)?.stable_dt.0;
        for factor in [0.9, 2.0] {
            let name = format!("{label}, dt = {factor}× the stable bound {stable:.2e} s");
            rows.push(run_case(
                &name,
                &time_step_case(factor, stable, model)
                    .replace("name = \"dt\"", &format!("name = \"dt-{model}-{factor}\"")),
                &scratch,
                quiet,
            )?);
        }
    }
    for (name, text) in cases() {
        rows.push(run_case(name, &text, &scratch, quiet)?);
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let mut report = String::new();
    let _ = writeln!(
        report,
        "# Stability under stress\n\n\
         Each case runs through `perifrac run`'s code path. The simulator checks every 16 steps and after \
         every frame for non-finite positions or velocities and for kinetic energy above \
         `blowup_energy_growth` (10) × what the scene can supply (initial kinetic and strain energy, free fall, \
         colliders, anchors); a caught run stops with the step, the particle and the last good frame on disk.\n\n\
         | case | particles | steps | bonds broken | wall (s) | outcome |\n|---|---|---|---|---|---|"
    );
    for r in rows {
        let _ = writeln!(report, "{r}");
    }
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", out.display())))?;
    let path = out.join("stability.md");
    std::fs::write(&path, &report)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", path.display())))?;
    println!("{report}");
    Ok(())
}
