//! The material point method: MLS-MPM (Lyu 2021 ch. 3; Hu et al. 2018) behind the
//! [`Model`] interface, stepping itself ([`Stepping::Own`]).
//!
//! One step is `sort → stress → p2g → grid_update → g2p` on a sparse grid of
//! spacing Δx (the smallest `resolution` of the scene's bodies): see [`grid`] for the
//! blocks and the deterministic scatter, [`constitutive`] for the energies,
//! [`plasticity`] for the impact models of ch. 7 (J2 with Johnson–Cook hardening,
//! Mie–Grüneisen; their return maps and pressures, not yet wired into the step). Transfers
//! are APIC with quadratic B-splines; time stepping is explicit.
//!
//! **Time step.** The world's step is bounded by the elastic wave: Δt ≤
//! [`ELASTIC_COURANT`] Δx / c_p with c_p = √((λ + 2μ)/ρ) of the stiffest material
//! and by the CFL condition v_max Δt ≤ [`CFL`] Δx at the initial velocities (both in
//! [`Model::stable_time_step`]). The step is not adapted during the run (that would
//! hide an elastic instability from the blow-up detector): a scene whose particles
//! end up faster than its fastest initial one (a long fall) sets a smaller
//! `dt_safety` or `dt`.
//!
//! **Data layout** (for models built on it, such as SPB-MPM's bonds on a subset of the
//! particles): particle state is structure-of-arrays in [`MpmParticles`], indexed by
//! particle and never reordered after seeding; the grid keeps its own sorted order,
//! so a later module can hold families over particle indices and add per-particle
//! terms between the transfers without copying them.

pub mod constitutive;
pub mod grid;
pub mod plasticity;
mod seed;
#[cfg(test)]
mod tests;

use std::time::Instant;

use rayon::prelude::*;

use crate::cache::checkpoint::{Decoder, Encoder};
use crate::error::{Result, SimError};
use crate::model::{Environment, Model, ParticleColumns, Points, PointsMut, Stepping};
use crate::scene::Scene;
use constitutive::{Elastic, IDENTITY, Mat3, mul_transpose};
use grid::{Boundary, D_INVERSE_FACTOR, SparseGrid};

pub use seed::{PARTICLES_PER_CELL_AXIS, SEED_JITTER};

/// CFL number: the stable step keeps v_max Δt ≤ `CFL` Δx at the initial velocities.
pub const CFL: f64 = 0.3;
/// Elastic Courant number: Δt ≤ `ELASTIC_COURANT` Δx / c_p. Measured on a block on
/// the ground (fixed corotated, 8 particles a cell): c_p Δt/Δx = 0.9 runs 3000 steps,
/// 1.05 grows, 1.2 blows up within 32 steps; so twice this bound is caught.
pub const ELASTIC_COURANT: f64 = 0.6;

/// Particle state, structure-of-arrays, one entry a particle.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MpmParticles {
    /// Positions x_p (m).
    pub position: Vec<[f64; 3]>,
    /// Velocities v_p (m/s).
    pub velocity: Vec<[f64; 3]>,
    /// Positions at seeding (m).
    pub reference: Vec<[f64; 3]>,
    /// Masses m_p (kg).
    pub mass: Vec<f64>,
    /// Initial volumes V_p⁰ (m³).
    pub volume: Vec<f64>,
    /// Scene body of each particle.
    pub body: Vec<u32>,
    /// Deformation gradients F_p.
    pub deformation: Vec<Mat3>,
    /// APIC affine velocity matrices C_p (1/s).
    pub affine: Vec<Mat3>,
    /// Equivalent plastic strain ε^p (0 for elastic materials).
    pub plastic: Vec<f64>,
}

impl MpmParticles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }
}

/// A body's material in the MPM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MpmMaterial {
    /// Density ρ⁰ (kg/m³).
    pub density: f64,
    /// Elastic energy and Lamé parameters.
    pub elastic: Elastic,
}

/// Wall time of the stages (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct StageTimes {
    sort: f64,
    p2g: f64,
    grid: f64,
    g2p: f64,
}

/// The MLS-MPM model of a scene's bodies on one sparse grid.
#[derive(Debug, Clone)]
pub struct Mpm {
    /// The particles.
    pub particles: MpmParticles,
    /// Each body's material.
    pub materials: Vec<MpmMaterial>,
    /// The grid.
    pub grid: SparseGrid,
    /// Scratch: each particle's affine momentum A_p of [`SparseGrid::p2g`].
    momentum_affine: Vec<Mat3>,
    times: StageTimes,
}

impl Mpm {
    /// The model of `particles` (for example seeded by [`Mpm::from_scene`]) on a grid
    /// of spacing `dx`.
    pub fn new(particles: MpmParticles, materials: Vec<MpmMaterial>, dx: f64) -> Mpm {
        let n = particles.len();
        Mpm {
            particles,
            materials,
            grid: SparseGrid::new(dx),
            momentum_affine: vec![[[0.0; 3]; 3]; n],
            times: StageTimes::default(),
        }
    }

    /// The model of a scene whose bodies all use `model = "mpm"`: particles seeded
    /// from each body's shape with the scene's seed, each body's angular velocity in
    /// C (the velocities are the caller's).
    pub fn from_scene(scene: &Scene) -> Result<Mpm> {
        let particles = seed::seed(scene)?;
        let materials = scene
            .bodies
            .iter()
            .map(|b| {
                let spec = &scene.materials[&b.material];
                let m = crate::material::Material::from_spec(spec);
                let energy = spec.mpm.clone().unwrap_or_default().elasticity;
                MpmMaterial {
                    density: spec.density,
                    elastic: Elastic::from_young(energy, m.youngs_modulus(), m.poisson_ratio()),
                }
            })
            .collect();
        let dx = scene
            .bodies
            .iter()
            .map(|b| b.resolution)
            .fold(f64::INFINITY, f64::min);
        let mut model = Mpm::new(particles, materials, dx);
        for (p, c) in model.particles.affine.iter_mut().enumerate() {
            let w = scene.bodies[model.particles.body[p] as usize].angular_velocity;
            *c = [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]];
        }
        Ok(model)
    }

    /// The largest speed of any particle (m/s).
    pub fn max_speed(&self) -> f64 {
        self.particles
            .velocity
            .par_iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .reduce(|| 0.0, f64::max)
    }

    /// One explicit MLS-MPM step of length `dt`.
    pub fn step(&mut self, dt: f64, boundary: &Boundary<'_>) {
        let t0 = Instant::now();
        let p = &mut self.particles;
        self.grid.rebuild(&p.position);
        let t1 = Instant::now();
        let dx = self.grid.dx;
        let d_inv = D_INVERSE_FACTOR / (dx * dx);
        let materials = &self.materials;
        self.momentum_affine
            .par_iter_mut()
            .enumerate()
            .with_min_len(256)
            .for_each(|(i, a)| {
                let elastic = &materials[p.body[i] as usize].elastic;
                let f = &p.deformation[i];
                let stress = mul_transpose(&elastic.first_piola(f), f);
                let scale = dt * p.volume[i] * d_inv;
                let (m, c) = (p.mass[i], &p.affine[i]);
                *a = [0, 1, 2].map(|r| [0, 1, 2].map(|s| m * c[r][s] - scale * stress[r][s]));
            });
        self.grid
            .p2g(&p.position, &p.mass, &p.velocity, &self.momentum_affine);
        let t2 = Instant::now();
        self.grid.grid_update(dt, boundary);
        let t3 = Instant::now();
        self.grid.g2p(
            dt,
            &mut p.position,
            &mut p.velocity,
            &mut p.affine,
            &mut p.deformation,
        );
        let t4 = Instant::now();
        self.times.sort += (t1 - t0).as_secs_f64();
        self.times.p2g += (t2 - t1).as_secs_f64();
        self.times.grid += (t3 - t2).as_secs_f64();
        self.times.g2p += (t4 - t3).as_secs_f64();
    }

    /// Total linear momentum Σ m_p v_p (kg m/s), summed in particle order.
    pub fn momentum(&self) -> [f64; 3] {
        let p = &self.particles;
        let mut total = [0.0; 3];
        for (m, v) in p.mass.iter().zip(&p.velocity) {
            for a in 0..3 {
                total[a] += m * v[a];
            }
        }
        total
    }

    /// Total angular momentum about the origin including APIC's affine part (Jiang et
    /// al. 2015): Σ m_p (x_p × v_p + (Δx²/4) ε : C_pᵀ).
    pub fn angular_momentum(&self) -> [f64; 3] {
        let p = &self.particles;
        let d = self.grid.dx * self.grid.dx / D_INVERSE_FACTOR;
        let mut total = [0.0; 3];
        for i in 0..p.len() {
            let (x, v, c, m) = (p.position[i], p.velocity[i], p.affine[i], p.mass[i]);
            let l = [
                x[1] * v[2] - x[2] * v[1] + d * (c[2][1] - c[1][2]),
                x[2] * v[0] - x[0] * v[2] + d * (c[0][2] - c[2][0]),
                x[0] * v[1] - x[1] * v[0] + d * (c[1][0] - c[0][1]),
            ];
            for a in 0..3 {
                total[a] += m * l[a];
            }
        }
        total
    }
}

fn flatten(m: &[Mat3]) -> Vec<f64> {
    m.iter().flat_map(|r| r.iter().flatten().copied()).collect()
}

fn unflatten(values: &[f64], out: &mut [Mat3]) {
    for (m, chunk) in out.iter_mut().zip(values.chunks_exact(9)) {
        for (r, row) in m.iter_mut().enumerate() {
            row.copy_from_slice(&chunk[3 * r..3 * r + 3]);
        }
    }
}

impl Model for Mpm {
    fn name(&self) -> &'static str {
        "mpm"
    }

    fn points(&self) -> Points<'_> {
        Points {
            position: &self.particles.position,
            velocity: &self.particles.velocity,
            reference: &self.particles.reference,
            mass: &self.particles.mass,
        }
    }

    fn points_mut(&mut self) -> PointsMut<'_> {
        PointsMut {
            position: &mut self.particles.position,
            velocity: &mut self.particles.velocity,
            reference: &self.particles.reference,
            mass: &self.particles.mass,
        }
    }

    fn point_bodies(&self) -> &[u32] {
        &self.particles.body
    }

    fn stepping(&self) -> Stepping {
        Stepping::Own
    }

    /// Forces live on the grid: nothing to compute at the world's request.
    fn internal_forces(&mut self) -> usize {
        0
    }

    /// Gravity only: the MPM's accelerations come from its grid inside
    /// [`Model::advance`].
    fn accelerations(&self, gravity: [f64; 3], out: &mut [[f64; 3]]) {
        out.iter_mut().for_each(|a| *a = gravity);
    }

    fn damp(&mut self, _dt: f64, _anchored: &[bool]) {}

    fn advance(&mut self, dt: f64, environment: &Environment<'_>) -> Result<usize> {
        let boundary = Boundary {
            gravity: environment.gravity,
            colliders: environment.colliders,
        };
        self.step(dt, &boundary);
        Ok(0)
    }

    /// min(ELASTIC_COURANT Δx / c_p, CFL Δx / v_max); the limiting particle is the
    /// fastest one when the CFL bound is the smaller, else the first particle of the
    /// stiffest body.
    fn stable_time_step(&self) -> (f64, usize) {
        let p = &self.particles;
        let dx = self.grid.dx;
        let (elastic, stiffest) = (0..p.len())
            .map(|i| {
                let m = &self.materials[p.body[i] as usize];
                (ELASTIC_COURANT * dx / m.elastic.p_wave_speed(m.density), i)
            })
            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
        let (speed, fastest) = (0..p.len())
            .map(|i| {
                let v = p.velocity[i];
                ((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt(), i)
            })
            .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
        let cfl = CFL * dx / speed;
        if cfl < elastic {
            (cfl, fastest)
        } else {
            (elastic, stiffest)
        }
    }

    fn kinetic_energy(&self) -> f64 {
        let p = &self.particles;
        p.mass
            .iter()
            .zip(&p.velocity)
            .map(|(m, v)| 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
            .sum()
    }

    /// Σ_p V_p⁰ ψ(F_p).
    fn strain_energy(&self) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .map(|i| {
                let elastic = &self.materials[p.body[i] as usize].elastic;
                p.volume[i] * elastic.energy_density(&p.deformation[i])
            })
            .sum()
    }

    fn particles(&self) -> ParticleColumns {
        let p = &self.particles;
        let f32x3 = |v: &[f64; 3]| v.map(|x| x as f32);
        ParticleColumns {
            position: p.position.iter().map(f32x3).collect(),
            velocity: p.velocity.iter().map(f32x3).collect(),
            damage: vec![0.0; p.len()],
            plastic: p.plastic.iter().map(|&e| e as f32).collect(),
            body: p.body.clone(),
            fragment: p.body.clone(),
            extra: vec![(
                "J".to_string(),
                p.deformation
                    .iter()
                    .map(|f| constitutive::determinant(f) as f32)
                    .collect(),
            )],
        }
    }

    fn save(&self, out: &mut Encoder) {
        let p = &self.particles;
        out.put_f64x3_slice(&p.position);
        out.put_f64x3_slice(&p.velocity);
        out.put_f64_slice(&flatten(&p.deformation));
        out.put_f64_slice(&flatten(&p.affine));
        out.put_f64_slice(&p.plastic);
    }

    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let p = &mut self.particles;
        let n = p.len();
        p.position = input.take_f64x3_slice("MPM positions", n)?;
        p.velocity = input.take_f64x3_slice("MPM velocities", n)?;
        let f = input.take_f64_slice("MPM deformation gradients", 9 * n)?;
        unflatten(&f, &mut p.deformation);
        let c = input.take_f64_slice("MPM affine matrices", 9 * n)?;
        unflatten(&c, &mut p.affine);
        p.plastic = input.take_f64_slice("MPM plastic strains", n)?;
        Ok(())
    }

    fn stage_times(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("mpm sort", self.times.sort),
            ("p2g", self.times.p2g),
            ("grid", self.times.grid),
            ("g2p", self.times.g2p),
        ]
    }

    fn reset_stage_times(&mut self) {
        self.times = StageTimes::default();
    }
}

/// A particle set at rest with F = I and C = 0.
fn at_rest(
    position: Vec<[f64; 3]>,
    volume: Vec<f64>,
    mass: Vec<f64>,
    body: Vec<u32>,
) -> MpmParticles {
    let n = position.len();
    MpmParticles {
        reference: position.clone(),
        position,
        velocity: vec![[0.0; 3]; n],
        mass,
        volume,
        body,
        deformation: vec![IDENTITY; n],
        affine: vec![[[0.0; 3]; 3]; n],
        plastic: vec![0.0; n],
    }
}

/// The error of a body without particles.
fn empty_body(name: &str) -> SimError {
    SimError::Mesh {
        body: name.to_string(),
        message: "no MPM particle lies inside the shape: use a finer resolution".into(),
    }
}
