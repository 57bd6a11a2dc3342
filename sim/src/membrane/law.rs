//! The bond laws of Han Eq. 18–20: the force f_ij of a bond as a function of its
//! strain η = s − 1, in units of the micromodulus c (Eq. 24).
//!
//! The expansion term of Eq. 18–20, −(3λ + 2μ)αθ_j, is taken in the law's own
//! modulus: every law sees the strain of the bond relative to its expanded rest length
//! |ξ|(1 + αθ̄_ij), η' = (1 + η)/(1 + αθ̄_ij) − 1, with θ̄_ij = ½(θ_i + θ_j). For the
//! linear law that is c η − c αθ̄ + O(ηαθ), Eq. 18's form, and a free sheet at uniform
//! θ expands by αθ without stress. Departures, each for a reason: the printed term
//! mixes a stress (Pa) with c η (N/m⁶), so it is taken with c; and the bond mean
//! θ̄_ij instead of θ_j keeps the pair forces equal and opposite (momentum).

use crate::scene::{MembraneLaw, MembraneMaterialSpec};

/// A bond law with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// Linear elastic, Eq. 18: f = c η.
    Linear,
    /// Power-law rubber, Eq. 19: f = 2c(s − s⁻³) + c* n (s^(n−1) − 1). Departure: the
    /// constant c* n is subtracted so that the rest state carries no force (as printed
    /// a bond at rest pushes with c* n).
    Rubber {
        /// c*/c ≤ 0.
        ratio: f64,
        /// n > 1.
        exponent: f64,
    },
    /// Elastoplastic with exponential softening, Eq. 20: f = c η for η < η₀ and
    /// c η₀ exp(−β(η − η₀)/η₀) above. The softening is Eq. 27's γ for η₀ < η ≤ η_c,
    /// so γ is not applied a second time; beyond η_c the bond breaks (γ = 0).
    Elastoplastic {
        /// η₀, the elastic limit.
        onset: f64,
        /// β, the softening rate.
        softening: f64,
    },
}

impl Law {
    /// The law of a membrane material.
    pub fn of(spec: &MembraneMaterialSpec) -> Law {
        match spec.law {
            MembraneLaw::Linear => Law::Linear,
            MembraneLaw::Rubber => Law::Rubber {
                ratio: spec.rubber_coefficient,
                exponent: spec.rubber_exponent,
            },
            MembraneLaw::Elastoplastic => Law::Elastoplastic {
                onset: spec.elastic_limit,
                softening: spec.softening,
            },
        }
    }

    /// f_ij / c at strain η (Eq. 18–20).
    #[inline]
    pub fn force(&self, eta: f64) -> f64 {
        match *self {
            Law::Linear => eta,
            Law::Rubber { ratio, exponent } => {
                let s = 1.0 + eta;
                2.0 * (s - 1.0 / (s * s * s)) + ratio * exponent * (s.powf(exponent - 1.0) - 1.0)
            }
            Law::Elastoplastic { onset, softening } => {
                if eta < onset {
                    eta
                } else {
                    onset * (-softening * (eta - onset) / onset).exp()
                }
            }
        }
    }

    /// The slope df/dη / c at rest, the stable step's spring constant: 1 for the
    /// linear and elastoplastic laws, 8 + (c*/c) n(n − 1) ≤ 8 for the rubber, taken
    /// as 8 (c* ≤ 0; its slope grows under compression, which `dt_safety` covers).
    pub fn stiffness(&self) -> f64 {
        match *self {
            Law::Linear | Law::Elastoplastic { .. } => 1.0,
            Law::Rubber { .. } => 8.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn laws_start_at_rest_with_their_slopes() {
        let h = 1e-7;
        let rubber = Law::Rubber {
            ratio: -0.5,
            exponent: 3.0,
        };
        for (law, slope) in [
            (Law::Linear, 1.0),
            (rubber, 8.0 - 0.5 * 3.0 * 2.0),
            (
                Law::Elastoplastic {
                    onset: 1e-3,
                    softening: 2.0,
                },
                1.0,
            ),
        ] {
            assert_eq!(law.force(0.0), 0.0, "{law:?} at rest");
            let d = (law.force(h) - law.force(-h)) / (2.0 * h);
            assert!((d - slope).abs() < 1e-5, "{law:?}: slope {d}");
        }
        let plastic = Law::Elastoplastic {
            onset: 1e-3,
            softening: 2.0,
        };
        // Continuous at η₀, then softening by e^(−β) per η₀ of further strain.
        assert!((plastic.force(1e-3 - 1e-12) - plastic.force(1e-3)).abs() < 1e-10);
        let ratio = plastic.force(2e-3) / plastic.force(1e-3);
        assert!((ratio - (-2.0f64).exp()).abs() < 1e-12);
    }
}
