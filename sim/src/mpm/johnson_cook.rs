//! The Johnson–Cook flow stress (Lyu 2021 Eq. 7.7–7.8, with Johnson & Cook 1983's
//! thermal term) and J2's radial return onto it (Eq. 7.5–7.6, App. B): what
//! [`super::plasticity`]'s J2 projection returns the trial stress with.

use super::constitutive::Mat3;

/// The Taylor–Quinney fraction β when the scene does not give one (Johnson & Cook
/// 1983 convert "90 to 100%" of the plastic work into heat; 0.9 is the usual choice).
pub const TAYLOR_QUINNEY: f64 = 0.9;

/// The thermal term of Johnson & Cook (1983, Eq. 1): σ_y is multiplied by 1 − T*^m,
/// T* = (T − T_room)/(T_melt − T_room), and the plastic work heats the particle
/// adiabatically (§2 of the paper: "the deformation is assumed adiabatic" at high
/// rates): ΔT = β σ_y Δε^p/(ρ c), β the Taylor–Quinney fraction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thermal {
    /// Melting temperature T_melt (K).
    pub melting_temperature: f64,
    /// Room temperature T_room (K), also the particles' initial temperature.
    pub room_temperature: f64,
    /// Thermal exponent m.
    pub exponent: f64,
    /// Specific heat c (J/(kg K)).
    pub specific_heat: f64,
    /// Taylor–Quinney fraction β of the plastic work turned into heat.
    pub taylor_quinney: f64,
}

impl Thermal {
    /// 1 − T*^m, clamped to 1 at and below room temperature (T* ≤ 0, as Johnson &
    /// Cook's fit is defined above it) and to 0 from the melting point on.
    pub fn softening(&self, temperature: f64) -> f64 {
        let t = (temperature - self.room_temperature)
            / (self.melting_temperature - self.room_temperature);
        if t <= 0.0 {
            1.0
        } else if t >= 1.0 {
            0.0
        } else {
            1.0 - t.powf(self.exponent)
        }
    }

    /// The temperature rise β σ_y Δε^p/(ρ c) of a plastic increment `increment` at flow
    /// stress `stress` (Pa) in a material of density `density` (kg/m³). The flow stress
    /// and ε^p here are Kirchhoff (per reference volume), so ρ is the reference
    /// density.
    pub fn heating(&self, stress: f64, increment: f64, density: f64) -> f64 {
        self.taylor_quinney * stress * increment / (density * self.specific_heat)
    }
}

/// Johnson–Cook flow stress σ_y(ε^p, ε̇^p) = (A + B (ε^p)ⁿ)(1 + C ln(ε̇^p/ε̇₀)) (Eq. 7.7),
/// times the thermal factor of [`Thermal`] when it has one (Johnson & Cook 1983).
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
    /// The thermal term, or `None` for the thesis' form.
    pub thermal: Option<Thermal>,
}

/// The plastic strain at which the hardening modulus of an exponent n < 1 is taken
/// when ε^p is smaller (B n (ε^p)ⁿ⁻¹ is infinite at ε^p = 0).
pub const HARDENING_STRAIN_FLOOR: f64 = 1e-6;
/// Newton iterations of the return map at most.
pub const RETURN_ITERATIONS: usize = 50;
/// Relative tolerance of the return map's consistency condition |f| ≤ tol σ_y.
pub const RETURN_TOLERANCE: f64 = 1e-12;

impl JohnsonCook {
    /// The flow stress law at temperature `temperature` (K): A and B scaled by the
    /// thermal factor 1 − T*^m (so [`JohnsonCook::yield_stress`] and
    /// [`JohnsonCook::plastic_modulus`] of the result include it); itself without a
    /// thermal term.
    pub fn at_temperature(&self, temperature: f64) -> JohnsonCook {
        let Some(thermal) = &self.thermal else {
            return *self;
        };
        let factor = thermal.softening(temperature);
        JohnsonCook {
            a: self.a * factor,
            b: self.b * factor,
            ..*self
        }
    }

    /// The rate factor 1 + C ln(ε̇^p/ε̇₀), never below 1 (rates under the reference do
    /// not soften).
    fn rate_factor(&self, rate: f64) -> f64 {
        if self.c == 0.0 || rate <= self.reference_rate {
            return 1.0;
        }
        1.0 + self.c * (rate / self.reference_rate).ln().max(0.0)
    }

    /// The flow stress law at the plastic strain rate `rate`: A and B scaled by the
    /// rate factor 1 + C ln(ε̇^p/ε̇₀) and C set to 0, so that the return map's Newton
    /// iterations do not take the logarithm again (the result's own `rate` argument is
    /// then ignored).
    pub fn at_rate(&self, rate: f64) -> JohnsonCook {
        let factor = self.rate_factor(rate);
        JohnsonCook {
            a: self.a * factor,
            b: self.b * factor,
            c: 0.0,
            ..*self
        }
    }

    /// σ_y (Eq. 7.7). An exponent n = 0 is the von Mises criterion σ_y = A (Lyu
    /// §7.3.2: "if we set n = 0, the yield function becomes a von-Mises type yield
    /// criterion with E^p = 0, A = K²"), not A + B of a literal (ε^p)⁰ = 1.
    pub fn yield_stress(&self, plastic_strain: f64, rate: f64) -> f64 {
        let hardening = if self.n == 0.0 {
            0.0
        } else {
            self.b * self.power(plastic_strain.max(0.0))
        };
        (self.a + hardening) * self.rate_factor(rate)
    }

    /// σ_y and E^p together ([`JohnsonCook::yield_stress`],
    /// [`JohnsonCook::plastic_modulus`]) from one power (ε^p)ⁿ when ε^p is past
    /// [`HARDENING_STRAIN_FLOOR`]: E^p = B n (ε^p)ⁿ/ε^p times the rate factor.
    fn flow_and_modulus(&self, plastic_strain: f64, rate: f64) -> (f64, f64) {
        if self.n == 0.0 || plastic_strain < HARDENING_STRAIN_FLOOR {
            return (
                self.yield_stress(plastic_strain, rate),
                self.plastic_modulus(plastic_strain, rate),
            );
        }
        let factor = self.rate_factor(rate);
        let power = self.power(plastic_strain);
        (
            (self.a + self.b * power) * factor,
            self.b * self.n * power / plastic_strain * factor,
        )
    }

    /// (ε^p)ⁿ: a square root for n = ½ and ε^p itself for n = 1, the exponents of the
    /// thesis' containers (Fig. 7.5), where `powf` would take a logarithm and an
    /// exponential in every Newton iteration of the return.
    fn power(&self, plastic_strain: f64) -> f64 {
        if self.n == 0.5 {
            plastic_strain.sqrt()
        } else if self.n == 1.0 {
            plastic_strain
        } else {
            plastic_strain.powf(self.n)
        }
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
    /// The radial scaling k = (s* − 3μ Δε^p)/s* of the trial stress (1 when elastic).
    pub scale: f64,
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
    let (plastic_increment, scale) = return_map(
        equivalent_stress(trial),
        mu,
        plastic_strain,
        hardening,
        rate,
    );
    Return {
        deviatoric: trial.map(|row| row.map(|x| scale * x)),
        plastic_increment,
        scale,
    }
}

/// [`radial_return`] on the equivalent trial stress `s` = s* alone: Δε^p and the
/// radial scaling k = (s* − 3μ Δε^p)/s* (0 and 1 when elastic).
pub(super) fn return_map(
    s: f64,
    mu: f64,
    plastic_strain: f64,
    hardening: &JohnsonCook,
    rate: f64,
) -> (f64, f64) {
    // σ_y and E^p at the step's ε^p serve the yield test and Newton's first iterate.
    let (mut yield_stress, mut modulus) = hardening.flow_and_modulus(plastic_strain, rate);
    if s - yield_stress <= 0.0 {
        return (0.0, 1.0);
    }
    let mut increment = 0.0;
    for _ in 0..RETURN_ITERATIONS {
        let f = s - 3.0 * mu * increment - yield_stress;
        if f.abs() <= RETURN_TOLERANCE * yield_stress {
            break;
        }
        let slope = 3.0 * mu + modulus;
        let next = (increment + f / slope).max(0.0);
        // A zero flow stress (at the melting point) has no relative tolerance: stop
        // when Newton no longer moves.
        if next == increment {
            break;
        }
        increment = next;
        (yield_stress, modulus) = hardening.flow_and_modulus(plastic_strain + increment, rate);
    }
    (increment, (s - 3.0 * mu * increment) / s)
}
