//! From a scene to frames on disk: discretize, build families, choose the time step,
//! step frame by frame, write the cache, checkpoint, and stop cleanly on blow-up.

use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;

use crate::cache::manifest::{BodyInfo, Manifest, Timings};
use crate::cache::ply::ParticleFrame;
use crate::cache::vtu::TetFrame;
use crate::cache::{Layout, write_atomic};
use crate::checkpoint_state as checkpoint;
use crate::contact::{Anchor, Collider};
use crate::embed::{EmbeddedMesh, NO_PARENT, deformation_gradients};
use crate::error::{Result, SimError};
use crate::family;
use crate::fem::{FemBody, FemModel, FemSimulation};
use crate::geometry::discretize::{Discretization, discretize};
use crate::geometry::shape::to_sdf;
use crate::material::Material;
use crate::pd::{BodyModel, PdModel, StageTimes};
use crate::scene::{ModelKind, Scene};
use crate::step::{Simulation, stable_time_step};

/// A scene made ready to step.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The simulation at t = 0.
    pub sim: Simulation,
    /// Particles and meshes.
    pub discretization: Discretization,
    /// The stable time step bound (s) and the particle that limits it.
    pub stable_dt: (f64, usize),
    /// Steps per output frame.
    pub steps_per_frame: usize,
    /// Setup timings.
    pub timings: Timings,
}

/// Bytes per particle of state and scratch (positions, velocities, reference data,
/// θ, forces, accelerations, masses, flags).
pub const BYTES_PER_PARTICLE: usize = 8 * 3 * 5 + 8 * 5 + 4 * 3 + 2;

/// What a scene will cost in memory, estimated before any bond is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryEstimate {
    /// Particles.
    pub particles: usize,
    /// Directed bonds expected from each body's particle density and horizon.
    pub bonds: f64,
    /// Bytes a bond takes (more with plasticity).
    pub bytes_per_bond: usize,
    /// Total bytes of the run's state.
    pub bytes: f64,
}

/// Estimates the memory of a discretized scene: a particle's family holds about
/// V_H / (mean particle volume) − 1 bonds (fewer near surfaces).
pub fn estimate_memory(scene: &Scene, disc: &Discretization) -> MemoryEstimate {
    let plastic = scene
        .materials
        .values()
        .any(|m| (m.yield_psi0.is_some() || m.yield_stretch.is_some()) && m.plastic_limit > 0.0);
    let bytes_per_bond = family::BYTES_PER_BOND + if plastic { 12 } else { 0 };
    let bonds: f64 = scene
        .bodies
        .iter()
        .enumerate()
        .map(|(b, spec)| {
            let mesh = &disc.meshes[b];
            let count = mesh.tets.len() as f64;
            if count == 0.0 {
                return 0.0;
            }
            let mean_volume = mesh.total_volume() / count;
            let family = crate::pd::family_volume(spec.horizon * spec.resolution) / mean_volume;
            count * (family - 1.0).max(0.0)
        })
        .sum();
    let particles = disc.position.len();
    MemoryEstimate {
        particles,
        bonds,
        bytes_per_bond,
        bytes: bonds * bytes_per_bond as f64 + (particles * BYTES_PER_PARTICLE) as f64,
    }
}

/// Memory the system can still give (MemAvailable of /proc/meminfo), if known.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Refuses a scene whose bonds would not fit in the available memory.
pub fn check_memory(estimate: &MemoryEstimate) -> Result<()> {
    let Some(available) = available_memory() else {
        return Ok(());
    };
    if estimate.bytes > available as f64 {
        let gib = |b: f64| b / (1u64 << 30) as f64;
        return Err(SimError::Refused(format!(
            "the run needs about {:.1} GiB ({} particles, {:.3e} bonds of {} bytes) but {:.1} GiB are \
             available: use a coarser resolution or a smaller horizon",
            gib(estimate.bytes),
            estimate.particles,
            estimate.bonds,
            estimate.bytes_per_bond,
            gib(available as f64)
        )));
    }
    Ok(())
}

/// Builds the particles, bonds, colliders and anchors of a scene and picks the time
/// step (refusing a scene that would not fit in memory, and a `dt` above the stable
/// bound unless `force_dt`).
pub fn prepare(scene: &Scene) -> Result<Prepared> {
    let t0 = Instant::now();
    let disc = discretize(scene)?;
    let t_disc = t0.elapsed().as_secs_f64();
    let mut prepared = prepare_discretized(scene, disc)?;
    prepared.timings.discretize = t_disc;
    Ok(prepared)
}

/// [`prepare`] for a scene already discretized.
pub fn prepare_discretized(scene: &Scene, disc: Discretization) -> Result<Prepared> {
    check_memory(&estimate_memory(scene, &disc))?;
    let t1 = Instant::now();
    let horizon: Vec<f64> = disc
        .body
        .iter()
        .map(|&b| {
            let spec = &scene.bodies[b as usize];
            spec.horizon * spec.resolution
        })
        .collect();
    let (bonds, corrections) = family::build(
        &disc.position,
        &disc.volume,
        &disc.body,
        &horizon,
        scene.scene.surface_correction,
    )?;
    let bodies: Vec<BodyModel> = scene
        .bodies
        .iter()
        .map(|b| {
            BodyModel::new(
                Material::from_spec(&scene.materials[&b.material]),
                b.horizon * b.resolution,
            )
        })
        .collect();
    let mut model = PdModel::new(
        disc.position.clone(),
        disc.volume.clone(),
        disc.body.clone(),
        bonds,
        corrections,
        bodies,
        scene.scene.dilatation,
    );
    initial_velocities(scene, &mut model);
    for (b, spec) in scene.bodies.iter().enumerate() {
        for crack in &spec.cracks {
            let Some(region) = to_sdf(&crack.region) else {
                continue;
            };
            let (p, n) = (crack.point, crack.normal);
            let side =
                |x: [f64; 3]| (x[0] - p[0]) * n[0] + (x[1] - p[1]) * n[1] + (x[2] - p[2]) * n[2];
            let body = model.reference.body.clone();
            let x = model.reference.position.clone();
            model.cut_bonds(|i, j| {
                let (xi, xj) = (x[i], x[j]);
                let mid = [
                    (xi[0] + xj[0]) / 2.0,
                    (xi[1] + xj[1]) / 2.0,
                    (xi[2] + xj[2]) / 2.0,
                ];
                body[i] == b as u32 && side(xi) * side(xj) < 0.0 && region.distance(mid) <= 0.0
            });
        }
    }
    let stable = stable_time_step(&model);
    let t_fam = t1.elapsed().as_secs_f64();
    let (dt, steps_per_frame) = time_step(scene, stable)?;
    let anchors = anchors(
        scene,
        &model.reference.position,
        &model.reference.volume,
        &model.reference.body,
    );
    let colliders = scene.colliders.iter().map(Collider::from_spec).collect();
    let sim = Simulation::new(
        model,
        colliders,
        anchors,
        scene.scene.gravity,
        dt,
        scene.scene.duration,
        scene.scene.blowup_energy_growth,
    );
    Ok(Prepared {
        sim,
        discretization: disc,
        stable_dt: stable,
        steps_per_frame,
        timings: Timings {
            families: t_fam,
            ..Timings::default()
        },
    })
}

/// The time step (a multiple of the frame time) and the steps per frame: the scene's
/// `dt`, refused above the stable bound unless `force_dt`, or `dt_safety` × the bound.
fn time_step(scene: &Scene, stable: (f64, usize)) -> Result<(f64, usize)> {
    let dt = match scene.scene.dt {
        Some(dt) if dt > stable.0 && !scene.scene.force_dt => {
            return Err(SimError::Refused(format!(
                "dt = {dt:e} s is above the stable time step {:e} s (limited at particle {}); \
                 use dt ≤ {:e} or set force_dt = true in [scene] to run anyway",
                stable.0, stable.1, stable.0
            )));
        }
        Some(dt) => dt,
        None => scene.scene.dt_safety * stable.0,
    };
    let frame_time = scene.frame_time();
    let steps_per_frame = (frame_time / dt).ceil().max(1.0) as usize;
    Ok((frame_time / steps_per_frame as f64, steps_per_frame))
}

/// A FEM reference scene made ready to step.
#[derive(Debug, Clone)]
pub struct FemPrepared {
    /// The simulation at t = 0.
    pub sim: FemSimulation,
    /// Particles (tet barycentres) and meshes.
    pub discretization: Discretization,
    /// The stable time step bound (s) and the particle (tet) that limits it.
    pub stable_dt: (f64, usize),
    /// Steps per output frame.
    pub steps_per_frame: usize,
    /// Setup timings (`families`: element setup and the stable step).
    pub timings: Timings,
}

/// Whether the scene runs the FEM reference solvers (every body then does).
pub fn uses_fem(scene: &Scene) -> bool {
    scene.bodies.iter().any(|b| b.model.is_fem())
}

/// Builds the FEM reference of a scene whose bodies use `fem-linear` or
/// `fem-corotated`: the same meshes, anchors, colliders, gravity and initial
/// velocities as the peridynamic run, with the time step from the element sizes.
pub fn prepare_fem(scene: &Scene) -> Result<FemPrepared> {
    let t0 = Instant::now();
    let disc = discretize(scene)?;
    let t_disc = t0.elapsed().as_secs_f64();
    let mut prepared = prepare_fem_discretized(scene, disc)?;
    prepared.timings.discretize = t_disc;
    Ok(prepared)
}

/// [`prepare_fem`] for a scene already discretized.
pub fn prepare_fem_discretized(scene: &Scene, disc: Discretization) -> Result<FemPrepared> {
    let t1 = Instant::now();
    let bodies = scene
        .bodies
        .iter()
        .map(|b| {
            FemBody::new(
                Material::from_spec(&scene.materials[&b.material]),
                b.model == ModelKind::FemCorotated,
            )
        })
        .collect();
    let mut model = FemModel::new(&disc, bodies)?;
    let weight = model.mass.clone();
    set_initial_velocities(
        scene,
        &model.rest,
        &weight,
        &model.vertex_body,
        &mut model.velocity,
    );
    let stable = model.stable_time_step();
    let (dt, steps_per_frame) = time_step(scene, stable)?;
    let anchors = anchors(scene, &model.rest, &weight, &model.vertex_body);
    let colliders = scene.colliders.iter().map(Collider::from_spec).collect();
    let sim = FemSimulation::new(
        model,
        colliders,
        anchors,
        scene.scene.gravity,
        dt,
        scene.scene.duration,
        scene.scene.blowup_energy_growth,
    );
    Ok(FemPrepared {
        sim,
        discretization: disc,
        stable_dt: stable,
        steps_per_frame,
        timings: Timings {
            families: t1.elapsed().as_secs_f64(),
            ..Timings::default()
        },
    })
}

fn initial_velocities(scene: &Scene, model: &mut PdModel) {
    set_initial_velocities(
        scene,
        &model.reference.position,
        &model.reference.volume,
        &model.reference.body,
        &mut model.particles.velocity,
    );
}

/// Each body's initial velocity and spin about its centroid (weighted by `weight`).
fn set_initial_velocities(
    scene: &Scene,
    position: &[[f64; 3]],
    weight: &[f64],
    body: &[u32],
    velocity: &mut [[f64; 3]],
) {
    for (b, spec) in scene.bodies.iter().enumerate() {
        let members: Vec<usize> = (0..position.len())
            .filter(|&i| body[i] == b as u32)
            .collect();
        let c = centroid(position, weight, &members);
        let w = spec.angular_velocity;
        for &i in &members {
            let r = position[i];
            let r = [r[0] - c[0], r[1] - c[1], r[2] - c[2]];
            velocity[i] = [
                spec.velocity[0] + w[1] * r[2] - w[2] * r[1],
                spec.velocity[1] + w[2] * r[0] - w[0] * r[2],
                spec.velocity[2] + w[0] * r[1] - w[1] * r[0],
            ];
        }
    }
}

fn centroid(x: &[[f64; 3]], v: &[f64], members: &[usize]) -> [f64; 3] {
    let mut c = [0.0; 3];
    let mut total = 0.0;
    for &i in members {
        for a in 0..3 {
            c[a] += x[i][a] * v[i];
        }
        total += v[i];
    }
    if total > 0.0 { c.map(|s| s / total) } else { c }
}

/// The anchors of the scene over points at `position` (particles, or FEM vertices)
/// of bodies `body`; a default centre is the centroid weighted by `weight`.
fn anchors(scene: &Scene, position: &[[f64; 3]], weight: &[f64], body: &[u32]) -> Vec<Anchor> {
    let mut out = Vec::new();
    for (b, spec) in scene.bodies.iter().enumerate() {
        for a in &spec.anchors {
            let Some(region) = to_sdf(&a.region) else {
                continue;
            };
            let members: Vec<usize> = (0..position.len())
                .into_par_iter()
                .filter(|&i| body[i] == b as u32 && region.distance(position[i]) <= 0.0)
                .collect();
            let center = a
                .center
                .unwrap_or_else(|| centroid(position, weight, &members));
            out.push(Anchor {
                particles: members.iter().map(|&i| i as u32).collect(),
                velocity: a.velocity,
                angular_velocity: a.angular_velocity,
                center,
                until: a.until,
            });
        }
    }
    out
}

/// FNV-1a of the resolved scene: ties checkpoints to their scene.
pub fn scene_hash(scene: &Scene) -> u64 {
    scene.to_toml().bytes().fold(0xcbf29ce484222325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    })
}

/// The split tet mesh of the current state (Chen §5.2): updates the crack-face set
/// and splits vertices, then places the vertices (see [`crate::embed`]).
pub fn tet_frame(mesh: &mut EmbeddedMesh, sim: &Simulation) -> TetFrame {
    let m = &sim.model;
    mesh.update(&m.bonds);
    let reference = &m.reference.position;
    let position = &m.particles.position;
    let gradient = deformation_gradients(&m.bonds, reference, position, &m.reference.volume);
    let mass: Vec<f64> = (0..m.len()).map(|i| m.mass(i)).collect();
    TetFrame {
        points: mesh.positions(reference, position, &mass, &gradient),
        tets: mesh.tets.clone(),
        particle: (0..m.len() as u32).collect(),
        damage: m.particles.damage.iter().map(|&d| d as f32).collect(),
        parent: mesh
            .parent
            .iter()
            .map(|&p| if p == NO_PARENT { -1 } else { p as i32 })
            .collect(),
    }
}

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Stop after this many frames (after the initial one).
    pub frames: Option<usize>,
    /// Continue from the checkpoint in the output directory.
    pub resume: bool,
}

/// Progress of a run, reported after each frame.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// Frames written (including the initial one).
    pub frame: usize,
    /// Frames the run will write.
    pub frames: usize,
    /// Steps taken.
    pub steps: u64,
    /// Steps per frame.
    pub steps_per_frame: usize,
}

/// The frame of the current state, for the cache.
pub fn snapshot(sim: &Simulation, frame: usize) -> ParticleFrame {
    let m = &sim.model;
    let p = &m.particles;
    let f32x3 = |v: &[f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32];
    ParticleFrame {
        frame,
        time: sim.time,
        position: p.position.iter().map(f32x3).collect(),
        velocity: p.velocity.iter().map(f32x3).collect(),
        damage: p.damage.iter().map(|&d| d as f32).collect(),
        plastic: m.plastic_strain().into_iter().map(|s| s as f32).collect(),
        material: m.reference.body.iter().map(|&b| b as f32).collect(),
        fragment: m.fragments().into_iter().map(|f| f as f32).collect(),
        extra: Vec::new(),
    }
}

/// What the run loop needs of a solver: the peridynamic [`Simulation`] or the FEM
/// reference [`FemSimulation`].
trait Stepper {
    fn step(&mut self) -> Result<usize>;
    fn check_blowup(&self) -> Result<()>;
    fn frame(&self, frame: usize) -> ParticleFrame;
    fn time(&self) -> f64;
    fn steps(&self) -> u64;
    /// The model's stage times and the rest (integration, contact, damping).
    fn times(&self) -> (StageTimes, f64);
    /// The checkpoint after `frame`, if the solver writes them.
    fn checkpoint(&self, frame: usize, broken: u64, hash: u64) -> Option<Vec<u8>>;
    /// Each collider's centre now (scene order), for the previews.
    fn collider_centers(&self) -> Vec<[f64; 3]>;
    /// The peridynamic simulation, whose bonds drive the embedded mesh.
    fn peridynamics(&self) -> Option<&Simulation>;
}

impl Stepper for Simulation {
    fn step(&mut self) -> Result<usize> {
        Simulation::step(self)
    }
    fn check_blowup(&self) -> Result<()> {
        Simulation::check_blowup(self)
    }
    fn frame(&self, frame: usize) -> ParticleFrame {
        snapshot(self, frame)
    }
    fn time(&self) -> f64 {
        self.time
    }
    fn steps(&self) -> u64 {
        self.steps
    }
    fn times(&self) -> (StageTimes, f64) {
        (self.model.times, self.other_time)
    }
    fn checkpoint(&self, frame: usize, broken: u64, hash: u64) -> Option<Vec<u8>> {
        Some(checkpoint::encode(self, frame, broken, hash))
    }
    fn collider_centers(&self) -> Vec<[f64; 3]> {
        self.colliders.iter().map(|c| c.center).collect()
    }
    fn peridynamics(&self) -> Option<&Simulation> {
        Some(self)
    }
}

impl Stepper for FemSimulation {
    fn step(&mut self) -> Result<usize> {
        FemSimulation::step(self)
    }
    fn check_blowup(&self) -> Result<()> {
        FemSimulation::check_blowup(self)
    }
    fn frame(&self, frame: usize) -> ParticleFrame {
        FemSimulation::frame(self, frame)
    }
    fn time(&self) -> f64 {
        self.time
    }
    fn steps(&self) -> u64 {
        self.steps
    }
    fn times(&self) -> (StageTimes, f64) {
        (
            StageTimes {
                dilatation: 0.0,
                forces: self.force_time,
            },
            self.other_time,
        )
    }
    fn checkpoint(&self, _: usize, _: u64, _: u64) -> Option<Vec<u8>> {
        None
    }
    fn collider_centers(&self) -> Vec<[f64; 3]> {
        self.colliders.iter().map(|c| c.center).collect()
    }
    fn peridynamics(&self) -> Option<&Simulation> {
        None
    }
}

/// Runs a scene into `out`; `progress` is called after each frame. On a blow-up the
/// frames written so far stay on disk, the manifest records what happened and the
/// error names the step, the particle and the last good frame. FEM reference scenes
/// run the same way but write no checkpoints (and cannot be resumed).
pub fn run(
    scene: &Scene,
    out: &Path,
    options: &RunOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Manifest> {
    let start = Instant::now();
    let layout = Layout::new(out);
    layout.create()?;
    write_atomic(&layout.scene(), scene.to_toml().as_bytes())?;
    let hash = scene_hash(scene);
    let frames = options
        .frames
        .unwrap_or_else(|| scene.frame_count())
        .min(scene.frame_count());
    let mut drive = Drive {
        scene,
        layout: &layout,
        frames,
        first: 1,
        broken_total: 0,
        start,
        hash,
        manifest: Manifest::default(),
        progress,
        embedded: None,
        split_time: 0.0,
    };
    if uses_fem(scene) {
        if options.resume {
            return Err(SimError::Refused(
                "FEM reference runs write no checkpoints and cannot be resumed: run again without --resume"
                    .into(),
            ));
        }
        if scene.output.writes_tets() {
            return Err(SimError::Refused(
                "FEM reference bodies do not fracture, so they have no split tet mesh: set [output] tets = false and a surface method other than \"embedded\"".into(),
            ));
        }
        let mut prepared = prepare_fem(scene)?;
        let d = &prepared.discretization;
        drive.manifest = manifest_for(scene, d, prepared.sim.dt, prepared.stable_dt.0, 0);
        return drive.run(
            &mut prepared.sim,
            prepared.steps_per_frame,
            &prepared.timings,
        );
    }
    let mut prepared = prepare(scene)?;
    drive.manifest = manifest_for(
        scene,
        &prepared.discretization,
        prepared.sim.dt,
        prepared.stable_dt.0,
        prepared.sim.model.bonds.len(),
    );
    if scene.output.writes_tets() {
        let dir = layout.root.join("tets");
        std::fs::create_dir_all(&dir).map_err(|e| SimError::io(&dir, e))?;
        let names: Vec<String> = scene.bodies.iter().map(|b| b.name.clone()).collect();
        drive.embedded = Some(EmbeddedMesh::build(
            &prepared.discretization,
            &prepared.sim.model.bonds,
            &names,
        )?);
    }
    if options.resume && layout.checkpoint().is_file() {
        let resume = checkpoint::restore(&layout.checkpoint(), &mut prepared.sim, hash)?;
        drive.first = resume.frame + 1;
        drive.broken_total = resume.broken_bonds;
        if let Ok(old) = Manifest::read(&layout.manifest()) {
            drive.manifest.frame_times = old.frame_times.into_iter().take(resume.frame).collect();
            drive.manifest.collider_centers = old
                .collider_centers
                .into_iter()
                .take(resume.frame)
                .collect();
        }
        if let Some(mesh) = drive.embedded.as_mut() {
            // The topology written at the checkpoint's frame keeps the vertex
            // numbering of the frames already on disk.
            let last = TetFrame::read(&layout.tets(resume.frame))?;
            let parent = last
                .parent
                .iter()
                .map(|&p| if p < 0 { NO_PARENT } else { p as u32 })
                .collect();
            mesh.restore(last.tets, parent, &prepared.sim.model.bonds)?;
        }
    }
    drive.run(
        &mut prepared.sim,
        prepared.steps_per_frame,
        &prepared.timings,
    )
}

/// The frame loop of [`run`], shared by both solvers.
struct Drive<'a> {
    scene: &'a Scene,
    layout: &'a Layout,
    frames: usize,
    first: usize,
    broken_total: u64,
    start: Instant,
    hash: u64,
    manifest: Manifest,
    progress: &'a mut dyn FnMut(Progress),
    /// The embedded tet mesh, when the scene writes `tets/` (peridynamics only).
    embedded: Option<EmbeddedMesh>,
    /// Seconds spent splitting vertices and placing them.
    split_time: f64,
}

impl Drive<'_> {
    fn run(
        mut self,
        sim: &mut impl Stepper,
        steps_per_frame: usize,
        setup: &Timings,
    ) -> Result<Manifest> {
        let (scene, layout, frames) = (self.scene, self.layout, self.frames);
        let mut output_time = 0.0;
        for frame in self.first..=frames + 1 {
            if frame > 1 {
                let mut result = Ok(());
                for _ in 0..steps_per_frame {
                    match sim.step() {
                        Ok(broken) => self.broken_total += broken as u64,
                        Err(e) => {
                            result = Err(e);
                            break;
                        }
                    }
                }
                match result.and_then(|_| sim.check_blowup()) {
                    Ok(()) => {}
                    Err(SimError::BlowUp {
                        step,
                        time,
                        what,
                        particle,
                        position,
                        ..
                    }) => {
                        let err = SimError::BlowUp {
                            step,
                            time,
                            what,
                            particle,
                            position,
                            last_good_frame: frame - 1,
                        };
                        self.manifest.status = err.to_string();
                        self.finish(sim, output_time, setup);
                        self.manifest.write(&layout.manifest())?;
                        return Err(err);
                    }
                    Err(e) => return Err(e),
                }
            }
            let t = Instant::now();
            let mut frame_split = 0.0;
            if scene.output.particles {
                sim.frame(frame).write(&layout.particles(frame))?;
            }
            if let (Some(mesh), Some(pd)) = (self.embedded.as_mut(), sim.peridynamics()) {
                let s = Instant::now();
                let tets = tet_frame(mesh, pd);
                frame_split = s.elapsed().as_secs_f64();
                self.split_time += frame_split;
                tets.write(&layout.tets(frame))?;
            }
            self.manifest.frame_times.push(sim.time());
            self.manifest.collider_centers.push(sim.collider_centers());
            self.manifest.status = if frame == frames + 1 {
                "complete".into()
            } else {
                "running".into()
            };
            self.finish(sim, output_time, setup);
            self.manifest.write(&layout.manifest())?;
            let every = scene.output.checkpoint_every;
            if every > 0 && frame % every == 0 && frame <= frames {
                if let Some(bytes) = sim.checkpoint(frame, self.broken_total, self.hash) {
                    write_atomic(&layout.checkpoint(), &bytes)?;
                }
            }
            output_time += t.elapsed().as_secs_f64() - frame_split;
            (self.progress)(Progress {
                frame,
                frames: frames + 1,
                steps: sim.steps(),
                steps_per_frame,
            });
        }
        self.finish(sim, output_time, setup);
        self.manifest.write(&layout.manifest())?;
        Ok(self.manifest)
    }

    fn finish(&mut self, sim: &impl Stepper, output: f64, setup: &Timings) {
        let (stages, other) = sim.times();
        let m = &mut self.manifest;
        m.steps = sim.steps();
        m.broken_bonds = self.broken_total;
        m.timings = Timings {
            discretize: setup.discretize,
            families: setup.families,
            stages: [("dilatation", stages.dilatation), ("forces", stages.forces)]
                .map(|(name, seconds)| (name.to_string(), seconds))
                .into(),
            integrate_contact: other,
            output,
            split: self.split_time,
            surface: 0.0,
            total: self.start.elapsed().as_secs_f64(),
        };
    }
}

fn manifest_for(
    scene: &Scene,
    d: &Discretization,
    dt: f64,
    stable_dt: f64,
    bonds: usize,
) -> Manifest {
    Manifest {
        scene: scene.scene.name.clone(),
        units: "SI: m, kg, s, Pa; y up".into(),
        tool_version: env!("CARGO_PKG_VERSION").into(),
        dt,
        stable_dt,
        fps: scene.scene.fps,
        particles: d.position.len(),
        bonds,
        bodies: scene
            .bodies
            .iter()
            .enumerate()
            .map(|(b, spec)| BodyInfo {
                name: spec.name.clone(),
                material: spec.material.clone(),
                particles: d.meshes[b].tets.len(),
                vertices: d.meshes[b].vertices.len(),
                min_dihedral_deg: d.quality[b].min_dihedral_deg,
                max_dihedral_deg: d.quality[b].max_dihedral_deg,
                mean_edge: d.quality[b].mean_edge,
            })
            .collect(),
        status: "running".into(),
        ..Manifest::default()
    }
}
