//! The rotation of a deformation gradient, R of the polar decomposition F = R S, by
//! the iterative method of Müller, Bender, Chentanez and Macklin 2016 ("A Robust
//! Method to Extract the Rotational Part of Deformations", Eq. 4–5): starting from a
//! rotation q, repeatedly turn q by
//!
//! ```text
//! ω = Σ_i r_i × f_i / (|Σ_i r_i · f_i| + ε)
//! ```
//!
//! (r_i, f_i the columns of R(q) and F) until |ω| vanishes. It always returns a
//! rotation (det R = +1, also for inverted tets), converges to the polar rotation
//! when det F > 0, and warm-started from the previous step's rotation takes one or two
//! iterations.

use super::{M3, col, cross, dot3};

/// A unit quaternion [w, x, y, z].
pub type Quaternion = [f64; 4];

/// The identity rotation.
pub const IDENTITY: Quaternion = [1.0, 0.0, 0.0, 0.0];

/// Iterations at most; from a warm start one or two suffice.
const MAX_ITERATIONS: usize = 40;

/// Stop when the correction angle is below this (radians).
const TOLERANCE: f64 = 1e-12;

/// The rotation matrix of a unit quaternion.
pub fn matrix(q: Quaternion) -> M3 {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

fn multiply(a: Quaternion, b: Quaternion) -> Quaternion {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// Updates `q` to the rotational part of `f` (Müller et al. 2016, Algorithm 1) and
/// returns its matrix.
pub fn extract(f: &M3, q: &mut Quaternion) -> M3 {
    let mut r = matrix(*q);
    for _ in 0..MAX_ITERATIONS {
        let (mut num, mut den) = ([0.0; 3], 0.0);
        for i in 0..3 {
            let (ri, fi) = (col(&r, i), col(f, i));
            let c = cross(ri, fi);
            for k in 0..3 {
                num[k] += c[k];
            }
            den += dot3(ri, fi);
        }
        let scale = 1.0 / (den.abs() + 1e-9);
        let omega = num.map(|x| x * scale);
        let angle = dot3(omega, omega).sqrt();
        if !(angle >= TOLERANCE) {
            break;
        }
        let (s, c) = (0.5 * angle).sin_cos();
        let turn = [
            c,
            s * omega[0] / angle,
            s * omega[1] / angle,
            s * omega[2] / angle,
        ];
        let next = multiply(turn, *q);
        let n = next.iter().map(|x| x * x).sum::<f64>().sqrt();
        *q = next.map(|x| x / n);
        r = matrix(*q);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mul(a: &M3, b: &M3) -> M3 {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        c
    }

    #[test]
    fn recovers_the_rotation_of_a_stretched_rotation() {
        // F = R S with R a 100° turn about (1, 2, 3) and S symmetric positive definite.
        let axis = [1.0, 2.0, 3.0].map(|x: f64| x / 14f64.sqrt());
        let (s, c) = (50f64.to_radians().sin(), 50f64.to_radians().cos());
        let q = [c, s * axis[0], s * axis[1], s * axis[2]];
        let rot = matrix(q);
        let stretch = [[1.2, 0.1, 0.0], [0.1, 0.9, 0.05], [0.0, 0.05, 1.05]];
        let f = mul(&rot, &stretch);
        let mut guess = IDENTITY;
        let r = extract(&f, &mut guess);
        for i in 0..3 {
            for j in 0..3 {
                assert!((r[i][j] - rot[i][j]).abs() < 1e-9, "{r:?} vs {rot:?}");
            }
        }
    }
}
