//! The surface correction of Chen et al. §6 ("Choice of δ"): per-bond weights for a
//! family cut by a free surface, or too small to be isotropic (δ ≈ λ on a tet
//! lattice), whose sums over bonds differ from the continuum integrals the constants
//! of Chen Eq. 10 assume. Each of the two moments the model uses, q_ij (second
//! moment, for θ of Eq. 6) and p_ij (fourth moment weighted by |ξ|, for the b-term of
//! Eq. 8), gets the smallest polynomial change of uniform weights that makes the
//! discrete moment equal the continuum one, so θ and the energy are exact for every
//! homogeneous deformation wherever positive weights can do it.

/// Exponents (a, b, c) of the monomials n_x^a n_y^b n_z^c of degree `degree`.
fn monomials(degree: u32) -> Vec<[u32; 3]> {
    let mut out = Vec::new();
    for a in (0..=degree).rev() {
        for b in (0..=degree - a).rev() {
            out.push([a, b, degree - a - b]);
        }
    }
    out
}

/// ∫ n_x^a n_y^b n_z^c dΩ over the unit sphere (zero unless all exponents are even).
fn sphere_moment(e: [u32; 3]) -> f64 {
    if e.iter().any(|x| x % 2 == 1) {
        return 0.0;
    }
    // 2 Γ((a+1)/2) Γ((b+1)/2) Γ((c+1)/2) / Γ((a+b+c+3)/2), via double factorials.
    let df = |k: i64| -> f64 {
        (1..=k)
            .rev()
            .step_by(2)
            .map(|x| x as f64)
            .product::<f64>()
            .max(1.0)
    };
    let [a, b, c] = e.map(|x| x as i64);
    4.0 * std::f64::consts::PI * df(a - 1) * df(b - 1) * df(c - 1) / df(a + b + c + 1)
}

/// The K monomials n_x^a n_y^b n_z^c of degree `degree` at `n` (K = 6 for degree 2,
/// 15 for degree 4), in the order of [`monomials`].
fn monomial_values<const K: usize>(n: [f64; 3], degree: u32) -> [f64; K] {
    let powers = |x: f64| {
        let mut p = [1.0f64; 5];
        for e in 1..5 {
            p[e] = p[e - 1] * x;
        }
        p
    };
    let (px, py, pz) = (powers(n[0]), powers(n[1]), powers(n[2]));
    let mut out = [0.0; K];
    let mut k = 0;
    for a in (0..=degree as usize).rev() {
        for b in (0..=degree as usize - a).rev() {
            out[k] = px[a] * py[b] * pz[degree as usize - a - b];
            k += 1;
        }
    }
    out
}

/// Per-bond weights w_j (a polynomial of degree `degree` in ξ̂, K coefficients, which
/// includes the constant for even degrees) that make Σ_j w_j m_j ξ̂^⊗degree equal
/// `target` times the unit-sphere moments, checked to stay within [0.1, 10]; `None`
/// otherwise.
fn moment_weights<const K: usize>(
    dirs: &[[f64; 3]],
    measure: &[f64],
    degree: u32,
    target: f64,
) -> Option<Vec<f32>> {
    let phis: Vec<[f64; K]> = dirs
        .iter()
        .map(|n| monomial_values::<K>(*n, degree))
        .collect();
    let mut mat = [[0.0f64; K]; K];
    for (phi, &m) in phis.iter().zip(measure) {
        for r in 0..K {
            let mr = m * phi[r];
            for c in r..K {
                mat[r][c] += mr * phi[c];
            }
        }
    }
    for r in 1..K {
        let (upper, lower) = mat.split_at_mut(r);
        for (c, row) in upper.iter().enumerate() {
            lower[0][c] = row[r];
        }
    }
    let rhs: Vec<f64> = monomials(degree)
        .into_iter()
        .map(|e| target * sphere_moment(e))
        .collect();
    let coef = solve(mat.iter().map(|row| row.to_vec()).collect(), rhs)?;
    let w: Vec<f64> = phis
        .iter()
        .map(|phi| phi.iter().zip(&coef).map(|(p, c)| p * c).sum())
        .collect();
    w.iter()
        .all(|&x| x > 0.1 && x < 10.0)
        .then(|| w.into_iter().map(|x| x as f32).collect())
}

/// Dilatation weights q_j: Σ_j q_j V_j ξ̂⊗ξ̂ = (V_H∞/3) I, V_H∞ = 4πδ³/3, so θ is exact
/// for every homogeneous deformation (a quadratic form in ξ̂, the least change from
/// uniform weights). Where that needs weights that are not positive (near edges and
/// corners no positive weights are exact for shear: Σ q V n_y n_z > 0 there), the
/// weights match the diagonal (axis stretches) only; failing that, the family-volume
/// ratio V_H∞/V_H,i (exact for isotropic expansion).
pub(super) fn dilatation_weights(dirs: &[[f64; 3]], vols: &[f64], delta: f64) -> Vec<f32> {
    let full = 4.0 / 3.0 * std::f64::consts::PI * delta.powi(3);
    // Target moments (V_H∞/4π) ∫ n⊗n dΩ.
    if let Some(q) = moment_weights::<6>(dirs, vols, 2, full / (4.0 * std::f64::consts::PI)) {
        return q;
    }
    let mut k = [[0.0f64; 3]; 3];
    for (n, &v) in dirs.iter().zip(vols) {
        for r in 0..3 {
            for c in 0..3 {
                k[r][c] += v * n[r] * n[r] * n[c] * n[c];
            }
        }
    }
    let diag = solve(k.iter().map(|r| r.to_vec()).collect(), vec![full / 3.0; 3]);
    if let Some(d) = diag {
        let q: Vec<f64> = dirs
            .iter()
            .map(|n| d[0] * n[0] * n[0] + d[1] * n[1] * n[1] + d[2] * n[2] * n[2])
            .collect();
        if q.iter().all(|&x| x > 0.1 && x < 10.0) {
            return q.into_iter().map(|x| x as f32).collect();
        }
    }
    let family_volume: f64 = vols.iter().sum();
    let scalar = if family_volume > 0.0 {
        full / family_volume
    } else {
        1.0
    };
    vec![scalar as f32; dirs.len()]
}

/// Deviatoric weights p_j: Σ_j p_j |ξ_j| V_j ξ̂^⊗4 = (δ⁴/4) ∫ n^⊗4 dΩ, the fourth
/// moment of a complete continuum family, so that the b-term of Chen Eq. 8 has the
/// continuum's isotropic stiffness (μ) for every homogeneous deformation; families of
/// few bonds (δ ≈ λ) are far from isotropic otherwise. Falls back to the trace
/// correction πδ⁴ / Σ_j |ξ_j| V_j where positive polynomial weights do not exist.
pub(super) fn deviatoric_weights(
    dirs: &[[f64; 3]],
    vols: &[f64],
    lengths: &[f64],
    delta: f64,
) -> Vec<f32> {
    let measure: Vec<f64> = vols.iter().zip(lengths).map(|(v, l)| v * l).collect();
    if let Some(p) = moment_weights::<15>(dirs, &measure, 4, delta.powi(4) / 4.0) {
        return p;
    }
    let m: f64 = measure.iter().sum();
    let scalar = if m > 0.0 {
        std::f64::consts::PI * delta.powi(4) / m
    } else {
        1.0
    };
    vec![scalar as f32; dirs.len()]
}

/// Gaussian elimination with partial pivoting; `None` if (nearly) singular.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    let scale = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    if scale == 0.0 {
        return None;
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))?;
        if a[pivot][col].abs() < 1e-10 * scale {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let (top, rest) = a.split_at_mut(col + 1);
        let pivot_row = &top[col];
        for (r, row) in rest.iter_mut().enumerate() {
            let f = row[col] / pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= f * p;
            }
            b[col + 1 + r] -= f * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|c| a[r][c] * x[c]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_moments() {
        let pi = std::f64::consts::PI;
        assert!((sphere_moment([0, 0, 0]) - 4.0 * pi).abs() < 1e-12);
        assert!((sphere_moment([2, 0, 0]) - 4.0 * pi / 3.0).abs() < 1e-12);
        assert!((sphere_moment([4, 0, 0]) - 4.0 * pi / 5.0).abs() < 1e-12);
        assert!((sphere_moment([2, 2, 0]) - 4.0 * pi / 15.0).abs() < 1e-12);
        assert_eq!(sphere_moment([3, 1, 0]), 0.0);
        assert_eq!(monomials(4).len(), 15);
    }
}
