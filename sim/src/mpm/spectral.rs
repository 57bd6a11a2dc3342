//! Powers of the right Cauchy–Green tensor C = F̂ᵀF̂ without its eigenvectors, for
//! the plastic projections whose map of singular values is a power law (J2,
//! Drucker–Prager) or one on each of a few pieces (snow, [`Spectrum::clamp`]).
//!
//! J2's radial return and Drucker–Prager's cone projection both move the log singular
//! values l = log Σ̂ by an affine map of themselves, l ↦ (1 + s) l + t (J2: s = k − 1,
//! t = −(k − 1) tr(l)/3 for the return's radial scaling k; Drucker–Prager: s = −δγ/‖dev
//! l‖, t = −s tr(l)/3, and s = −1, t = 0 at the cone's tip). Then Σ/Σ̂ = Σ̂ˢ eᵗ, so the
//! projected F_E = U Σ Vᵀ = F̂ V (Σ̂ˢ eᵗ) Vᵀ = eᵗ F̂ C^{s/2}: a function of C applied to
//! F̂, which needs C's eigenvalues and not its eigenvectors.
//!
//! **The eigenvalues** come in closed form (Smith 1961, "Eigenvalues of a symmetric 3 × 3
//! matrix"): with q = tr C/3, p² = ‖C − qI‖²_F/6 and r = det((C − qI)/p)/2, they are
//! q + 2p cos(φ + 2πj/3), φ = arccos(r)/3, instead of the Jacobi sweeps of
//! [`symmetric_eigen`](super::constitutive::symmetric_eigen). cos φ and sin φ are not
//! taken from the arccosine and a sine–cosine pair (with them the eigenvalues took 55
//! of a snow projection's 120 ns): c = cos φ' is the root in [cos π/6, 1] of the
//! triple-angle equation 4c³ − 3c = |r| (φ' = arccos(|r|)/3, φ = φ' for r ≥ 0 and
//! π/3 − φ' below), where the equation's slope 12c² − 3 is at least 6, so one Newton
//! step from a polynomial of degree 8 in |r| (within 1.9·10⁻⁹) reaches it to round-off
//! (the steps of 2026-12-07 went from a quartic, twice), and sin φ' =
//! √((1 − c)(1 + c)). Near a double eigenvalue (|r| → 1) r → φ is ill-conditioned and
//! the two close eigenvalues err by up to √ε p, in opposite directions, as they would
//! through arccos; the interpolation below is insensitive to that to second order
//! (its error at a true eigenvalue μ is a divided difference times the product of μ's
//! distances to the nodes, both of them √ε p), so C^a keeps an error of about ε ‖C‖.
//!
//! **C^a** is the quadratic that interpolates h(x) = x^a at the three eigenvalues, in
//! Newton's form with the nodes ordered largest x₀, smallest x₁, middle x₂ (Higham,
//! *Functions of Matrices*, 2008, §1.2.2, polynomial interpolation):
//! `h(C) = h[x₀] I + h[x₀, x₁](C − x₀I) + h[x₀, x₁, x₂](C − x₀I)(C − x₁I)`,
//! exact for a symmetric C whatever its eigenvectors.
//! A first divided difference of close nodes is taken from logarithms, `h[x, y] =
//! e^{(a−1)(L_x+L_y)/2} sinh(a d)/sinh(d)` with d = (L_x − L_y)/2 (a series in d), so it
//! does not cancel; the second has the widest gap x₀ − x₁ as its denominator, and its
//! cancellation error is multiplied by ‖(C − x₀I)(C − x₁I)‖, at most (x₀ − x₁)²/4.
//! Snow's law b C^{−½} needs neither: with s_k = √x_k its divided differences are
//! `h[x_i, x_j] = −b/(s_i s_j (s_i + s_j))` and `h[x₀, x₁, x₂] = b (s₀ + s₁ + s₂)/(s₀ s₁
//! s₂ (s₀ + s₁)(s₀ + s₂)(s₁ + s₂))`, which do not cancel, close nodes or not
//! (`inverse_root_difference`, `inverse_root_second_difference`).

use super::constitutive::{IDENTITY, Mat3, determinant, gram, mul};

/// The smallest ratio λ_min/λ_max of C that [`Spectrum::of`] accepts: the closed-form
/// eigenvalues carry an absolute error of about ε λ_max, so a smaller one would lose
/// digits of its logarithm (the plastic strain). Below it the projections take the
/// Jacobi eigen-solve or the SVD ([`super::plasticity::Stretch`]).
pub const SPECTRUM_CONDITION_FLOOR: f64 = 1e-2;

/// cos(arccos(ρ)/3) on ρ ∈ [0, 1] as a polynomial of degree 8 in t = 2ρ − 1
/// (coefficients of t⁰ to t⁸; interpolated at the nine Chebyshev nodes, within
/// 1.9·10⁻⁹ of it): the start of [`Spectrum::of`]'s Newton step on the triple-angle
/// equation, which squares that error times at most 2 (the equation's second
/// derivative over twice its slope), to round-off.
const TRIPLE_ANGLE_START: [f64; 9] = [
    0.939_692_620_785_908_6,
    0.065_821_795_623_308_16,
    -0.006_431_410_664_312_829,
    0.001_106_809_315_405_361_2,
    -0.000_233_689_308_813_585_68,
    0.000_054_368_007_035_855_546,
    -0.000_013_635_492_770_842_144,
    0.000_004_323_750_560_944_164,
    -0.000_001_183_024_135_937_355_6,
];

/// Relative gap of two eigenvalues below which their divided difference is taken from
/// the series in their logarithms rather than as a difference quotient.
pub const CLOSE_NODES: f64 = 1e-3;

/// Distance of a singular value from snow's bounds, relative to the upper one, within
/// which [`Spectrum::clamp`] declines a close pair (the closed-form eigenvalues of a
/// near-double pair err by up to √ε ≈ 1.5e-8 of their spread).
pub const BOUND_GUARD: f64 = 1e-6;

/// Relative spread of all three eigenvalues below which the second divided difference
/// is h''(x₀)/2 (its error, about h''' times the spread, multiplies a matrix of the
/// spread's square).
pub const COINCIDENT_NODES: f64 = 1e-8;

/// A plastic projection as a map of the log singular values l of F̂: each to (1 + `slope`)
/// l + `shift`, keeping the singular vectors (J2, Drucker–Prager: see
/// `plasticity::j2_map`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogMap {
    /// s.
    pub slope: f64,
    /// t.
    pub shift: f64,
    /// The increment of the plastic strain measure the projection adds.
    pub increment: f64,
}

/// What the J2 and Drucker–Prager projections read of the log singular values l =
/// log Σ̂: invariants, so that they can come from l itself or from the matrix ½ ln C
/// whose eigenvalues l are ([`super::series::project`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogInvariants {
    /// tr(l)/3.
    pub mean: f64,
    /// ‖dev l‖².
    pub deviatoric_squared: f64,
    /// ‖l‖².
    pub squared: f64,
}

impl LogInvariants {
    /// The invariants of the log singular values `log` (in any order).
    pub fn of(log: [f64; 3]) -> LogInvariants {
        let mean = (log[0] + log[1] + log[2]) / 3.0;
        let dev = log.map(|e| e - mean);
        LogInvariants {
            mean,
            deviatoric_squared: dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2],
            squared: log[0] * log[0] + log[1] * log[1] + log[2] * log[2],
        }
    }
}

/// The eigenvalues of C = F̂ᵀF̂ of a well-conditioned, non-inverted F̂, and C itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spectrum {
    /// C = F̂ᵀF̂.
    c: Mat3,
    /// The eigenvalues of C as Newton nodes: largest, smallest, middle.
    nodes: [f64; 3],
}

impl Spectrum {
    /// The spectrum of FᵀF, or `None` when det F ≤ 0 (inverted) or C's condition
    /// number passes 1/[`SPECTRUM_CONDITION_FLOOR`] (or F is not finite).
    pub fn of(f: &Mat3) -> Option<Spectrum> {
        Spectrum::of_gram(gram(f), determinant(f))
    }

    /// [`Spectrum::of`] from C = FᵀF and det F, where the caller has them.
    pub fn of_gram(c: Mat3, det: f64) -> Option<Spectrum> {
        if det.is_nan() || det <= 0.0 {
            return None;
        }
        // Products by 1/3 and 1/6 rather than quotients, and r's quotient taken beside
        // the square root p = √p², not after it: every step of this chain waits for the
        // one before it.
        let q = (c[0][0] + c[1][1] + c[2][2]) * (1.0 / 3.0);
        let off = c[0][1] * c[0][1] + c[0][2] * c[0][2] + c[1][2] * c[1][2];
        let d = [c[0][0] - q, c[1][1] - q, c[2][2] - q];
        let p2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * off) * (1.0 / 6.0);
        let nodes = if p2 > 0.0 {
            let p = p2.sqrt();
            let mut shifted = c;
            for (k, row) in shifted.iter_mut().enumerate() {
                row[k] -= q;
            }
            // det((C − qI)/p)/2 = det(C − qI) p/(2p⁴); where p⁴ underflows, ±∞ clamps to ±1
            // and a NaN fails the floor test below.
            let r = (0.5 * determinant(&shifted) / (p2 * p2) * p).clamp(-1.0, 1.0);
            let rho = r.abs();
            let t = 2.0 * rho - 1.0;
            // The start by Estrin's scheme (its chain is four products deep, Horner's
            // eight), then one Newton step.
            let k = TRIPLE_ANGLE_START;
            let t2 = t * t;
            let t4 = t2 * t2;
            let low = (k[0] + k[1] * t) + (k[2] + k[3] * t) * t2;
            let high = (k[4] + k[5] * t) + (k[6] + k[7] * t) * t2;
            let mut cos = low + high * t4 + k[8] * (t4 * t4);
            cos -= (cos * (4.0 * cos * cos - 3.0) - rho) / (12.0 * cos * cos - 3.0);
            let sin = ((1.0 - cos) * (1.0 + cos)).max(0.0).sqrt();
            let root3 = 3f64.sqrt();
            if r >= 0.0 {
                // φ = φ': cos φ = c, sin φ = sin φ'.
                [
                    q + 2.0 * p * cos,
                    q - p * (cos + root3 * sin),
                    q + p * (root3 * sin - cos),
                ]
            } else {
                // φ = π/3 − φ' (s = sin φ'): 2 cos φ = c + √3 s, 2 cos(φ + 2π/3) = −2c and
                // 2 cos(φ − 2π/3) = c − √3 s.
                [
                    q + p * (cos + root3 * sin),
                    q - 2.0 * p * cos,
                    q + p * (cos - root3 * sin),
                ]
            }
        } else {
            [q; 3]
        };
        // NaN nodes fail the comparison too.
        let conditioned = nodes[1] > SPECTRUM_CONDITION_FLOOR * nodes[0];
        if !conditioned || !nodes[0].is_finite() {
            return None;
        }
        Some(Spectrum { c, nodes })
    }

    /// The natural logarithms of C's eigenvalues, twice those of F̂'s singular values,
    /// in the order largest, smallest, middle (what [`Spectrum::power`] takes; taken
    /// only where a projection needs them).
    pub fn logs(&self) -> [f64; 3] {
        self.nodes.map(f64::ln)
    }

    /// Applies `map` (none: elastic) to `f`, the F̂ this is the spectrum of: F_E = eᵗ F̂
    /// C^{s/2}; `logs` are [`Spectrum::logs`]. Returns the map's increment of the
    /// plastic strain measure (0 when elastic).
    pub fn project(&self, f: &mut Mat3, map: Option<LogMap>, logs: &[f64; 3]) -> f64 {
        let Some(map) = map else {
            return 0.0;
        };
        let g = self.power(0.5 * map.slope, map.shift, logs);
        *f = mul(f, &g);
        map.increment
    }

    /// e^b C^a by Newton's divided-difference interpolation of h(x) = e^b x^a at the
    /// eigenvalues (every divided difference is linear in h, so e^b rides along);
    /// `logs` are [`Spectrum::logs`].
    pub fn power(&self, a: f64, b: f64, logs: &[f64; 3]) -> Mat3 {
        let h = logs.map(|l| (a * l + b).exp());
        self.interpolate(a, &h, logs)
    }

    /// The first divided difference h[x_i, x_j] of h = e^b x^a, whose values at the
    /// eigenvalues are `h`. Nodes within [`CLOSE_NODES`] take it as e^{(a−1)(L_i+L_j)/2}
    /// sinh(a d)/sinh(d), d = (L_i − L_j)/2, a series in d, from `logs` (L_k = ln x_k).
    fn first_difference(
        &self,
        a: f64,
        h: &[f64; 3],
        (i, j): (usize, usize),
        logs: &[f64; 3],
    ) -> f64 {
        let (xi, xj) = (self.nodes[i], self.nodes[j]);
        if (xi - xj).abs() > CLOSE_NODES * xi.max(xj) {
            return (h[i] - h[j]) / (xi - xj);
        }
        // e^b e^{(a−1)(L_i+L_j)/2} = √(h_i h_j/(x_i x_j)); sinh(ad)/sinh(d) to d⁴.
        let d = 0.5 * (logs[i] - logs[j]);
        let (a2, d2) = (a * a, d * d);
        let ratio = a * (1.0 + (a2 - 1.0) * d2 / 6.0 * (1.0 + (3.0 * a2 - 7.0) * d2 / 60.0));
        (h[i] * h[j] / (xi * xj)).sqrt() * ratio
    }

    /// The quadratic through h(x_k) = `h`[k] at the eigenvalues, evaluated at C, for h
    /// = e^b x^a: Newton's form (the divided differences of
    /// [`Spectrum::first_difference`]).
    fn interpolate(&self, a: f64, h: &[f64; 3], logs: &[f64; 3]) -> Mat3 {
        let [x0, x1, _] = self.nodes;
        let h01 = self.first_difference(a, h, (0, 1), logs);
        let spread = x0 - x1;
        let h012 = if spread > COINCIDENT_NODES * x0 {
            (self.first_difference(a, h, (0, 2), logs) - self.first_difference(a, h, (2, 1), logs))
                / spread
        } else {
            0.5 * a * (a - 1.0) * h[0] / (x0 * x0)
        };
        self.newton_form(h[0], h01, h012)
    }

    /// h[x₀] I + h[x₀, x₁](C − x₀I) + h[x₀, x₁, x₂](C − x₀I)(C − x₁I): Newton's form of
    /// the quadratic with these divided differences, at C.
    fn newton_form(&self, h0: f64, h01: f64, h012: f64) -> Mat3 {
        let [x0, x1, _] = self.nodes;
        let m0 = self.shifted(x0);
        let product = self.shifted_product(x0, x1);
        let mut out = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] = h01 * m0[i][j] + h012 * product[i][j] + if i == j { h0 } else { 0.0 };
            }
        }
        out
    }

    /// C − xI.
    fn shifted(&self, x: f64) -> Mat3 {
        let mut m = self.c;
        for (k, row) in m.iter_mut().enumerate() {
            row[k] -= x;
        }
        m
    }

    /// (C − xI)(C − yI), symmetric (the two factors commute).
    fn shifted_product(&self, x: f64, y: f64) -> Mat3 {
        let (a, b) = (self.shifted(x), self.shifted(y));
        let mut out = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                let v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
                out[i][j] = v;
                out[j][i] = v;
            }
        }
        out
    }

    /// Snow's projection (Lyu §3.3.3, Stomakhin et al. 2013): F̂'s singular values
    /// clamped to lo ≤ σ ≤ hi, its singular vectors kept. Returns the increment
    /// ‖log Σ̂ − log Σ‖ (0, `f` untouched, when nothing is clamped), or `None`, `f`
    /// untouched, where two eigenvalues that the clamp treats differently are closer
    /// than [`CLOSE_NODES`] of the largest, or a close pair is within [`BOUND_GUARD`] of
    /// a bound (the caller takes the eigenvectors then).
    ///
    /// The clamp is a power law on each of three pieces (below lo: lo σ̂⁻¹ = lo C^{−½};
    /// inside: 1; above: hi C^{−½}), and the sorted eigenvalues fall on the pieces in
    /// order, so those sharing the middle eigenvalue x₂'s piece take its law m(C) (any
    /// function of C equal to the law at those eigenvalues: the polynomial through
    /// them alone) and an eigenvalue x_k alone on its piece is corrected by its
    /// spectral projector P_k = (C − x_iI)(C − x_jI)/((x_k − x_i)(x_k − x_j)): F_E =
    /// F̂ (m(C) + Σ_k (r_k − m(x_k)) P_k), r_k the clamp's ratio at x_k. A projector of
    /// an eigenvalue apart from the others by more than [`CLOSE_NODES`] is accurate to
    /// about ε/CLOSE_NODES; a close pair on one piece shares a law and needs no
    /// projector.
    pub fn clamp(&self, f: &mut Mat3, lo: f64, hi: f64) -> Option<f64> {
        let sigma = self.nodes.map(f64::sqrt);
        let piece = sigma.map(|s| {
            if s < lo {
                -1
            } else if s > hi {
                1
            } else {
                0
            }
        });
        let bound = |p: i32| if p < 0 { lo } else { hi };
        let [x0, x1, x2] = self.nodes;
        let (top, bottom) = (piece[0] != piece[2], piece[1] != piece[2]);
        // A close pair straddling a bound by less than the closed form's √ε error
        // could be put on one piece: decline it too.
        let near = |k: usize| {
            (sigma[k] - lo).abs() <= BOUND_GUARD * hi || (sigma[k] - hi).abs() <= BOUND_GUARD * hi
        };
        let (close_top, close_bottom) = (x0 - x2 <= CLOSE_NODES * x0, x2 - x1 <= CLOSE_NODES * x0);
        if close_top && (top || near(0) || near(2))
            || close_bottom && (bottom || near(2) || near(1))
        {
            return None;
        }
        if piece == [0; 3] {
            return Some(0.0);
        }
        // The middle piece's law m(C) and its values m(x_k): the clamp's ratio at the
        // nodes on that piece, interpolated through them alone (the others are
        // corrected by their projectors): bound C^{−½} through all three, a line
        // through two, by the divided differences of [`inverse_root_difference`] and
        // [`inverse_root_second_difference`]. (A clamped middle shares its piece with the
        // top or the bottom node, as the pieces are in the nodes' order.)
        let (mut g, law) = match piece[2] {
            0 => (IDENTITY, [1.0; 3]),
            p => {
                let b = bound(p);
                let h = sigma.map(|s| b / s);
                match (top, bottom) {
                    (false, false) => {
                        let h01 = inverse_root_difference(b, sigma[0], sigma[1]);
                        let h012 = inverse_root_second_difference(b, sigma);
                        (self.newton_form(h[0], h01, h012), h)
                    }
                    (top, _) => {
                        let (i, j) = if top { (2, 1) } else { (0, 2) };
                        let slope = inverse_root_difference(b, sigma[i], sigma[j]);
                        let base = h[i] - slope * self.nodes[i];
                        let mut line = self.c.map(|row| row.map(|x| slope * x));
                        for (k, row) in line.iter_mut().enumerate() {
                            row[k] += base;
                        }
                        (line, self.nodes.map(|x| base + slope * x))
                    }
                }
            }
        };
        let ratio = |k: usize| match piece[k] {
            0 => 1.0,
            p => bound(p) / sigma[k],
        };
        for (alone, k, i, j) in [(top, 0, 1, 2), (bottom, 1, 0, 2)] {
            if alone {
                let (xk, xi, xj) = (self.nodes[k], self.nodes[i], self.nodes[j]);
                // The reciprocal does not wait for the law, a quotient would.
                let weight = (ratio(k) - law[k]) * (1.0 / ((xk - xi) * (xk - xj)));
                let projector = self.shifted_product(xi, xj);
                for (row, p_row) in g.iter_mut().zip(&projector) {
                    for (x, p) in row.iter_mut().zip(p_row) {
                        *x += weight * p;
                    }
                }
            }
        }
        *f = mul(f, &g);
        let change: f64 = (0..3)
            .map(|k| {
                // log σ̂ − log σ = log(σ̂/bound).
                let d = match piece[k] {
                    0 => 0.0,
                    p => log_ratio(sigma[k], bound(p)),
                };
                d * d
            })
            .sum();
        Some(change.sqrt())
    }
}

/// The first divided difference of h(x) = b x^{−½} at x_i = s_i², x_j = s_j²:
/// (b/s_i − b/s_j)/(s_i² − s_j²) = −b/(s_i s_j (s_i + s_j)), without cancellation and
/// equal to h'(x_i) when the nodes coincide.
fn inverse_root_difference(b: f64, si: f64, sj: f64) -> f64 {
    -b / (si * sj * (si + sj))
}

/// The second divided difference of h(x) = b x^{−½} at x_k = s_k² (k = 0, 1, 2):
/// (h[x₀, x₂] − h[x₂, x₁])/(x₀ − x₁) by [`inverse_root_difference`], whose numerator
/// b (s₀ − s₁)(s₀ + s₁ + s₂)/(s₀ s₁ s₂ (s₀ + s₂)(s₁ + s₂)) shares the factor s₀ − s₁
/// with the denominator: b (s₀ + s₁ + s₂)/(s₀ s₁ s₂ (s₀ + s₁)(s₀ + s₂)(s₁ + s₂)),
/// h''(x)/2 = 3b/(8 s⁵) at a triple node.
fn inverse_root_second_difference(b: f64, [s0, s1, s2]: [f64; 3]) -> f64 {
    b * (s0 + s1 + s2) / (s0 * s1 * s2 * ((s0 + s1) * (s0 + s2) * (s1 + s2)))
}

/// The largest |u|, u = (s − b)/(s + b), for which [`log_ratio`] sums its series (s
/// within about 6% of b).
const LOG_SERIES_RADIUS: f64 = 3e-2;

/// ln(s/b) of positive `s` and `b`. Near b (|u| ≤ [`LOG_SERIES_RADIUS`]) by the series
/// ln(s/b) = 2 atanh u = 2u (1 + u²/3 + u⁴/5 + u⁶/7 + u⁸/9 + …) to u⁸, whose first
/// term left out is below 6·10⁻¹⁷ of the sum, with no call to the logarithm: a
/// singular value that snow clamped in the last step has grown from its bound by one
/// step's deformation; elsewhere the logarithm.
fn log_ratio(s: f64, b: f64) -> f64 {
    let u = (s - b) / (s + b);
    if u.abs() > LOG_SERIES_RADIUS {
        return (s / b).ln();
    }
    let u2 = u * u;
    2.0 * u * (1.0 + u2 * (1.0 / 3.0 + u2 * (1.0 / 5.0 + u2 * (1.0 / 7.0 + u2 * (1.0 / 9.0)))))
}
