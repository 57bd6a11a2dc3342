//! Material parameters and their conversion to the peridynamic constants of
//! Chen et al. 2018 (Eq. 10, 13, 16, 17, 19).

use crate::scene::MaterialSpec;

/// A material as the solver uses it: moduli in SI, with every option resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Mass density ρ (kg/m³).
    pub density: f64,
    /// Bulk modulus κ (Pa).
    pub bulk_modulus: f64,
    /// Shear modulus μ (Pa).
    pub shear_modulus: f64,
    /// How yielding is given, if the material yields.
    pub yield_rule: Option<YieldRule>,
    /// Plastic limit γ/|ξ| (Chen Eq. 16); infinite for none.
    pub plastic_limit: f64,
    /// Critical weighted stretch s^ω (Chen Eq. 19); `None` for unbreakable.
    pub critical_stretch: Option<f64>,
    /// Critical compressive strain ε_c of a bond (crushing; not in Chen et al.); `None`
    /// for no crushing.
    pub critical_compression: Option<f64>,
    /// Anti-shatter parameter α (Chen Eq. 19).
    pub alpha: f64,
    /// Anisotropy matrix G (Chen Eq. 17), `None` for isotropic.
    pub anisotropy: Option<[[f64; 3]; 3]>,
    /// Air damping rate (1/s).
    pub air_damping: f64,
    /// Laplacian smoothing rate (1/s).
    pub laplacian_damping: f64,
}

/// The yield threshold, either as the paper's Ψ0 or as a deviatoric stretch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum YieldRule {
    /// Ψ0 of Chen Eq. 13 in SI units.
    Psi0(f64),
    /// Deviatoric bond stretch at yield: Ψ0 = (4δ b s_y)²/2.
    Stretch(f64),
}

impl Material {
    /// Resolves a scene material (validated already).
    pub fn from_spec(spec: &MaterialSpec) -> Material {
        let (bulk_modulus, shear_modulus) = match (spec.bulk_modulus, spec.shear_modulus) {
            (Some(k), Some(mu)) => (k, mu),
            _ => {
                let e = spec.youngs_modulus.unwrap_or(1.0);
                let nu = spec.poisson_ratio.unwrap_or(0.25);
                (e / (3.0 * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu)))
            }
        };
        let yield_rule = match (spec.yield_psi0, spec.yield_stretch) {
            (Some(p), _) => Some(YieldRule::Psi0(p)),
            (None, Some(s)) => Some(YieldRule::Stretch(s)),
            (None, None) => None,
        };
        Material {
            density: spec.density,
            bulk_modulus,
            shear_modulus,
            yield_rule,
            plastic_limit: spec.plastic_limit,
            critical_stretch: spec.critical_stretch,
            critical_compression: spec.critical_compression,
            alpha: spec.alpha,
            anisotropy: spec.anisotropy,
            air_damping: spec.air_damping,
            laplacian_damping: spec.laplacian_damping,
        }
    }

    /// Young's modulus E = 9κμ/(3κ + μ).
    pub fn youngs_modulus(&self) -> f64 {
        9.0 * self.bulk_modulus * self.shear_modulus
            / (3.0 * self.bulk_modulus + self.shear_modulus)
    }

    /// Poisson ratio ν = (3κ − 2μ)/(2(3κ + μ)).
    pub fn poisson_ratio(&self) -> f64 {
        (3.0 * self.bulk_modulus - 2.0 * self.shear_modulus)
            / (2.0 * (3.0 * self.bulk_modulus + self.shear_modulus))
    }

    /// P-wave speed √((κ + 4μ/3)/ρ), the fastest signal in the solid.
    pub fn p_wave_speed(&self) -> f64 {
        ((self.bulk_modulus + 4.0 / 3.0 * self.shear_modulus) / self.density).sqrt()
    }

    /// Whether any bond can yield (plastic state is allocated only then).
    pub fn is_plastic(&self) -> bool {
        self.yield_rule.is_some() && self.plastic_limit > 0.0
    }

    /// The peridynamic constants for horizon δ.
    pub fn constants(&self, delta: f64) -> PdConstants {
        let pi = std::f64::consts::PI;
        // Chen Eq. 10.
        let a = 9.0 * self.bulk_modulus / (8.0 * pi * delta.powi(4));
        let b = 15.0 * self.shear_modulus / (2.0 * pi * delta.powi(5));
        let psi0 = match self.yield_rule {
            None => f64::INFINITY,
            Some(YieldRule::Psi0(p)) => p,
            Some(YieldRule::Stretch(s)) => 0.5 * (4.0 * delta * b * s).powi(2),
        };
        PdConstants {
            delta,
            a,
            b,
            psi0,
            critical_stretch: self.critical_stretch.unwrap_or(f64::INFINITY),
            critical_compression: self.critical_compression.unwrap_or(f64::INFINITY),
            alpha: self.alpha,
            plastic_limit: self.plastic_limit,
        }
    }
}

/// Chen et al.'s constants of one body (material and horizon δ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdConstants {
    /// Horizon δ (m).
    pub delta: f64,
    /// a = 9κ/(8πδ⁴) (Eq. 10).
    pub a: f64,
    /// b = 15μ/(2πδ⁵) (Eq. 10).
    pub b: f64,
    /// Ψ0 (Eq. 13); infinite for no yield.
    pub psi0: f64,
    /// s^ω threshold (Eq. 19); infinite for unbreakable.
    pub critical_stretch: f64,
    /// ε_c: a bond crushes when its strain (e − e^p)/|ξ| is below −(1 + αφ) ε_c;
    /// infinite for never.
    pub critical_compression: f64,
    /// α (Eq. 19).
    pub alpha: f64,
    /// γ/|ξ| (Eq. 16).
    pub plastic_limit: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> MaterialSpec {
        MaterialSpec {
            density: 1000.0,
            bulk_modulus: None,
            shear_modulus: None,
            youngs_modulus: Some(1e6),
            poisson_ratio: Some(0.3),
            yield_psi0: None,
            yield_stretch: None,
            plastic_limit: f64::INFINITY,
            critical_stretch: None,
            critical_compression: None,
            alpha: 0.0,
            anisotropy: None,
            air_damping: 0.0,
            laplacian_damping: 0.0,
            membrane: None,
            mpm: None,
            color: None,
        }
    }

    #[test]
    fn moduli_round_trip() {
        let m = Material::from_spec(&spec());
        assert!((m.youngs_modulus() - 1e6).abs() < 1e-6);
        assert!((m.poisson_ratio() - 0.3).abs() < 1e-12);
    }

    #[test]
    fn yield_stretch_is_psi0_without_delta() {
        let mut s = spec();
        s.yield_stretch = Some(0.01);
        let m = Material::from_spec(&s);
        for delta in [0.01, 0.02] {
            let c = m.constants(delta);
            let s_y = (2.0 * c.psi0).sqrt() / (4.0 * delta * c.b);
            assert!((s_y - 0.01).abs() < 1e-12);
        }
    }
}
