//! The plastic projections of J2 and Drucker–Prager at small strain, by series in
//! E = C − I (C = F̂ᵀF̂) instead of C's eigenvalues: no arccosine, sine–cosine,
//! logarithm or exponential.
//!
//! Both projections read three invariants of the log singular values l = log Σ̂ (their
//! mean, and the squared norms of dev l and l) and move l by the affine map l ↦ (1 + s)
//! l + t, that is F_E = eᵗ F̂ C^{s/2} ([`super::spectral`]). The eigenvalues of
//! ½ ln C are the l, so the invariants are those of the symmetric matrix ½ ln C (its
//! trace and Frobenius norms: a symmetric matrix's Frobenius norm is its eigenvalues'
//! Euclidean norm), and
//!
//! `ln C = Σ_{k≥1} (−1)^{k+1} E^k/k`,  `C^a = Σ_{k≥0} C(a, k) E^k`,
//!
//! both convergent for ‖E‖ < 1 (the Mercator and binomial series, which converge at a
//! matrix whose spectral radius is within their radius of convergence: Higham,
//! *Functions of Matrices*, 2008, Thm. 4.7). Both share the powers E^k; for the
//! projections' exponents a = s/2 ∈ [−½, 0] (J2: s = k − 1, Drucker–Prager s ∈ [−1,
//! 0)) every |C(a, k)| ≤ 1, so both series cut after n terms err by at most
//! ‖E‖^{n+1}/(1 − ‖E‖) in the 2-norm, and n is the first that makes this below
//! [`SERIES_TOLERANCE`] ([`project`]). Where ‖E‖_F ≤ [`SERIES_STRAIN`] (log strains up
//! to about half of it) that takes at most [`SERIES_TERMS`] terms, and the series are
//! more accurate than the closed-form eigenvalues, whose rounding error near a double
//! eigenvalue is √ε of the spread; the test `small_strain_projections_match_the_svd_ones`
//! holds them to the exact SVD. Above 10⁻² (tried: 1.5·10⁻², 3·10⁻², 5·10⁻²) the
//! extra terms cost more than the eigenvalues on the bench block's particles.

use super::constitutive::{Mat3, mul};
use super::spectral::{LogInvariants, LogMap};

/// The Frobenius norm of E = C − I up to which [`project`] takes the series.
pub const SERIES_STRAIN: f64 = 1e-2;

/// The most terms the series take: enough for ‖E‖ = [`SERIES_STRAIN`] to reach
/// [`SERIES_TOLERANCE`] (0.01⁸/0.99 ≈ 1.01·10⁻¹⁶).
pub const SERIES_TERMS: usize = 8;

/// The bound on the series' truncation error (in the 2-norm, against ‖C‖ ≈ 1):
/// below the rounding error of C = F̂ᵀF̂ itself, 2⁻⁵³ ≈ 1.1·10⁻¹⁶ of its entries.
pub const SERIES_TOLERANCE: f64 = 1.2e-16;

/// A symmetric 3×3 matrix as its entries xx, yy, zz, xy, xz, yz.
type Symmetric = [f64; 6];

/// The row-major index of each of [`Symmetric`]'s entries' (i, j).
const ENTRY: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

/// A B of two symmetric matrices that commute (powers of one matrix), symmetric.
fn product(a: &Symmetric, b: &Symmetric) -> Symmetric {
    let at = |m: &Symmetric, i: usize, j: usize| m[ENTRY[i][j]];
    let entry = |i: usize, j: usize| {
        at(a, i, 0) * at(b, 0, j) + at(a, i, 1) * at(b, 1, j) + at(a, i, 2) * at(b, 2, j)
    };
    [
        entry(0, 0),
        entry(1, 1),
        entry(2, 2),
        entry(0, 1),
        entry(0, 2),
        entry(1, 2),
    ]
}

/// E = C − I and ‖E‖_F when the series apply to F̂ with C = F̂ᵀF̂ and `det` = det F̂:
/// det F̂ > 0 (an inverted F̂ takes the SVD's convention) and ‖E‖_F ≤ [`SERIES_STRAIN`]
/// (NaN fails both).
fn near_identity(c: &Mat3, det: f64) -> Option<(Symmetric, f64)> {
    let e: Symmetric = [
        c[0][0] - 1.0,
        c[1][1] - 1.0,
        c[2][2] - 1.0,
        c[0][1],
        c[0][2],
        c[1][2],
    ];
    let squared =
        e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + 2.0 * (e[3] * e[3] + e[4] * e[4] + e[5] * e[5]);
    (squared <= SERIES_STRAIN * SERIES_STRAIN && det > 0.0).then(|| (e, squared.sqrt()))
}

/// Projects `f` = F̂, whose C = F̂ᵀF̂ and det F̂ are `c` and `det` (the caller has them
/// for the closed form too), by the map that `map` makes of the invariants of its log
/// singular values (`None`: elastic), F_E = eᵗ F̂ C^{s/2}, and returns the map's
/// increment (0 when elastic); or `None`, `f` untouched, where the series do not apply
/// (‖E‖_F above [`SERIES_STRAIN`], or det F ≤ 0). The invariants are those of ½ ln C = ½ Σ (−1)^{k+1} E^k/k, C^{s/2} =
/// Σ C(s/2, k) E^k, and eᵗ is summed by its own series (|t| ≤ |tr ln C|/6 is smaller
/// than ‖E‖).
pub fn project(
    f: &mut Mat3,
    c: &Mat3,
    det: f64,
    map: impl FnOnce(LogInvariants) -> Option<LogMap>,
) -> Option<f64> {
    let (e, norm) = near_identity(c, det)?;
    // E, E², …: ‖E‖^{n+1}/(1 − ‖E‖) ≤ tolerance decides how many.
    let limit = SERIES_TOLERANCE * (1.0 - norm);
    let mut powers = [e; SERIES_TERMS];
    let mut bound = norm * norm;
    let mut terms = 1;
    while bound > limit {
        if terms == SERIES_TERMS {
            return None;
        }
        powers[terms] = product(&powers[terms - 1], &e);
        terms += 1;
        bound *= norm;
    }
    let powers = &powers[..terms];
    let mut half_log = [0.0; 6];
    for (k, power) in powers.iter().enumerate() {
        let weight = if k % 2 == 0 { 0.5 } else { -0.5 } / (k + 1) as f64;
        for (x, p) in half_log.iter_mut().zip(power) {
            *x += weight * p;
        }
    }
    let mean = (half_log[0] + half_log[1] + half_log[2]) / 3.0;
    let off = half_log[3] * half_log[3] + half_log[4] * half_log[4] + half_log[5] * half_log[5];
    let diagonal: f64 = half_log[..3].iter().map(|x| x * x).sum();
    let deviatoric: f64 = half_log[..3].iter().map(|x| (x - mean) * (x - mean)).sum();
    let Some(map) = map(LogInvariants {
        mean,
        deviatoric_squared: deviatoric + 2.0 * off,
        squared: diagonal + 2.0 * off,
    }) else {
        return Some(0.0);
    };
    let a = 0.5 * map.slope;
    let mut power = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let mut coefficient = 1.0;
    let mut exponential = 1.0;
    let mut term = 1.0;
    for (k, e_k) in powers.iter().enumerate() {
        // C(a, k + 1) = C(a, k) (a − k)/(k + 1); tᵏ⁺¹/(k + 1)!.
        coefficient *= (a - k as f64) / (k + 1) as f64;
        term *= map.shift / (k + 1) as f64;
        exponential += term;
        for (x, p) in power.iter_mut().zip(e_k) {
            *x += coefficient * p;
        }
    }
    // One more term of eᵗ, whose series converges faster than the matrices'.
    exponential += term * map.shift / (terms + 1) as f64;
    let g: Mat3 = [0, 1, 2].map(|i| [0, 1, 2].map(|j| exponential * power[ENTRY[i][j]]));
    *f = mul(f, &g);
    Some(map.increment)
}
