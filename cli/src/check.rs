//! `perifrac check`: a scene validated and its cost printed before anything runs
//! (particles, bonds, memory, the stable step, run time, contact, clamps, the rigid
//! phase).

use std::path::Path;
use std::time::Instant;

use perifrac_cache::scene::{ModelKind, Scene};
use perifrac_sim::family;
use perifrac_sim::geometry::discretize::{Discretization, discretize};
use perifrac_sim::memory::{
    MemoryEstimate, SETUP_BYTES_PER_BOND, estimate_before_meshing, estimate_memory,
};
use perifrac_sim::mpm::{self, PARTICLES_PER_CELL_AXIS};
use perifrac_sim::run;

use crate::commands::Failure;

/// `perifrac check`: validates the scene and prints its cost.
pub fn command(path: &Path) -> Result<(), Failure> {
    let scene = Scene::load(path)?;
    let before = estimate_before_meshing(&scene)?;
    crate::memory::check_memory(&before)?;
    let disc = discretize(&scene)?;
    let delta: Vec<f64> = disc
        .body
        .iter()
        .map(|&b| scene.bodies[b as usize].delta())
        .collect();
    let estimate = estimate_memory(&scene, &disc);
    println!("scene {}: {}", scene.scene.name, path.display());
    for (b, spec) in scene.bodies.iter().enumerate() {
        if spec.model == ModelKind::Mpm {
            continue; // Seeded by the model, not meshed: see `check_mpm`.
        }
        if spec.model == ModelKind::Membrane {
            // A sheet of particles, not a tet mesh: no edges or angles to report.
            let n = disc.body.iter().filter(|&&i| i as usize == b).count();
            println!("  body {}: {n} membrane particles (a sheet)", spec.name);
            continue;
        }
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
    crate::memory::check_memory(&estimate)?;
    if scene.bodies.iter().any(|b| b.model == ModelKind::Mpm) {
        return check_mpm(&scene, disc, &before);
    }
    let bonds = family::count_bonds(&disc.position, &disc.body, &delta)?;
    let particles = disc.position.len();
    let after = MemoryEstimate::new(&scene, particles as f64, bonds as f64, 0.0);
    let memory = after.bytes;
    println!("  particles: {particles}");
    println!(
        "  bonds:     {bonds} directed ({:.1} per particle)",
        bonds as f64 / particles.max(1) as f64
    );
    println!(
        "  memory:    {:.1} MiB at the peak of set-up ({} bytes a bond during the run, {} more \
         while the families are built, and the process's {:.0} MiB)",
        memory / (1 << 20) as f64,
        estimate.bytes_per_bond,
        SETUP_BYTES_PER_BOND,
        perifrac_sim::memory::PROCESS_BYTES / (1 << 20) as f64
    );
    println!(
        "             {:.1} MiB as estimated before meshing ({:.0} particles, {:.3e} bonds)",
        before.bytes / (1 << 20) as f64,
        before.particles,
        before.bonds
    );
    print_ranks(&after);
    print_prepared(&scene, run::prepare_discretized(&scene, disc)?)
}

/// The memory a rank of `mpirun -np N perifrac run` needs (docs/ranks.md).
fn print_ranks(estimate: &MemoryEstimate) {
    let mib = |n| estimate.per_rank(n) / (1 << 20) as f64;
    if estimate.split > 0.0 {
        println!(
            "  ranks:     MiB a rank of `mpirun -np N perifrac run` needs, N = 2: {:.1}, \
             4: {:.1}, 16: {:.1}: each keeps the particles and the bonds' neighbours, \
             and the constants of its own bonds (docs/ranks.md)",
            mib(2),
            mib(4),
            mib(16)
        );
    } else {
        println!(
            "  ranks:     {:.1} MiB a rank of `mpirun -np N perifrac run`, whatever N: \
             every rank holds the whole model (docs/ranks.md)",
            mib(2)
        );
    }
}

/// What the prepared world tells of a scene: its clamps by default, the cost of its
/// steps, particle contact and the rigid phase.
fn print_prepared(scene: &Scene, mut prepared: run::Prepared) -> Result<(), Failure> {
    print_face_clamps(&prepared.world, scene);
    let (stable, dt) = (prepared.stable_dt, prepared.world.dt);
    prepared.world.reset_times();
    print_cost(scene, stable, dt, prepared.steps_per_frame, || {
        prepared.world.step()
    })?;
    print_contact(&prepared.world);
    print_rigid(&prepared.world, scene);
    Ok(())
}

/// Whether the rigid phase is on for a scene with a breaking body, and, when it is off
/// and the run is long, that it would shorten it (docs/rigid.md).
fn print_rigid(world: &perifrac_sim::world::World, scene: &Scene) {
    let breaks = world.parts.iter().any(|p| {
        p.model
            .fragments()
            .is_some_and(|f| f.breaking.iter().any(|&b| b >= 0.0))
    });
    if !breaks {
        return;
    }
    if let Some(rigid) = &world.rigid_settings {
        println!(
            "  rigid phase: on (fragments that stop breaking go to rapier; once only rigid \
             pieces move the step grows to [rigid] step)"
        );
        // The slowest hit that breaks a piece: s_c c_p of the weakest breaking body.
        let hit = world
            .parts
            .iter()
            .filter_map(|p| p.model.fragments())
            .flat_map(|f| f.hit_speed)
            .fold(f64::INFINITY, f64::min);
        if hit.is_finite() && rigid.reenter > 0.0 {
            println!(
                "  rigid pieces of more than {} particles go back to their model before \
                 a hit at {:.2} m/s or faster (reenter = {} × s_c c_p); the world is then \
                 stepped at dt until they settle (docs/rigid.md, \"Going back\")",
                rigid.reenter_points,
                rigid.reenter * hit,
                rigid.reenter
            );
        } else if hit.is_finite() {
            println!(
                "  rigid pieces stay rigid when hit again: a piece landing faster than \
                 about {:.2} m/s (0.6 s_c c_p) would chip or break as particles. \
                 `[rigid] reenter = 2` breaks the hardest hits (from {:.2} m/s) again, \
                 stepping the world at dt while they break (docs/rigid.md, \"Going back\")",
                0.6 * hit,
                2.0 * hit
            );
        }
    } else if scene.scene.duration >= 0.1 {
        println!(
            "  rigid phase: off, for a shot of {:.2} s. `[rigid] enabled = true` hands \
             fragments that stop breaking to rapier and grows the step once only rigid \
             pieces move (docs/rigid.md: the demo shot's 5 s in 8,984 steps)",
            scene.scene.duration
        );
    }
}

/// `perifrac check` of a scene with MPM bodies: the model seeds their particles
/// ([`PARTICLES_PER_CELL_AXIS`]³ a cell), so they are counted once it has, with the
/// memory they need.
fn check_mpm(scene: &Scene, disc: Discretization, before: &MemoryEstimate) -> Result<(), Failure> {
    let prepared = run::prepare_discretized(scene, disc)?;
    let owners = &prepared.discretization.body;
    for (b, spec) in scene.bodies.iter().enumerate() {
        let n = owners.iter().filter(|&&owner| owner as usize == b).count();
        println!(
            "  body {}: {n} MPM particles ({}³ a grid cell of {:.4} m)",
            spec.name, PARTICLES_PER_CELL_AXIS, spec.resolution
        );
        let material = &scene.materials[&spec.material];
        let bonded = material.mpm.as_ref().is_some_and(|m| m.bonds.is_some());
        let spb = material
            .mpm
            .as_ref()
            .is_some_and(|m| m.energy_release_rate.is_some() && m.bonds.is_none());
        if spb {
            let bonds = n as f64 * mpm::patches::interior_family();
            println!(
                "  note: body {} fractures by SPB-MPM: its bonds come as its particles join the \
                 peridynamic region, not counted below; if all {n} joined, {bonds:.3e} bonds \
                 would take {:.1} MiB more",
                spec.name,
                bonds * mpm::patches::BYTES_PER_BOND as f64 / (1 << 20) as f64
            );
        }
        let nu = perifrac_sim::material::Material::from_spec(material).poisson_ratio();
        if bonded && (nu - 0.25).abs() > 1e-9 {
            println!(
                "  note: body {}'s bonds (integral-based MPM) act as a bond-based solid of \
                 Poisson's ratio 1/4: they keep its P-wave modulus λ + 2μ, not its ratio {nu} \
                 (docs/mpm.md, \"Integral-based MPM\")",
                spec.name
            );
        }
    }
    let particles = owners.len();
    let bonds = prepared.world.bonds();
    let dx = mpm::grid::spacing(scene);
    let grid = mpm::grid::SparseGrid::estimate_bytes(&prepared.discretization.position, dx);
    let estimate = MemoryEstimate::new(scene, particles as f64, bonds as f64, 0.0).with_grid(grid);
    crate::memory::check_memory(&estimate)?;
    println!("  particles: {particles}");
    // SPB-MPM's bonds come as particles join, the integral-based MPM's at the start.
    let with_bonds = if bonds > 0 {
        format!(
            " and their {bonds} bonds ({} bytes each)",
            estimate.bytes_per_bond
        )
    } else {
        String::new()
    };
    println!(
        "  memory:    {:.1} MiB at the peak: {} bytes a particle (its state, the step's \
         buffers, the frame's columns){with_bonds}, the grid's {:.1} MiB ({:.0} bytes a \
         particle) and the process's {:.0} MiB",
        estimate.bytes / (1 << 20) as f64,
        perifrac_sim::memory::MPM_PEAK_BYTES_PER_PARTICLE,
        grid / (1 << 20) as f64,
        grid / particles.max(1) as f64,
        perifrac_sim::memory::PROCESS_BYTES / (1 << 20) as f64
    );
    println!(
        "             {:.1} MiB as estimated before seeding ({:.0} particles)",
        before.bytes / (1 << 20) as f64,
        before.particles
    );
    print_ranks(&estimate);
    print_prepared(scene, prepared)
}

/// Particle contact's pairs and share of the timed steps, when the scene has it.
fn print_contact(world: &perifrac_sim::world::World) {
    let Some(contact) = &world.contact else {
        println!("  particle contact: off");
        return;
    };
    let total: f64 = world.stage_times().iter().map(|(_, t)| t).sum::<f64>() + world.other_time;
    println!(
        "  particle contact: {} particles, stable dt {:.3e} s, {:.0}% of the step time",
        contact.len(),
        contact.stable_time_step().0,
        100.0 * contact.time / total.max(f64::MIN_POSITIVE)
    );
}

/// The anchors clamped at their region's face by default, one line each (issue 33:
/// users should see that the plain held region became a clamp, and how to undo it).
fn print_face_clamps(world: &perifrac_sim::world::World, scene: &Scene) {
    for part in &world.parts {
        for (b, k, plane) in perifrac_sim::contact::face_clamps(scene, &part.anchors) {
            println!(
                "  body {} anchor {}: clamped at the face where its box meets the body, {plane} \
                 (body.{b}.anchor.{k}: clamp = false holds the whole region instead)",
                scene.bodies[b].name,
                k + 1
            );
        }
    }
}

/// The stable step, the step count and the run time estimated from three timed steps.
fn print_cost(
    scene: &Scene,
    stable_dt: (f64, usize),
    dt: f64,
    steps_per_frame: usize,
    mut step: impl FnMut() -> perifrac_sim::error::Result<usize>,
) -> Result<(), Failure> {
    // Each segment of the frame schedule at its own steps a frame (the first at the
    // run's `steps_per_frame`).
    let segments = scene.frame_segments();
    let steps_total: usize = segments
        .iter()
        .enumerate()
        .map(|(k, &(frames, length))| {
            let per_frame = if k == 0 {
                steps_per_frame
            } else {
                perifrac_sim::world::steps_within(length, dt) as usize
            };
            frames * per_frame
        })
        .sum();
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
    if segments.len() == 1 {
        println!(
            "  steps:     {} frames × {steps_per_frame} = {steps_total}",
            scene.frame_count(),
        );
    } else {
        println!(
            "  steps:     {} frames in {} segments of the schedule = {steps_total}",
            scene.frame_count(),
            segments.len()
        );
    }
    println!(
        "  estimate:  {:.4} s a step, {:.0} s for the run on {} threads{}",
        per_step,
        per_step * steps_total as f64,
        rayon::current_num_threads(),
        if scene.rigid.enabled {
            " (every step at dt: an upper bound with the rigid phase)"
        } else {
            ""
        }
    );
    print_likely(scene, dt, per_step);
    Ok(())
}

/// With the rigid phase and a frame schedule (slow motion through an impact, then real
/// time), the run as such shots go: deformable through the schedule's first segment,
/// rigid after it at the rigid phase's step. The demo shot (`demo-shot.toml`) took about
/// 6,530 steps at dt to its last hand-off at about 4.8 ms, against the 5,460 to its
/// first segment's end (docs/rigid.md).
fn print_likely(scene: &Scene, dt: f64, per_step: f64) {
    let Some(first) = scene.output.schedule.first() else {
        return;
    };
    if !scene.rigid.enabled {
        return;
    }
    let duration = scene.scene.duration;
    let impact = first.until.min(duration);
    let deformable = (impact / dt).ceil();
    let rigid = ((duration - impact).max(0.0) / scene.rigid.step).ceil();
    println!(
        "  likely:    {:.0} s if the pieces are rigid by the end of the schedule's first \
         segment ({impact} s: {deformable:.0} steps at dt), then {rigid:.0} rigid-phase steps of \
         {:.2e} s (milliseconds each with a few thousand pieces)",
        per_step * deformable,
        scene.rigid.step
    );
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
    let prepared = run::prepare_discretized(scene, disc)?;
    print_prepared(scene, prepared)
}
