//! Membrane tables (Han et al. 2021): `[materials.NAME.membrane]` (fracture, diffusion)
//! and `[body.membrane]` (the sheet, its sources and scattered spots).

use serde::{Deserialize, Serialize};

use super::{ShapeSpec, default_inf};

/// `[materials.NAME.membrane]`: fracture and diffusion of a membrane material (Han et
/// al. 2021); its stiffness comes from the material's elastic constants.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MembraneMaterialSpec {
    /// Fracture energy G_f in J/m², giving the critical strain η_c = √(4πG_f/(9ER))
    /// of Han Eq. 27–28. Default: none (unbreakable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture_energy: Option<f64>,
    /// Diffusive capacity C of Han Eq. 25 in J/(kg·unit), per unit of the diffused
    /// quantity (K for temperature). Default 1.
    #[serde(default = "default_diffusion_capacity")]
    pub diffusion_capacity: f64,
    /// Diffusion coefficient k of Han Eq. 25 in W/(m·unit). Default 0 (no diffusion).
    #[serde(default)]
    pub diffusion_conductivity: f64,
    /// Coefficient of linear expansion α per unit of the diffused quantity (Han
    /// Eq. 18–20: a free sheet at θ expands by αθ). Default 0.
    #[serde(default)]
    pub expansion: f64,
    /// The bond law: `"linear"` (Eq. 18), `"rubber"` (power law, Eq. 19) or
    /// `"elastoplastic"` (exponential softening, Eq. 20). Default `"linear"`.
    #[serde(default)]
    pub law: MembraneLaw,
    /// Rubber only: c*/c of Eq. 19, ≤ 0. Default 0.
    #[serde(default)]
    pub rubber_coefficient: f64,
    /// Rubber only: the exponent n of Eq. 19, > 1. Default 2.
    #[serde(default = "default_rubber_exponent")]
    pub rubber_exponent: f64,
    /// Elastoplastic only: the elastic limit η₀ of Eq. 20 and 27, in (0, η_c).
    /// Default 10⁻⁴ (Han Table 1).
    #[serde(default = "default_elastic_limit")]
    pub elastic_limit: f64,
    /// Elastoplastic only: the softening rate β of Eq. 20 and 27, > 0. Default 1.
    #[serde(default = "default_softening")]
    pub softening: f64,
}

/// The bond law of a membrane material (Han Eq. 18–20).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MembraneLaw {
    /// Linear elastic, Eq. 18.
    #[default]
    Linear,
    /// Power-law rubber, Eq. 19.
    Rubber,
    /// Elastoplastic with exponential softening, Eq. 20.
    Elastoplastic,
}

fn default_rubber_exponent() -> f64 {
    2.0
}
fn default_elastic_limit() -> f64 {
    1e-4
}
fn default_softening() -> f64 {
    1.0
}

impl Default for MembraneMaterialSpec {
    fn default() -> Self {
        MembraneMaterialSpec {
            fracture_energy: None,
            diffusion_capacity: default_diffusion_capacity(),
            diffusion_conductivity: 0.0,
            expansion: 0.0,
            law: MembraneLaw::Linear,
            rubber_coefficient: 0.0,
            rubber_exponent: default_rubber_exponent(),
            elastic_limit: default_elastic_limit(),
            softening: default_softening(),
        }
    }
}

fn default_diffusion_capacity() -> f64 {
    1.0
}

/// `[body.membrane]`: settings of a membrane body (Han et al. 2021). The sheet is the
/// body's `shape`: a `box` or `slab` is a rectangle in the plane of its two larger
/// sides, its smallest side the thickness; a `cylinder` is a disc across its axis, its
/// height the thickness. `resolution` is the particle spacing of the triangular
/// lattice the sheet is sampled on.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MembraneSpec {
    /// Cutoff radius R of the weight W = 1 − r/R (Han Eq. 23) in particle spacings,
    /// in [1, 4]. Default 1.5 (Han §6).
    #[serde(default = "default_membrane_cutoff")]
    pub cutoff: f64,
    /// The formulation: `"bond"`, Han's bond-based micro-springs (Eq. 18–24: Poisson
    /// ratio fixed at 1/3), or `"state"`, an ordinary state-based sheet in plane
    /// stress that takes the material's Poisson ratio (linear law only). Default
    /// `"bond"`.
    #[serde(default)]
    pub membrane_model: MembraneFormulation,
    /// The diffused quantity θ everywhere at the start (temperature, solvent,
    /// moisture, in the material's unit). Default 0.
    #[serde(default)]
    pub quantity: f64,
    /// Sources and sinks of the diffused quantity (`[[body.membrane.source]]`).
    #[serde(default, rename = "source", skip_serializing_if = "Vec::is_empty")]
    pub sources: Vec<SourceSpec>,
    /// Sheet thickness in m of a membrane given by a mesh (`shape.type = "mesh"`, an
    /// open or closed triangle surface resampled to the body's resolution), where it
    /// is required; a box, slab or cylinder takes its thickness from its shape.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
}

/// The formulation of a membrane body (`[body.membrane] membrane_model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MembraneFormulation {
    /// Bond-based micro-springs (Han Eq. 18–24).
    #[default]
    Bond,
    /// Ordinary state-based peridynamics in the plane of the sheet (plane stress).
    State,
}

impl Default for MembraneSpec {
    fn default() -> Self {
        MembraneSpec {
            cutoff: default_membrane_cutoff(),
            membrane_model: MembraneFormulation::Bond,
            quantity: 0.0,
            sources: Vec::new(),
            thickness: None,
        }
    }
}

/// `[[body.membrane.source]]`: a source or sink of a membrane's diffused quantity θ
/// (the S of Han Eq. 8 and 25) on the particles inside `region`, or on spots scattered
/// over it with the scene's `seed`, between `start` and `until`. Exactly one of `rate`
/// and `value`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourceSpec {
    /// Where (particles with signed distance ≤ 0). Default: the whole sheet.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<ShapeSpec>,
    /// Scatter the source over `region` as spots (an acid spray, heat sources).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scatter: Option<ScatterSpec>,
    /// θ̇ added inside, in units of θ per second (S = ρ C × rate in Eq. 8); negative
    /// is a sink, which may drive θ below zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<f64>,
    /// θ held at this value inside (a fixed-value boundary: a reservoir, or an
    /// absorbing sink at 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// Time in s at which the source starts. Default 0.
    #[serde(default)]
    pub start: f64,
    /// Time in s after which the source stops. Default: never.
    #[serde(default = "default_inf")]
    pub until: f64,
}

/// `scatter = { count, radius }` of a source: `count` spots of `radius` metres, each
/// centred on a particle of the region drawn with the scene's `seed`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScatterSpec {
    /// Number of spots, at least 1.
    pub count: u32,
    /// Radius of a spot (m), positive.
    pub radius: f64,
}

fn default_membrane_cutoff() -> f64 {
    1.5
}
