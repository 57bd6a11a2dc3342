//! Colliders, anchors and prescribed motion (the wall and jello projectiles, the
//! stretched and twisted bars of Chen et al. 2018 §6).
//!
//! Contact is by projection: a particle found inside a collider after a step is moved
//! to the collider's surface, its normal velocity relative to the collider is made
//! non-negative and Coulomb friction removes at most μ|Δv_n| of the tangential
//! velocity. A dynamic collider receives the opposite of the impulses it gave.
//!
//! Anchors hold the points inside a region of the scene at a prescribed rigid motion
//! until their release time.

use std::sync::Arc;

use perifrac_math::{IDENTITY3, UnitQuaternion, dot, mat_vec, norm, sub};
use rayon::prelude::*;

use crate::error::{Result, SimError};
use crate::geometry::mesh::{MeshSdf, TriMesh};
use crate::geometry::sdf::Sdf;
use crate::geometry::shape::placement;
use crate::scene::{ColliderSpec, KeyframeSpec, Scene};

mod anchor;
mod face;
mod mesh;

pub use anchor::{
    Anchor, anchor_power, anchors, apply_anchors, carry_clamp_forces, centroid, energy_budget,
    mark_anchored, rotate,
};
pub use face::face_clamps;
pub use mesh::MeshCollider;
use mesh::euler;

/// A collider's shape.
#[derive(Debug, Clone, PartialEq)]
pub enum ColliderShape {
    /// The plane y = `center[1]`, solid below.
    Ground,
    /// A sphere of this radius.
    Sphere(f64),
    /// An axis-aligned box with these half extents.
    Box([f64; 3]),
    /// A closed triangle mesh moved rigidly (shared, never changed).
    Mesh(Arc<MeshCollider>),
}

/// A rigid collider: kinematic (infinite mass) or dynamic.
#[derive(Debug, Clone, PartialEq)]
pub struct Collider {
    /// Shape.
    pub shape: ColliderShape,
    /// Current centre (for the ground, a point on the plane).
    pub center: [f64; 3],
    /// Current velocity.
    pub velocity: [f64; 3],
    /// Mass; `None` for kinematic.
    pub mass: Option<f64>,
    /// Gravity acts on it (dynamic only).
    pub gravity: bool,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
    /// Rotation from the placed pose (rows; the identity except for moving meshes).
    pub rotation: [[f64; 3]; 3],
    /// Angular velocity (rad/s; zero except for rotating meshes).
    pub angular_velocity: [f64; 3],
    /// The collider's clock (s): where a mesh is on its keyframes.
    pub time: f64,
}

/// The colliders of a scene, mesh files read and transform files parsed; an error
/// names the collider, the file and the line.
pub fn colliders(scene: &Scene) -> Result<Vec<Collider>> {
    scene
        .colliders
        .iter()
        .enumerate()
        .map(|(i, spec)| Collider::from_spec(spec, scene, i))
        .collect()
}

/// Refuses points that start inside a collider, deeper than `tolerance` (m): a ground
/// above a body, or a sphere, box or mesh placed through it. Contact would throw them
/// out in the first steps, and with every point of a body a contact pair the steps
/// never end (a ground at 1e308 m above the fuzzed glass wall). The error names the
/// collider, the point and the fix.
pub fn refuse_points_inside(
    colliders: &[Collider],
    position: &[[f64; 3]],
    tolerance: f64,
) -> Result<()> {
    for (index, c) in colliders.iter().enumerate() {
        let inside = position
            .par_iter()
            .position_first(|&p| c.penetration(p).is_some_and(|(_, depth)| depth > tolerance));
        if let Some(i) = inside {
            let p = position[i];
            let depth = c.penetration(p).map_or(0.0, |(_, d)| d);
            let what = match c.shape {
                ColliderShape::Ground => format!("the ground at height {} m", c.center[1]),
                ColliderShape::Sphere(_) => "a sphere".to_string(),
                ColliderShape::Box(_) => "a box".to_string(),
                ColliderShape::Mesh(_) => "a mesh".to_string(),
            };
            return Err(SimError::Collider {
                index,
                message: format!(
                    "{what}: a particle at ({:.4}, {:.4}, {:.4}) m starts {depth:.3e} m \
                     inside it; move the collider (or the body) so that no body starts \
                     inside a collider",
                    p[0], p[1], p[2]
                ),
            });
        }
    }
    Ok(())
}

/// The keyframes of a per-frame transforms file: line k (from 0, comments and blank
/// lines skipped) is the pose at t = k × `frame_time`.
fn read_transforms(
    path: &std::path::Path,
    frame_time: f64,
) -> std::result::Result<Vec<KeyframeSpec>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let values: Vec<f64> = line
            .split_whitespace()
            .map(str::parse::<f64>)
            .collect::<std::result::Result<_, _>>()
            .map_err(|e| {
                format!(
                    "{}:{}: {e}: a line is `tx ty tz rx ry rz` (m, degrees)",
                    path.display(),
                    n + 1
                )
            })?;
        if values.len() != 6 || !values.iter().all(|v| v.is_finite()) {
            return Err(format!(
                "{}:{}: a line is six finite numbers `tx ty tz rx ry rz` (m, degrees), got {}",
                path.display(),
                n + 1,
                values.len()
            ));
        }
        out.push(KeyframeSpec {
            time: out.len() as f64 * frame_time,
            translation: [values[0], values[1], values[2]],
            rotation: [values[3], values[4], values[5]],
        });
    }
    if out.is_empty() {
        return Err(format!(
            "{}: no poses: one line `tx ty tz rx ry rz` an output frame",
            path.display()
        ));
    }
    Ok(out)
}

impl Collider {
    /// Builds collider `index` of `scene` from its entry; mesh files are read relative
    /// to the scene.
    pub fn from_spec(spec: &ColliderSpec, scene: &Scene, index: usize) -> Result<Collider> {
        let still = |shape, center, velocity, mass, gravity, friction| Collider {
            shape,
            center,
            velocity,
            mass,
            gravity,
            friction,
            rotation: IDENTITY3,
            angular_velocity: [0.0; 3],
            time: 0.0,
        };
        Ok(match spec {
            &ColliderSpec::Ground { height, friction } => still(
                ColliderShape::Ground,
                [0.0, height, 0.0],
                [0.0; 3],
                None,
                false,
                friction,
            ),
            &ColliderSpec::Sphere {
                center,
                radius,
                velocity,
                mass,
                gravity,
                friction,
            } => still(
                ColliderShape::Sphere(radius),
                center,
                velocity,
                mass,
                gravity,
                friction,
            ),
            &ColliderSpec::Box {
                center,
                size,
                velocity,
                mass,
                gravity,
                friction,
            } => still(
                ColliderShape::Box([size[0] / 2.0, size[1] / 2.0, size[2] / 2.0]),
                center,
                velocity,
                mass,
                gravity,
                friction,
            ),
            ColliderSpec::Mesh {
                path,
                pivot,
                keyframes,
                transforms,
                friction,
                ..
            } => {
                let fail = |message: String| SimError::Collider { index, message };
                let shape = spec.mesh_shape().ok_or_else(|| fail("not a mesh".into()))?;
                let placed = placement(&shape).unwrap_or_default();
                let surface = TriMesh::load(&scene.base_dir.join(path), &placed)
                    .map_err(|e| fail(e.to_string()))?;
                let sdf = MeshSdf::new(&surface);
                let (lo, hi) = sdf.bounds();
                let pivot = pivot.unwrap_or([0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k])));
                let keys = match transforms {
                    Some(file) => read_transforms(&scene.base_dir.join(file), scene.frame_time())
                        .map_err(fail)?,
                    None => keyframes.clone(),
                };
                let mesh = MeshCollider {
                    sdf,
                    surface,
                    lo,
                    hi,
                    pivot,
                    keyframes: keys
                        .iter()
                        .map(|k| (k.time, k.translation, euler(k.rotation)))
                        .collect(),
                };
                let mut collider = still(
                    ColliderShape::Mesh(Arc::new(mesh)),
                    pivot,
                    [0.0; 3],
                    None,
                    false,
                    *friction,
                );
                collider.set_time(0.0);
                collider
            }
        })
    }

    /// Moves a mesh collider to its pose at time `t` (other colliders keep theirs).
    pub fn set_time(&mut self, t: f64) {
        self.time = t;
        let ColliderShape::Mesh(mesh) = &self.shape else {
            return;
        };
        let (translation, rotation, velocity, spin) = mesh.pose(t);
        self.center = [0, 1, 2].map(|k| mesh.pivot[k] + translation[k]);
        let r = rotation.to_rotation_matrix();
        self.rotation = [0, 1, 2].map(|i| [0, 1, 2].map(|j| r[(i, j)]));
        self.velocity = velocity;
        self.angular_velocity = spin;
    }

    /// The rotation of a mesh collider as a unit quaternion [x, y, z, w] (the identity
    /// for the others), for the manifest.
    pub fn orientation(&self) -> [f64; 4] {
        let r = perifrac_math::Rotation3::from_matrix_unchecked(perifrac_math::to_matrix(
            self.rotation,
        ));
        let q = UnitQuaternion::from_rotation_matrix(&r);
        [q.i, q.j, q.k, q.w]
    }

    /// The velocity of the collider's material at `p`: v + ω × (p − centre).
    pub fn velocity_at(&self, p: [f64; 3]) -> [f64; 3] {
        if !matches!(self.shape, ColliderShape::Mesh(_)) {
            return self.velocity;
        }
        let r = sub(p, self.center);
        let w = self.angular_velocity;
        [
            self.velocity[0] + w[1] * r[2] - w[2] * r[1],
            self.velocity[1] + w[2] * r[0] - w[0] * r[2],
            self.velocity[2] + w[0] * r[1] - w[1] * r[0],
        ]
    }

    /// If `p` is inside, the outward normal and the penetration depth.
    pub fn penetration(&self, p: [f64; 3]) -> Option<([f64; 3], f64)> {
        match &self.shape {
            ColliderShape::Ground => {
                let depth = self.center[1] - p[1];
                (depth > 0.0).then_some(([0.0, 1.0, 0.0], depth))
            }
            &ColliderShape::Sphere(radius) => {
                let d = sub(p, self.center);
                let l = norm(d);
                if l >= radius {
                    return None;
                }
                let n = if l > 0.0 {
                    [d[0] / l, d[1] / l, d[2] / l]
                } else {
                    [0.0, 1.0, 0.0]
                };
                Some((n, radius - l))
            }
            &ColliderShape::Box(half) => {
                let mut best: Option<([f64; 3], f64)> = None;
                for axis in 0..3 {
                    let d = p[axis] - self.center[axis];
                    let depth = half[axis] - d.abs();
                    if depth <= 0.0 {
                        return None;
                    }
                    if best.is_none_or(|(_, b)| depth < b) {
                        let mut n = [0.0; 3];
                        n[axis] = if d >= 0.0 { 1.0 } else { -1.0 };
                        best = Some((n, depth));
                    }
                }
                best
            }
            ColliderShape::Mesh(mesh) => {
                // The point in the placed mesh's frame: pivot + Rᵀ(p − centre).
                let d = sub(p, self.center);
                let r = &self.rotation;
                let local = [0, 1, 2]
                    .map(|k| mesh.pivot[k] + r[0][k] * d[0] + r[1][k] * d[1] + r[2][k] * d[2]);
                if (0..3).any(|k| local[k] < mesh.lo[k] || local[k] > mesh.hi[k]) {
                    return None;
                }
                let depth = -mesh.sdf.distance(local);
                if depth <= 0.0 {
                    return None;
                }
                let out = sub(mesh.sdf.closest_point(local), local);
                let l = norm(out);
                let n = if l > 0.0 {
                    out.map(|x| x / l)
                } else {
                    [0.0, 1.0, 0.0]
                };
                Some((mat_vec(self.rotation, n), depth))
            }
        }
    }

    /// For a mesh collider and a point `p` outside it, the distance to its surface and
    /// the outward normal there; `None` inside it (or for the other shapes).
    pub fn outside(&self, p: [f64; 3]) -> Option<(f64, [f64; 3])> {
        let ColliderShape::Mesh(mesh) = &self.shape else {
            return None;
        };
        let d = sub(p, self.center);
        let r = &self.rotation;
        let local =
            [0, 1, 2].map(|k| mesh.pivot[k] + r[0][k] * d[0] + r[1][k] * d[1] + r[2][k] * d[2]);
        let gap = mesh.sdf.distance(local);
        if gap <= 0.0 {
            return None;
        }
        let out = sub(local, mesh.sdf.closest_point(local));
        let l = norm(out);
        let n = if l > 0.0 {
            out.map(|x| x / l)
        } else {
            [0.0, 1.0, 0.0]
        };
        Some((gap, mat_vec(self.rotation, n)))
    }

    /// Kinetic energy ½ M v² (zero for kinematic colliders).
    pub fn kinetic_energy(&self) -> f64 {
        self.mass
            .map_or(0.0, |m| 0.5 * m * dot(self.velocity, self.velocity))
    }
}

/// Resolves contact of every particle against every collider; returns the impulse
/// each collider received (the sum, in particle order, of the opposite of the
/// particles' momentum changes).
pub fn resolve(
    colliders: &[Collider],
    position: &mut [[f64; 3]],
    velocity: &mut [[f64; 3]],
    mass: &[f64],
    anchored: &[bool],
) -> Vec<[f64; 3]> {
    let mut impulses = vec![[0.0; 3]; colliders.len()];
    if colliders.is_empty() {
        return impulses;
    }
    let changes: Vec<(usize, usize, [f64; 3])> = position
        .par_iter_mut()
        .zip(velocity.par_iter_mut())
        .enumerate()
        .with_min_len(256)
        .flat_map_iter(|(i, (p, v))| {
            let mut out = Vec::new();
            if anchored.get(i).copied().unwrap_or(false) {
                return out;
            }
            for (c, col) in colliders.iter().enumerate() {
                let Some((n, depth)) = col.penetration(*p) else {
                    continue;
                };
                for a in 0..3 {
                    p[a] += depth * n[a];
                }
                let cv = col.velocity_at(*p);
                let rel = [v[0] - cv[0], v[1] - cv[1], v[2] - cv[2]];
                let vn = dot(rel, n);
                if vn >= 0.0 {
                    continue;
                }
                let tangential = [rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]];
                let vt = dot(tangential, tangential).sqrt();
                let keep = if vt > 0.0 {
                    (1.0 - col.friction * (-vn) / vt).max(0.0)
                } else {
                    0.0
                };
                let new = [
                    cv[0] + keep * tangential[0],
                    cv[1] + keep * tangential[1],
                    cv[2] + keep * tangential[2],
                ];
                let dv = [new[0] - v[0], new[1] - v[1], new[2] - v[2]];
                *v = new;
                out.push((c, i, dv));
            }
            out
        })
        .collect();
    for (c, i, dv) in changes {
        for a in 0..3 {
            impulses[c][a] -= mass[i] * dv[a];
        }
    }
    impulses
}

/// Moves the colliders by one step of `dt` ending at `time`: dynamic ones take their
/// impulses and gravity, meshes go to their pose at `time` (the world's clock, not a
/// sum of steps, so that a resumed run, whose clock restarts at the checkpoint's time,
/// puts them where the whole run does to the bit).
pub fn advance(
    colliders: &mut [Collider],
    impulses: &[[f64; 3]],
    gravity: [f64; 3],
    dt: f64,
    time: f64,
) {
    advance_except(colliders, impulses, gravity, dt, time, &[]);
}

/// [`advance`] for the colliders whose `skip` entry is not true (the rigid phase
/// moves those).
pub fn advance_except(
    colliders: &mut [Collider],
    impulses: &[[f64; 3]],
    gravity: [f64; 3],
    dt: f64,
    time: f64,
    skip: &[bool],
) {
    for (i, (c, j)) in colliders.iter_mut().zip(impulses).enumerate() {
        if skip.get(i).copied().unwrap_or(false) {
            continue;
        }
        if matches!(c.shape, ColliderShape::Mesh(_)) {
            c.set_time(time);
            continue;
        }
        if let Some(m) = c.mass {
            let g = if c.gravity { gravity } else { [0.0; 3] };
            for a in 0..3 {
                c.velocity[a] += j[a] / m + g[a] * dt;
            }
        }
        if !matches!(c.shape, ColliderShape::Ground) {
            for a in 0..3 {
                c.center[a] += c.velocity[a] * dt;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test_scene() -> Scene {
        let text = "[scene]\n[materials.m]\ndensity = 1.0\nbulk_modulus = 1.0\nshear_modulus = 1.0\n\
                    [[body]]\nmaterial = \"m\"\nresolution = 0.1\nshape = { type = \"sphere\", center = [0, 0, 0], radius = 1 }\n";
        Scene::parse(
            text,
            std::path::Path::new("t.toml"),
            std::path::Path::new("."),
        )
        .expect("scene")
    }

    #[test]
    fn ground_stops_and_frictions() {
        let scene = test_scene();
        let ground = Collider::from_spec(
            &ColliderSpec::Ground {
                height: 0.0,
                friction: 0.5,
            },
            &scene,
            0,
        )
        .expect("ground");
        let mut p = vec![[0.0, -0.01, 0.0]];
        let mut v = vec![[1.0, -1.0, 0.0]];
        resolve(&[ground], &mut p, &mut v, &[1.0], &[false]);
        assert_eq!(p[0][1], 0.0);
        assert_eq!(v[0][1], 0.0);
        assert!(
            (v[0][0] - 0.5).abs() < 1e-12,
            "friction removes μ|Δv_n| = 0.5"
        );
    }

    #[test]
    fn dynamic_sphere_gets_opposite_impulse() {
        let spec = ColliderSpec::Sphere {
            center: [0.0; 3],
            radius: 1.0,
            velocity: [1.0, 0.0, 0.0],
            mass: Some(10.0),
            gravity: false,
            friction: 0.0,
        };
        let mut cols = vec![Collider::from_spec(&spec, &test_scene(), 0).expect("sphere")];
        let mut p = vec![[0.9, 0.0, 0.0]];
        let mut v = vec![[0.0; 3]];
        let j = resolve(&cols, &mut p, &mut v, &[2.0], &[false]);
        assert!((v[0][0] - 1.0).abs() < 1e-12);
        advance(&mut cols, &j, [0.0; 3], 0.0, 0.0);
        let momentum = 2.0 * v[0][0] + 10.0 * cols[0].velocity[0];
        assert!(
            (momentum - 10.0).abs() < 1e-12,
            "momentum conserved: {momentum}"
        );
    }

    #[test]
    fn anchor_rotation_is_rigid() {
        let a = Anchor {
            clamp: None,
            particles: vec![],
            velocity: [0.0; 3],
            angular_velocity: [0.0, 0.0, std::f64::consts::FRAC_PI_2],
            center: [0.0; 3],
            until: f64::INFINITY,
        };
        let (y, v) = a.motion([1.0, 0.0, 0.0], 1.0);
        assert!((y[0]).abs() < 1e-12 && (y[1] - 1.0).abs() < 1e-12);
        assert!((v[0] + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
