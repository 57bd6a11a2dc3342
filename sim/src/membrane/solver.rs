//! The membrane model behind [`Model`]: Han et al.'s sheet particles stepped by the
//! world's velocity Verlet, the diffusion of Eq. 25 stepped by forward Euler after
//! each step, checkpoints of the saved state (positions, velocities, broken bonds, θ),
//! and θ as the particle cache's `quantity` column.
//!
//! Integrator: Han's Eq. 26 updates the velocity and then the position with the new
//! velocity, which is symplectic Euler; its positions are those of velocity Verlet
//! (Störmer), and both are stable for ω Δt < 2 on every bond-spring mode, so the
//! world's velocity Verlet is as stable as the paper's scheme (at second order) with
//! the same bound ([`MembraneModel::stable_time_step`]).

use std::sync::{Arc, OnceLock};

use rayon::prelude::*;

use super::MembraneModel;
use crate::cache::checkpoint::{Decoder, Encoder};
use crate::cache::ply::VOLUME;
use crate::cache::sheet::SheetFrame;
use crate::error::Result;
use crate::model::{Model, ParticleColumns, Points, PointsMut};
use crate::ranks::Ranks;

/// A [`MembraneModel`] behind the model interface.
#[derive(Debug, Clone)]
pub struct Membrane {
    /// The model.
    pub model: MembraneModel,
    /// The sheets' triangles, found the first time a sheet is written.
    triangles: OnceLock<Vec<[u32; 3]>>,
}

impl Membrane {
    /// The model behind the interface.
    pub fn new(model: MembraneModel) -> Membrane {
        Membrane {
            model,
            triangles: OnceLock::new(),
        }
    }
}

fn f32x3(v: &[f64; 3]) -> [f32; 3] {
    [v[0] as f32, v[1] as f32, v[2] as f32]
}

impl Model for Membrane {
    fn name(&self) -> &'static str {
        "membrane"
    }

    fn points(&self) -> Points<'_> {
        let m = &self.model;
        Points {
            position: &m.position,
            velocity: &m.velocity,
            reference: &m.reference,
            mass: &m.mass,
        }
    }

    fn points_mut(&mut self) -> PointsMut<'_> {
        let m = &mut self.model;
        PointsMut {
            position: &mut m.position,
            velocity: &mut m.velocity,
            reference: &m.reference,
            mass: &m.mass,
        }
    }

    fn point_bodies(&self) -> &[u32] {
        &self.model.body
    }

    fn internal_forces(&mut self) -> usize {
        self.model.internal_forces()
    }

    /// a_i = f_i/ρ + g, the force density over the density (Eq. 22 over V_i).
    fn accelerations(&self, gravity: [f64; 3], out: &mut [[f64; 3]]) {
        let m = &self.model;
        out.par_iter_mut()
            .enumerate()
            .with_min_len(8192)
            .for_each(|(i, a)| {
                let rho = m.bodies[m.body[i] as usize].density;
                let f = m.force[i];
                *a = [
                    f[0] / rho + gravity[0],
                    f[1] / rho + gravity[1],
                    f[2] / rho + gravity[2],
                ];
            });
    }

    /// The end of a step, the one stage the world gives Δt: the diffusion step of
    /// Eq. 26 with the rates this step's forces found (over the bonds intact after
    /// its fracture, Eq. 28), then air
    /// damping v ← (1 − rate·Δt) v of the points not anchored.
    fn damp(&mut self, dt: f64, anchored: &[bool]) {
        self.model.step_quantity(dt);
        let m = &mut self.model;
        if m.bodies.iter().all(|b| b.air_damping == 0.0) {
            return;
        }
        let (body, bodies) = (&m.body, &m.bodies);
        m.velocity
            .par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, v)| {
                if !anchored[i] {
                    let keep = 1.0 - (bodies[body[i] as usize].air_damping * dt).min(1.0);
                    *v = [v[0] * keep, v[1] * keep, v[2] * keep];
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

    fn particles(&self) -> ParticleColumns {
        let m = &self.model;
        ParticleColumns {
            position: m.position.iter().map(f32x3).collect(),
            velocity: m.velocity.iter().map(f32x3).collect(),
            damage: m.damage.iter().map(|&d| d as f32).collect(),
            plastic: vec![0.0; m.len()],
            body: m.body.clone(),
            fragment: m.fragments(),
            extra: vec![
                // The particle volume V_i = A_i h.
                (VOLUME.into(), m.volume.iter().map(|&v| v as f32).collect()),
                (
                    "quantity".into(),
                    m.quantity.iter().map(|&q| q as f32).collect(),
                ),
            ],
        }
    }

    fn bonds(&self) -> usize {
        self.model.bonds.len()
    }

    /// The particles (with their body's thickness) and the sheet triangles (lattice or
    /// mesh) whose three bonds are intact.
    fn sheet_frame(&self) -> Option<SheetFrame> {
        let m = &self.model;
        let triangles = self.triangles.get_or_init(|| m.sheet_triangles());
        Some(SheetFrame {
            positions: m.position.iter().map(f32x3).collect(),
            thickness: m
                .body
                .iter()
                .map(|&b| m.bodies[b as usize].thickness as f32)
                .collect(),
            quantity: m.quantity.iter().map(|&q| q as f32).collect(),
            damage: m.damage.iter().map(|&d| d as f32).collect(),
            triangles: triangles
                .iter()
                .copied()
                .filter(|&t| m.triangle_intact(t))
                .collect(),
        })
    }

    /// Positions, velocities, the bonds' broken bits, θ and the diffusion's time;
    /// damage is derived from the bonds on restore.
    fn save(&self, out: &mut Encoder) {
        let m = &self.model;
        out.put_f64x3_slice(&m.position);
        out.put_f64x3_slice(&m.velocity);
        out.put_u32_slice(&m.bonds.neighbours);
        out.put_f64_slice(&m.quantity);
        out.put_f64_slice(&[m.elapsed]);
    }

    fn broken_bonds(&self) -> u64 {
        self.model.bonds.broken_count()
    }

    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let m = &mut self.model;
        let n = m.len();
        m.position = input.take_finite_f64x3_slice("positions", n)?;
        m.velocity = input.take_finite_f64x3_slice("velocities", n)?;
        // Only the broken bit may differ from the bonds this scene builds.
        let neighbours = input.take_u32_slice("bonds", m.bonds.len())?;
        m.bonds
            .check_restored(&neighbours)
            .map_err(|message| input.error("bonds", message))?;
        m.bonds.neighbours = neighbours;
        m.quantity = input.take_finite_f64_slice("diffused quantity", n)?;
        m.elapsed = input.take_finite_f64_slice("diffusion time", 1)?[0];
        m.update_damage();
        Ok(())
    }

    fn stage_times(&self) -> Vec<(&'static str, f64)> {
        let t = self.model.times;
        let mut times = vec![("forces", t.forces), ("diffusion", t.diffusion)];
        if self.model.share.is_some() {
            times.push(("exchange", t.exchange));
        }
        times
    }

    fn reset_stage_times(&mut self) {
        self.model.times = Default::default();
    }

    /// Splits the pass over the bonds (strains, fracture, forces, diffusion rates)
    /// over the ranks ([`MembraneModel::share`]); the rest of the step on every
    /// rank.
    fn share(&mut self, ranks: Arc<dyn Ranks>) {
        self.model.share(ranks);
    }
}
