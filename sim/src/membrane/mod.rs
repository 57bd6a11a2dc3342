//! Thin membranes that tear and diffuse: the particle model of Han et al. 2021 ("A
//! Lagrangian particle-based formulation for coupled simulation of fracture and
//! diffusion in thin membranes"), §4–5.
//!
//! A sheet is one layer of particles ([`sheet`]) with area A_i and thickness h, volume
//! V_i = A_i h and mass m_i = ρ V_i. Particle i is bonded to every particle j of its
//! body within the cutoff R (Han §6: R = 1.5 × spacing), with the weight
//!
//! ```text
//! W_ij = 1 − |ξ_ij|/R                                       (Eq. 23)
//! c    = 18K/(πR⁴)                                          (Eq. 24)
//! η_ij = |y_j − y_i| / |ξ_ij| − 1   (s_ij − 1, Eq. 10)
//! f_ij = c F(η'_ij)                 (Eq. 18–20, [`law`]; η' with the expansion αθ̄)
//! ρ a_i = Σ_j γ_ij f_ij W_ij V_j (y_j − y_i)/|y_j − y_i|   (Eq. 22 with γ, Eq. 26)
//! ```
//!
//! Bond vectors live in 3D, so a sheet moves freely out of its plane and wrinkles and
//! folds by itself. Departure from Eq. 22 as printed: the force acts along the
//! *current* bond direction, not n⁰_ij = ξ/|ξ| (which is not objective: a rigidly
//! rotated sheet would push itself), and the bond's force is c η, not c η/|ξ|, per
//! unit volume of i and j: that is the derivative of Silling's micropotential
//! ½ c η² |ξ|, the one for which Eq. 24 is the calibration; the sum is over volumes
//! V_j = A_j h so that the units close (force per volume over density is an
//! acceleration).
//!
//! Fracture (Eq. 27–28): a bond breaks for good when η_ij passes the critical strain
//! η_c = √(4πG_f/(9ER)); broken bonds carry neither force nor the diffused quantity.
//!
//! Diffusion (Eq. 25, stepped by forward Euler as Eq. 26): every particle carries a
//! quantity θ (temperature, solvent, moisture) with
//!
//! ```text
//! ρ C A_i θ̇_i = Σ_j γ*_ij k (θ_j − θ_i)/|ξ_ij|² W_ij A_j
//! ```
//!
//! which conserves Σ_i ρ C A_i θ_i exactly when the bonded particles carry equal areas
//! (every particle of a sheet does, and bonds join particles of one body only).

pub mod law;
pub mod sheet;
mod solver;
pub mod source;
#[cfg(test)]
mod tests;

use std::time::Instant;

use perifrac_math::det_sum;
use rayon::prelude::*;

pub use law::Law;
pub use solver::Membrane;
pub use source::{Effect, Source};

use crate::error::{Result, SimError};
use crate::family::{self, BROKEN, Bonds, INDEX};
use crate::geometry::discretize::Discretization;
use crate::material::Material;
use crate::pd::{Cracks, rows_mut};
use crate::scene::{MembraneMaterialSpec, ModelKind, Scene};

/// The constants of one membrane body.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetBody {
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Sheet thickness h (m).
    pub thickness: f64,
    /// Cutoff radius R (m) of Eq. 23.
    pub cutoff: f64,
    /// Micromodulus c = 18K/(πR⁴) (N/m⁶, Eq. 24).
    pub micromodulus: f64,
    /// Critical strain η_c = √(4πG_f/(9ER)) (Eq. 27); infinite when unbreakable.
    pub critical_strain: f64,
    /// Diffusive capacity C (J/(kg·unit), Eq. 25).
    pub capacity: f64,
    /// Diffusion coefficient k (W/(m·unit), Eq. 25).
    pub conductivity: f64,
    /// Air damping rate (1/s): v ← (1 − rate·Δt) v.
    pub air_damping: f64,
    /// The bond law (Eq. 18–20).
    pub law: Law,
    /// Coefficient of linear expansion α (per unit of θ).
    pub expansion: f64,
}

impl SheetBody {
    /// The constants of a sheet of `material` (with its membrane properties `spec`),
    /// `thickness` thick, with cutoff radius `cutoff` (m).
    pub fn new(
        material: &Material,
        spec: &MembraneMaterialSpec,
        thickness: f64,
        cutoff: f64,
    ) -> SheetBody {
        let pi = std::f64::consts::PI;
        let critical_strain = spec.fracture_energy.map_or(f64::INFINITY, |g| {
            (4.0 * pi * g / (9.0 * material.youngs_modulus() * cutoff)).sqrt()
        });
        SheetBody {
            density: material.density,
            thickness,
            cutoff,
            micromodulus: 18.0 * material.bulk_modulus / (pi * cutoff.powi(4)),
            critical_strain,
            capacity: spec.diffusion_capacity,
            conductivity: spec.diffusion_conductivity,
            air_damping: material.air_damping,
            law: Law::of(spec),
            expansion: spec.expansion,
        }
    }
}

/// Wall time of the membrane's stages (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// Bond strains, fracture (Eq. 27–28) and forces (Eq. 18, 22).
    pub forces: f64,
    /// The diffusion step (Eq. 25–26).
    pub diffusion: f64,
}

/// The membrane particles of every body of a scene: state, bonds and scratch.
#[derive(Debug, Clone)]
pub struct MembraneModel {
    /// Reference positions x_i (m).
    pub reference: Vec<[f64; 3]>,
    /// Current positions y_i (m).
    pub position: Vec<[f64; 3]>,
    /// Velocities (m/s).
    pub velocity: Vec<[f64; 3]>,
    /// Particle areas A_i (m²).
    pub area: Vec<f64>,
    /// Particle volumes V_i = A_i h (m³).
    pub volume: Vec<f64>,
    /// Masses m_i = ρ V_i (kg).
    pub mass: Vec<f64>,
    /// Body index of each particle.
    pub body: Vec<u32>,
    /// Constants of each body.
    pub bodies: Vec<SheetBody>,
    /// Bonds within each body's cutoff R; the broken bit is γ_ij = 0 (Eq. 27–28).
    pub bonds: Bonds,
    /// W_ij = 1 − |ξ|/R per directed bond (Eq. 23).
    pub weight: Vec<f64>,
    /// The diffused quantity θ_i (Eq. 25).
    pub quantity: Vec<f64>,
    /// Sources and sinks of θ (Eq. 8's S; [`source`]).
    pub sources: Vec<Source>,
    /// Time the diffusion has been stepped (s), for the sources' start and stop.
    pub elapsed: f64,
    /// Damage φ_i = 1 − intact/initial bonds.
    pub damage: Vec<f64>,
    /// Bonds of each particle before the run.
    initial_bonds: Vec<u32>,
    /// Force density ρ a_i without gravity (N/m³), from the last forces.
    pub force: Vec<[f64; 3]>,
    /// Stage timers.
    pub times: StageTimes,
}

impl MembraneModel {
    /// The model of particles at `reference` with areas `area` in bodies `body`:
    /// bonds within each body's cutoff R, weights W_ij (Eq. 23), θ = 0 everywhere.
    pub fn new(
        reference: Vec<[f64; 3]>,
        area: Vec<f64>,
        body: Vec<u32>,
        bodies: Vec<SheetBody>,
    ) -> Result<MembraneModel> {
        let n = reference.len();
        let volume: Vec<f64> = (0..n)
            .map(|i| area[i] * bodies[body[i] as usize].thickness)
            .collect();
        let mass: Vec<f64> = (0..n)
            .map(|i| volume[i] * bodies[body[i] as usize].density)
            .collect();
        let cutoff: Vec<f64> = body.iter().map(|&b| bodies[b as usize].cutoff).collect();
        let (bonds, _) = family::build(&reference, &volume, &body, &cutoff, false)?;
        let weight = (0..n)
            .flat_map(|i| bonds.range(i).map(move |k| (i, k)))
            .map(|(i, k)| (1.0 - bonds.rest_length[k] / cutoff[i]).max(0.0))
            .collect();
        let initial_bonds = (0..n).map(|i| bonds.range(i).len() as u32).collect();
        Ok(MembraneModel {
            position: reference.clone(),
            velocity: vec![[0.0; 3]; n],
            reference,
            area,
            volume,
            mass,
            body,
            bodies,
            bonds,
            weight,
            quantity: vec![0.0; n],
            sources: Vec::new(),
            elapsed: 0.0,
            damage: vec![0.0; n],
            initial_bonds,
            force: vec![[0.0; 3]; n],
            times: StageTimes::default(),
        })
    }

    /// The membrane bodies of a scene, on the sheet particles of its discretization
    /// ([`sheet::sample`]), with the scene's initial cracks (slits, notches) cut.
    pub fn from_scene(scene: &Scene, disc: &Discretization) -> Result<MembraneModel> {
        let mut bodies = Vec::with_capacity(scene.bodies.len());
        for b in &scene.bodies {
            if b.model != ModelKind::Membrane {
                return Err(SimError::Refused(format!(
                    "body '{}' is not a membrane: a membrane scene runs membranes only",
                    b.name
                )));
            }
            let sheet = sheet::sample(b).map_err(|message| SimError::Mesh {
                body: b.name.clone(),
                message,
            })?;
            let spec = &scene.materials[&b.material];
            let cutoff = b.membrane.clone().unwrap_or_default().cutoff * b.resolution;
            bodies.push(SheetBody::new(
                &Material::from_spec(spec),
                &spec.membrane.clone().unwrap_or_default(),
                sheet.thickness,
                cutoff,
            ));
        }
        let area = (0..disc.position.len())
            .map(|i| disc.volume[i] / bodies[disc.body[i] as usize].thickness)
            .collect();
        let mut model = MembraneModel::new(disc.position.clone(), area, disc.body.clone(), bodies)?;
        for (theta, &b) in model.quantity.iter_mut().zip(&model.body) {
            *theta = scene.bodies[b as usize]
                .membrane
                .as_ref()
                .map_or(0.0, |m| m.quantity);
        }
        model.sources = source::of_scene(scene, &model.reference, &model.body)?;
        let cracks = &Cracks::of_scene(scene)?;
        let (x, body, bonds) = (&model.reference, &model.body, &model.bonds);
        let cut: Vec<bool> = (0..model.len())
            .into_par_iter()
            .flat_map_iter(|i| {
                bonds.range(i).map(move |k| {
                    let j = (bonds.neighbours[k] & INDEX) as usize;
                    cracks.cuts(body[i], x[i], x[j])
                })
            })
            .collect();
        for (nb, cut) in model.bonds.neighbours.iter_mut().zip(cut) {
            if cut {
                *nb |= BROKEN;
            }
        }
        model.update_damage();
        Ok(model)
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.reference.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.reference.is_empty()
    }

    /// Bond strains η_ij (Eq. 10), fracture (Eq. 27–28: a bond whose strain passes
    /// η_c breaks for good) and the force densities of Eq. 18 and 22 into
    /// [`MembraneModel::force`], in one pass gathering over each particle's bonds in
    /// a fixed order. Returns the number of directed bonds that broke.
    pub fn internal_forces(&mut self) -> usize {
        let t = Instant::now();
        let (y, volume, body, bodies) = (&self.position, &self.volume, &self.body, &self.bodies);
        let theta = &self.quantity;
        let (rest, weight, offsets) = (&self.bonds.rest_length, &self.weight, &self.bonds.offsets);
        let initial = &self.initial_bonds;
        let rows = rows_mut(&mut self.bonds.neighbours, offsets);
        let broken: usize = rows
            .into_par_iter()
            .zip(self.force.par_iter_mut())
            .zip(self.damage.par_iter_mut())
            .enumerate()
            .with_min_len(256)
            .map(|(i, ((row, force), damage))| {
                let constants = &bodies[body[i] as usize];
                let (c, critical) = (constants.micromodulus, constants.critical_strain);
                let (law, alpha) = (constants.law, constants.expansion);
                let yi = y[i];
                let mut f = [0.0; 3];
                let (mut broke, mut intact) = (0, 0);
                for (k, nb) in (offsets[i]..).zip(row.iter_mut()) {
                    if *nb & BROKEN != 0 {
                        continue;
                    }
                    let j = (*nb & INDEX) as usize;
                    let r = [y[j][0] - yi[0], y[j][1] - yi[1], y[j][2] - yi[2]];
                    let length = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
                    // The strain over the expanded rest length |ξ|(1 + αθ̄) (see [`law`]).
                    let expanded = 1.0 + alpha * 0.5 * (theta[i] + theta[j]);
                    let eta = length / (rest[k] * expanded) - 1.0;
                    if eta > critical {
                        *nb |= BROKEN;
                        broke += 1;
                        continue;
                    }
                    intact += 1;
                    if length > 0.0 {
                        let s = c * law.force(eta) * weight[k] * volume[j] / length;
                        for a in 0..3 {
                            f[a] += s * r[a];
                        }
                    }
                }
                *force = f;
                *damage = if initial[i] == 0 {
                    0.0
                } else {
                    1.0 - intact as f64 / initial[i] as f64
                };
                broke
            })
            .sum();
        self.times.forces += t.elapsed().as_secs_f64();
        broken
    }

    /// The rate θ̇_i of Eq. 25 over intact bonds (Eq. 28), for every particle.
    pub fn quantity_rate(&self) -> Vec<f64> {
        let (theta, area, body, bodies) = (&self.quantity, &self.area, &self.body, &self.bodies);
        let bonds = &self.bonds;
        (0..self.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let b = &bodies[body[i] as usize];
                if b.conductivity == 0.0 {
                    return 0.0;
                }
                let mut sum = 0.0;
                for k in bonds.range(i) {
                    let nb = bonds.neighbours[k];
                    if nb & BROKEN != 0 {
                        continue;
                    }
                    let j = (nb & INDEX) as usize;
                    let xi2 = bonds.rest_length[k] * bonds.rest_length[k];
                    sum += (theta[j] - theta[i]) / xi2 * self.weight[k] * area[j];
                }
                b.conductivity * sum / (b.density * b.capacity * area[i])
            })
            .collect()
    }

    /// One forward Euler step of the diffusion (Eq. 26, first line, with γ* of
    /// Eq. 28): θ_i ← θ_i + Δt θ̇_i, then the sources active at the step's start
    /// ([`source`]): a rate adds Δt × rate, a value holds θ (sources in scene order, so
    /// a later value wins).
    pub fn diffuse(&mut self, dt: f64) {
        let conducts = self.bodies.iter().any(|b| b.conductivity != 0.0);
        if !conducts && self.sources.is_empty() {
            return;
        }
        let t = Instant::now();
        if conducts {
            let rate = self.quantity_rate();
            self.quantity
                .par_iter_mut()
                .zip(rate.par_iter())
                .with_min_len(1024)
                .for_each(|(theta, r)| *theta += dt * r);
        }
        for source in self.sources.iter().filter(|s| s.active(self.elapsed)) {
            for &i in &source.particles {
                let theta = &mut self.quantity[i as usize];
                match source.effect {
                    Effect::Rate(rate) => *theta += dt * rate,
                    Effect::Value(value) => *theta = value,
                }
            }
        }
        self.elapsed += dt;
        self.times.diffusion += t.elapsed().as_secs_f64();
    }

    /// The total quantity Σ_i ρ C A_i θ_i, which Eq. 25 conserves without sources.
    pub fn total_quantity(&self) -> f64 {
        det_sum(self.len(), |i| {
            let b = &self.bodies[self.body[i] as usize];
            b.density * b.capacity * self.area[i] * self.quantity[i]
        })
    }

    /// The largest stable step and the particle that limits it: the smaller of
    /// velocity Verlet's bound for the bond springs, Silling and Askari's
    /// Δt_i = √(2ρ / Σ_j c W_ij V_j/|ξ_ij|), and forward Euler's bound for the
    /// diffusion of Eq. 25, Δt_i = ρ C A_i / Σ_j k W_ij A_j/|ξ_ij|² (by Gershgorin
    /// the largest rate is at most twice that sum, and Euler is stable below 2 over
    /// the largest rate).
    pub fn stable_time_step(&self) -> (f64, usize) {
        let bonds = &self.bonds;
        let steps: Vec<f64> = (0..self.len())
            .into_par_iter()
            .map(|i| {
                let b = &self.bodies[self.body[i] as usize];
                let (mut springs, mut diffusion) = (0.0, 0.0);
                for k in bonds.range(i) {
                    let j = (bonds.neighbours[k] & INDEX) as usize;
                    let (xi, w) = (bonds.rest_length[k], self.weight[k]);
                    springs += b.law.stiffness() * b.micromodulus * w * self.volume[j] / xi;
                    diffusion += b.conductivity * w * self.area[j] / (xi * xi);
                }
                let mechanical = if springs > 0.0 {
                    (2.0 * b.density / springs).sqrt()
                } else {
                    f64::INFINITY
                };
                let diffusive = if diffusion > 0.0 {
                    b.density * b.capacity * self.area[i] / diffusion
                } else {
                    f64::INFINITY
                };
                mechanical.min(diffusive)
            })
            .collect();
        steps
            .iter()
            .copied()
            .enumerate()
            .fold(
                (f64::INFINITY, 0),
                |best, (i, dt)| {
                    if dt < best.0 { (dt, i) } else { best }
                },
            )
    }

    /// Kinetic energy ½ Σ m v² (J), summed in a fixed order.
    pub fn kinetic_energy(&self) -> f64 {
        det_sum(self.len(), |i| {
            let v = self.velocity[i];
            0.5 * self.mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        })
    }

    /// Strain energy ½ Σ_i V_i Σ_j ½ c η_ij² |ξ_ij| W_ij V_j (J) over intact bonds:
    /// Silling's micropotential, of which Eq. 18 is the derivative (the linear law's
    /// energy at the bond's mechanical strain; a measure for the other laws).
    pub fn strain_energy(&self) -> f64 {
        let (y, bonds) = (&self.position, &self.bonds);
        det_sum(self.len(), |i| {
            let c = self.bodies[self.body[i] as usize].micromodulus;
            let mut e = 0.0;
            for k in bonds.range(i) {
                let nb = bonds.neighbours[k];
                if nb & BROKEN != 0 {
                    continue;
                }
                let j = (nb & INDEX) as usize;
                let r = [y[j][0] - y[i][0], y[j][1] - y[i][1], y[j][2] - y[i][2]];
                let xi = bonds.rest_length[k];
                let b = &self.bodies[self.body[i] as usize];
                let expanded = 1.0 + b.expansion * 0.5 * (self.quantity[i] + self.quantity[j]);
                let eta = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt() / (xi * expanded) - 1.0;
                e += 0.5 * c * eta * eta * xi * self.weight[k] * self.volume[j];
            }
            0.5 * self.volume[i] * e
        })
    }

    /// Connected components of intact bonds, numbered by their smallest particle
    /// index in increasing order (deterministic).
    pub fn fragments(&self) -> Vec<u32> {
        self.bonds.fragments()
    }

    /// φ_i = 1 − intact/initial bonds, from the broken bits.
    pub fn update_damage(&mut self) {
        let (bonds, initial) = (&self.bonds, &self.initial_bonds);
        self.damage.par_iter_mut().enumerate().for_each(|(i, phi)| {
            let intact = bonds.neighbours[bonds.range(i)]
                .iter()
                .filter(|&&nb| nb & BROKEN == 0)
                .count();
            *phi = if initial[i] == 0 {
                0.0
            } else {
                1.0 - intact as f64 / initial[i] as f64
            };
        });
    }
}
