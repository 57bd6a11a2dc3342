//! `[materials.NAME]`: a material's constants and the model that steps it.

use serde::{Deserialize, Serialize};

use super::{ColorSpec, MembraneMaterialSpec, MpmSpec, default_inf, exact};

/// How the bond-projection factor ŷ·ξ̂ of Chen Eq. 4, 6, 8 is taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DilatationForm {
    /// ŷ·ξ̂ = 1: objective (Silling et al. 2007, linear peridynamic solid).
    #[default]
    Objective,
    /// ŷ·ξ̂ as printed in Chen et al. 2018 (after Madenci & Oterkus).
    Paper,
}

/// `[materials.NAME]`: elastic constants, plasticity, fracture, anisotropy, damping.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Mass density ρ in kg/m³ (required).
    pub density: f64,
    /// Bulk modulus κ in Pa (with `shear_modulus`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bulk_modulus: Option<f64>,
    /// Shear modulus μ in Pa (with `bulk_modulus`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_modulus: Option<f64>,
    /// Young's modulus E in Pa (with `poisson_ratio`, instead of κ and μ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs_modulus: Option<f64>,
    /// Poisson ratio ν, in (−1, 0.5) (with `youngs_modulus`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
    /// Yield parameter Ψ0 of Chen Eq. 13 in SI units ((N/m⁶)²/2). It depends on δ;
    /// prefer `yield_stretch`. Default: none (no plasticity).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_psi0: Option<f64>,
    /// Deviatoric bond stretch at yield, s_y = √(2Ψ0)/(4δb): Ψ0 without its dependence
    /// on the horizon. Default: none (no plasticity).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_stretch: Option<f64>,
    /// Plastic limit γ/|ξ| of Chen Eq. 16 (Table 1). Default: unlimited.
    #[serde(default = "default_inf")]
    pub plastic_limit: f64,
    /// Critical weighted stretch s^ω of Chen Eq. 19 (Table 1). Default: none (unbreakable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub critical_stretch: Option<f64>,
    /// Critical compressive strain ε_c: a bond also breaks (crushes) when its strain
    /// (e − e^p)/|ξ| falls below −ε_c (not in Chen et al., whose bonds break only in
    /// tension); a crushed bond carries no tension but goes on resisting compression,
    /// yielding at the strain ε_c (crushed glass). Between 0 and 1; needs
    /// `critical_stretch`. Default: none (no crushing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub critical_compression: Option<f64>,
    /// Anti-shatter parameter α of Chen Eq. 19. Default 0.
    #[serde(default)]
    pub alpha: f64,
    /// Anisotropy matrix G of Chen Eq. 17 (rows). Default: none (isotropic).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exact::option_matrix"
    )]
    pub anisotropy: Option<[[f64; 3]; 3]>,
    /// Air damping rate in 1/s: v ← (1 − rate·Δt) v each step (Chen §6, λa = rate·Δt).
    /// Default 0.
    #[serde(default)]
    pub air_damping: f64,
    /// Laplacian velocity smoothing rate in 1/s: v ← v + rate·Δt·L(v) (Chen §6,
    /// λl = rate·Δt). Default 0.
    #[serde(default)]
    pub laplacian_damping: f64,
    /// Membrane properties (`[materials.NAME.membrane]`), for bodies with
    /// `model = "membrane"` only. Default: the defaults of [`MembraneMaterialSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub membrane: Option<MembraneMaterialSpec>,
    /// Material point method settings (`[materials.NAME.mpm]`), read by bodies with
    /// `model = "mpm"`. Default: fixed corotated elasticity.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mpm: Option<MpmSpec>,
    /// Display colour in previews: `"#RRGGBB"` or an sRGB triple `[r, g, b]` in [0, 1].
    /// Default: a colour of [`PALETTE`](super::PALETTE) (see
    /// [`Scene::body_colors`](super::Scene::body_colors)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<ColorSpec>,
}

/// The simulation model of a body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// State-based peridynamics of Chen et al. 2018.
    #[default]
    Peridynamics,
    /// Reference solver: explicit linear-tet FEM with the linear (Cauchy) strain, on
    /// the body's tet mesh (Chen et al. 2018 §6, Figs. 11–12 left). Not objective:
    /// rotations cause ghost forces.
    FemLinear,
    /// Reference solver: explicit linear-tet FEM, corotated linear (Chen et al. 2018
    /// §6, Figs. 10–13): the linear stress of each tet in its rotated frame.
    FemCorotated,
    /// A thin membrane of one layer of particles (Han et al. 2021): the body's shape
    /// is the sheet (a `box` or `slab` for a rectangle, a `cylinder` for a disc) and
    /// `resolution` the particle spacing (see `perifrac_sim::membrane`).
    Membrane,
    /// The material point method (MLS-MPM, Lyu 2021 ch. 3): particles seeded in the
    /// shape on a sparse grid of spacing `resolution`; every body of the scene must then
    /// use it. Material settings in `[materials.NAME.mpm]`.
    Mpm,
}

impl ModelKind {
    /// Whether this is one of the FEM reference solvers.
    pub fn is_fem(self) -> bool {
        matches!(self, ModelKind::FemLinear | ModelKind::FemCorotated)
    }
}
