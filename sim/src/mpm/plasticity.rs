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

use super::constitutive::{Mat3, RotationSvd, rotation_svd};

/// Johnson–Cook flow stress σ_y(ε^p, ε̇^p) = (A + B (ε^p)ⁿ)(1 + C ln(ε̇^p/ε̇₀)) (Eq. 7.7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JohnsonCook {
    /// Yield stress A at the reference strain rate (Pa).
    pub a: f64,
    /// Strain hardening coefficient B (Pa).
    pub b: f64,
    /// Strain hardening exponent n (0: perfectly plastic, von Mises).
    pub n: f64,
    /// Strain-rate hardening coefficient C.
    pub c: f64,
    /// Reference equivalent plastic strain rate ε̇₀ (1/s); 1 in the thesis.
    pub reference_rate: f64,
}

/// The plastic strain at which the hardening modulus of an exponent n < 1 is taken
/// when ε^p is smaller (B n (ε^p)ⁿ⁻¹ is infinite at ε^p = 0).
pub const HARDENING_STRAIN_FLOOR: f64 = 1e-6;
/// Newton iterations of the return map at most.
pub const RETURN_ITERATIONS: usize = 50;
/// Relative tolerance of the return map's consistency condition |f| ≤ tol σ_y.
pub const RETURN_TOLERANCE: f64 = 1e-12;

impl JohnsonCook {
    /// The rate factor 1 + C ln(ε̇^p/ε̇₀), never below 1 (rates under the reference do
    /// not soften).
    fn rate_factor(&self, rate: f64) -> f64 {
        1.0 + self.c * (rate / self.reference_rate).ln().max(0.0)
    }

    /// σ_y (Eq. 7.7). An exponent n = 0 is the von Mises criterion σ_y = A (Lyu
    /// §7.3.2: "if we set n = 0, the yield function becomes a von-Mises type yield
    /// criterion with E^p = 0, A = K²"), not A + B of a literal (ε^p)⁰ = 1.
    pub fn yield_stress(&self, plastic_strain: f64, rate: f64) -> f64 {
        let hardening = if self.n == 0.0 {
            0.0
        } else {
            self.b * plastic_strain.max(0.0).powf(self.n)
        };
        (self.a + hardening) * self.rate_factor(rate)
    }

    /// The plastic modulus E^p = ∂σ_y/∂ε^p = B n (ε^p)ⁿ⁻¹ (1 + C ln(ε̇^p/ε̇₀)) (Eq. 7.8).
    pub fn plastic_modulus(&self, plastic_strain: f64, rate: f64) -> f64 {
        if self.n == 0.0 {
            return 0.0;
        }
        let e = plastic_strain.max(HARDENING_STRAIN_FLOOR);
        self.b * self.n * e.powf(self.n - 1.0) * self.rate_factor(rate)
    }
}

/// The equivalent (von Mises) stress s = √(3/2 σ_D : σ_D) of a deviatoric stress.
pub fn equivalent_stress(deviatoric: &Mat3) -> f64 {
    (1.5 * deviatoric.iter().flatten().map(|x| x * x).sum::<f64>()).sqrt()
}

/// The deviatoric part σ − tr(σ)/3 I.
pub fn deviatoric(stress: &Mat3) -> Mat3 {
    let mean = (stress[0][0] + stress[1][1] + stress[2][2]) / 3.0;
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| stress[i][j] - if i == j { mean } else { 0.0 }))
}

/// The outcome of [`radial_return`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Return {
    /// The corrected deviatoric stress, on the yield surface if it yielded.
    pub deviatoric: Mat3,
    /// The equivalent plastic strain increment Δε^p ≥ 0.
    pub plastic_increment: f64,
}

/// J2 radial return (Eq. 7.5–7.6, App. B): with the trial deviatoric stress σ*, its
/// equivalent stress s* and f = s* − σ_y(ε^p), a yielding state gets Δε^p from the
/// linearized consistency condition f − 3μ Δε^p − E^p Δε^p = 0 (Eq. B.4–B.5), iterated
/// by Newton until σ_y(ε^p + Δε^p) = s* − 3μ Δε^p for a nonlinear σ_y (the first
/// iterate is Eq. B.5 itself), and σ = (s* − 3μ Δε^p)/s* σ* (Eq. B.8).
/// `rate` is the equivalent plastic strain rate of Eq. 7.7 (1/s).
pub fn radial_return(
    trial: &Mat3,
    mu: f64,
    plastic_strain: f64,
    hardening: &JohnsonCook,
    rate: f64,
) -> Return {
    let s = equivalent_stress(trial);
    let f0 = s - hardening.yield_stress(plastic_strain, rate);
    if f0 <= 0.0 {
        return Return {
            deviatoric: *trial,
            plastic_increment: 0.0,
        };
    }
    let mut increment = 0.0;
    for _ in 0..RETURN_ITERATIONS {
        let yield_stress = hardening.yield_stress(plastic_strain + increment, rate);
        let f = s - 3.0 * mu * increment - yield_stress;
        if f.abs() <= RETURN_TOLERANCE * yield_stress {
            break;
        }
        let slope = 3.0 * mu + hardening.plastic_modulus(plastic_strain + increment, rate);
        increment = (increment + f / slope).max(0.0);
    }
    let scale = (s - 3.0 * mu * increment) / s;
    Return {
        deviatoric: trial.map(|row| row.map(|x| scale * x)),
        plastic_increment: increment,
    }
}

/// The simplified Mie–Grüneisen equation of state (Eq. 7.4).
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

impl MieGruneisen {
    /// The pressure p(J, e) with ζ = 1/J − 1 (Eq. 7.4): in compression (ζ ≥ 0)
    /// ρ₀c₀²ζ[1 + (1 − γ/2)ζ]/[1 + (S − 1)ζ]² + γ(e − e⁰), in tension ρ₀c₀²ζ + γ(e − e⁰);
    /// `energy_change` is e − e⁰ (J/m³).
    pub fn pressure(&self, j: f64, energy_change: f64) -> f64 {
        let zeta = 1.0 / j - 1.0;
        let k = self.density * self.sound_speed * self.sound_speed;
        let cold = if zeta >= 0.0 {
            let d = 1.0 + (self.slope - 1.0) * zeta;
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
    /// rate of Johnson–Cook's Eq. 7.7 (the plastic rate equals it while flowing).
    pub rate: f64,
    /// The particle's equivalent plastic strain ε^p before this step.
    pub plastic_strain: f64,
}

/// diag(d).
fn diagonal(d: [f64; 3]) -> Mat3 {
    [[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]]
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
    /// The Drucker–Prager flow of friction angle `degrees`.
    pub fn drucker_prager(degrees: f64) -> Plasticity {
        let s = degrees.to_radians().sin();
        Plasticity::DruckerPrager {
            alpha: (2.0f64 / 3.0).sqrt() * 2.0 * s / (3.0 - s),
        }
    }

    /// Projects the elastic deformation gradient `f` onto the material's admissible set
    /// and returns the increment of the plastic strain measure: Δε^p of the radial
    /// return (J2), ‖log Σ̂ − log Σ‖ (snow), δγ (Drucker–Prager); 0 when elastic.
    pub fn project(&self, f: &mut Mat3, input: &FlowInput) -> f64 {
        match *self {
            Plasticity::None => 0.0,
            Plasticity::JohnsonCook(ref hardening) => {
                let RotationSvd { u, sigma, v } = rotation_svd(f);
                let log = sigma.map(|s| s.max(SINGULAR_VALUE_FLOOR).ln());
                let mean = (log[0] + log[1] + log[2]) / 3.0;
                let trial = diagonal(log.map(|e| 2.0 * input.mu * (e - mean)));
                let r = radial_return(
                    &trial,
                    input.mu,
                    input.plastic_strain,
                    hardening,
                    input.rate,
                );
                if r.plastic_increment == 0.0 {
                    return 0.0;
                }
                let returned =
                    [0, 1, 2].map(|a| (r.deviatoric[a][a] / (2.0 * input.mu) + mean).exp());
                *f = compose(&u, returned, &v);
                r.plastic_increment
            }
            Plasticity::Snow {
                critical_compression,
                critical_stretch,
            } => {
                let RotationSvd { u, sigma, v } = rotation_svd(f);
                let clamped =
                    sigma.map(|s| s.clamp(1.0 - critical_compression, 1.0 + critical_stretch));
                if clamped == sigma {
                    return 0.0;
                }
                *f = compose(&u, clamped, &v);
                let change: f64 = (0..3)
                    .map(|a| {
                        let d = sigma[a].abs().max(SINGULAR_VALUE_FLOOR).ln() - clamped[a].ln();
                        d * d
                    })
                    .sum();
                change.sqrt()
            }
            Plasticity::DruckerPrager { alpha } => {
                let RotationSvd { u, sigma, v } = rotation_svd(f);
                let log = sigma.map(|s| s.max(SINGULAR_VALUE_FLOOR).ln());
                let trace = log[0] + log[1] + log[2];
                let dev = log.map(|e| e - trace / 3.0);
                let dev_norm = (dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2]).sqrt();
                if trace >= 0.0 || dev_norm == 0.0 {
                    // Stretched (or purely dilated): no cohesion, the tip of the cone.
                    *f = compose(&u, [1.0; 3], &v);
                    return (log[0] * log[0] + log[1] * log[1] + log[2] * log[2]).sqrt();
                }
                let gamma = dev_norm
                    + (3.0 * input.lambda + 2.0 * input.mu) / (2.0 * input.mu) * trace * alpha;
                if gamma <= 0.0 {
                    return 0.0;
                }
                let projected = [0, 1, 2].map(|a| (log[a] - gamma * dev[a] / dev_norm).exp());
                *f = compose(&u, projected, &v);
                gamma
            }
        }
    }
}
