//! The MPM model behind [`Model`]: its points, its own sub-step, the stable step, its
//! energies, cache columns, checkpoints and stage timings.

use super::constitutive::{self, Mat3};
use super::grid::Boundary;
use super::patches::{self, Patches};
use super::{CFL, ELASTIC_COURANT, Mpm, StageTimes};
use crate::cache::checkpoint::{Decoder, Encoder};
use crate::cache::ply::VOLUME;
use crate::error::Result;
use crate::model::{Environment, Model, ParticleColumns, Points, PointsMut, Stepping};

/// The matrices' entries, row by row (a checkpoint's column).
fn flatten(m: &[Mat3]) -> Vec<f64> {
    m.iter().flat_map(|r| r.iter().flatten().copied()).collect()
}

/// [`flatten`]'s entries back into `out`.
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
        self.hold(environment.anchors, environment.time);
        self.step(dt, &boundary)
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
                (ELASTIC_COURANT * dx / m.wave_speed(), i)
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

    /// Σ_p V_p⁰ ψ(F_p) of the elastic part; a shock material counts its stable
    /// Neo-Hookean energy plus the work it took in, J_p V_p⁰ (e_p − e⁰).
    fn strain_energy(&self) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .map(|i| {
                let material = &self.materials[p.body[i] as usize];
                let f = &p.deformation[i];
                let taken = match material.eos {
                    Some(_) => constitutive::determinant(f) * p.internal_energy[i],
                    None => 0.0,
                };
                p.volume[i] * (material.elastic.energy_density(f) + taken)
            })
            .sum()
    }

    fn particles(&self) -> ParticleColumns {
        let p = &self.particles;
        let f32x3 = |v: &[f64; 3]| v.map(|x| x as f32);
        // The search behind the fragments was built when the first particle joined.
        let fragment = self
            .patches
            .as_ref()
            .and_then(|patches| patches.fragments(p).ok())
            .unwrap_or_else(|| p.body.clone());
        ParticleColumns {
            position: p.position.iter().map(f32x3).collect(),
            velocity: p.velocity.iter().map(f32x3).collect(),
            damage: self
                .patches
                .as_ref()
                .map_or_else(|| vec![0.0; p.len()], Patches::damage),
            plastic: p.plastic.iter().map(|&e| e as f32).collect(),
            body: p.body.clone(),
            fragment,
            extra: vec![
                // The current volume V_p = J_p V_p⁰.
                (
                    VOLUME.to_string(),
                    (0..p.len())
                        .map(|i| {
                            (constitutive::determinant(&p.deformation[i]) * p.volume[i]) as f32
                        })
                        .collect(),
                ),
                (
                    "J".to_string(),
                    p.deformation
                        .iter()
                        .map(|f| constitutive::determinant(f) as f32)
                        .collect(),
                ),
                (
                    "constitutive".to_string(),
                    p.body
                        .iter()
                        .map(|&b| self.materials[b as usize].id() as f32)
                        .collect(),
                ),
            ]
            .into_iter()
            .chain((!p.temperature.is_empty()).then(|| {
                (
                    "temperature".to_string(),
                    p.temperature.iter().map(|&t| t as f32).collect(),
                )
            }))
            .chain(self.patches.as_ref().map(|patches| {
                // SPB-MPM's region: 0 a material point, 1 a peridynamic particle.
                (
                    "region".to_string(),
                    (0..p.len())
                        .map(|i| f32::from(u8::from(patches.is_member(i))))
                        .collect(),
                )
            }))
            .collect(),
        }
    }

    fn save(&self, out: &mut Encoder) {
        let p = &self.particles;
        out.put_f64x3_slice(&p.position);
        out.put_f64x3_slice(&p.velocity);
        out.put_f64_slice(&flatten(&p.deformation));
        out.put_f64_slice(&flatten(&p.affine));
        out.put_f64_slice(&p.plastic);
        out.put_f64_slice(&p.internal_energy);
        out.put_f64_slice(&p.temperature);
        if let Some(patches) = &self.patches {
            patches.save(out);
        }
    }

    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let p = &mut self.particles;
        let n = p.len();
        p.position = input.take_finite_f64x3_slice("MPM positions", n)?;
        p.velocity = input.take_finite_f64x3_slice("MPM velocities", n)?;
        let f = input.take_finite_f64_slice("MPM deformation gradients", 9 * n)?;
        unflatten(&f, &mut p.deformation);
        let c = input.take_finite_f64_slice("MPM affine matrices", 9 * n)?;
        unflatten(&c, &mut p.affine);
        p.plastic = input.take_finite_f64_slice("MPM plastic strains", n)?;
        if let Some(i) = p.plastic.iter().position(|&e| e < 0.0) {
            let message = format!("particle {i} has a negative plastic strain");
            return Err(input.error("MPM plastic strains", message).into());
        }
        let energies = p.internal_energy.len();
        p.internal_energy = input.take_finite_f64_slice("MPM internal energies", energies)?;
        let temperatures = p.temperature.len();
        p.temperature = input.take_finite_f64_slice("MPM temperatures", temperatures)?;
        if let Some(i) = p.temperature.iter().position(|&t| t <= 0.0) {
            let message = format!("particle {i} has a temperature at or below 0 K");
            return Err(input.error("MPM temperatures", message).into());
        }
        if let Some(patches) = &mut self.patches {
            patches.restore(input, &self.particles)?;
        }
        Ok(())
    }

    /// SPB-MPM's bonds (both directions), built as particles turn peridynamic.
    fn bonds(&self) -> usize {
        self.patches.as_ref().map_or(0, Patches::bonds)
    }

    fn broken_bonds(&self) -> u64 {
        self.patches
            .as_ref()
            .map_or(0, |patches| patches.broken_bonds() as u64)
    }

    fn stage_times(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("mpm sort", self.times.sort),
            ("stress", self.times.stress),
            ("p2g", self.times.p2g),
            ("grid", self.times.grid),
            ("g2p", self.times.g2p),
            ("plasticity", self.times.plasticity),
        ]
        .into_iter()
        .chain(self.patches.iter().flat_map(|patches| {
            [
                ("spb erosion", patches.times.erode),
                ("spb bonds", patches.times.evolve),
            ]
        }))
        .collect()
    }

    fn reset_stage_times(&mut self) {
        self.times = StageTimes::default();
        if let Some(patches) = &mut self.patches {
            patches.times = patches::PatchTimes::default();
        }
    }
}
