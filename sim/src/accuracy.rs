//! The error measure of Chen et al. 2018 §6: position deviation over the diagonal of
//! the body's bounding box,
//!
//! ```text
//! Error = |x_p − x_p^ref| / d
//! ```
//!
//! taken per frame as the mean over the particles, and summarized as the mean and the
//! maximum over the frames of a run. Two runs on the same tets (peridynamics and a FEM
//! reference of one scene) compare particle by particle; a run against a reference on
//! another mesh compares at the run's particles, where the reference FEM's piecewise
//! linear displacement field is interpolated ([`VertexTrajectory::sample`]).

use std::collections::HashMap;
use std::time::Instant;

use perifrac_math::{cross, dist, dot, sub};
use rayon::prelude::*;

use crate::error::Result;
use crate::run;
use crate::scene::Scene;

/// Particle positions of a run, frame by frame.
#[derive(Debug, Clone, Default)]
pub struct Trajectory {
    /// Reference (rest) positions of the particles.
    pub rest: Vec<[f64; 3]>,
    /// Time of each frame (s).
    pub times: Vec<f64>,
    /// Positions of the particles in each frame.
    pub frames: Vec<Vec<[f64; 3]>>,
}

/// Mesh vertex positions of a FEM run, frame by frame: a displacement field that can
/// be sampled anywhere in the body.
#[derive(Debug, Clone, Default)]
pub struct VertexTrajectory {
    /// Rest positions of the vertices.
    pub rest: Vec<[f64; 3]>,
    /// Tets (global vertex indices).
    pub tets: Vec<[u32; 4]>,
    /// Vertex positions in each frame.
    pub frames: Vec<Vec<[f64; 3]>>,
}

/// The deviation between two runs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Deviation {
    /// Per frame: mean over the particles of |x − x_ref| / d.
    pub per_frame: Vec<f64>,
    /// Largest over the frames.
    pub max: f64,
    /// Mean over the frames.
    pub mean: f64,
}

/// Length of the diagonal of the bounding box of `points`.
pub fn diagonal(points: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (0..3)
        .map(|k| (hi[k] - lo[k]).max(0.0).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Deviation of `run` from `reference`, particle by particle (the same particles,
/// the same frame times), over the diagonal `d`. Frames beyond the shorter run
/// are not compared.
pub fn deviation(run: &Trajectory, reference: &Trajectory, d: f64) -> Deviation {
    let per_frame: Vec<f64> = run
        .frames
        .iter()
        .zip(&reference.frames)
        .map(|(a, b)| {
            let n = a.len().min(b.len()).max(1);
            a.iter().zip(b).map(|(x, y)| dist(*x, *y)).sum::<f64>() / (n as f64 * d)
        })
        .collect();
    let max = per_frame.iter().copied().fold(0.0, f64::max);
    let mean = per_frame.iter().sum::<f64>() / per_frame.len().max(1) as f64;
    Deviation {
        per_frame,
        max,
        mean,
    }
}

/// A point inside a tet: the tet and the point's barycentric weights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probe {
    /// The tet.
    pub tet: u32,
    /// Barycentric weights of its four vertices (sum 1, none negative).
    pub weights: [f64; 4],
}

impl VertexTrajectory {
    /// Locates each point in the rest mesh: the tet that contains it, or for a
    /// point outside the mesh (a coarser mesh's barycentre near a curved surface) the
    /// nearby tet it is least outside of, with its weights clamped to the tet.
    pub fn locate(&self, points: &[[f64; 3]]) -> Vec<Probe> {
        let x = &self.rest;
        let edge = mean_edge(x, &self.tets).max(1e-12);
        let cell = 2.0 * edge;
        let key = |p: [f64; 3]| p.map(|c| (c / cell).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (e, t) in self.tets.iter().enumerate() {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for &v in t {
                for k in 0..3 {
                    lo[k] = lo[k].min(x[v as usize][k]);
                    hi[k] = hi[k].max(x[v as usize][k]);
                }
            }
            let (a, b) = (key(lo), key(hi));
            for i in a[0]..=b[0] {
                for j in a[1]..=b[1] {
                    for k in a[2]..=b[2] {
                        grid.entry([i, j, k]).or_default().push(e as u32);
                    }
                }
            }
        }
        points
            .par_iter()
            .map(|&p| {
                let c = key(p);
                let mut best: Option<(f64, u32, [f64; 4])> = None;
                for reach in [0i64, 1, 2] {
                    for i in -reach..=reach {
                        for j in -reach..=reach {
                            for k in -reach..=reach {
                                let Some(list) = grid.get(&[c[0] + i, c[1] + j, c[2] + k]) else {
                                    continue;
                                };
                                for &e in list {
                                    let w = barycentric(x, &self.tets[e as usize], p);
                                    let worst = w.iter().copied().fold(f64::INFINITY, f64::min);
                                    if best.is_none_or(|(b, be, _)| {
                                        worst > b || (worst == b && e < be)
                                    }) {
                                        best = Some((worst, e, w));
                                    }
                                }
                            }
                        }
                    }
                    if best.is_some_and(|(b, _, _)| b >= -1e-9) {
                        break;
                    }
                }
                let (_, tet, w) = best.unwrap_or((0.0, 0, [0.25; 4]));
                let w = w.map(|v| v.max(0.0));
                let s: f64 = w.iter().sum();
                Probe {
                    tet,
                    weights: w.map(|v| v / s),
                }
            })
            .collect()
    }

    /// The trajectory of material points at the rest positions `points`, following
    /// the piecewise linear motion of the mesh.
    pub fn sample(&self, points: &[[f64; 3]], times: &[f64]) -> Trajectory {
        let probes = self.locate(points);
        let frames = self
            .frames
            .iter()
            .map(|y| {
                probes
                    .par_iter()
                    .map(|pr| {
                        let t = self.tets[pr.tet as usize];
                        let mut s = [0.0; 3];
                        for (c, &v) in t.iter().enumerate() {
                            for k in 0..3 {
                                s[k] += pr.weights[c] * y[v as usize][k];
                            }
                        }
                        s
                    })
                    .collect()
            })
            .collect();
        Trajectory {
            rest: points.to_vec(),
            times: times.to_vec(),
            frames,
        }
    }
}

fn mean_edge(x: &[[f64; 3]], tets: &[[u32; 4]]) -> f64 {
    if tets.is_empty() {
        return 0.0;
    }
    let d = |a: u32, b: u32| dist(x[a as usize], x[b as usize]);
    tets.iter()
        .map(|t| {
            d(t[0], t[1])
                + d(t[0], t[2])
                + d(t[0], t[3])
                + d(t[1], t[2])
                + d(t[1], t[3])
                + d(t[2], t[3])
        })
        .sum::<f64>()
        / (6 * tets.len()) as f64
}

/// Barycentric coordinates of `p` in tet `t` (negative outside).
fn barycentric(x: &[[f64; 3]], t: &[u32; 4], p: [f64; 3]) -> [f64; 4] {
    let x0 = x[t[0] as usize];
    let e = |a: usize| sub(x[t[a] as usize], x0);
    let (a, b, c) = (e(1), e(2), e(3));
    let r = sub(p, x0);
    let det = |u: [f64; 3], v: [f64; 3], w: [f64; 3]| dot(u, cross(v, w));
    let d = det(a, b, c);
    let w1 = det(r, b, c) / d;
    let w2 = det(a, r, c) / d;
    let w3 = det(a, b, r) / d;
    [1.0 - w1 - w2 - w3, w1, w2, w3]
}

/// A run held in memory: particle positions per frame, and for FEM runs the mesh
/// vertices too, with what it cost.
#[derive(Debug, Clone, Default)]
pub struct Recording {
    /// Particle positions (PD particles or FEM tet barycentres).
    pub particles: Trajectory,
    /// Vertex positions (FEM runs only).
    pub vertices: Option<VertexTrajectory>,
    /// Wall-clock seconds: setup and stepping, no output.
    pub wall: f64,
    /// Steps taken.
    pub steps: u64,
    /// Time step (s).
    pub dt: f64,
}

/// Runs `scene` (peridynamics or FEM, as its bodies say) for `frames` frames after
/// the initial one and records every frame in memory; for the FEM also the mesh
/// vertices (the FEM's points: every body's mesh, one after another).
pub fn record(scene: &Scene, frames: usize) -> Result<Recording> {
    let start = Instant::now();
    let mut p = run::prepare(scene)?;
    let vertices = run::uses_fem(scene).then(|| {
        let mut tets = Vec::new();
        let mut base = 0u32;
        for mesh in &p.discretization.meshes {
            tets.extend(mesh.tets.iter().map(|t| t.map(|v| v + base)));
            base += mesh.vertices.len() as u32;
        }
        VertexTrajectory {
            rest: p.world.parts[0].model.points().reference.to_vec(),
            tets,
            frames: Vec::new(),
        }
    });
    let world = &mut p.world;
    let mut rec = Recording {
        particles: Trajectory {
            rest: p.discretization.position.clone(),
            ..Trajectory::default()
        },
        vertices,
        dt: world.dt,
        ..Recording::default()
    };
    for frame in 0..=frames {
        if frame > 0 {
            for _ in 0..p.steps_per_frame {
                world.step()?;
            }
        }
        let model = &world.parts[0].model;
        rec.particles.times.push(world.time);
        rec.particles.frames.push(model.particle_positions());
        if let Some(v) = &mut rec.vertices {
            v.frames.push(model.points().position.to_vec());
        }
    }
    rec.steps = world.steps;
    rec.wall = start.elapsed().as_secs_f64();
    Ok(rec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampling_a_mesh_at_its_own_barycentres_gives_the_barycentres() {
        let mesh = crate::geometry::stuff(
            &crate::geometry::Cuboid {
                center: [0.0; 3],
                half_extents: [0.1, 0.05, 0.05],
            },
            0.02,
        )
        .expect("meshes");
        let moved: Vec<[f64; 3]> = mesh
            .vertices
            .iter()
            .map(|x| [x[0] + 0.3 * x[1], 2.0 * x[1], x[2] - 0.1])
            .collect();
        let traj = VertexTrajectory {
            rest: mesh.vertices.clone(),
            tets: mesh.tets.clone(),
            frames: vec![moved],
        };
        // Any point of the box, mapped by the affine motion, is where the mesh puts it.
        let points = vec![[0.01, 0.02, -0.03], [-0.09, -0.04, 0.0], [0.0, 0.0, 0.0]];
        let s = traj.sample(&points, &[0.0]);
        for (p, y) in points.iter().zip(&s.frames[0]) {
            let exact = [p[0] + 0.3 * p[1], 2.0 * p[1], p[2] - 0.1];
            for k in 0..3 {
                assert!((y[k] - exact[k]).abs() < 1e-12, "{y:?} vs {exact:?}");
            }
        }
        let d = deviation(&s, &s, 1.0);
        assert_eq!(d.max, 0.0);
    }
}
