//! 3×3 decompositions shared by the models: the SVD with the inversion-safe sign
//! convention (Irving et al. 2004; Stomakhin et al. 2012): U and V are made rotations
//! and the sign goes to the smallest singular value, so that an inverted F has one
//! negative singular value and R = UVᵀ is a rotation (MPM's energies, Lyu 2021 §3.3;
//! the embedded mesh's rotations of the particles' deformation).

use nalgebra::Matrix3;

use crate::{from_matrix, to_matrix};

/// The SVD F = U Σ Vᵀ with U and V rotations (det = +1): when F is inverted the
/// smallest singular value is negative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotationSvd {
    /// Left rotation U.
    pub u: [[f64; 3]; 3],
    /// Singular values, the smallest possibly negative.
    pub sigma: [f64; 3],
    /// Right rotation V.
    pub v: [[f64; 3]; 3],
}

/// The inversion-safe SVD of `f` (nalgebra's SVD, then the sign fix).
pub fn rotation_svd(f: &[[f64; 3]; 3]) -> RotationSvd {
    let svd = to_matrix(*f).svd(true, true);
    // Both factors were asked for, so both are present.
    let mut u = svd.u.unwrap_or_else(Matrix3::identity);
    let mut v = svd.v_t.unwrap_or_else(Matrix3::identity).transpose();
    let mut sigma = [
        svd.singular_values[0],
        svd.singular_values[1],
        svd.singular_values[2],
    ];
    let smallest = (0..3)
        .min_by(|&a, &b| sigma[a].total_cmp(&sigma[b]))
        .unwrap_or(2);
    if u.determinant() < 0.0 {
        u.column_mut(smallest).neg_mut();
        sigma[smallest] = -sigma[smallest];
    }
    if v.determinant() < 0.0 {
        v.column_mut(smallest).neg_mut();
        sigma[smallest] = -sigma[smallest];
    }
    RotationSvd {
        u: from_matrix(&u),
        sigma,
        v: from_matrix(&v),
    }
}

/// A Bᵀ.
#[inline]
pub fn mul_transpose(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (row, a_row) in out.iter_mut().zip(a) {
        for (x, b_row) in row.iter_mut().zip(b) {
            *x = a_row[0] * b_row[0] + a_row[1] * b_row[1] + a_row[2] * b_row[2];
        }
    }
    out
}

/// A best-fit rigid motion X ↦ c + R(X − X̄) ([`rigid_fit`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidFit {
    /// The mass-weighted reference centre X̄.
    pub rest: [f64; 3],
    /// The mass-weighted centre c.
    pub centre: [f64; 3],
    /// The rotation R.
    pub rotation: [[f64; 3]; 3],
}

/// The best-fit rigid motion of points given as (mass m, reference position X,
/// position x), Kabsch's: X̄ and c the mass-weighted centres, R the polar factor of
/// Σ m (x − c)(X − X̄)ᵀ (`U Vᵀ` of its [`rotation_svd`]); `None` when the total mass is
/// not positive. The embedded mesh places small fragments with it; the rigid phase
/// turns a piece's surface with it.
pub fn rigid_fit<I>(points: I) -> Option<RigidFit>
where
    I: Iterator<Item = (f64, [f64; 3], [f64; 3])> + Clone,
{
    let total: f64 = points.clone().map(|(m, _, _)| m).sum();
    if total <= 0.0 {
        return None;
    }
    let centre = |current: bool| {
        [0, 1, 2].map(|a| {
            points
                .clone()
                .map(|(m, r, x)| m * if current { x[a] } else { r[a] })
                .sum::<f64>()
                / total
        })
    };
    let (rest, c) = (centre(false), centre(true));
    let mut h = [[0.0; 3]; 3];
    for (m, r, x) in points {
        let d = [0, 1, 2].map(|a| x[a] - c[a]);
        let e = [0, 1, 2].map(|a| r[a] - rest[a]);
        for (row, da) in h.iter_mut().zip(d) {
            for (value, eb) in row.iter_mut().zip(e) {
                *value += m * da * eb;
            }
        }
    }
    let svd = rotation_svd(&h);
    Some(RigidFit {
        rest,
        centre: c,
        rotation: mul_transpose(&svd.u, &svd.v),
    })
}
