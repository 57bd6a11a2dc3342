//! A mesh collider: its placed surface, exact signed distance and keyframed motion.

use perifrac_math::{UnitQuaternion, Vector3, from_vector, norm, sub};

use crate::cache::collider::ColliderMesh;
use crate::geometry::mesh::{MeshSdf, TriMesh};

/// A mesh collider: the placed mesh's exact signed distance and its rigid motion, x ↦
/// pivot + R(t)(x − pivot) + T(t), with T and R interpolated between keyframes
/// (linearly, and by slerp: a constant angular velocity within a segment).
#[derive(Debug)]
pub struct MeshCollider {
    pub(super) sdf: MeshSdf,
    /// The placed mesh (what the cache's `colliders/mesh_N.ply` is made of).
    pub(super) surface: TriMesh,
    /// Bounds of the placed mesh, for a quick rejection.
    pub(super) lo: [f64; 3],
    pub(super) hi: [f64; 3],
    /// Centre of rotation (m).
    pub pivot: [f64; 3],
    /// (time, translation, rotation) at increasing times; empty for a static mesh.
    pub(super) keyframes: Vec<(f64, [f64; 3], UnitQuaternion<f64>)>,
}

impl PartialEq for MeshCollider {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self, other)
    }
}

/// The rotation of a keyframe: degrees about x, then y, then z (R = Rz Ry Rx).
pub(super) fn euler(rotation_deg: [f64; 3]) -> UnitQuaternion<f64> {
    let [x, y, z] = rotation_deg.map(f64::to_radians);
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), z)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), y)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), x)
}

impl MeshCollider {
    /// The pose at time `t`: translation T, rotation R, and the velocity of the frame
    /// (Ṫ and the angular velocity ω of the segment).
    pub fn pose(&self, t: f64) -> ([f64; 3], UnitQuaternion<f64>, [f64; 3], [f64; 3]) {
        let keys = &self.keyframes;
        let still = |k: &(f64, [f64; 3], UnitQuaternion<f64>)| (k.1, k.2, [0.0; 3], [0.0; 3]);
        match keys.iter().position(|k| k.0 > t) {
            None => keys.last().map_or(
                ([0.0; 3], UnitQuaternion::identity(), [0.0; 3], [0.0; 3]),
                still,
            ),
            Some(0) => still(&keys[0]),
            Some(k) => {
                let (a, b) = (&keys[k - 1], &keys[k]);
                let span = b.0 - a.0;
                let s = (t - a.0) / span;
                let translation = [0, 1, 2].map(|i| a.1[i] + s * (b.1[i] - a.1[i]));
                let rotation = a.2.slerp(&b.2, s);
                let velocity = [0, 1, 2].map(|i| (b.1[i] - a.1[i]) / span);
                let relative = b.2 * a.2.inverse();
                let spin = relative.scaled_axis() / span;
                (translation, rotation, velocity, from_vector(&spin))
            }
        }
    }
}

impl MeshCollider {
    /// The placed mesh less the pivot, in f32: the collider's geometry as the cache
    /// stores it (`colliders/mesh_N.ply`), posed at each frame by the manifest's centre
    /// and rotation.
    pub fn cache_mesh(&self) -> ColliderMesh {
        ColliderMesh {
            positions: self
                .surface
                .vertices
                .iter()
                .map(|v| [0, 1, 2].map(|k| (v[k] - self.pivot[k]) as f32))
                .collect(),
            triangles: self.surface.triangles.clone(),
            pivot: self.pivot,
        }
    }

    /// The placed mesh less the pivot, and its triangles: the geometry in the frame
    /// that the collider's pose (centre pivot + T, rotation R) places.
    pub fn local_surface(&self) -> (Vec<[f64; 3]>, &[[u32; 3]]) {
        let positions = self
            .surface
            .vertices
            .iter()
            .map(|&v| sub(v, self.pivot))
            .collect();
        (positions, &self.surface.triangles)
    }

    /// The fastest any point of the mesh moves over its keyframes (m/s): |Ṫ| + |ω| ×
    /// the farthest corner of its bounds from the pivot, over the segments.
    pub fn max_speed(&self) -> f64 {
        let reach = (0..8)
            .map(|c| {
                let corner = [0, 1, 2].map(|k| {
                    if c >> k & 1 == 1 {
                        self.hi[k]
                    } else {
                        self.lo[k]
                    }
                });
                norm(sub(corner, self.pivot))
            })
            .fold(0.0f64, f64::max);
        self.keyframes
            .windows(2)
            .map(|w| {
                let span = w[1].0 - w[0].0;
                let v = norm(sub(w[1].1, w[0].1)) / span;
                let spin = (w[1].2 * w[0].2.inverse()).angle() / span;
                v + spin * reach
            })
            .fold(0.0f64, f64::max)
    }
}
