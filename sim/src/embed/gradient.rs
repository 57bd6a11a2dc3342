//! The gradient each particle places its tet's vertices with (the G_p of
//! [`super::EmbeddedMesh::positions`]): its bonds' deformation gradient where it can be
//! trusted, else its rotation.

use perifrac_math::{
    IDENTITY3, det3, inverse3, mat_mul, mul_transpose, rotation_svd, sub, to_matrix,
};
use rayon::prelude::*;

use crate::family::{BROKEN, Bonds, INDEX};

/// Smallest ratio of the smallest to the largest eigenvalue of a particle's bond
/// matrix K at which its deformation gradient is trusted for vertex placement.
/// A particle with its whole family, or a half-space family at a crack or a surface,
/// has a ratio near 1; the demo's particles whose F inverted or stretched their tets
/// had 3 or 4 intact bonds left and ratios far below this.
pub const TRUSTED_CONDITIONING: f64 = 0.1;
/// Singular values of a trusted deformation gradient lie in
/// [1 / `TRUSTED_STRETCH`, `TRUSTED_STRETCH`].
pub const TRUSTED_STRETCH: f64 = 2.0;

/// Each particle's gradient for placing vertices (the G_p of [`super::EmbeddedMesh::positions`]):
/// the deformation gradient of its intact bonds,
/// F = (Σ_j η_ij ⊗ ξ_ij V_j) K⁻¹ with K = Σ_j ξ_ij ⊗ ξ_ij V_j (the correspondence
/// estimate; exact for affine motions), where it can be trusted: K well conditioned
/// (smallest over largest eigenvalue at least [`TRUSTED_CONDITIONING`]) and F's
/// singular values within [1/[`TRUSTED_STRETCH`], [`TRUSTED_STRETCH`]]. Otherwise F's
/// rotation R = UVᵀ (its inversion-safe SVD F = UΣVᵀ, so R is a rotation even when F
/// is inverted). Where the intact bonds do not span 3-D: `turned[i]` if given (how
/// the rigid piece holding a frozen particle has turned, [`crate::model::Model::orient`]),
/// else the identity.
///
/// Why: F fitted to the few bonds a nearly detached particle keeps fits their
/// rotations and compressions exactly, and is then anything in the other
/// directions. In the demo (λ = 0.02 m) particles with 3–4 intact bonds of ~120 had
/// det F = −6.1, −0.8 or +5.0: their tets came out inverted or 5λ long, and the
/// vertices they share dragged their neighbours' tets inside out. Their rotation is
/// still the best estimate of how the tet turned; a tet placed by a rotation alone is
/// never inverted.
pub fn deformation_gradients(
    bonds: &Bonds,
    reference: &[[f64; 3]],
    position: &[[f64; 3]],
    volume: &[f64],
    turned: Option<&[[[f64; 3]; 3]]>,
) -> Vec<[[f64; 3]; 3]> {
    (0..reference.len())
        .into_par_iter()
        .map(|i| {
            let mut k = [[0.0; 3]; 3];
            let mut m = [[0.0; 3]; 3];
            for b in bonds.range(i) {
                let nb = bonds.neighbours[b];
                if nb & BROKEN != 0 {
                    continue;
                }
                let j = (nb & INDEX) as usize;
                let xi = sub(reference[j], reference[i]);
                let eta = sub(position[j], position[i]);
                let vj = volume[j];
                for r in 0..3 {
                    for c in 0..3 {
                        k[r][c] += xi[r] * xi[c] * vj;
                        m[r][c] += eta[r] * xi[c] * vj;
                    }
                }
            }
            let Some(ki) = inverse(k) else {
                return turned.map_or(IDENTITY3, |r| r[i]);
            };
            let f = mat_mul(&m, &ki);
            let svd = rotation_svd(&f);
            let stretch_ok = svd
                .sigma
                .iter()
                .all(|&s| (1.0 / TRUSTED_STRETCH..=TRUSTED_STRETCH).contains(&s));
            if stretch_ok && conditioning(k) >= TRUSTED_CONDITIONING {
                f
            } else {
                mul_transpose(&svd.u, &svd.v)
            }
        })
        .collect()
}

/// Smallest over largest eigenvalue of a symmetric positive semi-definite matrix.
fn conditioning(a: [[f64; 3]; 3]) -> f64 {
    let e = to_matrix(a).symmetric_eigenvalues();
    let (lo, hi) = (e.min(), e.max());
    if hi > 0.0 { lo / hi } else { 0.0 }
}

/// Inverse of a symmetric positive semi-definite 3×3 matrix, `None` when it is
/// nearly singular (det < 10⁻⁶ (tr/3)³: the bonds lie nearly in a plane).
pub(super) fn inverse(a: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let det = det3(&a);
    let tr = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    if det.is_nan() || det <= 1e-6 * tr * tr * tr {
        return None;
    }
    Some(inverse3(&a, det))
}
