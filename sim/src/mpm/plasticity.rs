//! Plastic flow of MPM materials and the impact models of Lyu 2021 ch. 7: J2
//! plasticity with Johnson–Cook hardening by radial return (Eq. 7.5–7.8, App. B), snow
//! plasticity by clamping singular values (§3.3.3, Stomakhin et al. 2013),
//! Drucker–Prager (Klár et al. 2016), and the simplified Mie–Grüneisen pressure with its
//! internal energy (Eq. 7.3–7.4).
//!
//! **Where plasticity acts.** Every model here projects the particle's deformation
//! gradient after G2P has grown it, F̂ = (I + Δt C_p) F_p (Lyu's "particle strain
//! update" step), so F_p always holds the *elastic* part F_E; the plastic part is not
//! needed for the stress and is not stored. With the SVD F̂ = U Σ̂ Vᵀ:
//! - snow clamps Σ̂ to [1 − θ_c, 1 + θ_s] (§3.3.3, step 2–3);
//! - J2 takes the trial deviatoric Kirchhoff stress τ* = 2μ dev(log Σ̂) (the Hencky
//!   strain's; the small-strain deviatoric stress of every energy here), returns it to
//!   the Johnson–Cook surface by [`radial_return`], and rebuilds Σ = exp(τ/(2μ) +
//!   tr(log Σ̂)/3) so that J is kept (J2 flow is isochoric, Lyu §7.3.1);
//! - Drucker–Prager projects log Σ̂ onto the cone of friction angle φ (Klár et al.
//!   2016, Eq. 27–28 with d = 3).
//!
//! **How F̂ is decomposed.** Every projection maps the singular values Σ̂ to new ones
//! Σ and keeps U and V. J2 and Drucker–Prager map log Σ̂ affinely, so F_E = eᵗ F̂
//! C^{s/2} with C = F̂ᵀF̂ needs only C's eigenvalues, in closed form, and no
//! eigenvectors ([`Spectrum`], [`LogMap`]), or at small strain (‖C − I‖ ≤
//! [`super::series::SERIES_STRAIN`]) not even those: ln C and C^{s/2} by their series
//! in C − I ([`series::project`]); snow's clamp is such a power on each
//! of its pieces ([`Spectrum::clamp`]). Where the closed form would lose digits, F_E =
//! U Σ Vᵀ = F̂ V Σ̂⁻¹ Σ Vᵀ takes V and Σ̂ from [`symmetric_eigen`] (Jacobi) at a
//! fraction of the cost of nalgebra's SVD ([`Stretch`]). Squaring F̂ squares its
//! condition number, so an inverted or nearly degenerate F̂ (det F̂ ≤ 0, or λ_min(C) <
//! [`EIGEN_CONDITION_FLOOR`] λ_max(C)) takes the inversion-safe SVD
//! ([`rotation_svd`]); the Jacobi path takes what lies between that and the closed
//! form's floor ([`super::spectral::SPECTRUM_CONDITION_FLOOR`]). Before
//! any of it, every model asks whether the particle can yield at all from invariants
//! that cost a few multiplications ([`j2_surely_elastic`], the Gershgorin discs of C
//! for snow, [`drucker_prager_surely_elastic`]), so a particle inside the yield surface
//! is not decomposed. The test
//! `fast_projections_match_the_svd_ones` holds every projection to its SVD form.

use perifrac_math::{RotationSvd, rotation_svd};

use super::constitutive::{Mat3, determinant, gram, mul, symmetric_eigen};
use super::johnson_cook::return_map;
pub use super::johnson_cook::{
    HARDENING_STRAIN_FLOOR, JohnsonCook, RETURN_ITERATIONS, RETURN_TOLERANCE, Return,
    TAYLOR_QUINNEY, Thermal, deviatoric, equivalent_stress, radial_return,
};
use super::series;
use super::spectral::{LogInvariants, LogMap, Spectrum};

/// The simplified Mie–Grüneisen equation of state (Eq. 7.4, with the sign of its
/// denominator corrected; see [`MieGruneisen::pressure`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MieGruneisen {
    /// Reference density ρ₀ (kg/m³).
    pub density: f64,
    /// Bulk sound speed c₀ (m/s).
    pub sound_speed: f64,
    /// Slope S of the shock–particle velocity relation v_s = c₀ + S v_p (1.1 in the
    /// thesis).
    pub slope: f64,
    /// Grüneisen parameter γ (1.6 in the thesis).
    pub gamma: f64,
}

/// The smallest value the Hugoniot's denominator base 1 − (S − 1)ζ is allowed: it
/// vanishes at the compression limit ρ/ρ₀ = S/(S − 1) of a linear u_s–u_p relation,
/// where the pressure would diverge and then change sign. Held at 0.1, the pressure
/// goes on rising (as ζ²) past ζ = 0.9/(S − 1), far beyond any compression a shot
/// reaches (ρ/ρ₀ ≈ 9.2 for S = 1.1, 2.8 for copper's S = 1.49).
const HUGONIOT_DENOMINATOR_MIN: f64 = 0.1;

impl MieGruneisen {
    /// The pressure p(J, e) with ζ = 1/J − 1: in compression (ζ ≥ 0)
    /// ρ₀c₀²ζ[1 + (1 − γ/2)ζ]/[1 − (S − 1)ζ]² + γ(e − e⁰), in tension ρ₀c₀²ζ + γ(e − e⁰);
    /// `energy_change` is e − e⁰ (J/m³).
    ///
    /// The thesis prints the denominator as [1 + (S − 1)ζ]² (Eq. 7.4). The Hugoniot of
    /// u_s = c₀ + S u_p is p_H = ρ₀c₀²η/(1 − Sη)² with η = 1 − J = ζ/(1 + ζ), that is
    /// ρ₀c₀²ζ(1 + ζ)/[1 − (S − 1)ζ]², the standard Mie–Grüneisen form (Steinberg 1996;
    /// LS-DYNA's `*EOS_GRUNEISEN`) that Eq. 7.4 abbreviates: the minus sign. The
    /// thesis' plus softens compression instead of stiffening it: a copper flyer plate
    /// at 1 km/s then sends its shock at 0.87 of the Hugoniot's speed, and at 1.0 with
    /// the minus (`tests/shock.rs`, docs/mpm.md).
    pub fn pressure(&self, j: f64, energy_change: f64) -> f64 {
        let zeta = 1.0 / j - 1.0;
        let k = self.density * self.sound_speed * self.sound_speed;
        let cold = if zeta >= 0.0 {
            let d = (1.0 - (self.slope - 1.0) * zeta).max(HUGONIOT_DENOMINATOR_MIN);
            k * zeta * (1.0 + (1.0 - 0.5 * self.gamma) * zeta) / (d * d)
        } else {
            k * zeta
        };
        cold + self.gamma * energy_change
    }
}

/// The internal energy increment Δe = Δt sym(C) : σ (Eq. 7.3), with C the APIC affine
/// matrix (the velocity gradient) and σ the Cauchy stress.
pub fn internal_energy_increment(dt: f64, affine: &Mat3, stress: &Mat3) -> f64 {
    let mut sum = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            sum += 0.5 * (affine[i][j] + affine[j][i]) * stress[i][j];
        }
    }
    dt * sum
}

/// The smallest singular value logarithms are taken of: an inverted or collapsed
/// elastic gradient is treated as compressed to this (J2 and Drucker–Prager only).
pub const SINGULAR_VALUE_FLOOR: f64 = 1e-6;

/// The plastic flow of a material, as the step applies it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plasticity {
    /// Elastic.
    None,
    /// J2 flow with Johnson–Cook hardening (Eq. 7.5–7.8).
    JohnsonCook(JohnsonCook),
    /// Singular values clamped to [1 − θ_c, 1 + θ_s] (§3.3.3).
    Snow {
        /// Critical compression θ_c.
        critical_compression: f64,
        /// Critical stretch θ_s.
        critical_stretch: f64,
    },
    /// Drucker–Prager with friction coefficient α = √(2/3) · 2 sin φ/(3 − sin φ)
    /// (Klár et al. 2016 Eq. 27).
    DruckerPrager {
        /// α of the friction angle.
        alpha: f64,
    },
}

/// What the projection needs of the particle and its material.
#[derive(Debug, Clone, Copy)]
pub struct FlowInput {
    /// Lamé shear modulus μ (Pa).
    pub mu: f64,
    /// Lamé's first parameter λ (Pa).
    pub lambda: f64,
    /// The equivalent strain rate ε̇ = √(2/3 dev D : dev D) of D = sym(C_p) (1/s): the
    /// rate of Johnson–Cook's Eq. 7.7 (the plastic rate equals it while flowing); the
    /// step leaves it 0 where [`Plasticity::reads_rate`] says it is not read.
    pub rate: f64,
    /// The particle's equivalent plastic strain ε^p before this step.
    pub plastic_strain: f64,
    /// The particle's temperature (K) before this step (read by the thermal
    /// Johnson–Cook term only).
    pub temperature: f64,
}

/// U diag(σ) Vᵀ.
pub fn compose(u: &Mat3, sigma: [f64; 3], v: &Mat3) -> Mat3 {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| u[i][k] * sigma[k] * v[j][k]).sum()))
}

/// The equivalent strain rate √(2/3 dev D : dev D) of D = sym(C) (1/s).
pub fn equivalent_strain_rate(affine: &Mat3) -> f64 {
    let d = [0, 1, 2].map(|i| [0, 1, 2].map(|j| 0.5 * (affine[i][j] + affine[j][i])));
    let dev = deviatoric(&d);
    (2.0 / 3.0 * dev.iter().flatten().map(|x| x * x).sum::<f64>()).sqrt()
}

impl Plasticity {
    /// Whether the projection reads [`FlowInput::rate`]: only Johnson–Cook with a rate
    /// coefficient C ≠ 0 does.
    pub fn reads_rate(&self) -> bool {
        matches!(self, Plasticity::JohnsonCook(hardening) if hardening.c != 0.0)
    }

    /// The Drucker–Prager flow of friction angle `degrees`.
    pub fn drucker_prager(degrees: f64) -> Plasticity {
        let s = degrees.to_radians().sin();
        Plasticity::DruckerPrager {
            alpha: (2.0f64 / 3.0).sqrt() * 2.0 * s / (3.0 - s),
        }
    }

    /// Projects the elastic deformation gradient `f` onto the material's admissible set
    /// and returns the increment of the plastic strain measure: Δε^p of the radial
    /// return (J2), ‖log Σ̂ − log Σ‖ (snow), δγ (Drucker–Prager); 0 when elastic:
    /// [`Plasticity::surely_elastic`], then [`Plasticity::project_yielding`]. Snow's
    /// check and clamp share C = F̂ᵀF̂ and det F̂ (on a melon's flesh, nine particles in
    /// ten fail the check and are clamped, every step).
    pub fn project(&self, f: &mut Mat3, input: &FlowInput) -> f64 {
        if let Plasticity::Snow {
            critical_compression,
            critical_stretch,
        } = *self
        {
            let (lo, hi) = snow_bounds(critical_compression, critical_stretch);
            let (det, c) = (determinant(f), gram(f));
            if snow_surely_elastic(det, &c, lo, hi) {
                return 0.0;
            }
            return self.clamp(f, input, lo, hi, Spectrum::of_gram(c, det));
        }
        if self.surely_elastic(f, input) {
            return 0.0;
        }
        self.project_yielding(f, input)
    }

    /// Whether `f` cannot yield, from invariants that cost a few multiplications
    /// and without a decomposition or the strain rate: J2 by [`j2_surely_elastic`] at
    /// the flow stress of the reference rate (the rate factor is never below 1),
    /// snow by the Gershgorin discs of C, Drucker–Prager by
    /// [`drucker_prager_surely_elastic`]. False when it may yield.
    pub fn surely_elastic(&self, f: &Mat3, input: &FlowInput) -> bool {
        match *self {
            Plasticity::None => true,
            Plasticity::JohnsonCook(ref hardening) => {
                let law = hardening.at_temperature(input.temperature).at_rate(0.0);
                // A ≤ σ_y (B ≥ 0 or n = 0) first: it spares the power (ε^p)ⁿ where it
                // suffices.
                ((law.b >= 0.0 || law.n == 0.0) && j2_surely_elastic(f, input.mu, law.a))
                    || (law.n != 0.0
                        && j2_surely_elastic(
                            f,
                            input.mu,
                            law.yield_stress(input.plastic_strain, 0.0),
                        ))
            }
            Plasticity::Snow {
                critical_compression,
                critical_stretch,
            } => {
                let (lo, hi) = snow_bounds(critical_compression, critical_stretch);
                snow_surely_elastic(determinant(f), &gram(f), lo, hi)
            }
            Plasticity::DruckerPrager { alpha } => {
                drucker_prager_surely_elastic(f, alpha, input.mu, input.lambda)
            }
        }
    }

    /// [`Plasticity::project`] without its first check. Where F̂ is well conditioned
    /// every model takes the closed-form eigenvalues of F̂ᵀF̂ ([`Spectrum`]): J2 and
    /// Drucker–Prager rebuild F_E as a power of it, snow as a power on each piece of
    /// its clamp ([`Spectrum::clamp`], unless two eigenvalues the clamp treats
    /// differently are close); otherwise F̂ is decomposed once by [`Stretch::of`].
    pub fn project_yielding(&self, f: &mut Mat3, input: &FlowInput) -> f64 {
        let map = match *self {
            Plasticity::None => return 0.0,
            Plasticity::Snow {
                critical_compression,
                critical_stretch,
            } => {
                let (lo, hi) = snow_bounds(critical_compression, critical_stretch);
                return self.clamp(f, input, lo, hi, Spectrum::of(f));
            }
            Plasticity::JohnsonCook(_) | Plasticity::DruckerPrager { .. } => {
                // The series and the closed form share C and det F̂.
                let (c, det) = (gram(f), determinant(f));
                if let Some(increment) = series::project(f, &c, det, |log| self.log_map(log, input))
                {
                    return increment;
                }
                Spectrum::of_gram(c, det).map(|spectrum| {
                    let logs = spectrum.logs();
                    let map = self.log_map(LogInvariants::of(logs.map(|l| 0.5 * l)), input);
                    (spectrum, logs, map)
                })
            }
        };
        if let Some((spectrum, logs, map)) = map {
            return spectrum.project(f, map, &logs);
        }
        let stretch = Stretch::of(f);
        self.project_with(f, input, &stretch)
    }

    /// Snow's clamp of `f` to singular values lo ≤ σ ≤ hi by its `spectrum`
    /// ([`Spectrum::clamp`]), or by [`Stretch::of`] where there is none or the clamp
    /// declines it.
    fn clamp(
        &self,
        f: &mut Mat3,
        input: &FlowInput,
        lo: f64,
        hi: f64,
        spectrum: Option<Spectrum>,
    ) -> f64 {
        if let Some(increment) = spectrum.and_then(|spectrum| spectrum.clamp(f, lo, hi)) {
            return increment;
        }
        let stretch = Stretch::of(f);
        self.project_with(f, input, &stretch)
    }

    /// [`Plasticity::project`] with the decomposition `stretch` of `f` given (the
    /// tests give it the SVD to compare with).
    pub fn project_with(&self, f: &mut Mat3, input: &FlowInput, stretch: &Stretch) -> f64 {
        let sigma = stretch.sigma();
        match *self {
            Plasticity::None => 0.0,
            Plasticity::JohnsonCook(_) | Plasticity::DruckerPrager { .. } => {
                let log = sigma.map(|s| s.max(SINGULAR_VALUE_FLOOR).ln());
                let Some(map) = self.log_map(LogInvariants::of(log), input) else {
                    return 0.0;
                };
                let projected = log.map(|l| ((1.0 + map.slope) * l + map.shift).exp());
                *f = stretch.rebuild(f, projected);
                map.increment
            }
            Plasticity::Snow {
                critical_compression,
                critical_stretch,
            } => {
                let (lo, hi) = snow_bounds(critical_compression, critical_stretch);
                let clamped = sigma.map(|s| s.clamp(lo, hi));
                if clamped == sigma {
                    return 0.0;
                }
                *f = stretch.rebuild(f, clamped);
                let change: f64 = (0..3)
                    .map(|a| {
                        let d = sigma[a].abs().max(SINGULAR_VALUE_FLOOR).ln() - clamped[a].ln();
                        d * d
                    })
                    .sum();
                change.sqrt()
            }
        }
    }

    /// The projection of J2 or Drucker–Prager as a map of the log singular values
    /// whose invariants are `log` ([`j2_map`], [`drucker_prager_map`]); `None` when
    /// elastic and for the other models, whose projections are not of this form.
    fn log_map(&self, log: LogInvariants, input: &FlowInput) -> Option<LogMap> {
        match *self {
            Plasticity::JohnsonCook(ref hardening) => {
                let law = hardening
                    .at_temperature(input.temperature)
                    .at_rate(input.rate);
                j2_map(&law, log, input)
            }
            Plasticity::DruckerPrager { alpha } => drucker_prager_map(alpha, log, input),
            Plasticity::None | Plasticity::Snow { .. } => None,
        }
    }
}

/// J2's projection as a map of the log singular values l = log Σ̂ whose invariants
/// are `log`, each l to (1 + s) l + t; `None` when elastic. The trial deviatoric
/// Kirchhoff stress τ* = 2μ dev l, returned by [`radial_return`] on the flow stress law
/// `law` (at the step's rate and temperature) with scaling k, gives log Σ = k dev l +
/// tr(l)/3 (J kept): s = k − 1, t = −s tr(l)/3.
fn j2_map(law: &JohnsonCook, log: LogInvariants, input: &FlowInput) -> Option<LogMap> {
    let mean = log.mean;
    // s* = √(3/2) ‖2μ dev l‖.
    let trial = 2.0 * input.mu * (1.5 * log.deviatoric_squared).sqrt();
    let (increment, scale) = return_map(trial, input.mu, input.plastic_strain, law, input.rate);
    (increment > 0.0).then(|| {
        let slope = scale - 1.0;
        LogMap {
            slope,
            shift: -slope * mean,
            increment,
        }
    })
}

/// Drucker–Prager's projection of friction coefficient `alpha` as a map of `log` (as
/// [`j2_map`]). Compressed (tr l < 0): log Σ = l − δγ dev l/‖dev l‖ with δγ = ‖dev l‖ +
/// (3λ + 2μ)/(2μ) tr(l) α (Klár et al. 2016 Eq. 28): s = −δγ/‖dev l‖, t = −s tr(l)/3;
/// stretched (tr l ≥ 0): the tip Σ = I, s = −1, t = 0.
fn drucker_prager_map(alpha: f64, log: LogInvariants, input: &FlowInput) -> Option<LogMap> {
    let mean = log.mean;
    let trace = 3.0 * mean;
    if trace >= 0.0 {
        // Stretched: no cohesion, the tip of the cone.
        return Some(LogMap {
            slope: -1.0,
            shift: 0.0,
            increment: log.squared.sqrt(),
        });
    }
    let dev_norm = log.deviatoric_squared.sqrt();
    // Compressed: a purely volumetric state (dev = 0) is inside the cone.
    let gamma = dev_norm + (3.0 * input.lambda + 2.0 * input.mu) / (2.0 * input.mu) * trace * alpha;
    (gamma > 0.0).then(|| {
        let slope = -gamma / dev_norm;
        LogMap {
            slope,
            shift: -slope * mean,
            increment: gamma,
        }
    })
}

/// The smallest ratio λ_min/λ_max of C = F̂ᵀF̂ (the squared inverse condition number
/// of F̂) that [`Stretch::of`] decomposes by the eigen-solve: below it the singular
/// values' relative error, about 10⁻¹⁵ λ_max/λ_min, could pass 10⁻⁹, and the SVD is
/// taken.
pub const EIGEN_CONDITION_FLOOR: f64 = 1e-6;

/// The decomposition of F̂ that the projections share: what they need is Σ̂ and a way
/// to rebuild U Σ Vᵀ for new singular values Σ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stretch {
    /// From the eigen-solve of C = F̂ᵀF̂ = V Σ̂² Vᵀ (det F̂ > 0): U Σ Vᵀ = F̂ V Σ̂⁻¹ Σ Vᵀ.
    Eigen {
        /// Singular values Σ̂ = √λ(C), positive.
        sigma: [f64; 3],
        /// Right singular vectors V (the eigenvectors of C, as columns).
        v: Mat3,
    },
    /// The inversion-safe SVD, for an inverted or nearly degenerate F̂.
    Svd(RotationSvd),
}

impl Stretch {
    /// The eigen-solve of F̂ᵀF̂ where F̂ is well conditioned and not inverted, else the
    /// SVD.
    pub fn of(f: &Mat3) -> Stretch {
        if determinant(f) > 0.0 {
            let (lambda, v) = symmetric_eigen(&gram(f));
            let largest = lambda[0].max(lambda[1]).max(lambda[2]);
            let smallest = lambda[0].min(lambda[1]).min(lambda[2]);
            if smallest > EIGEN_CONDITION_FLOOR * largest {
                return Stretch::Eigen {
                    sigma: lambda.map(f64::sqrt),
                    v,
                };
            }
        }
        Stretch::Svd(rotation_svd(f))
    }

    /// The singular values Σ̂ (the smallest negative when F̂ is inverted).
    pub fn sigma(&self) -> [f64; 3] {
        match self {
            Stretch::Eigen { sigma, .. } => *sigma,
            Stretch::Svd(svd) => svd.sigma,
        }
    }

    /// U diag(`sigma`) Vᵀ of the decomposition of `f`.
    pub fn rebuild(&self, f: &Mat3, sigma: [f64; 3]) -> Mat3 {
        match self {
            Stretch::Eigen { sigma: old, v } => {
                let ratio = [0, 1, 2].map(|a| sigma[a] / old[a]);
                mul(f, &compose(v, ratio, v))
            }
            Stretch::Svd(svd) => compose(&svd.u, sigma, &svd.v),
        }
    }
}

/// The margin in δ = I_C/J^{2/3} − 3 that [`j2_surely_elastic`] and
/// [`drucker_prager_surely_elastic`] leave for the round-off of I_C and J (about
/// 10⁻¹⁵ in δ, which is about 2‖dev log Σ̂‖²): a particle that would yield at a
/// deviatoric strain below about 2·10⁻⁷ is never accepted and goes to the exact test.
/// Without it, J2 accepted trial states strained 10⁻⁸ past a yield strain of 10⁻⁸
/// (found by `small_strain_projections_match_the_svd_ones`).
pub const INVARIANT_ROUNDING: f64 = 1e-13;

/// Whether the J2 trial state of `f` lies inside the yield surface σ_y for certain,
/// from the invariants I_C = tr FᵀF and J = det F alone. With ν_a = σ̂_a²/J^{2/3} (so
/// Π ν_a = 1), x_a = ln ν_a and δ = Σ ν_a − 3 = Σ (e^{x_a} − 1 − x_a) = I_C/J^{2/3} − 3,
/// Taylor's remainder gives x² ≤ 2 (e^x − 1 − x) e^{max(−x, 0)}, and
/// e^{−y} − 1 + y ≥ y²/3 for 0 ≤ y ≤ 1 bounds −x_a by √(3δ) when δ < 1/3. The trial
/// deviatoric Hencky strain is x/2, so its equivalent stress s* = 2μ √(3/2) ‖x/2‖
/// satisfies s*² ≤ 3μ² δ e^{√(3δ)}, and the particle is elastic if that is ≤ σ_y².
/// The bound is tight at small strain (s*² → 3μ² δ); δ is taken
/// [`INVARIANT_ROUNDING`] larger than computed.
pub fn j2_surely_elastic(f: &Mat3, mu: f64, yield_stress: f64) -> bool {
    let j = determinant(f);
    if j.is_nan() || j <= 0.0 {
        return false;
    }
    let ic: f64 = f.iter().flatten().map(|x| x * x).sum();
    let limit = yield_stress * yield_stress;
    // The bound without its factor e^{√(3δ)} ≥ 1 first, and without the cube root:
    // 3μ²δ ≤ σ_y² is I_C³ ≤ (3 + σ_y²/(3μ²))³ J², which a flowing particle fails.
    let most = 3.0 + limit / (3.0 * mu * mu);
    if ic * ic * ic > most * most * most * j * j {
        return false;
    }
    let cbrt = j.cbrt();
    let delta = (ic / (cbrt * cbrt) - 3.0).max(0.0) + INVARIANT_ROUNDING;
    delta < 1.0 / 3.0 && 3.0 * mu * mu * delta * (3.0 * delta).sqrt().exp() <= limit
}

/// Whether the Drucker–Prager trial state of `f` lies inside the cone of friction
/// coefficient `alpha` for certain, from I_C = tr FᵀF and J = det F alone. With l =
/// log Σ̂, the state is inside when ‖dev l‖ ≤ k α (−tr l), k = (3λ + 2μ)/(2μ) (δγ ≤ 0 of
/// Klár et al. 2016 Eq. 28), tr l = ln J; a stretched particle (J ≥ 1) goes to the
/// tip and is never inside. The bound of [`j2_surely_elastic`] with x = 2 dev l gives
/// ‖dev l‖² ≤ δ e^{√(3δ)}/2 for δ = I_C/J^{2/3} − 3 < 1/3, and −ln J ≥ u + u²/2 with
/// u = 1 − J (the series of −ln(1 − u) has no negative term). So with m = kα(u + u²/2),
/// δ₀ = min(2m², 0.3) and e^{√(3δ₀)} ≤ 1/(1 − √(3δ₀)), the state is inside if δ ≤
/// δ₀(1 − √(3δ₀)), that is I_C³ ≤ (3 + δ₀(1 − √(3δ₀)))³ J² (less a rounding margin,
/// [`INVARIANT_ROUNDING`]): no logarithm, cube root or exponential. At small
/// strain it accepts states up to about 1 − √(3δ₀)/2 of the cone's radius.
pub fn drucker_prager_surely_elastic(f: &Mat3, alpha: f64, mu: f64, lambda: f64) -> bool {
    let j = determinant(f);
    // NaN fails too.
    if !(j > 0.0 && j < 1.0) {
        return false;
    }
    let u = 1.0 - j;
    let radius = (3.0 * lambda + 2.0 * mu) / (2.0 * mu) * alpha * u * (1.0 + 0.5 * u);
    // δ₀ = 2m² and √(3δ₀) = √6 m, or 0.3 and √0.9: no square root to wait for.
    let (cap, root) = if radius * radius < 0.15 {
        (2.0 * radius * radius, 6f64.sqrt() * radius)
    } else {
        (0.3, 0.9f64.sqrt())
    };
    let most = cap * (1.0 - root) - INVARIANT_ROUNDING;
    if most <= 0.0 {
        return false;
    }
    let ic: f64 = f.iter().flatten().map(|x| x * x).sum();
    let bound = 3.0 + most;
    ic * ic * ic <= bound * bound * bound * j * j
}

/// Snow's range of singular values: [1 − θ_c, 1 + θ_s].
fn snow_bounds(critical_compression: f64, critical_stretch: f64) -> (f64, f64) {
    (1.0 - critical_compression, 1.0 + critical_stretch)
}

/// Whether snow's clamp to lo ≤ σ ≤ hi leaves F̂ alone for certain, from C = F̂ᵀF̂
/// and det F̂: not inverted, and every Gershgorin disc of C within [lo², hi²].
fn snow_surely_elastic(det: f64, c: &Mat3, lo: f64, hi: f64) -> bool {
    det > 0.0 && gershgorin_within(c, lo * lo, hi * hi)
}

/// Whether every Gershgorin disc of the symmetric `c` lies in [lo, hi], so that its
/// eigenvalues do.
fn gershgorin_within(c: &Mat3, lo: f64, hi: f64) -> bool {
    (0..3).all(|i| {
        let radius = c[i][(i + 1) % 3].abs() + c[i][(i + 2) % 3].abs();
        c[i][i] - radius >= lo && c[i][i] + radius <= hi
    })
}
