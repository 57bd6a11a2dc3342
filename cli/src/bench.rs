//! `perifrac bench`: measured figures for the README.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use perifrac_cache::scene::Scene;
use perifrac_sim::memory::estimate_memory;
use perifrac_sim::pd::{PdModel, Peridynamics};
use perifrac_sim::run;
use perifrac_sim::world::World;

use crate::args::BenchCommand;
use crate::commands::{Failure, set_threads};
use crate::memory::check_memory;

/// Runs a benchmark.
pub fn run(which: BenchCommand, quiet: bool) -> Result<(), Failure> {
    match which {
        BenchCommand::Throughput {
            particles,
            steps,
            table1,
            out,
            threads,
        } => {
            set_threads(threads)?;
            match table1 {
                Some(dir) => table1_throughput(&dir, steps, &out, quiet),
                None => throughput(particles, steps, &out, quiet),
            }
        }
        BenchCommand::Accuracy {
            quick,
            scenes,
            out,
            threads,
        } => {
            set_threads(threads)?;
            accuracy(quick, &scenes, &out, quiet)
        }
        BenchCommand::Stability { out, threads } => {
            set_threads(threads)?;
            crate::stability::stability(&out, quiet)
        }
        BenchCommand::Render {
            size,
            triangles,
            particles,
            frames,
            demo,
            out,
        } => {
            let size = crate::args::parse_size("--size", &size)
                .map_err(|m| Failure::input(anyhow::anyhow!(m)))?;
            crate::bench_render::run(size, triangles, particles, frames.max(1), demo, &out, quiet)
        }
    }
}

fn accuracy(quick: bool, scenes: &Path, out: &Path, quiet: bool) -> Result<(), Failure> {
    let sweep = if quick {
        &crate::accuracy::QUICK
    } else {
        &crate::accuracy::FULL
    };
    let (points, same_tets) = crate::accuracy::sweep(sweep, scenes, quiet)?;
    let mut report =
        crate::accuracy::report(&points, &same_tets, sweep, rayon::current_num_threads());
    report.push('\n');
    report.push_str(&crate::accuracy::analytic(scenes, quiet)?);
    report.push('\n');
    report.push_str(&crate::accuracy::crack_angles(scenes, quick, quiet)?);
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", out.display())))?;
    let path = out.join("accuracy.md");
    std::fs::write(&path, &report)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", path.display())))?;
    crate::plot::accuracy_png(&points, &out.join("accuracy.png"))?;
    println!("{report}");
    Ok(())
}

/// The three walls of Chen Table 1 (glass, plastic, elastic) at `particles`
/// particles, δ = 1.45λ, hit by a sphere.
pub fn wall_scene(kind: &str, particles: usize) -> String {
    // A 1 × 1 × 0.1 m wall; the BCC mesher makes about 9.1 tets per λ³.
    let volume = 0.1;
    let lambda = (volume * 9.1 / particles as f64).cbrt();
    let material = match kind {
        "elastic" => "density = 1200\nbulk_modulus = 1.0e7\nshear_modulus = 6.0e6",
        "plastic" => {
            "density = 1200\nbulk_modulus = 1.0e7\nshear_modulus = 6.0e6\nyield_stretch = 0.002\nplastic_limit = 0.2"
        }
        _ => {
            "density = 2200\nbulk_modulus = 3.3e10\nshear_modulus = 2.0e10\ncritical_stretch = 0.0005"
        }
    };
    format!(
        "[scene]\nname = \"{kind}-wall\"\nduration = 1.0\nfps = 24\n\n[materials.wall]\n{material}\n\n\
         [[body]]\nmaterial = \"wall\"\nshape = {{ type = \"box\", center = [0, 0.5, 0], size = [1, 1, 0.1] }}\n\
         resolution = {lambda}\nhorizon = 1.45\nvelocity = [0, 0, 0]\n\n\
         [[collider]]\ntype = \"ground\"\n\n\
         [[collider]]\ntype = \"sphere\"\ncenter = [0, 0.5, 0.2]\nradius = 0.1\nvelocity = [0, 0, -20]\nmass = 50\n"
    )
}

/// Chen Table 1 rows we have scenes for: scene file, paper particle count, paper
/// s/step. The armadillos and the bunny need mesh input, which this build lacks.
const TABLE1: [(&str, f64, f64); 12] = [
    ("glass-wall", 3.0e5, 2.4),
    ("plastic-wall", 3.0e5, 2.4),
    ("elastic-wall", 3.0e5, 2.4),
    ("plastic-wall-fig4", 3.0e5, 2.4),
    ("wall-fig5-gamma-0.15", 3.0e5, 2.4),
    ("jello-bullet", 4.6e5, 3.8),
    ("beam-stretch-nu-0.30", 2.2e4, 0.2),
    ("soft-beam-bend", 4.5e4, 0.6),
    ("stiff-beam-bend", 4.5e4, 0.6),
    ("bar-swing", 9.2e3, 0.05),
    ("bar-twist", 9.2e3, 0.06),
    ("thin-sheet-tear", 1.6e5, 1.8),
];

/// The Table 1 scenes rescaled (λ × (N_scene / N_paper)^(1/3)) to the paper's
/// particle counts, `steps` timed steps each after one warm-up.
fn table1_throughput(dir: &Path, steps: usize, out: &Path, quiet: bool) -> Result<(), Failure> {
    let mut table = String::new();
    let _ = writeln!(
        table,
        "| scene | particles (paper) | particles | bonds | s/step (paper) | s/step | bond-updates/s |"
    );
    let _ = writeln!(table, "|---|---|---|---|---|---|---|");
    for (name, paper_particles, paper_step) in TABLE1 {
        let mut scene = Scene::load(&dir.join(format!("{name}.toml")))?;
        let disc = perifrac_sim::geometry::discretize::discretize(&scene)?;
        let scale = (disc.position.len() as f64 / paper_particles).cbrt();
        for b in &mut scene.bodies {
            b.resolution *= scale;
        }
        let disc = perifrac_sim::geometry::discretize::discretize(&scene)?;
        let estimate = estimate_memory(&scene, &disc);
        if let Err(e) = check_memory(&estimate) {
            let _ = writeln!(
                table,
                "| {name} | {paper_particles:.1e} | {} | – | {paper_step} | does not fit: {} | – |",
                disc.position.len(),
                e.error
            );
            continue;
        }
        let mut p = run::prepare_discretized(&scene, disc)?;
        p.world.step()?;
        let t = Instant::now();
        for _ in 0..steps {
            p.world.step()?;
        }
        let per_step = t.elapsed().as_secs_f64() / steps as f64;
        let m = peridynamics(&p.world)?;
        let updates = m.bonds.len() as f64 / per_step;
        let _ = writeln!(
            table,
            "| {name} | {paper_particles:.1e} | {} | {:.2e} | {paper_step} | {per_step:.3} | {updates:.3e} |",
            m.len(),
            m.bonds.len() as f64
        );
        if !quiet {
            eprintln!(
                "{name}: {} particles, {per_step:.3} s/step, {updates:.3e} bond-updates/s",
                m.len()
            );
        }
    }
    let threads = rayon::current_num_threads();
    let report = format!(
        "# Throughput: Chen Table 1 scenes at the paper's particle counts\n\n\
         Scene files of `assets/scenes` with λ scaled to the paper's particle count, the paper's δ/λ; \
         {steps} timed steps after one warm-up, {threads} threads. The paper's s/step is on its own \
         machine (not ours). The armadillos and the bunny need mesh input and are not included.\n\n{table}"
    );
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", out.display())))?;
    let path = out.join("throughput-table1.md");
    std::fs::write(&path, &report)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", path.display())))?;
    println!("{report}");
    Ok(())
}

/// The peridynamic model of a benchmark's world.
fn peridynamics(world: &World) -> Result<&PdModel, Failure> {
    world
        .model::<Peridynamics>()
        .map(|p| &p.model)
        .ok_or_else(|| anyhow::anyhow!("the benchmark scene has no peridynamic body").into())
}

fn throughput(particles: usize, steps: usize, out: &Path, quiet: bool) -> Result<(), Failure> {
    let mut table = String::new();
    let _ = writeln!(
        table,
        "| wall | particles | bonds | bytes/bond | setup (s) | s/step | bond-updates/s | dilatation + plasticity | forces + fracture | particle contact | other |"
    );
    let _ = writeln!(table, "|---|---|---|---|---|---|---|---|---|---|---|");
    for kind in ["elastic", "plastic", "glass"] {
        let text = wall_scene(kind, particles);
        let scene = Scene::parse(
            &text,
            Path::new(&format!("{kind}-wall (bench)")),
            Path::new("."),
        )?;
        let t = Instant::now();
        let mut p = run::prepare(&scene)?;
        let setup = t.elapsed().as_secs_f64();
        p.world.step()?;
        p.world.reset_times();
        let t = Instant::now();
        for _ in 0..steps {
            p.world.step()?;
        }
        let wall = t.elapsed().as_secs_f64();
        let m = peridynamics(&p.world)?;
        let per_step = wall / steps as f64;
        let updates = m.bonds.len() as f64 / per_step;
        let st = m.times;
        let contact = p.world.contact.as_ref().map(|c| c.time);
        let stage = |s: f64| format!("{:.0}%", 100.0 * s / wall);
        let _ = writeln!(
            table,
            "| {kind} | {} | {} | {:.1} | {setup:.1} | {per_step:.3} | {updates:.3e} | {} | {} | {} | {} |",
            m.len(),
            m.bonds.len(),
            m.bond_bytes() as f64 / m.bonds.len() as f64,
            stage(st.dilatation),
            stage(st.forces),
            contact.map_or("off".to_string(), stage),
            stage(wall - st.dilatation - st.forces - contact.unwrap_or(0.0)),
        );
        if !quiet {
            eprintln!(
                "{kind} wall: {} particles, {:.3} s/step, {updates:.3e} bond-updates/s",
                m.len(),
                per_step
            );
        }
    }
    let threads = rayon::current_num_threads();
    let report = format!(
        "# Throughput\n\nThree walls of Chen Table 1 (δ = 1.45λ), {steps} timed steps after one warm-up, \
         {threads} threads. Bond-updates/s = directed bonds × steps / wall seconds.\n\n{table}"
    );
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", out.display())))?;
    let path = out.join("throughput.md");
    std::fs::write(&path, &report)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", path.display())))?;
    println!("{report}");
    Ok(())
}
