//! A model added from outside the crate, through the public [`Model`] interface only:
//! a mass–spring lattice on a body's particles. It runs through the same frame loop as
//! peridynamics — anchors, a dynamic collider, the ground, checkpoints and resume — and
//! writes a valid cache, without any change to the loop.

use std::path::Path;
use std::time::Instant;

use perifrac_math::{norm, sub};
use perifrac_sim::cache::Layout;
use perifrac_sim::cache::checkpoint::{Decoder, Encoder};
use perifrac_sim::cache::manifest::{Manifest, Timings};
use perifrac_sim::cache::ply::ParticleFrame;
use perifrac_sim::contact;
use perifrac_sim::error::Result;
use perifrac_sim::geometry::discretize::discretize;
use perifrac_sim::model::{Model, ParticleColumns, Points, PointsMut};
use perifrac_sim::run::{self, Prepared, RunOptions};
use perifrac_sim::scene::Scene;
use perifrac_sim::world::{Part, World, WorldSettings};

/// Linear springs of stiffness `k` between particles closer than `reach`.
#[derive(Debug)]
struct Springs {
    reference: Vec<[f64; 3]>,
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    mass: Vec<f64>,
    body: Vec<u32>,
    /// (i, j, rest length), i < j.
    springs: Vec<(usize, usize, f64)>,
    k: f64,
    force: Vec<[f64; 3]>,
    force_time: f64,
}

impl Springs {
    fn new(x: &[[f64; 3]], mass: Vec<f64>, body: Vec<u32>, reach: f64, k: f64) -> Springs {
        let mut springs = Vec::new();
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                let l = norm(sub(x[j], x[i]));
                if l < reach {
                    springs.push((i, j, l));
                }
            }
        }
        Springs {
            reference: x.to_vec(),
            position: x.to_vec(),
            velocity: vec![[0.0; 3]; x.len()],
            force: vec![[0.0; 3]; x.len()],
            mass,
            body,
            springs,
            k,
            force_time: 0.0,
        }
    }
}

impl Model for Springs {
    fn name(&self) -> &'static str {
        "springs"
    }
    fn points(&self) -> Points<'_> {
        Points {
            position: &self.position,
            velocity: &self.velocity,
            reference: &self.reference,
            mass: &self.mass,
        }
    }
    fn points_mut(&mut self) -> PointsMut<'_> {
        PointsMut {
            position: &mut self.position,
            velocity: &mut self.velocity,
            reference: &self.reference,
            mass: &self.mass,
        }
    }
    fn point_bodies(&self) -> &[u32] {
        &self.body
    }
    fn internal_forces(&mut self) -> usize {
        let t = Instant::now();
        self.force.iter_mut().for_each(|f| *f = [0.0; 3]);
        for &(i, j, l) in &self.springs {
            let d = sub(self.position[j], self.position[i]);
            let len = norm(d);
            let s = self.k * (len - l) / len;
            for (a, d) in d.iter().enumerate() {
                self.force[i][a] += s * d;
                self.force[j][a] -= s * d;
            }
        }
        self.force_time += t.elapsed().as_secs_f64();
        0
    }
    fn accelerations(&self, gravity: [f64; 3], out: &mut [[f64; 3]]) {
        for (i, a) in out.iter_mut().enumerate() {
            for k in 0..3 {
                a[k] = self.force[i][k] / self.mass[i] + gravity[k];
            }
        }
    }
    fn damp(&mut self, _dt: f64, _anchored: &[bool]) {}
    fn stable_time_step(&self) -> (f64, usize) {
        let mut row = vec![0.0; self.mass.len()];
        for &(i, j, _) in &self.springs {
            row[i] += 2.0 * self.k;
            row[j] += 2.0 * self.k;
        }
        let (worst, rate) = (0..row.len())
            .map(|i| (i, row[i] / self.mass[i]))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        (2.0 / rate.sqrt(), worst)
    }
    fn kinetic_energy(&self) -> f64 {
        (0..self.mass.len())
            .map(|i| 0.5 * self.mass[i] * norm(self.velocity[i]).powi(2))
            .sum()
    }
    fn strain_energy(&self) -> f64 {
        self.springs
            .iter()
            .map(|&(i, j, l)| {
                0.5 * self.k * (norm(sub(self.position[j], self.position[i])) - l).powi(2)
            })
            .sum()
    }
    fn particles(&self) -> ParticleColumns {
        let f32x3 = |v: &[f64; 3]| v.map(|x| x as f32);
        let n = self.mass.len();
        ParticleColumns {
            position: self.position.iter().map(f32x3).collect(),
            velocity: self.velocity.iter().map(f32x3).collect(),
            damage: vec![0.0; n],
            plastic: vec![0.0; n],
            body: self.body.clone(),
            fragment: vec![0; n],
            extra: Vec::new(),
        }
    }
    fn save(&self, out: &mut Encoder) {
        out.put_f64x3_slice(&self.position);
        out.put_f64x3_slice(&self.velocity);
    }
    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let n = self.mass.len();
        self.position = input.take_f64x3_slice("positions", n)?;
        self.velocity = input.take_f64x3_slice("velocities", n)?;
        Ok(())
    }
    fn stage_times(&self) -> Vec<(&'static str, f64)> {
        vec![("springs", self.force_time)]
    }
    fn reset_stage_times(&mut self) {
        self.force_time = 0.0;
    }
}

const SCENE: &str = "\
[scene]\nname = \"springs\"\nduration = 0.02\nfps = 250\n\
[materials.m]\ndensity = 1000\nyoungs_modulus = 1e6\npoisson_ratio = 0.25\n\
[[body]]\nmaterial = \"m\"\nresolution = 0.02\n\
shape = { type = \"box\", center = [0, 0.05, 0], size = [0.2, 0.06, 0.06] }\n\
[[body.anchor]]\nregion = { type = \"box\", center = [-0.1, 0.05, 0], size = [0.03, 0.1, 0.1] }\n\
velocity = [0, 0.5, 0]\n\
[[collider]]\ntype = \"ground\"\n\
[[collider]]\ntype = \"sphere\"\ncenter = [0.08, 0.14, 0]\nradius = 0.04\nvelocity = [0, -2, 0]\nmass = 0.2\n\
[output]\ncheckpoint_every = 2\npreview = false\n";

/// The scene's world with the spring model on its particles.
fn springs_world(scene: &Scene) -> Prepared {
    let disc = discretize(scene).expect("meshes");
    let rho = scene.materials["m"].density;
    let mass: Vec<f64> = disc.volume.iter().map(|v| rho * v).collect();
    let model = Springs::new(&disc.position, mass.clone(), disc.body.clone(), 0.03, 2e3);
    let stable = model.stable_time_step();
    let anchors =
        contact::anchors(scene, &disc.position, &mass, &disc.body).expect("anchor regions");
    assert!(
        !anchors[0].particles.is_empty(),
        "the anchor holds particles"
    );
    let steps_per_frame = (scene.frame_time() / (0.5 * stable.0)).ceil() as usize;
    let world = World::new(
        vec![Part::new(Box::new(model), anchors)],
        contact::colliders(scene).expect("colliders"),
        WorldSettings {
            gravity: scene.scene.gravity,
            dt: scene.frame_time() / steps_per_frame as f64,
            duration: scene.scene.duration,
            energy_growth: scene.scene.blowup_energy_growth,
        },
    );
    Prepared {
        world,
        discretization: disc,
        stable_dt: stable,
        steps_per_frame,
        timings: Timings::default(),
    }
}

fn run_springs(scene: &Scene, out: &Path, options: &RunOptions) -> Manifest {
    run::run_prepared(
        scene,
        &Layout::new(out),
        options,
        springs_world(scene),
        Instant::now(),
        &mut |_| {},
    )
    .expect("runs")
}

#[test]
fn a_model_from_outside_runs_through_the_loop_with_checkpoints_and_resume() {
    let scene = Scene::parse(SCENE, Path::new("springs.toml"), Path::new(".")).expect("scene");
    let frames = scene.frame_count() + 1;
    let full = tempfile::tempdir().expect("temp dir");
    let manifest = run_springs(&scene, full.path(), &RunOptions::default());
    assert_eq!(manifest.status.to_string(), "complete");
    assert_eq!(manifest.frame_times.len(), frames);
    let first = ParticleFrame::read(&Layout::new(full.path()).particles(1)).expect("frame 1");
    let last = ParticleFrame::read(&Layout::new(full.path()).particles(frames)).expect("last");
    assert_eq!(first.len(), last.len());
    // The anchored end rose with the anchor (0.5 m/s for 0.02 s); the sphere fell
    // onto the free end and was pushed back by it.
    let lift = |f: &ParticleFrame| {
        let ids: Vec<usize> = (0..f.len())
            .filter(|&i| first.position[i][0] < -0.09)
            .collect();
        ids.iter().map(|&i| f.position[i][1] as f64).sum::<f64>() / ids.len() as f64
    };
    assert!(
        (lift(&last) - lift(&first) - 0.01).abs() < 1e-4,
        "anchored particles moved {} m",
        lift(&last) - lift(&first)
    );
    let centers = &manifest.collider_centers;
    assert!(centers[frames - 1][1][1] < 0.14, "the sphere moved");
    assert!(
        last.position.iter().all(|p| p[1] >= -1e-6),
        "the ground holds the particles"
    );

    let part = tempfile::tempdir().expect("temp dir");
    let stop = RunOptions {
        frames: Some(3),
        ..RunOptions::default()
    };
    let stopped = run_springs(&scene, part.path(), &stop).status;
    assert!(stopped.to_string() == "interrupted", "{stopped}");
    let resume = RunOptions {
        resume: true,
        ..RunOptions::default()
    };
    let resumed = run_springs(&scene, part.path(), &resume);
    assert_eq!(resumed.status.to_string(), "complete");
    for f in 1..=frames {
        let name = format!("particles/{f:04}.ply");
        let a = std::fs::read(full.path().join(&name)).expect("frame");
        let b = std::fs::read(part.path().join(&name)).expect("frame");
        assert!(
            a == b,
            "{name}: a resumed run differs from an uninterrupted one"
        );
    }
    assert_eq!(resumed.deterministic_json(), manifest.deterministic_json());
}
