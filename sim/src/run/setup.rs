//! From a scene to a world ready to step: discretize, build each model (families and
//! initial cracks for peridynamics, elements for the FEM, sheets for membranes), initial velocities,
//! anchors, colliders, and the time step.

use std::sync::Arc;
use std::time::Instant;

use perifrac_math::sub;

use crate::cache::manifest::Timings;
use crate::contact::{self, centroid};
use crate::embed::EmbeddedMesh;
use crate::error::{Result, SimError};
use crate::family::{self, Solid};
use crate::fem::{Fem, FemBody, FemModel};
use crate::geometry::discretize::{Discretization, discretize};
use crate::geometry::shape::bond_shapes;
use crate::material::Material;
use crate::membrane::{Membrane, MembraneModel};
use crate::model::Model;
use crate::mpm::Mpm;
use crate::particle_contact::ParticleContact;
use crate::pd::{BodyModel, PdModel, Peridynamics, Setup, cut_initial_cracks};
use crate::ranks::{Ranks, Share};
use crate::scene::{ModelKind, Scene};
use crate::world::{Part, World, WorldSettings};

/// A scene made ready to step.
#[derive(Debug)]
pub struct Prepared {
    /// The world at t = 0.
    pub world: World,
    /// Particles and meshes.
    pub discretization: Discretization,
    /// The stable time step bound (s) and the point that limits it.
    pub stable_dt: (f64, usize),
    /// Steps per output frame.
    pub steps_per_frame: usize,
    /// Setup timings.
    pub timings: Timings,
}

/// Whether the scene runs the FEM reference solvers (every body then does).
pub fn uses_fem(scene: &Scene) -> bool {
    scene.bodies.iter().any(|b| b.model.is_fem())
}

/// Whether the scene's bodies are membranes (every body then is).
pub fn uses_membrane(scene: &Scene) -> bool {
    scene.bodies.iter().any(|b| b.model == ModelKind::Membrane)
}

/// Builds the particles, bonds (or elements), colliders and anchors of a scene and
/// picks the time step (refusing a `dt` above the stable bound unless `force_dt`).
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
    prepare_shared(scene, disc, None)
}

/// [`prepare_discretized`] for one of the `ranks` of a distributed run: a peridynamic
/// model keeps the per-bond constants of its own rows alone from the start (the
/// memory of a rank, docs/ranks.md); the other models are split later
/// ([`Model::share`]).
pub fn prepare_shared(
    scene: &Scene,
    disc: Discretization,
    ranks: Option<&Arc<dyn Ranks>>,
) -> Result<Prepared> {
    let t1 = Instant::now();
    let mut disc = disc;
    let part = if uses_fem(scene) {
        fem_part(scene, &disc)?
    } else if uses_membrane(scene) {
        membrane_part(scene, &disc)?
    } else if scene.bodies.iter().any(|b| b.model == ModelKind::Mpm) {
        mpm_part(scene, &mut disc)?
    } else {
        peridynamic_part(scene, &disc, ranks)?
    };
    let parts = vec![part];
    let mut stable = parts
        .iter()
        .map(|p| p.model.stable_time_step())
        .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
    let contact = scene.particle_contact().then(|| {
        let models: Vec<&dyn Model> = parts.iter().map(|p| p.model.as_ref()).collect();
        ParticleContact::new(scene, &models)
    });
    if let Some(contact) = &contact {
        let bound = contact.stable_time_step();
        if bound.0 < stable.0 {
            stable = bound;
        }
    }
    let t_setup = t1.elapsed().as_secs_f64();
    let (dt, steps_per_frame) = time_step(scene, stable)?;
    let colliders = contact::colliders(scene)?;
    // A body meshed against a collider's face has its particles at most half a
    // spacing inside it; one a spacing deep is a body placed through the collider.
    let tolerance = crate::mpm::grid::spacing(scene);
    for part in &parts {
        contact::refuse_points_inside(&colliders, part.model.points().position, tolerance)?;
    }
    let mut world = World::new(
        parts,
        colliders,
        WorldSettings {
            gravity: scene.scene.gravity,
            dt,
            duration: scene.scene.duration,
            energy_growth: scene.scene.blowup_energy_growth,
        },
    );
    if let Some(contact) = contact {
        world.set_particle_contact(contact);
    }
    world.step_bound = scene.scene.dt.unwrap_or(scene.scene.dt_safety * stable.0);
    // Fragments go rigid only from bodies that can break (their fragments say so).
    if scene.rigid.enabled && world.parts.iter().any(|p| p.model.fragments().is_some()) {
        world.rigid_settings = Some(scene.rigid.clone());
    }
    Ok(Prepared {
        world,
        discretization: disc,
        stable_dt: stable,
        steps_per_frame,
        timings: Timings {
            families: t_setup,
            ..Timings::default()
        },
    })
}

/// The peridynamic model of every body (Chen et al. 2018): families within each
/// body's horizon δ, initial velocities, initial cracks, anchors, and the embedded tet
/// mesh when the scene writes `tets/`.
fn peridynamic_part(
    scene: &Scene,
    disc: &Discretization,
    ranks: Option<&Arc<dyn Ranks>>,
) -> Result<Part> {
    let delta: Vec<f64> = disc
        .body
        .iter()
        .map(|&b| scene.bodies[b as usize].delta())
        .collect();
    // Bonds of a body that is not convex must stay inside its shape (issue 13).
    let shapes = bond_shapes(scene)?;
    let solids: Vec<Option<Solid>> = shapes
        .iter()
        .zip(&scene.bodies)
        .map(|(sdf, b)| sdf.as_deref().map(|sdf| Solid::of(sdf, b.resolution)))
        .collect();
    let bonds = family::families_through(&disc.position, &disc.body, &delta, &solids)?;
    let share = ranks
        .filter(|r| r.size() > 1)
        .map(|r| Share::by_bonds(r.clone(), &bonds.offsets));
    let bodies: Vec<BodyModel> = scene
        .bodies
        .iter()
        .map(|b| {
            BodyModel::new(
                Material::from_spec(&scene.materials[&b.material]),
                b.delta(),
            )
        })
        .collect();
    let mut model = PdModel::new(
        disc.position.clone(),
        disc.volume.clone(),
        disc.body.clone(),
        bonds,
        bodies,
        Setup {
            form: scene.scene.dilatation,
            surface_correction: scene.scene.surface_correction,
            share,
        },
    );
    let r = &model.reference;
    set_initial_velocities(
        scene,
        &r.position,
        &r.volume,
        &r.body,
        &mut model.particles.velocity,
    );
    cut_initial_cracks(&mut model, scene)?;
    let r = &model.reference;
    let anchors = contact::anchors(scene, &r.position, &r.volume, &r.body)?;
    // The rigid phase takes its pieces' colliders from the mesh's faces; a mesh it
    // cannot build (face-adjacent tets without a bond) leaves them the particles'.
    let writes_tets = scene.output.writes_tets();
    let names: Vec<String> = scene.bodies.iter().map(|b| b.name.clone()).collect();
    let embedded = if writes_tets {
        Some(EmbeddedMesh::build(disc, &model.bonds, &names)?)
    } else if scene.rigid.enabled {
        EmbeddedMesh::build(disc, &model.bonds, &names).ok()
    } else {
        None
    };
    Ok(Part::new(
        Box::new(Peridynamics::new(model, embedded, writes_tets)),
        anchors,
    ))
}

/// The FEM reference of a scene whose bodies use `fem-linear` or `fem-corotated`: the
/// same meshes, anchors and initial velocities as the peridynamic run, on the mesh
/// vertices (weighted by their lumped masses).
fn fem_part(scene: &Scene, disc: &Discretization) -> Result<Part> {
    if scene.output.writes_tets() {
        return Err(SimError::Refused(
            "FEM reference bodies do not fracture, so they have no split tet mesh: set [output] tets = false and a surface method other than \"embedded\"".into(),
        ));
    }
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
    let mut model = FemModel::new(disc, bodies)?;
    set_initial_velocities(
        scene,
        &model.rest,
        &model.mass,
        &model.vertex_body,
        &mut model.velocity,
    );
    let anchors = contact::anchors(scene, &model.rest, &model.mass, &model.vertex_body)?;
    Ok(Part::new(Box::new(Fem::new(model)), anchors))
}

/// The membranes of a scene (Han et al. 2021): the sheets' particles, bonds within
/// each body's cutoff R, slits and notches from `[[body.crack]]`, initial velocities
/// and anchors.
fn membrane_part(scene: &Scene, disc: &Discretization) -> Result<Part> {
    if scene.output.writes_tets() {
        return Err(SimError::Refused(
            "membranes have no tet mesh: set [output] tets = false and a surface method other than \"embedded\"".into(),
        ));
    }
    let mut model = MembraneModel::from_scene(scene, disc)?;
    set_initial_velocities(
        scene,
        &model.reference,
        &model.mass,
        &model.body,
        &mut model.velocity,
    );
    let anchors = contact::anchors(scene, &model.reference, &model.mass, &model.body)?;
    Ok(Part::new(Box::new(Membrane::new(model)), anchors))
}

/// The MPM model of a scene whose bodies use `model = "mpm"` (Lyu 2021 ch. 3):
/// particles seeded in each body's shape, initial velocities and anchors on them. The
/// discretization's particles become the MPM particles (the manifest counts them).
fn mpm_part(scene: &Scene, disc: &mut Discretization) -> Result<Part> {
    if scene.output.writes_tets() {
        return Err(SimError::Refused(
            "MPM bodies have no tet mesh to split: set [output] tets = false and a surface method other than \"embedded\"".into(),
        ));
    }
    let mut model = Mpm::from_scene(scene)?;
    let p = &mut model.particles;
    set_initial_velocities(scene, &p.reference, &p.mass, &p.body, &mut p.velocity);
    let anchors = contact::anchors(scene, &p.reference, &p.mass, &p.body)?;
    disc.position = p.reference.clone();
    disc.volume = p.volume.clone();
    disc.body = p.body.clone();
    disc.tet = vec![0; p.len()];
    Ok(Part::new(Box::new(model), anchors))
}

/// The most steps a run may take: the world's time is steps × dt, exact in the step
/// count up to 2^53.
const MAX_STEPS: f64 = 9_007_199_254_740_992.0;

/// The time step (a multiple of the frame time) and the steps per frame: the scene's
/// `dt`, refused above the stable bound unless `force_dt`, or `dt_safety` × the bound;
/// a run of more than [`MAX_STEPS`] steps is refused.
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
    let steps_per_frame = (frame_time / dt).ceil().max(1.0);
    let total = steps_per_frame * scene.frame_count() as f64;
    if total.is_nan() || total > MAX_STEPS {
        return Err(SimError::Refused(format!(
            "the run would take {total:e} steps of {dt:e} s ({steps_per_frame:e} a frame); at \
             most {MAX_STEPS:e} (2^53, where the step count stops being exact in the time): use \
             a larger dt or a shorter duration"
        )));
    }
    let steps_per_frame = steps_per_frame as usize;
    Ok((frame_time / steps_per_frame as f64, steps_per_frame))
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
            let r = sub(position[i], c);
            // v + ω × r, summed left to right as before the restructure (pinned bytes).
            velocity[i] = [
                spec.velocity[0] + w[1] * r[2] - w[2] * r[1],
                spec.velocity[1] + w[2] * r[0] - w[0] * r[2],
                spec.velocity[2] + w[0] * r[1] - w[1] * r[0],
            ];
        }
    }
}
