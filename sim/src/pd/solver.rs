//! The peridynamic model behind [`Model`]: Chen et al. 2018's particles stepped by the
//! world's integrator, with air and Laplacian damping (Chen §6), the stable step of
//! [`stable_time_step`], checkpoints of the saved state, and the split tet mesh
//! (Chen §5.2) when the scene writes one.

use std::sync::Arc;

use perifrac_math::IDENTITY3;
use rayon::prelude::*;

use super::{PdModel, stable_time_step};
use crate::cache::checkpoint::{Decoder, Encoder};
use crate::cache::ply::VOLUME;
use crate::cache::vtu::TetFrame;
use crate::embed::{EmbeddedMesh, NO_PARENT, deformation_gradients};
use crate::error::Result;
use crate::family::{BROKEN, INDEX};
use crate::model::{
    ContactPoints, Fragments, Model, ParticleColumns, PieceSurface, Points, PointsMut,
};
use crate::ranks::Ranks;

/// A [`PdModel`] with its particle masses and, when the scene writes `tets/` or hands
/// fragments to rigid bodies, its embedded tet mesh.
#[derive(Debug, Clone)]
pub struct Peridynamics {
    /// The model.
    pub model: PdModel,
    /// Particle masses ρV (kg).
    mass: Vec<f64>,
    /// The embedded tet mesh: split along the cracks when written (`writes_tets`),
    /// else only the faces of rigid pieces' colliders ([`Model::reference_surface`]).
    embedded: Option<EmbeddedMesh>,
    /// Whether the run writes the split mesh: then it is split at every frame and its
    /// crack faces are checkpointed.
    writes_tets: bool,
    /// How each frozen particle's rigid piece has turned from the reference
    /// configuration ([`Model::orient`]), the identity for the others; `None` until a
    /// piece is oriented. Set again before every frame, so never checkpointed.
    orientation: Option<Vec<[[f64; 3]; 3]>>,
}

impl Peridynamics {
    /// The model with the tet mesh `embedded` if given, writing it split along the
    /// cracks if `writes_tets`.
    pub fn new(model: PdModel, embedded: Option<EmbeddedMesh>, writes_tets: bool) -> Peridynamics {
        let mass = (0..model.len()).map(|i| model.mass(i)).collect();
        Peridynamics {
            model,
            mass,
            embedded,
            writes_tets,
            orientation: None,
        }
    }
}

fn f32x3(v: &[f64; 3]) -> [f32; 3] {
    [v[0] as f32, v[1] as f32, v[2] as f32]
}

impl Model for Peridynamics {
    fn name(&self) -> &'static str {
        "peridynamics"
    }

    fn points(&self) -> Points<'_> {
        let m = &self.model;
        Points {
            position: &m.particles.position,
            velocity: &m.particles.velocity,
            reference: &m.reference.position,
            mass: &self.mass,
        }
    }

    fn points_mut(&mut self) -> PointsMut<'_> {
        let m = &mut self.model;
        PointsMut {
            position: &mut m.particles.position,
            velocity: &mut m.particles.velocity,
            reference: &m.reference.position,
            mass: &self.mass,
        }
    }

    fn point_bodies(&self) -> &[u32] {
        &self.model.reference.body
    }

    fn internal_forces(&mut self) -> usize {
        self.model.internal_forces()
    }

    /// Dilatation, return mapping, forces and fracture over this rank's particles
    /// ([`crate::pd::share`]); the rest of the step on every rank.
    fn share(&mut self, ranks: Arc<dyn Ranks>) {
        self.model.share(ranks);
    }

    /// a_i = f_i/ρ_i + g: the force *density* over the density (Chen Eq. 1).
    fn accelerations(&self, gravity: [f64; 3], out: &mut [[f64; 3]]) {
        let m = &self.model;
        out.par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, a)| {
                let rho = m.bodies[m.reference.body[i] as usize].material.density;
                let f = m.force[i];
                *a = [
                    f[0] / rho + gravity[0],
                    f[1] / rho + gravity[1],
                    f[2] / rho + gravity[2],
                ];
            });
    }

    /// Air damping v ← (1 − λa) v and Laplacian smoothing v ← v + λl L(v) over
    /// intact bonds, L(v)_i = Σ_j V_j (v_j − v_i) / Σ_j V_j (Chen §6), with the
    /// per-step coefficients λ = rate·Δt.
    fn damp(&mut self, dt: f64, anchored: &[bool]) {
        let m = &self.model;
        let any_air = m.bodies.iter().any(|b| b.material.air_damping > 0.0);
        let any_laplace = m.bodies.iter().any(|b| b.material.laplacian_damping > 0.0);
        if !any_air && !any_laplace {
            return;
        }
        let old = &m.particles.velocity;
        let bonds = &m.bonds;
        let volume = &m.reference.volume;
        let new: Vec<[f64; 3]> = (0..m.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let mat = &m.bodies[m.reference.body[i] as usize].material;
                let mut v = old[i];
                if anchored[i] {
                    return v;
                }
                let lambda_l = (mat.laplacian_damping * dt).min(1.0);
                if lambda_l > 0.0 {
                    let mut sum = [0.0; 3];
                    let mut w = 0.0;
                    for k in bonds.range(i) {
                        let nb = bonds.neighbours[k];
                        if nb & BROKEN != 0 {
                            continue;
                        }
                        let j = (nb & INDEX) as usize;
                        for a in 0..3 {
                            sum[a] += volume[j] * (old[j][a] - old[i][a]);
                        }
                        w += volume[j];
                    }
                    if w > 0.0 {
                        for a in 0..3 {
                            v[a] += lambda_l * sum[a] / w;
                        }
                    }
                }
                let keep = 1.0 - (mat.air_damping * dt).min(1.0);
                [v[0] * keep, v[1] * keep, v[2] * keep]
            })
            .collect();
        self.model.particles.velocity = new;
    }

    fn stable_time_step(&self) -> (f64, usize) {
        stable_time_step(&self.model)
    }

    fn kinetic_energy(&self) -> f64 {
        self.model.kinetic_energy()
    }

    fn strain_energy(&self) -> f64 {
        self.model.strain_energy()
    }

    fn particles(&self) -> ParticleColumns {
        let m = &self.model;
        let p = &m.particles;
        ParticleColumns {
            position: p.position.iter().map(f32x3).collect(),
            velocity: p.velocity.iter().map(f32x3).collect(),
            damage: p.damage.iter().map(|&d| d as f32).collect(),
            plastic: m.plastic_strain().into_iter().map(|s| s as f32).collect(),
            body: m.reference.body.clone(),
            fragment: m.fragments(),
            extra: vec![(
                VOLUME.into(),
                m.reference.volume.iter().map(|&v| v as f32).collect(),
            )],
        }
    }

    fn bonds(&self) -> usize {
        self.model.bonds.len()
    }

    /// Only a body that can break hands its fragments over.
    fn fragments(&self) -> Option<Fragments> {
        let m = &self.model;
        m.features.fracture.then(|| Fragments {
            fragment: m.fragments(),
            breaking: m.breaking_ratios(),
            damaged: m.particles.damage.iter().map(|&d| d > 0.0).collect(),
            wave_speed: m.bodies.iter().map(|b| b.material.p_wave_speed()).collect(),
            hit_speed: m
                .bodies
                .iter()
                .map(|b| b.constants.critical_stretch * b.material.p_wave_speed())
                .collect(),
        })
    }

    fn freeze(&mut self, points: &[u32]) {
        let n = self.model.len();
        let frozen = self.model.frozen.get_or_insert_with(|| vec![false; n]);
        for &i in points {
            frozen[i as usize] = true;
        }
    }

    fn thaw(&mut self, points: &[u32]) {
        if let Some(frozen) = &mut self.model.frozen {
            for &i in points {
                frozen[i as usize] = false;
            }
        }
        if let Some(orientation) = &mut self.orientation {
            for &i in points {
                orientation[i as usize] = IDENTITY3;
            }
        }
    }

    fn orient(&mut self, points: &[u32], rotation: [[f64; 3]; 3]) {
        if self.embedded.is_none() || !self.writes_tets {
            return;
        }
        let n = self.model.len();
        let orientation = self.orientation.get_or_insert_with(|| vec![IDENTITY3; n]);
        for &i in points {
            orientation[i as usize] = rotation;
        }
    }

    fn frozen(&self) -> Option<&[bool]> {
        self.model.frozen.as_deref()
    }

    /// Particles touch across bodies and, where no intact bond joins them, within one.
    fn contact_points(&self) -> Option<ContactPoints<'_>> {
        Some(ContactPoints {
            volume: &self.model.reference.volume,
            bonds: Some(&self.model.bonds),
            self_contact: true,
        })
    }

    /// Positions, velocities, the bonds' broken bits, the plastic extensions and the
    /// crushed bonds' e^c; damage and the `yielded` flags are derived from them on
    /// restore.
    fn save(&self, out: &mut Encoder) {
        let m = &self.model;
        out.put_f64x3_slice(&m.particles.position);
        out.put_f64x3_slice(&m.particles.velocity);
        out.put_u32_slice(&m.bonds.neighbours);
        if let Some(p) = &m.plastic {
            out.put_f64_slice(&p.extension);
        }
        if let Some(c) = &m.crushed {
            out.put_f32_slice(c);
        }
        if let Some(mesh) = self.embedded.as_ref().filter(|_| self.writes_tets) {
            out.put_u32_slice(&mesh.crack_faces());
        }
    }

    fn reference_surface(&self, points: &[u32]) -> Option<PieceSurface> {
        Some(self.embedded.as_ref()?.piece_surface(points))
    }

    fn broken_bonds(&self) -> u64 {
        self.model.bonds.broken_count()
    }

    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let m = &mut self.model;
        let n = m.len();
        m.particles.position = input.take_finite_f64x3_slice("positions", n)?;
        m.particles.velocity = input.take_finite_f64x3_slice("velocities", n)?;
        // Only the broken bit may differ from the bonds this scene builds.
        let neighbours = input.take_u32_slice("bonds", m.bonds.len())?;
        m.bonds
            .check_restored(&neighbours)
            .map_err(|message| input.error("bonds", message))?;
        m.bonds.neighbours = neighbours;
        if let Some(p) = &mut m.plastic {
            p.extension = input.take_finite_f64_slice("plastic extensions", p.extension.len())?;
        }
        if let Some(c) = &mut m.crushed {
            let saved = input.take_f32_slice("crushed bonds", c.len())?;
            // Finite (at most 0) only on a bond broken in compression; infinite otherwise.
            if let Some(k) = saved.iter().zip(&m.bonds.neighbours).position(|(&e, &nb)| {
                !(e == f32::INFINITY || (e.is_finite() && e <= 0.0 && nb & BROKEN != 0))
            }) {
                return Err(input
                    .error(
                        "crushed bonds",
                        format!("bond {k} has e^c = {}, which no run writes", saved[k]),
                    )
                    .into());
            }
            *c = saved;
        }
        if let Some(mesh) = self.embedded.as_mut().filter(|_| self.writes_tets) {
            let words = input.take_u32_slice("crack faces", mesh.crack_face_words())?;
            mesh.restore_crack_faces(&words, &m.bonds)
                .map_err(|message| input.error("crack faces", message))?;
        }
        m.update_damage();
        m.update_yielded();
        Ok(())
    }

    fn stage_times(&self) -> Vec<(&'static str, f64)> {
        let t = self.model.times;
        let mut times = vec![("dilatation", t.dilatation), ("forces", t.forces)];
        if self.model.share.is_some() {
            times.push(("exchange", t.exchange));
        }
        times
    }

    fn reset_stage_times(&mut self) {
        self.model.times = Default::default();
    }

    /// Updates the crack-face set and splits vertices, then places the vertices (see
    /// [`crate::embed`]).
    fn tet_frame(&mut self) -> Option<TetFrame> {
        let mesh = self.embedded.as_mut().filter(|_| self.writes_tets)?;
        let m = &self.model;
        mesh.update(&m.bonds);
        let reference = &m.reference.position;
        let position = &m.particles.position;
        let gradient = deformation_gradients(
            &m.bonds,
            reference,
            position,
            &m.reference.volume,
            self.orientation.as_deref(),
        );
        Some(TetFrame {
            points: mesh.positions(reference, position, &self.mass, &gradient),
            tets: mesh.tets.clone(),
            particle: (0..m.len() as u32).collect(),
            damage: m.particles.damage.iter().map(|&d| d as f32).collect(),
            parent: mesh
                .parent
                .iter()
                .map(|&p| if p == NO_PARENT { -1 } else { p as i32 })
                .collect(),
        })
    }

    fn restore_tet_frame(&mut self, last: TetFrame) -> Result<()> {
        let Some(mesh) = self.embedded.as_mut().filter(|_| self.writes_tets) else {
            return Ok(());
        };
        let parent = last
            .parent
            .iter()
            .map(|&p| if p < 0 { NO_PARENT } else { p as u32 })
            .collect();
        mesh.restore(last.tets, parent)
    }
}
