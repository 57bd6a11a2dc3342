//! From a cache frame to what a surfacer needs: each particle's sphere radius, the
//! particle spacing, the fragments (and which are too small to surface), and the
//! check that refuses single layers of particles (membranes, sheets).
//!
//! Particle volumes are not in the cache. The BCC mesher makes about
//! [`TETS_PER_LAMBDA3`] tets per λ³, λ being a body's mean tet edge (in the
//! manifest), so a particle's volume is about λ³/9.1 and its spacing
//! s = (λ³/9.1)^(1/3).

use std::collections::{BTreeMap, HashMap};

use perifrac_cache::manifest::BodyInfo;
use perifrac_cache::ply::ParticleFrame;
use perifrac_math::{dot, sub};

use crate::error::{Result, SurfaceError};

/// Tets (particles) the BCC mesher makes per λ³, λ the mean tet edge.
pub const TETS_PER_LAMBDA3: f64 = 9.1;

pub use perifrac_cache::scene::SPHERE_RADIUS_PER_SPACING;

/// A body whose particles' neighbourhoods are thinner than this (median, in particle
/// spacings) is taken for a single layer.
pub const SINGLE_LAYER_THICKNESS: f64 = 1.0;

/// Particle spacing s = (λ³/9.1)^(1/3) of a body with mean tet edge λ.
pub fn spacing(mean_edge: f64) -> f64 {
    (mean_edge.powi(3) / TETS_PER_LAMBDA3).cbrt()
}

/// The particle spacing of a body of the manifest: its own `particle_spacing` where
/// the model set one (MPM, membranes), else [`spacing`] of its mean tet edge.
pub fn body_spacing(info: &BodyInfo) -> f64 {
    if info.particle_spacing > 0.0 {
        info.particle_spacing
    } else {
        spacing(info.mean_edge)
    }
}

/// Each particle's body index, checked against the manifest's bodies.
pub fn body_indices(
    frame: usize,
    particles: &ParticleFrame,
    bodies: &[BodyInfo],
) -> Result<Vec<u32>> {
    particles
        .material
        .iter()
        .enumerate()
        .map(|(i, &m)| {
            if m >= 0.0 && m.fract() == 0.0 && (m as usize) < bodies.len() {
                Ok(m as u32)
            } else {
                Err(SurfaceError::Frame {
                    frame,
                    message: format!(
                        "particle {i} has body index {m}, but the manifest lists {} bodies",
                        bodies.len()
                    ),
                })
            }
        })
        .collect()
}

/// Fails on a frame without particles or with a non-finite position or velocity.
pub fn check_finite(frame: usize, particles: &ParticleFrame) -> Result<()> {
    if particles.is_empty() {
        return Err(SurfaceError::Frame {
            frame,
            message: "the frame has no particles: nothing to surface".into(),
        });
    }
    let bad = |v: &[f32; 3]| !v.iter().all(|x| x.is_finite());
    if let Some(i) = particles.position.iter().position(bad) {
        return Err(SurfaceError::Frame {
            frame,
            message: format!(
                "particle {i} has a non-finite position {:?} (did the simulation blow up?)",
                particles.position[i]
            ),
        });
    }
    if let Some(i) = particles.velocity.iter().position(bad) {
        return Err(SurfaceError::Frame {
            frame,
            message: format!(
                "particle {i} has a non-finite velocity {:?}",
                particles.velocity[i]
            ),
        });
    }
    Ok(())
}

/// The particles of each fragment id, fragments in increasing id order.
pub fn fragments(frame: usize, particles: &ParticleFrame) -> Result<Vec<(u32, Vec<u32>)>> {
    let mut groups: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (i, &f) in particles.fragment.iter().enumerate() {
        if !(f >= 0.0 && f.fract() == 0.0 && f <= u32::MAX as f32) {
            return Err(SurfaceError::Frame {
                frame,
                message: format!("particle {i} has fragment id {f}, not a whole number ≥ 0"),
            });
        }
        groups.entry(f as u32).or_default().push(i as u32);
    }
    Ok(groups.into_iter().collect())
}

/// Fails if a body's particles form a single layer: the median, over up to 256
/// sampled particles, of the thickness of the particles within two spacings
/// (their extent along their thinnest principal axis) is below
/// [`SINGLE_LAYER_THICKNESS`] spacings. Such a body has no volume to rasterize.
pub fn check_volumetric(
    frame: usize,
    particles: &ParticleFrame,
    body: &[u32],
    bodies: &[BodyInfo],
) -> Result<()> {
    let mut members: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (i, &b) in body.iter().enumerate() {
        members.entry(b).or_default().push(i as u32);
    }
    for (b, indices) in members {
        let info = &bodies[b as usize];
        let s = body_spacing(info);
        if let Some(thickness) = local_thickness(&particles.position, &indices, s)
            && thickness < SINGLE_LAYER_THICKNESS
        {
            return Err(SurfaceError::SingleLayer {
                frame,
                body: info.name.clone(),
                thickness,
            });
        }
    }
    Ok(())
}

/// Median thickness, in spacings, of the neighbourhoods (radius two spacings) of up
/// to 256 of `indices`; `None` when no sampled particle has enough neighbours to
/// tell (sparse debris).
pub fn local_thickness(positions: &[[f32; 3]], indices: &[u32], spacing: f64) -> Option<f64> {
    const SAMPLES: usize = 256;
    const MIN_NEIGHBOURS: usize = 6;
    let radius = 2.0 * spacing;
    let grid = Bins::new(positions, indices, radius);
    let stride = indices.len().div_ceil(SAMPLES).max(1);
    let mut thickness: Vec<f64> = Vec::new();
    let mut neighbours: Vec<[f64; 3]> = Vec::new();
    for &i in indices.iter().step_by(stride) {
        let p = positions[i as usize].map(f64::from);
        neighbours.clear();
        for j in grid.around(positions[i as usize]) {
            let q = positions[j as usize].map(f64::from);
            let d = sub(q, p);
            if dot(d, d) <= radius * radius {
                neighbours.push(q);
            }
        }
        if neighbours.len() < MIN_NEIGHBOURS {
            continue;
        }
        let n = neighbours.len() as f64;
        let mut mean = [0.0; 3];
        for q in &neighbours {
            for k in 0..3 {
                mean[k] += q[k] / n;
            }
        }
        let mut cov = [[0.0; 3]; 3];
        for q in &neighbours {
            let d = [q[0] - mean[0], q[1] - mean[1], q[2] - mean[2]];
            for r in 0..3 {
                for c in 0..3 {
                    cov[r][c] += d[r] * d[c] / n;
                }
            }
        }
        let axis = thinnest_axis(cov);
        let (lo, hi) = neighbours.iter().fold((f64::MAX, f64::MIN), |(lo, hi), q| {
            let t = (q[0] - mean[0]) * axis[0]
                + (q[1] - mean[1]) * axis[1]
                + (q[2] - mean[2]) * axis[2];
            (lo.min(t), hi.max(t))
        });
        thickness.push((hi - lo) / spacing);
    }
    if thickness.is_empty() {
        return None;
    }
    thickness.sort_by(f64::total_cmp);
    Some(thickness[thickness.len() / 2])
}

/// Particle indices binned in cubes of a side `size`, for searches within `size`.
struct Bins {
    size: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl Bins {
    fn new(positions: &[[f32; 3]], indices: &[u32], size: f64) -> Bins {
        let mut bins = Bins {
            size,
            cells: HashMap::new(),
        };
        for &i in indices {
            let c = bins.cell(positions[i as usize]);
            bins.cells.entry(c).or_default().push(i);
        }
        bins
    }

    fn cell(&self, p: [f32; 3]) -> [i64; 3] {
        p.map(|x| (f64::from(x) / self.size).floor() as i64)
    }

    /// The indices in the 27 cubes around `p`: every one within `size` of it, and more.
    fn around(&self, p: [f32; 3]) -> impl Iterator<Item = u32> + '_ {
        let c = self.cell(p);
        (0..27).flat_map(move |k| {
            let at = [c[0] + k % 3 - 1, c[1] + (k / 3) % 3 - 1, c[2] + k / 9 - 1];
            self.cells.get(&at).into_iter().flatten().copied()
        })
    }
}

/// Each of `vertices`' damage: that of the nearest of the particles `indices` within
/// `reach` of it, or 0 where none is (a surface's vertex lies about a sphere radius
/// from its particles). The `vdb` method's meshes carry it, so that previews
/// coloured by damage show the cracks of particle caches.
pub fn nearest_damage(
    vertices: &[[f32; 3]],
    positions: &[[f32; 3]],
    damage: &[f32],
    indices: &[u32],
    reach: f64,
) -> Vec<f32> {
    let bins = Bins::new(positions, indices, reach);
    vertices
        .iter()
        .map(|&v| {
            let p = v.map(f64::from);
            let nearest = bins
                .around(v)
                .map(|j| {
                    let d = sub(positions[j as usize].map(f64::from), p);
                    (dot(d, d), j)
                })
                .filter(|&(r2, _)| r2 <= reach * reach)
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            nearest.map_or(0.0, |(_, j)| damage[j as usize])
        })
        .collect()
}

/// The unit eigenvector of the smallest eigenvalue of a symmetric 3×3 matrix
/// (cyclic Jacobi rotations).
pub fn thinnest_axis(mut a: [[f64; 3]; 3]) -> [f64; 3] {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
    for _sweep in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= 1e-15 * scale || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * row_p[k] - s * row_q[k]);
            a[q] = std::array::from_fn(|k| s * row_p[k] + c * row_q[k]);
            for row in v.iter_mut() {
                let (vkp, vkq) = (row[p], row[q]);
                row[p] = c * vkp - s * vkq;
                row[q] = s * vkp + c * vkq;
            }
        }
    }
    let smallest = (0..3)
        .min_by(|&i, &j| a[i][i].total_cmp(&a[j][j]))
        .unwrap_or(0);
    [v[0][smallest], v[1][smallest], v[2][smallest]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertex_takes_its_nearest_particles_damage() {
        let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [5.0, 0.0, 0.0]];
        let damage = [0.1, 0.7, 0.9];
        let vertices = [
            [0.2, 0.1, 0.0],
            [0.8, -0.1, 0.0],
            [3.0, 0.0, 0.0],
            [5.0, 1.0, 0.5],
        ];
        // Particle 2 is left out: the last vertex is nearest to it but it is not asked.
        let got = nearest_damage(&vertices, &positions, &damage, &[0, 1], 1.5);
        assert_eq!(got, vec![0.1, 0.7, 0.0, 0.0]);
        let got = nearest_damage(&vertices, &positions, &damage, &[0, 1, 2], 2.5);
        assert_eq!(got, vec![0.1, 0.7, 0.7, 0.9]);
    }

    #[test]
    fn thinnest_axis_of_a_rotated_ellipsoid() {
        // diag(4, 1, 0.25) rotated 30° about z: the thinnest axis stays z.
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let r = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let d = [4.0, 1.0, 0.25];
        let mut a = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] = (0..3).map(|k| r[i][k] * d[k] * r[j][k]).sum();
            }
        }
        let axis = thinnest_axis(a);
        assert!((axis[2].abs() - 1.0).abs() < 1e-9, "{axis:?}");
        // Now rotated about x so the thin axis tilts.
        let a = [[1.0, 0.0, 0.0], [0.0, 2.0, 1.9], [0.0, 1.9, 2.0]];
        let axis = thinnest_axis(a);
        let expected = [0.0, -(0.5f64).sqrt(), (0.5f64).sqrt()];
        let dot: f64 = (0..3).map(|k| axis[k] * expected[k]).sum();
        assert!((dot.abs() - 1.0).abs() < 1e-9, "{axis:?}");
    }

    #[test]
    fn a_plane_is_thin_and_a_block_is_not() {
        let s = 0.01;
        let plane: Vec<[f32; 3]> = (0..30 * 30)
            .map(|i| {
                let (x, y) = ((i % 30) as f32, (i / 30) as f32);
                // A tilted plane, so no axis is special.
                [x * 0.01, y * 0.007, y * 0.00714]
            })
            .collect();
        let all: Vec<u32> = (0..plane.len() as u32).collect();
        let t = local_thickness(&plane, &all, s).expect("dense enough");
        assert!(t < 0.05, "{t}");
        let block: Vec<[f32; 3]> = (0..12 * 12 * 4)
            .map(|i| {
                [
                    (i % 12) as f32 * 0.01,
                    (i / 12 % 12) as f32 * 0.01,
                    (i / 144) as f32 * 0.01,
                ]
            })
            .collect();
        let all: Vec<u32> = (0..block.len() as u32).collect();
        let t = local_thickness(&block, &all, s).expect("dense enough");
        assert!(t >= 2.0, "{t}");
        assert_eq!(local_thickness(&block[..3], &[0, 1, 2], s), None);
    }
}
