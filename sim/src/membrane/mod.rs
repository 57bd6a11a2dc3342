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
//! Sources and sinks (Eq. 8's S) are in [`source`].
//!
//! # The state-based option
//!
//! Han §7 names the bond-based limit (ν = 1/3 in plane stress) and the area loss it
//! causes under large stretch (their Fig. 13) as open problems. `membrane_model =
//! "state"` replaces the micro-springs with an ordinary state-based sheet in plane
//! stress (in the spirit of Chen's solid model and of Le, Silling and Bobaru's 2D
//! ordinary state-based model), on the same bonds and weights W_ij:
//!
//! ```text
//! m_i   = Σ_j W_ij |ξ_ij|² A_j                     weighted area moment (reference)
//! e_ij  = |y_j − y_i| − |ξ_ij|(1 + αθ̄)            extension over the expanded length
//! ϑ_i   = (2/m_i) Σ_j W_ij |ξ_ij| e_ij A_j          dilatation (2ε under ε·I)
//! W_i   = κ'ϑ_i²/2 + (α_i/2) Σ_j W_ij (e_ij − ϑ_i|ξ_ij|/2)² A_j,   α_i = 8μ/m_i
//! t_ij  = ∂W_i/∂e_ij = (2κ'ϑ_i/m_i) W_ij |ξ_ij| + α_i W_ij (e_ij − ϑ_i|ξ_ij|/2)
//! ρ a_i = Σ_j (t_ij + t_ji) A_j (y_j − y_i)/|y_j − y_i|
//! ```
//!
//! with the plane-stress moduli κ' = E/(2(1 − ν)) and μ = E/(2(1 + ν)): W_i equals
//! the continuum's κ'(tr ε)²/2 + μ ε_dev : ε_dev for every homogeneous strain (the
//! deviatoric sum is zero-mean over an isotropic family, which also drops ϑ's
//! derivative from t). The material's Poisson ratio is then the sheet's; fracture is
//! the same critical strain η_c on each bond. Linear law only.

mod diffusion;
mod forces;
pub mod law;
#[cfg(test)]
mod mesh_tests;
mod share;
pub mod sheet;
mod solver;
pub mod source;
#[cfg(test)]
mod tests;
mod triangles;

use perifrac_math::{det_sum, dist};
use rayon::prelude::*;

pub use law::Law;
pub use solver::Membrane;
pub use source::{Effect, Source};

use crate::error::{Result, SimError};
use crate::family::Cracks;
use crate::family::{self, BROKEN, Bonds, INDEX};
use crate::geometry::discretize::Discretization;
use crate::material::Material;
use crate::ranks::Share;
use crate::scene::{MembraneFormulation, MembraneMaterialSpec, ModelKind, Scene};

/// Particles per parallel task of the passes over the bonds.
const BLOCK: usize = 256;

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
    /// The state-based formulation's plane-stress moduli, or none for Han's bond-based
    /// micro-springs.
    pub state: Option<PlaneStress>,
}

/// The moduli of an ordinary state-based sheet in plane stress ([`state`](self#the-state-based-option)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneStress {
    /// The 2D bulk modulus κ' = E/(2(1 − ν)) (Pa).
    pub bulk: f64,
    /// The shear modulus μ = E/(2(1 + ν)) (Pa).
    pub shear: f64,
}

impl SheetBody {
    /// The constants of a sheet of `material` (with its membrane properties `spec`),
    /// `thickness` thick, with cutoff radius `cutoff` (m), in the formulation
    /// `formulation`.
    pub fn new(
        material: &Material,
        spec: &MembraneMaterialSpec,
        thickness: f64,
        cutoff: f64,
        formulation: MembraneFormulation,
    ) -> SheetBody {
        let (e, nu) = (material.youngs_modulus(), material.poisson_ratio());
        let state = (formulation == MembraneFormulation::State).then(|| PlaneStress {
            bulk: e / (2.0 * (1.0 - nu)),
            shear: e / (2.0 * (1.0 + nu)),
        });
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
            state,
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
    /// Sending this rank's part of the pass over the bonds and taking in the others'
    /// ([`MembraneModel::share`]), waiting for the slowest rank included.
    pub exchange: f64,
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
    /// Reference bond length |ξ_ij| per directed bond.
    pub rest_length: Vec<f64>,
    /// W_ij = 1 − |ξ|/R per directed bond (Eq. 23).
    pub weight: Vec<f64>,
    /// 1/|ξ_ij| per directed bond: the strain and the diffusion's 1/|ξ|² without a
    /// division in the pass over the bonds.
    inverse_rest: Vec<f64>,
    /// The diffused quantity θ_i (Eq. 25).
    pub quantity: Vec<f64>,
    /// Weighted volume m_i = Σ_j W_ij |ξ_ij|² A_j (m⁴) over each particle's bonds
    /// before any crack, for the state-based option; empty when no body uses it.
    pub weighted_volume: Vec<f64>,
    /// Dilatation ϑ_i of the state-based option from the last forces; empty when no
    /// body uses it.
    pub dilatation: Vec<f64>,
    /// Sources and sinks of θ (Eq. 8's S; [`source`]).
    pub sources: Vec<Source>,
    /// Time the diffusion has been stepped (s), for the sources' start and stop.
    pub elapsed: f64,
    /// Damage φ_i = 1 − intact/initial bonds.
    pub damage: Vec<f64>,
    /// Bonds of each particle before the run.
    initial_bonds: Vec<u32>,
    /// The triangles of the sheets given by a mesh (their remeshed triangles); empty
    /// when every sheet is a lattice.
    pub mesh_triangles: Vec<[u32; 3]>,
    /// Force density ρ a_i without gravity (N/m³), from the last forces.
    pub force: Vec<[f64; 3]>,
    /// The rate θ̇_i of Eq. 25 over the bonds intact after the last forces, found in
    /// the same pass over the bonds for the diffusion step that follows; empty when
    /// no body conducts.
    rate: Vec<f64>,
    /// Stage timers.
    pub times: StageTimes,
    /// The ranks the pass over the bonds is split over ([`share`]); `None` in one
    /// process.
    share: Option<Share>,
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
        let (bonds, family::Weights { rest_length, .. }) =
            family::build(&reference, &volume, &body, &cutoff, false)?;
        let weight = (0..n)
            .flat_map(|i| bonds.range(i).map(move |k| (i, k)))
            .map(|(i, k)| (1.0 - rest_length[k] / cutoff[i]).max(0.0))
            .collect();
        let inverse_rest = rest_length.iter().map(|&xi| 1.0 / xi).collect();
        let initial_bonds = (0..n).map(|i| bonds.range(i).len() as u32).collect();
        let weighted_volume: Vec<f64> = if bodies.iter().any(|b| b.state.is_some()) {
            (0..n)
                .map(|i| {
                    bonds
                        .range(i)
                        .map(|k| {
                            let j = (bonds.neighbours[k] & INDEX) as usize;
                            let xi = rest_length[k];
                            (1.0 - xi / cutoff[i]).max(0.0) * xi * xi * area[j]
                        })
                        .sum()
                })
                .collect()
        } else {
            Vec::new()
        };
        let dilatation = vec![0.0; weighted_volume.len()];
        let conducts = bodies.iter().any(|b| b.conductivity != 0.0);
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
            rest_length,
            weight,
            inverse_rest,
            quantity: vec![0.0; n],
            weighted_volume,
            dilatation,
            sources: Vec::new(),
            elapsed: 0.0,
            damage: vec![0.0; n],
            initial_bonds,
            mesh_triangles: Vec::new(),
            force: vec![[0.0; 3]; n],
            rate: if conducts { vec![0.0; n] } else { Vec::new() },
            times: StageTimes::default(),
            share: None,
        })
    }

    /// The membrane bodies of a scene, on the sheet particles of its discretization
    /// ([`sheet::sample`]; a mesh sheet's triangles with them), with the scene's
    /// initial cracks (slits, notches) cut.
    pub fn from_scene(scene: &Scene, disc: &Discretization) -> Result<MembraneModel> {
        let mut bodies = Vec::with_capacity(scene.bodies.len());
        for b in &scene.bodies {
            if b.model != ModelKind::Membrane {
                return Err(SimError::Refused(format!(
                    "body '{}' is not a membrane: a membrane scene runs membranes only",
                    b.name
                )));
            }
            let thickness = sheet::thickness(b).map_err(|message| SimError::Mesh {
                body: b.name.clone(),
                message,
            })?;
            let spec = &scene.materials[&b.material];
            let membrane = b.membrane.clone().unwrap_or_default();
            bodies.push(SheetBody::new(
                &Material::from_spec(spec),
                &spec.membrane.clone().unwrap_or_default(),
                thickness,
                membrane.cutoff * b.resolution,
                membrane.membrane_model,
            ));
        }
        let area = (0..disc.position.len())
            .map(|i| disc.volume[i] / bodies[disc.body[i] as usize].thickness)
            .collect();
        let mut model = MembraneModel::new(disc.position.clone(), area, disc.body.clone(), bodies)?;
        model.mesh_triangles = disc.sheet_triangles.clone();
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

    /// The largest stable step and the particle that limits it: the smaller of
    /// velocity Verlet's bound for the bond springs, Silling and Askari's
    /// Δt_i = √(2ρ / Σ_j c W_ij V_j/|ξ_ij|) (for the state-based option the sum of
    /// |∂f_i/∂e_ij| over the bonds, each bond's force state depending on every
    /// extension of i's family through ϑ_i), and forward Euler's bound for the
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
                // The state-based option: Σ_k W_ik |ξ_ik| A_k, the reach of one bond's
                // extension through the dilatation into every force state of i.
                let reach: f64 = match b.state {
                    None => 0.0,
                    Some(_) => bonds
                        .range(i)
                        .map(|k| {
                            let j = (bonds.neighbours[k] & INDEX) as usize;
                            self.weight[k] * self.rest_length[k] * self.area[j]
                        })
                        .sum(),
                };
                for k in bonds.range(i) {
                    let j = (bonds.neighbours[k] & INDEX) as usize;
                    let (xi, w) = (self.rest_length[k], self.weight[k]);
                    springs += match b.state {
                        None => b.law.stiffness() * b.micromodulus * w * self.volume[j] / xi,
                        Some(plane) => {
                            let m = self.weighted_volume[i];
                            2.0 * (8.0 * plane.shear / m + 4.0 * plane.bulk * xi * reach / (m * m))
                                * w
                                * self.area[j]
                        }
                    };
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

    /// Strain energy (J) over intact bonds: ½ Σ_i V_i Σ_j ½ c η_ij² |ξ_ij| W_ij V_j,
    /// Silling's micropotential, of which Eq. 18 is the derivative (the linear law's
    /// energy at the bond's mechanical strain; a measure for the other laws); for the
    /// state-based option Σ_i V_i (κ'ϑ_i²/2 + (α_i/2) Σ_j W_ij (e^d_ij)² A_j).
    pub fn strain_energy(&self) -> f64 {
        let (y, bonds) = (&self.position, &self.bonds);
        det_sum(self.len(), |i| {
            let b = &self.bodies[self.body[i] as usize];
            // (W_ij, |ξ_ij|, the expansion 1 + αθ̄, |y_j − y_i|, j) over the intact bonds.
            let intact = bonds.range(i).filter_map(|k| {
                let nb = bonds.neighbours[k];
                if nb & BROKEN != 0 {
                    return None;
                }
                let j = (nb & INDEX) as usize;
                let xi = self.rest_length[k];
                let expanded = 1.0 + b.expansion * 0.5 * (self.quantity[i] + self.quantity[j]);
                Some((self.weight[k], xi, expanded, dist(y[i], y[j]), j))
            });
            match b.state {
                None => {
                    let e: f64 = intact
                        .map(|(w, xi, expanded, length, j)| {
                            let eta = length / (xi * expanded) - 1.0;
                            0.5 * b.micromodulus * eta * eta * xi * w * self.volume[j]
                        })
                        .sum();
                    0.5 * self.volume[i] * e
                }
                Some(plane) => {
                    let m = self.weighted_volume[i];
                    if m == 0.0 {
                        return 0.0;
                    }
                    let bonds: Vec<_> = intact
                        .map(|(w, xi, expanded, length, j)| (w, xi, length - xi * expanded, j))
                        .collect();
                    let dilatation = 2.0 / m
                        * bonds
                            .iter()
                            .map(|&(w, xi, e, j)| w * xi * e * self.area[j])
                            .sum::<f64>();
                    let deviatoric: f64 = bonds
                        .iter()
                        .map(|&(w, xi, e, j)| {
                            w * (e - 0.5 * dilatation * xi).powi(2) * self.area[j]
                        })
                        .sum();
                    self.volume[i]
                        * (0.5 * plane.bulk * dilatation * dilatation
                            + 0.5 * 8.0 * plane.shear / m * deviatoric)
                }
            }
        })
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
