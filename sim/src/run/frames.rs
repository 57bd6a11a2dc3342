//! The frame loop: step the world to each output frame, write its particles (and split
//! tet mesh), the manifest (with each file's size and checksum) and, every
//! `checkpoint_every` frames, a checkpoint. It stops cleanly three ways: at the
//! `--frames` limit it checkpoints the last frame, when asked to (a signal) it
//! checkpoints the world between two steps, and both mark the manifest interrupted;
//! on a blow-up or a failed write it marks the manifest failed with the message, the
//! frames written so far on disk.

use std::sync::Arc;
use std::time::Instant;

use super::resume::Resumed;
use super::{Prepared, Progress, RunOptions, scene_hash};
use crate::cache::checkpoint::Checkpoint;
use crate::cache::manifest::{BodyInfo, FileRecord, Manifest, Status, Timings};
use crate::cache::ply::ParticleFrame;
use crate::cache::{CacheError, Layout, human_bytes};
use crate::contact::ColliderShape;
use crate::error::{Result, SimError};
use crate::mpm::PARTICLES_PER_CELL_AXIS;
use crate::ranks::Ranks;
use crate::scene::{ModelKind, Scene};
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
    /// Seconds spent writing frames.
    output_time: f64,
    /// Where a request to stop comes from.
    stop: super::StopRequest,
    /// Bytes of the files of the last frame written, and of the last checkpoint (for
    /// a full disk's message).
    frame_bytes: u64,
    checkpoint_bytes: u64,
    /// The other ranks of a distributed run, which must agree on when to stop.
    ranks: Option<Arc<dyn Ranks>>,
    /// Whether this process writes the cache: rank 0 of a distributed run writes it
    /// alone (every rank holds every particle and broken bit), the others only step.
    writes: bool,
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
        let mut manifest = manifest_for(scene, prepared);
        // `scene.toml` as the run wrote it, so that `perifrac verify` checks it.
        let record = FileRecord::of(scene.to_toml().as_bytes());
        manifest.record(&layout.root, &layout.scene(), record);
        Frames {
            scene,
            layout,
            frames,
            first: 1,
            steps_per_frame: prepared.steps_per_frame,
            broken_total: 0,
            start,
            manifest,
            progress,
            split_time: 0.0,
            output_time: 0.0,
            stop: options.stop.clone(),
            frame_bytes: 0,
            checkpoint_bytes: 0,
            ranks: options.ranks.clone(),
            writes: options.writes(),
        }
    }

    /// Writes the geometry of each mesh collider, `colliders/mesh_N.ply` (the placed
    /// mesh less its pivot; the manifest poses it at each frame), and records it. The
    /// same scene gives the same bytes, so a resumed run rewrites them unchanged.
    pub fn write_collider_meshes(&mut self, world: &World) -> Result<()> {
        if !self.writes {
            return Ok(());
        }
        for (i, collider) in world.colliders.iter().enumerate() {
            let ColliderShape::Mesh(mesh) = &collider.shape else {
                continue;
            };
            let dir = self.layout.colliders_dir();
            std::fs::create_dir_all(&dir).map_err(|e| SimError::io(&dir, e))?;
            let path = self.layout.collider_mesh(i);
            let record = mesh.cache_mesh().write(&path)?;
            self.manifest.record(&self.layout.root, &path, record);
        }
        Ok(())
    }

    /// Continues after the frames a checkpoint left on disk.
    pub fn resume_from(&mut self, from: Resumed) {
        self.first = from.frame + 1;
        self.broken_total = from.broken_bonds;
        self.manifest.frame_times = from.manifest.frame_times;
        self.manifest.collider_centers = from.manifest.collider_centers;
        self.manifest.collider_rotations = from.manifest.collider_rotations;
        // The frames' records; `scene.toml`'s is the same (the plan checked the scene).
        self.manifest.files.extend(from.manifest.files);
        // Where it stood, should nothing be left to run (`--resume --frames` at the
        // frame it stopped at).
        self.manifest.status = from.manifest.status;
        self.manifest.message = from.manifest.message;
    }

    /// Steps `world` through the remaining frames. On any error but an interruption
    /// (which marks the manifest itself) the manifest is marked failed with the
    /// message before the error is returned.
    pub fn run(mut self, world: &mut World, setup: &Timings) -> Result<Manifest> {
        match self.frames(world, setup) {
            Ok(()) => {
                self.finish(world, setup);
                self.write_manifest()?;
                Ok(self.manifest)
            }
            Err(err) => {
                if !matches!(err, SimError::Interrupted { .. }) {
                    self.manifest.status = Status::Failed;
                    self.manifest.message = err.to_string();
                    self.finish(world, setup);
                    // A second failure (the disk still full) must not hide the first;
                    // the manifest then still says "running".
                    let _ = self.write_manifest();
                }
                Err(err)
            }
        }
    }

    fn frames(&mut self, world: &mut World, setup: &Timings) -> Result<()> {
        if world.clock.steps_per_frame == 0 {
            world.clock.steps_per_frame = self.steps_per_frame as u64;
            world.clock.frame_length = self.scene.frame_time();
        }
        for frame in self.first..=self.frames + 1 {
            if frame > 1
                && let Some(reason) = self.advance(world, frame)?
            {
                return self.stop_during(world, setup, frame, reason);
            }
            if let Some(reason) = self
                .write_frame(world, setup, frame)
                .map_err(|e| self.with_frame_need(e))?
            {
                return Err(SimError::Interrupted {
                    reason,
                    frame,
                    step: world.steps,
                });
            }
        }
        Ok(())
    }

    /// Writes `frame`: its files, the manifest and (on schedule, or when stopping) a
    /// checkpoint; returns the reason when a stop was asked for.
    fn write_frame(
        &mut self,
        world: &mut World,
        setup: &Timings,
        frame: usize,
    ) -> Result<Option<String>> {
        let (scene, layout, frames) = (self.scene, self.layout, self.frames);
        let t = Instant::now();
        let mut bytes = 0;
        let mut frame_split = 0.0;
        let mut wrote_tets = false;
        if scene.output.particles && self.writes {
            let path = layout.particles(frame);
            let record = particle_frame(world, frame).write(&path)?;
            bytes += record.bytes;
            self.manifest.record(&layout.root, &path, record);
        }
        if let Some(rigid) = &world.rigid {
            rigid.orient(&mut world.parts);
        }
        for part in &mut world.parts {
            let s = Instant::now();
            // Split on every rank: the split is state the rigid phase reads.
            if let Some(tets) = part.model.tet_frame() {
                frame_split += s.elapsed().as_secs_f64();
                if !self.writes {
                    continue;
                }
                let path = layout.tets(frame);
                let record = tets.write(&path)?;
                bytes += record.bytes;
                self.manifest.record(&layout.root, &path, record);
                wrote_tets = true;
            }
            if scene.output.writes_sheets()
                && self.writes
                && let Some(sheet) = part.model.sheet_frame()
            {
                let path = layout.sheet(frame);
                let record = sheet.write(&path)?;
                bytes += record.bytes;
                self.manifest.record(&layout.root, &path, record);
            }
        }
        self.split_time += frame_split;
        self.manifest.frame_times.push(world.time);
        if wrote_tets && self.writes {
            crate::cache::vtu::write_collection(
                &layout.tets_collection(),
                &self.manifest.frame_times,
                scene.output.playback_fps,
            )?;
        }
        self.manifest
            .collider_centers
            .push(world.colliders.iter().map(|c| c.center).collect());
        if world
            .colliders
            .iter()
            .any(|c| matches!(c.shape, ColliderShape::Mesh(_)))
        {
            self.manifest
                .collider_rotations
                .push(world.colliders.iter().map(|c| c.orientation()).collect());
        }
        let last = frame == frames + 1;
        let stop = self.stop_reason(world.steps).filter(|_| !last);
        let (status, message) = match (&stop, last) {
            (Some(reason), _) => (
                Status::Interrupted,
                format!("{reason}: stopped after frame {frame}; --resume continues"),
            ),
            (None, false) => (Status::Running, String::new()),
            (None, true) if frames == scene.frame_count() => (Status::Complete, String::new()),
            (None, true) => (
                Status::Interrupted,
                format!(
                    "stopped as asked (--frames {frames}: {frames} frames after the initial \
                     one, files 0001 to {frame:04}); --resume continues"
                ),
            ),
        };
        let every = scene.output.checkpoint_every;
        let on_schedule = every > 0 && frame % every == 0 && !last;
        let stopping = status == Status::Interrupted;
        (self.manifest.status, self.manifest.message) = (status, message);
        self.finish(world, setup);
        // The manifest before the checkpoint: a kill between the two leaves a
        // manifest ahead of the checkpoint, which a resume cuts back.
        self.write_manifest()?;
        // A run stopped before the scene's end checkpoints where it stopped.
        if on_schedule || stopping {
            self.checkpoint(world, frame)?;
        }
        self.output_time += t.elapsed().as_secs_f64() - frame_split;
        (self.progress)(Progress {
            frame,
            frames: frames + 1,
            steps: world.steps,
            steps_per_frame: world.clock.steps_per_frame as usize,
        });
        self.frame_bytes = bytes;
        Ok(stop)
    }

    /// Writes the manifest, on the rank that writes the cache.
    fn write_manifest(&self) -> Result<()> {
        if self.writes {
            self.manifest.write(&self.layout.manifest())?;
        }
        Ok(())
    }

    /// The reason to stop after `steps` steps, if any; in a distributed run every rank
    /// stops where any was asked to (a signal reaches the ranks at different steps).
    fn stop_reason(&self, steps: u64) -> Option<String> {
        let reason = self.stop.reason_after(steps);
        match &self.ranks {
            Some(ranks) if ranks.any(reason.is_some()) => {
                Some(reason.unwrap_or_else(|| "a stop asked of another rank".to_string()))
            }
            Some(_) => None,
            None => reason,
        }
    }

    /// Adds to a full disk's message what a whole frame of this cache writes (its
    /// files, and the checkpoint on checkpoint frames), from the last frame written.
    fn with_frame_need(&self, error: SimError) -> SimError {
        use std::io::ErrorKind::{QuotaExceeded, StorageFull};
        match error {
            SimError::Cache(CacheError::Write {
                path,
                error,
                mut hint,
            }) if matches!(error.kind(), StorageFull | QuotaExceeded) && self.frame_bytes > 0 => {
                hint.push_str(&format!(
                    "; each frame of this cache writes about {}",
                    human_bytes(self.frame_bytes)
                ));
                if self.checkpoint_bytes > 0 {
                    hint.push_str(&format!(
                        " and each checkpoint {}",
                        human_bytes(self.checkpoint_bytes)
                    ));
                }
                SimError::Cache(CacheError::Write { path, error, hint })
            }
            other => other,
        }
    }

    /// Stops a run asked to stop during `frame`: the manifest says where, the
    /// checkpoint holds the world between two steps (with the frames up to `frame` − 1
    /// on disk), and a resume takes the rest of the frame's steps from there.
    fn stop_during(
        &mut self,
        world: &World,
        setup: &Timings,
        frame: usize,
        reason: String,
    ) -> Result<()> {
        let into = world.steps - world.frame_end(frame - 1);
        self.manifest.status = Status::Interrupted;
        self.manifest.message = format!(
            "{reason}: stopped during frame {frame}, after {into} of its {} steps; --resume \
             continues from there",
            world.clock.steps_per_frame
        );
        self.finish(world, setup);
        self.write_manifest()?;
        self.checkpoint(world, frame - 1)?;
        Err(SimError::Interrupted {
            reason,
            frame: frame - 1,
            step: world.steps,
        })
    }

    /// Writes the checkpoint of the world as it is at `frame` (the last frame on
    /// disk; the world may be part way to the next one).
    fn checkpoint(&mut self, world: &World, frame: usize) -> Result<()> {
        if !self.writes {
            return Ok(());
        }
        let checkpoint = Checkpoint {
            scene_hash: scene_hash(self.scene),
            frame: frame as u64,
            steps: world.steps,
            broken_bonds: self.broken_total,
            time: world.time,
            payload: Vec::new(),
        };
        self.checkpoint_bytes =
            checkpoint.write_encoded(&self.layout.checkpoint(), |payload| world.save(payload))?;
        Ok(())
    }

    /// The steps from frame − 1 to `frame` not taken yet (a run resumed from a
    /// checkpoint written during a frame starts part way), then the blow-up check; a
    /// blow-up names the last good frame. A request to stop is looked at before each
    /// step that is a stop point ([`World::at_stop_point`]): its reason is returned
    /// with the world between two steps.
    fn advance(&mut self, world: &mut World, frame: usize) -> Result<Option<String>> {
        // A new frame rate, or only rigid pieces left to move: a new clock.
        world.start_clock(frame - 1, self.scene.frame_length(frame));
        let mut end = world.frame_end(frame);
        let start = world.steps;
        let stepped = (|| {
            while world.steps < end {
                // A stop waits for the next stop point (the rigid phase's; the
                // frame's start is one).
                if (world.steps == start || world.at_stop_point())
                    && let Some(reason) = self.stop_reason(world.steps)
                {
                    return Ok(Some(reason));
                }
                // A rigid piece about to be hit hard goes back to its model: the rest
                // of the frame at the deformable step.
                if world.reenter() && world.start_deformable_clock(frame) {
                    end = world.frame_end(frame);
                }
                self.broken_total += world.step()? as u64;
                // Everything went rigid part way through the frame: the rest of it
                // at the rigid phase's step.
                if world.at_stop_point() && world.start_rigid_clock(frame) {
                    end = world.frame_end(frame);
                }
            }
            world.end_frame();
            world.check_blowup().map(|_| None)
        })();
        match stepped {
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

    fn finish(&mut self, world: &World, setup: &Timings) {
        let output = self.output_time;
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
                particle_spacing: match spec.model {
                    ModelKind::Mpm => spec.resolution / PARTICLES_PER_CELL_AXIS as f64,
                    ModelKind::Membrane => spec.resolution,
                    _ => 0.0,
                },
            })
            .collect(),
        status: Status::Running,
        ..Manifest::default()
    }
}
