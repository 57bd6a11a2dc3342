//! Setting up the MPM model from a scene: particles seeded from each body's shape,
//! each body's material (elasticity, plasticity, the shock model, SPB-MPM's fracture,
//! the integral-based MPM's bonds)
//! from its scene keys, and the transfer and grid the scene asks for.

use super::constitutive::Elastic;
use super::patches::{Fracture, IntegralBonds, PatchBody, Patches};
use super::plasticity::{self, Plasticity};
use super::{Mpm, MpmMaterial, Transfer, seed};
use crate::error::{Result, SimError};
use crate::scene::{MpmPlasticity, MpmTransfer, Scene};

impl Mpm {
    /// The model of a scene whose bodies all use `model = "mpm"`: particles seeded
    /// from each body's shape with the scene's seed, each body's angular velocity in
    /// C (the velocities are the caller's).
    pub fn from_scene(scene: &Scene) -> Result<Mpm> {
        let mut particles = seed::seed(scene)?;
        let materials: Vec<MpmMaterial> = scene
            .bodies
            .iter()
            .map(|b| {
                let spec = &scene.materials[&b.material];
                let m = crate::material::Material::from_spec(spec);
                let mpm = spec.mpm.clone().unwrap_or_default();
                let elastic =
                    Elastic::from_young(mpm.elasticity, m.youngs_modulus(), m.poisson_ratio());
                MpmMaterial {
                    density: spec.density,
                    elastic,
                    eos: mpm.bulk_sound_speed.map(|c| plasticity::MieGruneisen {
                        density: spec.density,
                        sound_speed: c,
                        slope: mpm.shock_slope,
                        gamma: mpm.gruneisen,
                    }),
                    plasticity: match mpm.plasticity {
                        MpmPlasticity::None => Plasticity::None,
                        MpmPlasticity::JohnsonCook {
                            yield_stress,
                            hardening,
                            exponent,
                            rate_coefficient,
                            reference_rate,
                            melting_temperature,
                            room_temperature,
                            thermal_exponent,
                            specific_heat,
                            taylor_quinney,
                        } => Plasticity::JohnsonCook(plasticity::JohnsonCook {
                            a: yield_stress,
                            b: hardening,
                            n: exponent,
                            c: rate_coefficient,
                            reference_rate,
                            // The scene's checks make the four keys all or none.
                            thermal: match (
                                melting_temperature,
                                room_temperature,
                                thermal_exponent,
                                specific_heat,
                            ) {
                                (Some(melt), Some(room), Some(m), Some(c)) => {
                                    Some(plasticity::Thermal {
                                        melting_temperature: melt,
                                        room_temperature: room,
                                        exponent: m,
                                        specific_heat: c,
                                        taylor_quinney: taylor_quinney
                                            .unwrap_or(plasticity::TAYLOR_QUINNEY),
                                    })
                                }
                                _ => None,
                            },
                        }),
                        MpmPlasticity::Snow {
                            critical_compression,
                            critical_stretch,
                        } => Plasticity::Snow {
                            critical_compression,
                            critical_stretch,
                        },
                        MpmPlasticity::DruckerPrager { friction_angle } => {
                            Plasticity::drucker_prager(friction_angle)
                        }
                    },
                    volume_modulus: match mpm.bonds.and_then(|b| b.viscosity) {
                        Some(_) => elastic.bulk_modulus(),
                        None => 0.0,
                    },
                }
            })
            .collect();
        if materials.iter().any(|m| m.eos.is_some()) {
            particles.internal_energy = vec![0.0; particles.len()];
        }
        let room = |m: &MpmMaterial| match m.plasticity {
            Plasticity::JohnsonCook(plasticity::JohnsonCook {
                thermal: Some(t), ..
            }) => Some(t.room_temperature),
            _ => None,
        };
        if let Some(lowest) = materials.iter().filter_map(room).reduce(f64::min) {
            particles.temperature = particles
                .body
                .iter()
                .map(|&b| room(&materials[b as usize]).unwrap_or(lowest))
                .collect();
        }
        let dx = super::grid::spacing(scene);
        let reach = super::grid::reach(dx);
        if let Some(i) =
            (particles.reference.iter()).position(|x| x.iter().any(|c| c.abs() > reach))
        {
            let x = particles.reference[i];
            return Err(SimError::Mesh {
                body: scene.bodies[particles.body[i] as usize].name.clone(),
                message: format!(
                    "a particle at ({:.4e}, {:.4e}, {:.4e}) m lies beyond the MPM grid's \
                     reach of {reach:.3e} m from the origin along each axis at Δx = {dx} m; \
                     place the scene nearer the origin",
                    x[0], x[1], x[2]
                ),
            });
        }
        let mut model = Mpm::new(particles, materials, dx);
        let shapes = crate::geometry::shape::bond_shapes(scene)?;
        let bodies = scene
            .bodies
            .iter()
            .zip(shapes)
            .zip(&model.materials)
            .map(|((b, shape), material)| {
                let spec = scene.materials[&b.material].mpm.clone().unwrap_or_default();
                PatchBody {
                    fracture: spec.energy_release_rate.map(|g| Fracture {
                        release_rate: g,
                        erosion_rate: spec.erosion_release_rate.unwrap_or(g),
                        young: material.elastic.young(),
                    }),
                    bonds: spec.bonds.map(|bonds| IntegralBonds {
                        lambda: material.elastic.lambda,
                        mu: material.elastic.mu,
                        yield_stress: bonds.yield_stress,
                        critical_stretch: bonds.critical_stretch,
                        viscosity: bonds.viscosity,
                    }),
                    shape,
                    resolution: b.resolution,
                }
            })
            .collect();
        model.patches = Patches::new(bodies, model.particles.len(), dx);
        if let Some(patches) = &mut model.patches {
            patches.join_bonded(&model.particles)?;
        }
        let settings = scene.mpm.unwrap_or_default();
        model.transfer = match settings.transfer {
            MpmTransfer::Apic => Transfer::Apic,
            MpmTransfer::PicFlip => Transfer::PicFlip {
                flip_ratio: settings.flip_ratio,
            },
        };
        for (p, c) in model.particles.affine.iter_mut().enumerate() {
            let w = scene.bodies[model.particles.body[p] as usize].angular_velocity;
            *c = [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]];
        }
        Ok(model)
    }
}
