//! The FEM reference behind [`Model`]: the same integrator, anchors, colliders,
//! gravity, air damping and blow-up check as the peridynamic model, on the mesh
//! vertices; the cache gets the tet barycentres in the peridynamic particle order.

use std::time::Instant;

use rayon::prelude::*;

use super::FemModel;
use crate::cache::checkpoint::{Decoder, Encoder};
use crate::cache::ply::VOLUME;
use crate::error::Result;
use crate::model::{ContactPoints, Model, ParticleColumns, Points, PointsMut};

/// A [`FemModel`] with the time spent in its force kernel.
#[derive(Debug, Clone)]
pub struct Fem {
    /// The model.
    pub model: FemModel,
    /// Seconds spent computing internal forces.
    force_time: f64,
    /// Each vertex's share of its body's volume, m/ρ (particle contact).
    vertex_volume: Vec<f64>,
}

impl Fem {
    /// The model.
    pub fn new(model: FemModel) -> Fem {
        let vertex_volume = (0..model.mass.len())
            .map(|i| model.mass[i] / model.bodies[model.vertex_body[i] as usize].material.density)
            .collect();
        Fem {
            model,
            force_time: 0.0,
            vertex_volume,
        }
    }
}

impl Model for Fem {
    fn name(&self) -> &'static str {
        "fem"
    }

    fn point_kind(&self) -> &'static str {
        "mesh vertex"
    }

    fn points(&self) -> Points<'_> {
        let m = &self.model;
        Points {
            position: &m.position,
            velocity: &m.velocity,
            reference: &m.rest,
            mass: &m.mass,
        }
    }

    fn points_mut(&mut self) -> PointsMut<'_> {
        let m = &mut self.model;
        PointsMut {
            position: &mut m.position,
            velocity: &mut m.velocity,
            reference: &m.rest,
            mass: &m.mass,
        }
    }

    fn point_bodies(&self) -> &[u32] {
        &self.model.vertex_body
    }

    fn internal_forces(&mut self) -> usize {
        let t = Instant::now();
        self.model.internal_forces();
        self.force_time += t.elapsed().as_secs_f64();
        0
    }

    /// a = f/m + g with the lumped vertex masses.
    fn accelerations(&self, gravity: [f64; 3], out: &mut [[f64; 3]]) {
        let m = &self.model;
        out.par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, a)| {
                let f = m.force[i];
                let inv = 1.0 / m.mass[i];
                *a = [
                    f[0] * inv + gravity[0],
                    f[1] * inv + gravity[1],
                    f[2] * inv + gravity[2],
                ];
            });
    }

    /// Air damping v ← (1 − λa) v with λa = rate·Δt.
    fn damp(&mut self, dt: f64, anchored: &[bool]) {
        let m = &mut self.model;
        if m.bodies.iter().all(|b| b.material.air_damping <= 0.0) {
            return;
        }
        let (bodies, vertex_body) = (&m.bodies, &m.vertex_body);
        m.velocity
            .par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, v)| {
                if anchored[i] {
                    return;
                }
                let rate = bodies[vertex_body[i] as usize].material.air_damping;
                let keep = 1.0 - (rate * dt).min(1.0);
                for x in v.iter_mut() {
                    *x *= keep;
                }
            });
    }

    fn stable_time_step(&self) -> (f64, usize) {
        self.model.stable_time_step()
    }

    fn kinetic_energy(&self) -> f64 {
        self.model.kinetic_energy()
    }

    fn strain_energy(&self) -> f64 {
        self.model.strain_energy()
    }

    fn particle_of_point(&self, point: usize) -> usize {
        self.model.particle_of_vertex(point)
    }

    /// Tet barycentres in the peridynamic particle order, damage and plastic strain
    /// 0, one fragment per body.
    fn particles(&self) -> ParticleColumns {
        let m = &self.model;
        let f32x3 = |v: &[f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32];
        let body: Vec<u32> = m
            .particle_tet
            .iter()
            .map(|&e| m.tet_body[e as usize])
            .collect();
        let mut label = vec![u32::MAX; m.bodies.len()];
        let mut next = 0u32;
        let fragment = body
            .iter()
            .map(|&b| {
                if label[b as usize] == u32::MAX {
                    label[b as usize] = next;
                    next += 1;
                }
                label[b as usize]
            })
            .collect();
        ParticleColumns {
            position: m.particle_positions().iter().map(f32x3).collect(),
            velocity: m.particle_velocities().iter().map(f32x3).collect(),
            damage: vec![0.0; body.len()],
            plastic: vec![0.0; body.len()],
            body,
            fragment,
            // A barycentre stands for its tet: the tet's rest volume.
            extra: vec![(
                VOLUME.into(),
                m.particle_tet
                    .iter()
                    .map(|&e| m.volume[e as usize] as f32)
                    .collect(),
            )],
        }
    }

    fn particle_positions(&self) -> Vec<[f64; 3]> {
        self.model.particle_positions()
    }

    /// Vertex positions and velocities, and the corotated tets' rotations (the warm
    /// start of the polar decomposition, which the next forces depend on).
    /// Vertices of different bodies touch; a body's own vertices never do (the
    /// reference FEM does not fracture).
    fn contact_points(&self) -> Option<ContactPoints<'_>> {
        Some(ContactPoints {
            volume: &self.vertex_volume,
            bonds: None,
            self_contact: false,
        })
    }

    fn save(&self, out: &mut Encoder) {
        let m = &self.model;
        out.put_f64x3_slice(&m.position);
        out.put_f64x3_slice(&m.velocity);
        let rotation: Vec<f64> = m.rotation.iter().flatten().copied().collect();
        out.put_f64_slice(&rotation);
    }

    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let m = &mut self.model;
        m.position = input.take_finite_f64x3_slice("positions", m.len())?;
        m.velocity = input.take_finite_f64x3_slice("velocities", m.len())?;
        let rotation = input.take_finite_f64_slice("rotations", 4 * m.rotation.len())?;
        // The warm starts are unit quaternions; anything else is not a rotation.
        if let Some(e) = rotation
            .chunks_exact(4)
            .position(|q| (q.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() > 1e-9)
        {
            let message = format!("tet {e}'s rotation is not a unit quaternion");
            return Err(input.error("rotations", message).into());
        }
        for (q, r) in m.rotation.iter_mut().zip(rotation.chunks_exact(4)) {
            q.copy_from_slice(r);
        }
        Ok(())
    }

    fn stage_times(&self) -> Vec<(&'static str, f64)> {
        vec![("dilatation", 0.0), ("forces", self.force_time)]
    }

    fn reset_stage_times(&mut self) {
        self.force_time = 0.0;
    }
}
