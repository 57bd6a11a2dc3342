//! Elastic energies of the material point method (Lyu 2021 §3.3) and their first
//! Piola–Kirchhoff stresses, on 3×3 matrices stored as `[[f64; 3]; 3]` (row major).
//!
//! The SVD is perifrac-math's inversion-safe one ([`rotation_svd`]). The fixed
//! corotated model's rotation of a non-inverted F comes from Higham's Newton iteration
//! instead ([`polar_rotation`]), checked against that SVD.

use perifrac_math::{mul_transpose, rotation_svd};

use crate::scene::MpmElasticity;

/// A 3×3 matrix, row major.
pub type Mat3 = [[f64; 3]; 3];

/// The identity.
pub const IDENTITY: Mat3 = perifrac_math::IDENTITY3;

/// Lamé parameters μ, λ (Lyu Eq. 3.6) and the elastic energy of a material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    /// Which energy density ψ(F).
    pub energy: MpmElasticity,
    /// Shear modulus μ (Pa).
    pub mu: f64,
    /// Lamé's first parameter λ (Pa).
    pub lambda: f64,
}

/// The rotation R of the polar decomposition F = RS (R = UVᵀ of [`rotation_svd`]).
///
/// For det F > 0, R is the orthogonal polar factor, found by Higham's scaled Newton
/// iteration (Higham 1986, "Computing the polar decomposition — with applications",
/// Eq. 3.1 with the determinant scaling of §3.3): X₀ = F,
/// X_{k+1} = ½(γ_k X_k + γ_k⁻¹ X_k⁻ᵀ), γ_k = |det X_k|^{−1/3}. It converges
/// quadratically from any non-singular F (4–5 iterations at the strains of a
/// simulation) and costs a tenth of nalgebra's 3×3 SVD, which is the whole
/// fixed-corotated stress stage (see docs/mpm.md). An inverted or degenerate F
/// (det F ≤ 0), or one the iteration does not settle within [`NEWTON_POLAR_ITERATIONS`],
/// goes through [`rotation_svd`] for the inversion-safe convention; the tests check the
/// two against each other to 1e-12 on random and ill-conditioned matrices.
pub fn polar_rotation(f: &Mat3) -> Mat3 {
    newton_polar(f).unwrap_or_else(|| {
        let s = rotation_svd(f);
        mul_transpose(&s.u, &s.v)
    })
}

/// Most Newton steps [`polar_rotation`] takes before it falls back to the SVD.
pub const NEWTON_POLAR_ITERATIONS: usize = 24;

/// The orthogonal polar factor of `f` by the scaled Newton iteration, or `None` when
/// det F ≤ 0 or the iteration has not settled.
fn newton_polar(f: &Mat3) -> Option<Mat3> {
    let mut x = *f;
    for _ in 0..NEWTON_POLAR_ITERATIONS {
        let cof = cofactor(&x);
        // det X from its first row and cofactors; X⁻ᵀ = cof X / det X.
        let det = x[0][0] * cof[0][0] + x[0][1] * cof[0][1] + x[0][2] * cof[0][2];
        if !(det.is_finite() && det > 0.0) {
            return None;
        }
        // Higham's scaling speeds up the first steps from a far-from-orthogonal F;
        // near convergence (det X ≈ 1) it is 1 to round-off and skipped.
        let gamma = if (det - 1.0).abs() < 1e-2 {
            1.0
        } else {
            det.cbrt().recip()
        };
        let (a, b) = (0.5 * gamma, 0.5 / (gamma * det));
        let mut change = 0.0;
        for (row, cof_row) in x.iter_mut().zip(&cof) {
            for (value, c) in row.iter_mut().zip(cof_row) {
                let next = a * *value + b * c;
                change += (next - *value) * (next - *value);
                *value = next;
            }
        }
        // Quadratic convergence: a change of 1e-9 leaves an error near 1e-18, below
        // the round-off of the iterate.
        if change < 1e-18 {
            return Some(x);
        }
    }
    None
}

/// Most sweeps of [`symmetric_eigen`]'s cyclic Jacobi method (3 to 4 suffice at the
/// strains of a simulation; convergence is quadratic).
pub const JACOBI_SWEEPS: usize = 16;

/// The eigenvalues and eigenvectors (the columns of the second value, a rotation up
/// to the sign of a column) of a symmetric matrix `a`, by the cyclic Jacobi method
/// (Golub & Van Loan, *Matrix Computations*, §8.5.2; the rotation of Rutishauser's
/// Numerical Recipes form, t = sgn θ/(|θ| + √(θ² + 1)), θ = (a_qq − a_pp)/(2a_pq)).
/// It sweeps the three off-diagonal entries until their squares sum to less than
/// (10⁻¹⁵)² of the diagonal's, so the eigenvalues carry an error of about 10⁻¹⁵ ‖A‖;
/// the order of the eigenvalues is not sorted.
pub fn symmetric_eigen(a: &Mat3) -> ([f64; 3], Mat3) {
    let mut v = IDENTITY;
    let values = jacobi(a, Some(&mut v));
    (values, v)
}

/// The eigenvalues of [`symmetric_eigen`], to the bit, without the work on the
/// eigenvectors.
pub fn symmetric_eigenvalues(a: &Mat3) -> [f64; 3] {
    jacobi(a, None)
}

/// The cyclic Jacobi sweeps of [`symmetric_eigen`], accumulating the rotations in `v`
/// when given; inlined so that each caller gets the loop without the test.
#[inline(always)]
fn jacobi(a: &Mat3, mut v: Option<&mut Mat3>) -> [f64; 3] {
    let mut a = *a;
    for _ in 0..JACOBI_SWEEPS {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diagonal = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= 1e-30 * diagonal {
            break;
        }
        for (p, q, r) in [(0, 1, 2), (0, 2, 1), (1, 2, 0)] {
            let apq = a[p][q];
            if apq == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
            // θ² overflows past 10¹⁵⁴; there t = 1/(2θ) to round-off.
            let t = if theta.abs() > 1e150 {
                0.5 / theta
            } else {
                theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
            };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            a[p][p] -= t * apq;
            a[q][q] += t * apq;
            a[p][q] = 0.0;
            a[q][p] = 0.0;
            let (arp, arq) = (a[r][p], a[r][q]);
            a[r][p] = c * arp - s * arq;
            a[p][r] = a[r][p];
            a[r][q] = s * arp + c * arq;
            a[q][r] = a[r][q];
            if let Some(v) = v.as_deref_mut() {
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    [a[0][0], a[1][1], a[2][2]]
}

/// FᵀF, the right Cauchy–Green tensor C.
pub fn gram(f: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in i..3 {
            let x = f[0][i] * f[0][j] + f[1][i] * f[1][j] + f[2][i] * f[2][j];
            c[i][j] = x;
            c[j][i] = x;
        }
    }
    c
}

/// A B.
pub fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// det A.
pub fn determinant(a: &Mat3) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// The cofactor matrix ∂J/∂F = J F⁻ᵀ, defined for singular F too.
pub fn cofactor(a: &Mat3) -> Mat3 {
    [
        [
            a[1][1] * a[2][2] - a[1][2] * a[2][1],
            a[1][2] * a[2][0] - a[1][0] * a[2][2],
            a[1][0] * a[2][1] - a[1][1] * a[2][0],
        ],
        [
            a[0][2] * a[2][1] - a[0][1] * a[2][2],
            a[0][0] * a[2][2] - a[0][2] * a[2][0],
            a[0][1] * a[2][0] - a[0][0] * a[2][1],
        ],
        [
            a[0][1] * a[1][2] - a[0][2] * a[1][1],
            a[0][2] * a[1][0] - a[0][0] * a[1][2],
            a[0][0] * a[1][1] - a[0][1] * a[1][0],
        ],
    ]
}

/// The bulk modulus K = λ + 2μ/3 of Lamé's `lambda` and `mu`.
pub fn bulk_modulus(lambda: f64, mu: f64) -> f64 {
    lambda + 2.0 * mu / 3.0
}

impl Elastic {
    /// The material of Young's modulus `e` and Poisson ratio `nu` (Lyu Eq. 3.6).
    pub fn from_young(energy: MpmElasticity, e: f64, nu: f64) -> Elastic {
        Elastic {
            energy,
            mu: e / (2.0 * (1.0 + nu)),
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        }
    }

    /// The bulk modulus K = λ + 2μ/3.
    pub fn bulk_modulus(&self) -> f64 {
        bulk_modulus(self.lambda, self.mu)
    }

    /// Young's modulus E = μ(3λ + 2μ)/(λ + μ).
    pub fn young(&self) -> f64 {
        self.mu * (3.0 * self.lambda + 2.0 * self.mu) / (self.lambda + self.mu)
    }

    /// The parameters (μ̃, λ̃, α) of the stable Neo-Hookean energy (Smith et al. 2018
    /// §3.4): μ̃ = 4μ/3 and λ̃ = λ + 5μ/6 so that it linearizes to the Lamé moduli μ, λ
    /// of the scene, and α = 1 + 3μ̃/(4λ̃) so that P(I) = 0 (rest stability). Lyu's
    /// Eq. 7.1 prints α = 1 + μ/λ − μλ/4, a misprint of Smith's 1 + μ/λ − μ/(4λ).
    pub fn stable_parameters(&self) -> (f64, f64, f64) {
        let mu = 4.0 * self.mu / 3.0;
        let lambda = self.lambda + 5.0 * self.mu / 6.0;
        (mu, lambda, 1.0 + 0.75 * mu / lambda)
    }

    /// The first Piola–Kirchhoff stress P = ∂ψ/∂F:
    /// fixed corotated (Eq. 3.5) P = 2μ(F − R) + λ(J − 1) J F⁻ᵀ;
    /// Neo-Hookean (Eq. 3.8) P = μ(F − F⁻ᵀ) + λ log J F⁻ᵀ (not defined for J ≤ 0);
    /// stable Neo-Hookean (Eq. 7.2) P = μ̃(1 − 1/(I_C + 1)) F + λ̃(J − α) ∂J/∂F, also
    /// for the shock model, whose pressure [`super::Mpm`] then replaces.
    pub fn first_piola(&self, f: &Mat3) -> Mat3 {
        let j = determinant(f);
        let cof = cofactor(f);
        match self.energy {
            MpmElasticity::StableNeoHookean | MpmElasticity::Shock => {
                let (mu, lambda, alpha) = self.stable_parameters();
                let ic: f64 = f.iter().flatten().map(|x| x * x).sum();
                let shear = mu * (1.0 - 1.0 / (ic + 1.0));
                let volume = lambda * (j - alpha);
                [0, 1, 2].map(|a| [0, 1, 2].map(|b| shear * f[a][b] + volume * cof[a][b]))
            }
            MpmElasticity::FixedCorotated => {
                let r = polar_rotation(f);
                let volume = self.lambda * (j - 1.0);
                [0, 1, 2].map(|a| {
                    [0, 1, 2].map(|b| 2.0 * self.mu * (f[a][b] - r[a][b]) + volume * cof[a][b])
                })
            }
            MpmElasticity::NeoHookean => {
                let log_j = j.ln();
                [0, 1, 2].map(|a| {
                    [0, 1, 2].map(|b| {
                        let f_inv_t = cof[a][b] / j;
                        self.mu * (f[a][b] - f_inv_t) + self.lambda * log_j * f_inv_t
                    })
                })
            }
        }
    }

    /// The Kirchhoff stress τ = P Fᵀ of [`Elastic::first_piola`], in closed form (the
    /// cofactor term becomes J I since ∂J/∂F Fᵀ = J I):
    /// fixed corotated τ = 2μ(F − R)Fᵀ + λ(J − 1)J I;
    /// Neo-Hookean τ = μ(FFᵀ − I) + λ log J I;
    /// stable Neo-Hookean τ = μ̃(1 − 1/(I_C + 1)) FFᵀ + λ̃(J − α)J I.
    pub fn kirchhoff(&self, f: &Mat3) -> Mat3 {
        let j = determinant(f);
        let (left, scale, diagonal) = match self.energy {
            MpmElasticity::FixedCorotated => {
                let mut stretch = polar_rotation(f);
                for (row, f_row) in stretch.iter_mut().zip(f) {
                    for (x, fx) in row.iter_mut().zip(f_row) {
                        *x = fx - *x;
                    }
                }
                (stretch, 2.0 * self.mu, self.lambda * (j - 1.0) * j)
            }
            MpmElasticity::NeoHookean => (*f, self.mu, self.lambda * j.ln() - self.mu),
            MpmElasticity::StableNeoHookean | MpmElasticity::Shock => {
                let (mu, lambda, alpha) = self.stable_parameters();
                let ic: f64 = f.iter().flatten().map(|x| x * x).sum();
                (*f, mu * (1.0 - 1.0 / (ic + 1.0)), lambda * (j - alpha) * j)
            }
        };
        let mut tau = mul_transpose(&left, f);
        for (a, row) in tau.iter_mut().enumerate() {
            for x in row.iter_mut() {
                *x *= scale;
            }
            row[a] += diagonal;
        }
        tau
    }

    /// The energy density ψ(F) (J/m³) of Eq. 3.5, 3.8 or 7.1 (the last less its
    /// value at rest, so that every energy vanishes at F = I).
    pub fn energy_density(&self, f: &Mat3) -> f64 {
        let j = determinant(f);
        match self.energy {
            MpmElasticity::StableNeoHookean | MpmElasticity::Shock => {
                let (mu, lambda, alpha) = self.stable_parameters();
                let ic: f64 = f.iter().flatten().map(|x| x * x).sum();
                let psi = |ic: f64, j: f64| {
                    0.5 * mu * (ic - 3.0) + 0.5 * lambda * (j - alpha) * (j - alpha)
                        - 0.5 * mu * (ic + 1.0).ln()
                };
                psi(ic, j) - psi(3.0, 1.0)
            }
            MpmElasticity::FixedCorotated => {
                let s = rotation_svd(f);
                let dev: f64 = s.sigma.iter().map(|x| (x - 1.0) * (x - 1.0)).sum();
                self.mu * dev + 0.5 * self.lambda * (j - 1.0) * (j - 1.0)
            }
            MpmElasticity::NeoHookean => {
                let ic: f64 = f.iter().flatten().map(|x| x * x).sum();
                let log_j = j.ln();
                0.5 * self.mu * (ic - 3.0) - self.mu * log_j + 0.5 * self.lambda * log_j * log_j
            }
        }
    }

    /// P-wave speed √((λ + 2μ)/ρ) at density `rho`: the fastest elastic signal.
    pub fn p_wave_speed(&self, rho: f64) -> f64 {
        ((self.lambda + 2.0 * self.mu) / rho).sqrt()
    }
}
