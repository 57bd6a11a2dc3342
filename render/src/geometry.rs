//! What a preview draws, as flat arrays ready for upload: one triangle buffer (surfaces,
//! crack faces, colliders) and one point buffer (particles as sphere impostors), plus
//! the ground height; and the colour maps that turn per-particle or per-vertex values
//! into colours.

use perifrac_math::{Quaternion, UnitQuaternion, Vector3, add, cross, normalize, scale, sub};

use crate::camera::{self, Bounds, Mat4};

/// Floats a mesh vertex: position (3), normal (3), linear colour (3), material (1).
pub const MESH_STRIDE: usize = 10;
/// Floats a point: position (3), radius (1), linear colour (3).
pub const POINT_STRIDE: usize = 7;

/// How a mesh face is shaded (stored in the vertex, read by the fragment shader).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shading {
    /// The original surface.
    Surface = 0,
    /// A crack face (the inside that fracture exposed): rougher, no gloss.
    Crack = 1,
    /// A rigid collider: polished metal.
    Collider = 2,
}

/// Geometry of one frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameGeometry {
    /// Interleaved mesh vertices ([`MESH_STRIDE`] floats each).
    pub mesh_vertices: Vec<f32>,
    /// Three vertex indices a triangle.
    pub mesh_indices: Vec<u32>,
    /// Interleaved points ([`POINT_STRIDE`] floats each).
    pub points: Vec<f32>,
    /// Height of the ground plane, if the scene has one (else the ground sits under the
    /// bounds).
    pub ground: Option<f32>,
}

impl FrameGeometry {
    /// Mesh vertices.
    pub fn vertex_count(&self) -> usize {
        self.mesh_vertices.len() / MESH_STRIDE
    }

    /// Triangles.
    pub fn triangle_count(&self) -> usize {
        self.mesh_indices.len() / 3
    }

    /// Points.
    pub fn point_count(&self) -> usize {
        self.points.len() / POINT_STRIDE
    }

    /// Appends a triangle mesh; `normals` are recomputed from the faces when `None`.
    pub fn push_mesh(
        &mut self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
        colors: &dyn Fn(usize) -> [f32; 3],
        indices: &[u32],
        shading: Shading,
    ) {
        let base = self.vertex_count() as u32;
        let computed;
        let normals = match normals {
            Some(n) if n.len() == positions.len() => n,
            _ => {
                computed = face_normals(positions, indices);
                &computed
            }
        };
        self.mesh_vertices.reserve(positions.len() * MESH_STRIDE);
        for (i, (p, n)) in positions.iter().zip(normals).enumerate() {
            self.mesh_vertices.extend_from_slice(p);
            self.mesh_vertices.extend_from_slice(n);
            self.mesh_vertices.extend_from_slice(&colors(i));
            self.mesh_vertices.push(shading as u32 as f32);
        }
        self.mesh_indices.extend(
            indices
                .iter()
                .filter(|&&i| (i as usize) < positions.len())
                .map(|&i| base + i),
        );
        let whole = self.mesh_indices.len() / 3 * 3;
        self.mesh_indices.truncate(whole);
    }

    /// Appends a point.
    pub fn push_point(&mut self, position: [f32; 3], radius: f32, color: [f32; 3]) {
        self.points.extend_from_slice(&position);
        self.points.push(radius);
        self.points.extend_from_slice(&color);
    }

    /// Appends a sphere (a latitude–longitude mesh, smooth normals).
    pub fn push_sphere(&mut self, center: [f32; 3], radius: f32, color: [f32; 3]) {
        let (rings, segments) = (24u32, 48u32);
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        for r in 0..=rings {
            let theta = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..=segments {
                let phi = std::f32::consts::TAU * s as f32 / segments as f32;
                let n = [
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                ];
                positions.push(add(center, scale(n, radius)));
                normals.push(n);
            }
        }
        let mut indices = Vec::new();
        let row = segments + 1;
        for r in 0..rings {
            for s in 0..segments {
                let (a, b) = (r * row + s, (r + 1) * row + s);
                indices.extend_from_slice(&[a, a + 1, b, b, a + 1, b + 1]);
            }
        }
        self.push_mesh(
            &positions,
            Some(&normals),
            &|_| color,
            &indices,
            Shading::Collider,
        );
    }

    /// Appends a collider's triangles with flat faces (each triangle its own three
    /// vertices and its face normal), as the solver sees them.
    pub fn push_flat_mesh(
        &mut self,
        positions: &[[f32; 3]],
        triangles: &[[u32; 3]],
        color: [f32; 3],
    ) {
        let corners: Vec<[f32; 3]> = triangles
            .iter()
            .filter(|t| t.iter().all(|&v| (v as usize) < positions.len()))
            .flat_map(|t| t.map(|v| positions[v as usize]))
            .collect();
        let indices: Vec<u32> = (0..corners.len() as u32).collect();
        let normals: Vec<[f32; 3]> = corners
            .chunks_exact(3)
            .flat_map(|t| [normalize(cross(sub(t[1], t[0]), sub(t[2], t[0]))); 3])
            .collect();
        self.push_mesh(
            &corners,
            Some(&normals),
            &|_| color,
            &indices,
            Shading::Collider,
        );
    }

    /// Appends an axis-aligned box (flat faces).
    pub fn push_box(&mut self, center: [f32; 3], size: [f32; 3], color: [f32; 3]) {
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut indices = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let base = positions.len() as u32;
                let mut n = [0.0; 3];
                n[axis] = sign;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    let mut p = center;
                    p[axis] += sign * 0.5 * size[axis];
                    p[u] += a * 0.5 * size[u];
                    p[v] += b * 0.5 * size[v];
                    positions.push(p);
                    normals.push(n);
                }
                if sign > 0.0 {
                    indices.extend_from_slice(&[
                        base,
                        base + 1,
                        base + 2,
                        base,
                        base + 2,
                        base + 3,
                    ]);
                } else {
                    indices.extend_from_slice(&[
                        base,
                        base + 2,
                        base + 1,
                        base,
                        base + 3,
                        base + 2,
                    ]);
                }
            }
        }
        self.push_mesh(
            &positions,
            Some(&normals),
            &|_| color,
            &indices,
            Shading::Collider,
        );
    }

    /// Bounds of everything drawn (points grown by their radius).
    pub fn bounds(&self) -> Bounds {
        let mut b = Bounds::EMPTY;
        for v in self.mesh_vertices.chunks_exact(MESH_STRIDE) {
            b.add([v[0], v[1], v[2]]);
        }
        for p in self.points.chunks_exact(POINT_STRIDE) {
            let r = p[3];
            b.add([p[0] - r, p[1] - r, p[2] - r]);
            b.add([p[0] + r, p[1] + r, p[2] + r]);
        }
        b
    }

    /// How many mesh vertices and points of the simulated bodies (colliders not
    /// counted) land inside the view volume of `view_projection`.
    pub fn count_in_view(&self, view_projection: &Mat4) -> usize {
        let inside = |p: [f32; 3]| {
            let c = camera::transform(view_projection, p);
            c[3] > 0.0 && (0..3).all(|k| c[k].abs() <= c[3])
        };
        self.mesh_vertices
            .chunks_exact(MESH_STRIDE)
            .filter(|v| v[9] != Shading::Collider as u32 as f32 && inside([v[0], v[1], v[2]]))
            .count()
            + self
                .points
                .chunks_exact(POINT_STRIDE)
                .filter(|p| inside([p[0], p[1], p[2]]))
                .count()
    }
}

/// `positions` moved to the pose x ↦ `center` + R x, R the unit quaternion `rotation`
/// [x, y, z, w] (a mesh collider at a frame: `manifest.json`'s centre and rotation).
pub fn posed(positions: &[[f32; 3]], center: [f64; 3], rotation: [f64; 4]) -> Vec<[f32; 3]> {
    let [x, y, z, w] = rotation;
    let r = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
    positions
        .iter()
        .map(|p| {
            let q = r * Vector3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            [0, 1, 2].map(|k| (center[k] + q[k]) as f32)
        })
        .collect()
}

/// Area-weighted vertex normals.
pub fn face_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut normals = vec![[0.0f32; 3]; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
        if a.max(b).max(c) >= positions.len() {
            continue;
        }
        let n = cross(
            sub(positions[b], positions[a]),
            sub(positions[c], positions[a]),
        );
        for i in [a, b, c] {
            normals[i] = add(normals[i], n);
        }
    }
    normals.into_iter().map(normalize).collect()
}

/// sRGB-encoded component → linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// An sRGB colour (components in [0, 1]) as the linear values the shaders take.
pub fn linear(rgb: [f32; 3]) -> [f32; 3] {
    rgb.map(srgb_to_linear)
}

/// Piecewise-linear map through sRGB `stops` at `t` in [0, 1], returned linear.
fn ramp(stops: &[[f32; 3]], t: f32) -> [f32; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (stops.len() - 1) as f32;
    let i = (x.floor() as usize).min(stops.len() - 2);
    let f = x - i as f32;
    linear(std::array::from_fn(|k| {
        stops[i][k] * (1.0 - f) + stops[i + 1][k] * f
    }))
}

/// Damage φ ∈ [0, 1] as a colour: blue intact → red broken, as in Chen et al. 2018,
/// Fig. 6 ("blue as no damage and red as complete damage"); Moreland's cool–warm map, so
/// half-broken reads as neutral grey.
pub fn damage_color(phi: f32) -> [f32; 3] {
    ramp(
        &[
            [0.230, 0.299, 0.754],
            [0.865, 0.865, 0.865],
            [0.706, 0.016, 0.150],
        ],
        phi,
    )
}

/// Five sRGB stops of a sequential map, dark purple → blue → green → yellow
/// (viridis-like: lightness rises steadily, readable in grey and by the colour-blind).
const VIRIDIS: [[f32; 3]; 5] = [
    [0.267, 0.005, 0.329],
    [0.231, 0.322, 0.545],
    [0.129, 0.569, 0.549],
    [0.369, 0.788, 0.384],
    [0.993, 0.906, 0.144],
];

/// The viridis-like map for plastic strain `t` already scaled to [0, 1].
pub fn plastic_color(t: f32) -> [f32; 3] {
    ramp(&VIRIDIS, t)
}

/// A membrane's diffused quantity θ as a colour (linear RGB): the viridis-like map
/// over `range` = [θ_lo, θ_hi], dark purple at θ_lo, yellow at θ_hi, clamped outside
/// (a range of zero width gives θ_lo's colour). The previews and the sheet glb files'
/// `COLOR_0` use this one map.
pub fn quantity_color(theta: f32, range: [f32; 2]) -> [f32; 3] {
    let span = range[1] - range[0];
    let t = if span > 0.0 {
        (theta - range[0]) / span
    } else {
        0.0
    };
    ramp(&VIRIDIS, t)
}

/// A black-body-like map (inferno-like) for temperature `t` scaled to [0, 1].
pub fn temperature_color(t: f32) -> [f32; 3] {
    ramp(
        &[
            [0.0015, 0.0005, 0.014],
            [0.341, 0.062, 0.429],
            [0.735, 0.215, 0.330],
            [0.978, 0.557, 0.035],
            [0.988, 0.998, 0.645],
        ],
        t,
    )
}

/// A distinct colour for fragment `id` (twelve well-separated hues, cycled).
pub fn fragment_color(id: f32) -> [f32; 3] {
    const PALETTE: [[f32; 3]; 12] = [
        [0.121, 0.467, 0.706],
        [1.000, 0.498, 0.055],
        [0.173, 0.627, 0.173],
        [0.839, 0.153, 0.157],
        [0.580, 0.404, 0.741],
        [0.549, 0.337, 0.294],
        [0.890, 0.467, 0.761],
        [0.498, 0.498, 0.498],
        [0.737, 0.741, 0.133],
        [0.090, 0.745, 0.812],
        [0.682, 0.780, 0.910],
        [1.000, 0.733, 0.471],
    ];
    let i = if id.is_finite() && id >= 0.0 {
        id as usize % PALETTE.len()
    } else {
        0
    };
    linear(PALETTE[i])
}

/// The original surface's colour (linear): a pale stone grey.
pub fn surface_color() -> [f32; 3] {
    linear([0.78, 0.79, 0.81])
}

/// Crack faces' colour (linear): a warm ochre, so fracture reads at a glance.
pub fn crack_color() -> [f32; 3] {
    linear([0.86, 0.52, 0.26])
}

/// Colliders' colour (linear): dark steel.
pub fn collider_color() -> [f32; 3] {
    linear([0.36, 0.40, 0.46])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damage_runs_blue_to_red() {
        let (a, b) = (damage_color(0.0), damage_color(1.0));
        assert!(a[2] > a[0] && b[0] > b[2], "{a:?} {b:?}");
        assert_eq!(damage_color(f32::NAN), damage_color(0.0));
    }

    #[test]
    fn a_collider_turns_then_moves_with_flat_faces() {
        // A quarter turn about y takes x to −z.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let p = posed(
            &[[0.0; 3], [1.0, 0.0, 0.0]],
            [1.0, 2.0, 3.0],
            [0.0, h, 0.0, h],
        );
        assert_eq!(p[0], [1.0, 2.0, 3.0]);
        assert!(
            (0..3).all(|k| (p[1][k] - [1.0, 2.0, 2.0][k]).abs() < 1e-6),
            "{p:?}"
        );
        let mut g = FrameGeometry::default();
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
        ];
        g.push_flat_mesh(&square, &[[0, 2, 1], [0, 3, 2], [0, 1, 9]], [1.0; 3]);
        // The triangle past the vertices is dropped; each face has its own normal.
        assert_eq!((g.triangle_count(), g.vertex_count()), (2, 6));
        let normal = &g.mesh_vertices[3..6];
        assert_eq!(normal, [0.0, 1.0, 0.0]);
    }

    #[test]
    fn meshes_append_with_offsets() {
        let mut g = FrameGeometry::default();
        g.push_box([0.0; 3], [1.0; 3], [1.0; 3]);
        g.push_sphere([0.0; 3], 1.0, [1.0; 3]);
        assert_eq!(g.triangle_count(), 12 + 24 * 48 * 2);
        assert!(
            g.mesh_indices
                .iter()
                .all(|&i| (i as usize) < g.vertex_count())
        );
        let b = g.bounds();
        assert!((b.max[0] - 1.0).abs() < 1e-6 && (b.min[1] + 1.0).abs() < 1e-6);
    }
}
