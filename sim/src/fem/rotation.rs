//! The rotation of a deformation gradient, R of the polar decomposition F = R S.
//!
//! R is the rotation that makes G = RᵀF symmetric. Starting from a guess (the
//! previous step's rotation of the same tet), each iteration turns R by the Newton
//! step for skew(G) = 0 in the tet's rotated frame,
//!
//! ```text
//! (tr(G) I − sym(G)) ω = (G₃₂ − G₂₃, G₁₃ − G₃₁, G₂₁ − G₁₂),   R ← R exp([ω]×)
//! ```
//!
//! which converges quadratically (one or two iterations from a warm start). Where
//! tr(G) I − sym(G) is not safely positive definite (a tet near inversion) the step is
//! the always-convergent one of Müller, Bender, Chentanez and Macklin 2016 ("A Robust
//! Method to Extract the Rotational Part of Deformations", Eq. 4–5), ω = (…)/|tr G|.
//! Either way R stays a rotation (det R = +1), also for inverted tets.

use perifrac_math::dot;

use super::{M3, col};

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

/// Updates `q` to the rotational part of `f` and returns its matrix.
pub fn extract(f: &M3, q: &mut Quaternion) -> M3 {
    let mut r = matrix(*q);
    for _ in 0..MAX_ITERATIONS {
        // G = Rᵀ F.
        let mut g = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                g[i][j] = r[0][i] * f[0][j] + r[1][i] * f[1][j] + r[2][i] * f[2][j];
            }
        }
        let v = [g[2][1] - g[1][2], g[0][2] - g[2][0], g[1][0] - g[0][1]];
        let tr = g[0][0] + g[1][1] + g[2][2];
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = -0.5 * (g[i][j] + g[j][i]);
            }
            m[i][i] += tr;
        }
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        let scale = tr.abs().max(1e-300);
        let newton = m[0][0] > 0.0
            && m[0][0] * m[1][1] - m[0][1] * m[1][0] > 0.0
            && det > 1e-6 * scale * scale * scale;
        let omega = if newton {
            solve(&m, v, det)
        } else {
            v.map(|x| x / (tr.abs() + 1e-9))
        };
        let angle = dot(omega, omega).sqrt();
        if angle.is_nan() || angle < TOLERANCE {
            break;
        }
        let (s, c) = (0.5 * angle).sin_cos();
        let turn = [
            c,
            s * omega[0] / angle,
            s * omega[1] / angle,
            s * omega[2] / angle,
        ];
        // ω is in the rotated frame: R ← R exp([ω]×), q ← q ⊗ turn.
        let next = multiply(*q, turn);
        let n = next.iter().map(|x| x * x).sum::<f64>().sqrt();
        *q = next.map(|x| x / n);
        r = matrix(*q);
    }
    r
}

/// m⁻¹ v by Cramer's rule (`det` = det m).
fn solve(m: &M3, v: [f64; 3], det: f64) -> [f64; 3] {
    let d = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        a[0] * (b[1] * c[2] - b[2] * c[1]) - b[0] * (a[1] * c[2] - a[2] * c[1])
            + c[0] * (a[1] * b[2] - a[2] * b[1])
    };
    let (c0, c1, c2) = (col(m, 0), col(m, 1), col(m, 2));
    [d(v, c1, c2) / det, d(c0, v, c2) / det, d(c0, c1, v) / det]
}

#[cfg(test)]
mod tests {
    use perifrac_math::mat_mul;

    use super::*;

    #[test]
    fn recovers_the_rotation_of_a_stretched_rotation() {
        // F = R S with R a 100° turn about (1, 2, 3) and S symmetric positive definite.
        let axis = [1.0, 2.0, 3.0].map(|x: f64| x / 14f64.sqrt());
        let (s, c) = (50f64.to_radians().sin(), 50f64.to_radians().cos());
        let q = [c, s * axis[0], s * axis[1], s * axis[2]];
        let rot = matrix(q);
        let stretch = [[1.2, 0.1, 0.0], [0.1, 0.9, 0.05], [0.0, 0.05, 1.05]];
        let f = mat_mul(&rot, &stretch);
        let mut guess = IDENTITY;
        let r = extract(&f, &mut guess);
        for i in 0..3 {
            for j in 0..3 {
                assert!((r[i][j] - rot[i][j]).abs() < 1e-9, "{r:?} vs {rot:?}");
            }
        }
        // Warm-started from the answer, F is left as it is.
        let again = extract(&f, &mut guess);
        assert_eq!(again, r);
    }

    #[test]
    fn an_inverted_tet_still_gets_a_rotation() {
        let f = [[-0.5, 0.1, 0.0], [0.0, 1.0, 0.2], [0.1, 0.0, 1.0]];
        let mut q = IDENTITY;
        let r = extract(&f, &mut q);
        let rtr = mat_mul(
            &r,
            &[
                [r[0][0], r[1][0], r[2][0]],
                [r[0][1], r[1][1], r[2][1]],
                [r[0][2], r[1][2], r[2][2]],
            ],
        );
        for (i, row) in rtr.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                let id = if i == j { 1.0 } else { 0.0 };
                assert!((x - id).abs() < 1e-12);
            }
        }
    }
}
