//! The frame loop: step the world to each output frame, write its particles (and split
//! tet mesh), the manifest and, every `checkpoint_every` frames, a checkpoint; stop
//! cleanly on a blow-up with the last good frame on disk.

use std::time::Instant;

use super::resume::Resumed;
use super::{Prepared, Progress, RunOptions, scene_hash};
use crate::cache::Layout;
use crate::cache::checkpoint::{Checkpoint, Encoder};
use crate::cache::manifest::{BodyInfo, Manifest, Timings};
use crate::cache::ply::ParticleFrame;
use crate::error::{Result, SimError};
use crate::scene::Scene;
use crate::world::World;

/// The state of the frame loop of one run.
pub struct Frames<'a> {
    scene: &'a Scene,
    layout: &'a Layout,
    /// Frames after the initial one.
    frames: usize,
    /// The first frame to write.
    first: usize,
    steps_per_frame: usize,
    broken_total: u64,
    start: Instant,
    manifest: Manifest,
    progress: &'a mut dyn FnMut(Progress),
    /// Seconds spent splitting vertices and placing them.
    split_time: f64,
}

impl<'a> Frames<'a> {
    /// The loop of a run of `prepared` from its first frame.
    pub fn new(
        scene: &'a Scene,
        layout: &'a Layout,
        prepared: &Prepared,
        options: &RunOptions,
        start: Instant,
        progress: &'a mut dyn FnMut(Progress),
    ) -> Frames<'a> {
        let frames = options
            .frames
            .unwrap_or_else(|| scene.frame_count())
            .min(scene.frame_count());
        Frames {
            scene,
            layout,
            frames,
            first: 1,
            steps_per_frame: prepared.steps_per_frame,
            broken_total: 0,
            start,
            manifest: manifest_for(scene, prepared),
            progress,
            split_time: 0.0,
        }
    }

    /// Continues after the frames a checkpoint left on disk.
    pub fn resume_from(&mut self, from: Resumed) {
        self.first = from.frame + 1;
        self.broken_total = from.broken_bonds;
        self.manifest.frame_times = from.frame_times;
        self.manifest.collider_centers = from.collider_centers;
    }

    /// Steps `world` through the remaining frames.
    pub fn run(mut self, world: &mut World, setup: &Timings) -> Result<Manifest> {
        let (scene, layout, frames) = (self.scene, self.layout, self.frames);
        let hash = scene_hash(scene);
        let mut output_time = 0.0;
        for frame in self.first..=frames + 1 {
            if frame > 1 {
                if let Err(err) = self.advance(world, frame) {
                    if matches!(err, SimError::BlowUp { .. }) {
                        self.manifest.status = err.to_string();
                        self.finish(world, output_time, setup);
                        self.manifest.write(&layout.manifest())?;
                    }
                    return Err(err);
                }
            }
            let t = Instant::now();
            let mut frame_split = 0.0;
            let mut wrote_tets = false;
            if scene.output.particles {
                particle_frame(world, frame).write(&layout.particles(frame))?;
            }
            for part in &mut world.parts {
                let s = Instant::now();
                if let Some(tets) = part.model.tet_frame() {
                    frame_split += s.elapsed().as_secs_f64();
                    tets.write(&layout.tets(frame))?;
                    wrote_tets = true;
                }
            }
            self.split_time += frame_split;
            self.manifest.frame_times.push(world.time);
            if wrote_tets {
                crate::cache::vtu::write_collection(
                    &layout.tets_collection(),
                    &self.manifest.frame_times,
                    scene.output.playback_fps,
                )?;
            }
            self.manifest
                .collider_centers
                .push(world.colliders.iter().map(|c| c.center).collect());
            self.manifest.status = if frame <= frames {
                "running".into()
            } else if frames == scene.frame_count() {
                "complete".into()
            } else {
                format!(
                    "interrupted: stopped after frame {frame} as asked (--frames {frames}); \
                     --resume continues"
                )
            };
            self.finish(world, output_time, setup);
            self.manifest.write(&layout.manifest())?;
            let every = scene.output.checkpoint_every;
            if every > 0 && frame % every == 0 && frame <= frames {
                let mut payload = Encoder::new();
                world.save(&mut payload);
                let checkpoint = Checkpoint {
                    scene_hash: hash,
                    frame: frame as u64,
                    steps: world.steps,
                    broken_bonds: self.broken_total,
                    time: world.time,
                    payload: payload.finish(),
                };
                checkpoint.write(&layout.checkpoint())?;
            }
            output_time += t.elapsed().as_secs_f64() - frame_split;
            (self.progress)(Progress {
                frame,
                frames: frames + 1,
                steps: world.steps,
                steps_per_frame: self.steps_per_frame,
            });
        }
        self.finish(world, output_time, setup);
        self.manifest.write(&layout.manifest())?;
        Ok(self.manifest)
    }

    /// The steps from frame − 1 to `frame`, then the blow-up check; a blow-up names
    /// the last good frame.
    fn advance(&mut self, world: &mut World, frame: usize) -> Result<()> {
        let stepped = (0..self.steps_per_frame).try_for_each(|_| {
            self.broken_total += world.step()? as u64;
            Ok(())
        });
        match stepped.and_then(|_| world.check_blowup()) {
            Err(SimError::BlowUp {
                step,
                time,
                what,
                particle,
                position,
                ..
            }) => Err(SimError::BlowUp {
                step,
                time,
                what,
                particle,
                position,
                last_good_frame: frame - 1,
            }),
            other => other,
        }
    }

    fn finish(&mut self, world: &World, output: f64, setup: &Timings) {
        let m = &mut self.manifest;
        m.steps = world.steps;
        m.broken_bonds = self.broken_total;
        m.timings = Timings {
            discretize: setup.discretize,
            families: setup.families,
            stages: world
                .stage_times()
                .into_iter()
                .map(|(name, t)| (name.to_string(), t))
                .collect(),
            integrate_contact: world.other_time,
            output,
            split: self.split_time,
            surface: 0.0,
            total: self.start.elapsed().as_secs_f64(),
        };
    }
}

/// The cache frame of the world's current state.
pub fn particle_frame(world: &World, frame: usize) -> ParticleFrame {
    let c = world.particles();
    ParticleFrame {
        frame,
        time: world.time,
        position: c.position,
        velocity: c.velocity,
        damage: c.damage,
        plastic: c.plastic,
        material: c.body.iter().map(|&b| b as f32).collect(),
        fragment: c.fragment.iter().map(|&f| f as f32).collect(),
        extra: c.extra,
    }
}

fn manifest_for(scene: &Scene, prepared: &Prepared) -> Manifest {
    let d = &prepared.discretization;
    Manifest {
        scene: scene.scene.name.clone(),
        units: "SI: m, kg, s, Pa; y up".into(),
        tool_version: env!("CARGO_PKG_VERSION").into(),
        dt: prepared.world.dt,
        stable_dt: prepared.stable_dt.0,
        fps: scene.scene.fps,
        particles: d.position.len(),
        bonds: prepared.world.bonds(),
        bodies: scene
            .bodies
            .iter()
            .enumerate()
            .map(|(b, spec)| BodyInfo {
                name: spec.name.clone(),
                material: spec.material.clone(),
                particles: d.body.iter().filter(|&&owner| owner as usize == b).count(),
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
