//! The stuffing lattice turned by a rotation, and seeded uniform random rotations
//! (issue 13: a breaking body's lattice turned so its weak directions are not the
//! scene's axes).

use perifrac_math::{dot, sub};

use super::super::sdf::Sdf;
use super::super::{MeshError, TetMesh};
use super::stuff;

/// [`stuff`] with the lattice turned by `rotation` (a proper rotation matrix, rows)
/// about the centre of the shape's bounds: the mesh of the shape turned by Rᵀ, turned
/// back by R. Boundary vertices still lie on the zero set and every tetrahedron stays
/// positively oriented (det R = 1); the lattice's axes, and so the directions along
/// which a mesh is weakest, are those of R instead of the scene's.
///
/// # Errors
/// As [`stuff`].
pub fn stuff_rotated(
    sdf: &dyn Sdf,
    edge_length: f64,
    rotation: [[f64; 3]; 3],
) -> Result<TetMesh, MeshError> {
    let turned = Turned::new(sdf, rotation);
    let mut mesh = stuff(&turned, edge_length)?;
    for v in &mut mesh.vertices {
        *v = turned.to_shape(*v);
    }
    Ok(mesh)
}

/// The shape of `inner` turned by Rᵀ about the centre c of its bounds:
/// d(p) = d_inner(c + R (p − c)).
struct Turned<'a> {
    inner: &'a dyn Sdf,
    centre: [f64; 3],
    rotation: [[f64; 3]; 3],
}

impl<'a> Turned<'a> {
    fn new(inner: &'a dyn Sdf, rotation: [[f64; 3]; 3]) -> Self {
        let (lo, hi) = inner.bounds();
        let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        Self {
            inner,
            centre,
            rotation,
        }
    }

    /// c + R (p − c): a point of the turned shape to the shape.
    fn to_shape(&self, p: [f64; 3]) -> [f64; 3] {
        let d = sub(p, self.centre);
        [0, 1, 2].map(|k| self.centre[k] + dot(self.rotation[k], d))
    }
}

impl Sdf for Turned<'_> {
    fn distance(&self, p: [f64; 3]) -> f64 {
        self.inner.distance(self.to_shape(p))
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        // The box around the turned corners of the inner bounds: c + Rᵀ (q − c).
        let (lo, hi) = self.inner.bounds();
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for corner in 0..8 {
            let q = [0, 1, 2].map(|k| if corner >> k & 1 == 0 { lo[k] } else { hi[k] });
            let d = sub(q, self.centre);
            for k in 0..3 {
                let x = self.centre[k] + (0..3).map(|r| self.rotation[r][k] * d[r]).sum::<f64>();
                min[k] = min[k].min(x);
                max[k] = max[k].max(x);
            }
        }
        (min, max)
    }
}

/// A uniformly distributed random rotation (rows of the matrix) from `seed` and
/// `stream` (e.g. a body index): the unit quaternion of Shoemake (1992), "Uniform
/// random rotations", from three uniform numbers.
pub fn random_rotation(seed: u64, stream: u64) -> [[f64; 3]; 3] {
    use std::f64::consts::TAU;
    let mut rng = perifrac_math::SplitMix64::new(seed ^ stream.wrapping_mul(0xd1b5_4a32_d192_ed03));
    let (u1, u2, u3) = (rng.next_f64(), rng.next_f64(), rng.next_f64());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    crate::fem::rotation::matrix([
        a * (TAU * u2).sin(),
        a * (TAU * u2).cos(),
        b * (TAU * u3).sin(),
        b * (TAU * u3).cos(),
    ])
}
