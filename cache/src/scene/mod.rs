//! The scene file: TOML in SI units (m, kg, s, Pa), y up.
//!
//! [`Scene::load`] reads a file, fills in defaults, checks every value and returns
//! a [`Scene`]; any problem is a [`CacheError::Scene`] naming the file, the line and
//! the dotted key. Unknown keys are errors. The resolved scene (defaults filled in)
//! is written next to the cache by [`Scene::to_toml`].

mod locate;
mod mpm;
mod output;
mod validate;

pub use mpm::{MpmElasticity, MpmPlasticity, MpmSettings, MpmSpec, MpmTransfer};
pub use output::{EmbeddedSpec, OutputSpec, SurfaceMethod, VdbFilter, VdbSpec};
pub use validate::SPHERE_RADIUS_PER_SPACING;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{CacheError, Result};

/// A whole scene: global settings, materials, bodies, colliders and outputs.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Global settings (`[scene]`).
    pub scene: Settings,
    /// Named materials (`[materials.NAME]`).
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// Deformable bodies (`[[body]]`).
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodySpec>,
    /// Rigid colliders (`[[collider]]`).
    #[serde(default, rename = "collider")]
    pub colliders: Vec<ColliderSpec>,
    /// MPM grid settings (`[mpm]`), for scenes with `model = "mpm"` bodies only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mpm: Option<MpmSettings>,
    /// Contact between the bodies' particles (`[contact]`).
    #[serde(default)]
    pub contact: ContactSpec,
    /// What to write (`[output]`).
    #[serde(default)]
    pub output: OutputSpec,
    /// The directory mesh paths are relative to (the scene file's directory).
    #[serde(skip)]
    pub base_dir: PathBuf,
    /// Read from a cache ([`Scene::load_cached`]): the source files it names (meshes,
    /// transforms) need not exist any more.
    #[serde(skip)]
    cached: bool,
}

/// `[scene]`: name, timing, gravity.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Scene name, used in the manifest and for the output directory. Default `"scene"`.
    #[serde(default = "default_name")]
    pub name: String,
    /// Simulated time in seconds. Default 1.0.
    #[serde(default = "default_duration")]
    pub duration: f64,
    /// Output frames per second. Default 24.
    #[serde(default = "default_fps")]
    pub fps: f64,
    /// Gravity acceleration in m/s². Default `[0, -9.81, 0]`.
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    /// Seed for anything random (jitter); the same seed gives the same bytes. Default 0.
    #[serde(default)]
    pub seed: u64,
    /// Time step in seconds. Default: `dt_safety` × the stable time step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Fraction of the stable time step used when `dt` is not given. Default 0.7.
    #[serde(default = "default_dt_safety")]
    pub dt_safety: f64,
    /// Run with a `dt` above the stable bound instead of refusing. Default false.
    #[serde(default)]
    pub force_dt: bool,
    /// The projection factor ŷ·ξ̂ in Chen Eq. 4, 6, 8: `"objective"` (taken as 1, as in
    /// the linear peridynamic solid; objective under rotation) or `"paper"` (as printed).
    /// Default `"objective"`.
    #[serde(default)]
    pub dilatation: DilatationForm,
    /// Correct dilatation and force constants of particles with incomplete families
    /// (near free surfaces). Default true.
    #[serde(default = "default_true")]
    pub surface_correction: bool,
    /// Relative growth of total energy over its initial value (plus the work of
    /// gravity, anchors and colliders) that counts as a blow-up. Default 10.
    #[serde(default = "default_energy_growth")]
    pub blowup_energy_growth: f64,
}

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
    /// tension). Between 0 and 1; needs `critical_stretch`. Default: none (no
    /// crushing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub critical_compression: Option<f64>,
    /// Anti-shatter parameter α of Chen Eq. 19. Default 0.
    #[serde(default)]
    pub alpha: f64,
    /// Anisotropy matrix G of Chen Eq. 17 (rows). Default: none (isotropic).
    #[serde(default, skip_serializing_if = "Option::is_none")]
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
}

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

/// A shape given by a signed distance function, or a CSG combination of shapes.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeSpec {
    /// Axis-aligned box: centre and full size in m.
    Box {
        /// Centre.
        center: [f64; 3],
        /// Full extents along x, y, z.
        size: [f64; 3],
    },
    /// A thin axis-aligned slab (a box; named for intent). Its thinnest side must be at
    /// least about 1.5 resolutions.
    Slab {
        /// Centre.
        center: [f64; 3],
        /// Full extents along x, y, z.
        size: [f64; 3],
    },
    /// Sphere.
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// Capped cylinder along a coordinate axis.
    Cylinder {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
        /// Full height along `axis`.
        height: f64,
        /// `"x"`, `"y"` or `"z"`. Default `"y"`.
        #[serde(default)]
        axis: Axis,
    },
    /// Union of shapes.
    Union {
        /// The parts.
        parts: Vec<ShapeSpec>,
    },
    /// `base` minus `minus` (notches, holes).
    Difference {
        /// The shape to cut from.
        base: Box<ShapeSpec>,
        /// The shape removed.
        minus: Box<ShapeSpec>,
    },
    /// A closed triangle mesh file, relative to the scene file, placed by
    /// `p ↦ R (scale ⊙ p) + translation`.
    Mesh {
        /// The mesh file (`.obj`, `.ply`, `.gltf`, `.glb`).
        path: PathBuf,
        /// Scale: one factor or one per axis `[x, y, z]`, applied first. Default 1.
        #[serde(default)]
        scale: MeshScale,
        /// Rotation in degrees about x, then y, then z (fixed axes; R = Rz Ry Rx).
        /// Default 0.
        #[serde(default)]
        rotation: [f64; 3],
        /// Translation in m, applied last. Default 0.
        #[serde(default)]
        translation: [f64; 3],
    },
}

impl ShapeSpec {
    /// Makes every mesh path in this shape absolute: `base` joined with it,
    /// canonicalized where the file exists.
    fn resolve_mesh_paths(&mut self, base: &Path) {
        match self {
            ShapeSpec::Mesh { path, .. } => {
                let joined = base.join(&*path);
                *path = std::fs::canonicalize(&joined)
                    .or_else(|_| std::path::absolute(&joined))
                    .unwrap_or(joined);
            }
            ShapeSpec::Union { parts } => {
                for part in parts {
                    part.resolve_mesh_paths(base);
                }
            }
            ShapeSpec::Difference { base: b, minus } => {
                b.resolve_mesh_paths(base);
                minus.resolve_mesh_paths(base);
            }
            ShapeSpec::Box { .. }
            | ShapeSpec::Slab { .. }
            | ShapeSpec::Sphere { .. }
            | ShapeSpec::Cylinder { .. } => {}
        }
    }
}

/// The scale of a mesh shape: uniform or per axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum MeshScale {
    /// The same factor on every axis.
    Uniform(f64),
    /// One factor per axis (negative factors mirror).
    PerAxis([f64; 3]),
}

impl Default for MeshScale {
    fn default() -> Self {
        MeshScale::Uniform(1.0)
    }
}

impl MeshScale {
    /// The factor on each axis.
    pub fn factors(self) -> [f64; 3] {
        match self {
            MeshScale::Uniform(s) => [s; 3],
            MeshScale::PerAxis(s) => s,
        }
    }
}

/// A coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// x.
    X,
    /// y.
    #[default]
    Y,
    /// z.
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
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

/// `[[body]]`: a deformable body.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name, for messages. Default `body<N>`.
    #[serde(default)]
    pub name: String,
    /// The material's name in `[materials]` (required).
    pub material: String,
    /// The shape (required).
    pub shape: ShapeSpec,
    /// Resolution λ: the target mean tet edge length in m (required).
    pub resolution: f64,
    /// Horizon δ in units of λ, at least 1.0. Default 1.45 (Chen Table 1).
    #[serde(default = "default_horizon")]
    pub horizon: f64,
    /// Simulation model: `"peridynamics"`, or a FEM reference solver on the same tet
    /// mesh, `"fem-linear"` or `"fem-corotated"` (elastic only; every body of a scene
    /// must then use FEM), or `"membrane"` (a sheet of one particle layer; every body
    /// of the scene must then be a membrane). Default `"peridynamics"`.
    #[serde(default)]
    pub model: ModelKind,
    /// Membrane settings (`[body.membrane]`, `model = "membrane"` only). Default: the
    /// defaults of [`MembraneSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub membrane: Option<MembraneSpec>,
    /// Initial velocity in m/s. Default 0.
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Initial angular velocity in rad/s about the body's centroid. Default 0.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Regions held at prescribed motion (`[[body.anchor]]`).
    #[serde(default, rename = "anchor")]
    pub anchors: Vec<AnchorSpec>,
    /// Initial cracks (`[[body.crack]]`): bonds cut before the run starts.
    #[serde(default, rename = "crack")]
    pub cracks: Vec<CrackSpec>,
    /// The body's meshing lattice: `"aligned"` with the scene axes, `"rotated"` by a
    /// random rotation drawn from the scene's `seed` and the body's index, so that
    /// the lattice's preferred crack directions are not the scene's axes (within the
    /// body cracks still follow the turned lattice: docs/lattice.md), or
    /// `"unstructured"`: no lattice, a Delaunay mesh of blue-noise points drawn from
    /// the same seed, whose cracks have no preferred directions.
    /// Default: `"rotated"`
    /// for a peridynamic body whose material breaks (`critical_stretch`), `"aligned"`
    /// otherwise; a mesh body that the turned lattice fits worse than λ/4 (it bevels
    /// creases the aligned one follows) takes the lattice that fits it better.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lattice: Option<LatticeOrientation>,
}

/// Orientation of a body's meshing lattice (`lattice` of `[[body]]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LatticeOrientation {
    /// Lattice axes along the scene axes, centred on the shape's bounds: a shape
    /// symmetric about its mid-planes gets a symmetric set of particles.
    Aligned,
    /// Lattice turned by a random rotation seeded by the scene's `seed` and the body's
    /// index: the lattice's preferred crack directions are not the scene's axes; the
    /// same seed gives the same bytes.
    Rotated,
    /// No lattice: a Delaunay tetrahedralization of blue-noise points seeded by the
    /// scene's `seed` and the body's index, fitted to the surface; no preferred
    /// directions, at the price of slivers (docs/lattice.md).
    Unstructured,
}

impl BodySpec {
    /// The body's meshing lattice: its `lattice` key, by default rotated for a
    /// peridynamic body whose `material` breaks and aligned otherwise.
    pub fn lattice(&self, material: &MaterialSpec) -> LatticeOrientation {
        match self.lattice {
            Some(orientation) => orientation,
            None if self.model == ModelKind::Peridynamics
                && material.critical_stretch.is_some() =>
            {
                LatticeOrientation::Rotated
            }
            None => LatticeOrientation::Aligned,
        }
    }

    /// The horizon δ in metres: `horizon` (δ/λ) × `resolution` (λ).
    pub fn delta(&self) -> f64 {
        self.horizon * self.resolution
    }
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

/// `[[body.anchor]]`: particles inside `region` move rigidly with the given velocity.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnchorSpec {
    /// The region (a shape; particles with signed distance ≤ 0 are held).
    pub region: ShapeSpec,
    /// Linear velocity in m/s. Default 0 (fixed).
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Angular velocity in rad/s about `center`. Default 0.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Centre of rotation. Default: the region's particles' centroid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 3]>,
    /// Time in s after which the anchor releases. Default: never.
    #[serde(default = "default_inf")]
    pub until: f64,
    /// Makes the anchor a fixed clamp at a plane (peridynamic bodies only): the body's
    /// displacement is zero *at the plane*, not throughout a held slab. Of the
    /// region's particles, those behind the plane and farther than the horizon δ
    /// from it are held at rest; those within δ behind it are a ghost layer that
    /// continues the free particles' displacement smoothly through zero at the plane
    /// (recomputed each step), and the forces on the ghosts act on the particles they
    /// are made from; the region's particles in front of the plane are free.
    /// `velocity` and `angular_velocity` must be zero. Default: none (the whole
    /// region held, which acts as a clamp about λ/2 inside its face and is softer).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clamp: Option<ClampSpec>,
}

/// `clamp = { point, normal }` of an anchor: the clamp's plane, through `point`, with
/// `normal` pointing out of the clamp into the free body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClampSpec {
    /// A point of the plane (m).
    pub point: [f64; 3],
    /// The plane's normal, into the free body (any non-zero length).
    pub normal: [f64; 3],
}

/// `[[body.crack]]`: bonds crossing the plane through `point` with `normal`, whose
/// midpoints lie in `region`, are broken before the first step.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrackSpec {
    /// A point on the crack plane.
    pub point: [f64; 3],
    /// The crack plane's normal.
    pub normal: [f64; 3],
    /// Where on the plane the crack is.
    pub region: ShapeSpec,
}

/// `[[collider]]`: a rigid obstacle or projectile.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ColliderSpec {
    /// An infinite ground plane y = `height`.
    Ground {
        /// Height of the plane. Default 0.
        #[serde(default)]
        height: f64,
        /// Coulomb friction coefficient. Default 0.5.
        #[serde(default = "default_friction")]
        friction: f64,
    },
    /// A rigid sphere: kinematic (moves at `velocity`) or, with a `mass`, dynamic.
    Sphere {
        /// Centre at t = 0.
        center: [f64; 3],
        /// Radius.
        radius: f64,
        /// Velocity at t = 0 in m/s. Default 0.
        #[serde(default)]
        velocity: [f64; 3],
        /// Mass in kg: the sphere is pushed back by what it hits. Default: kinematic.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mass: Option<f64>,
        /// Whether gravity acts on a dynamic collider. Default true.
        #[serde(default = "default_true")]
        gravity: bool,
        /// Coulomb friction coefficient. Default 0.2.
        #[serde(default = "default_collider_friction")]
        friction: f64,
    },
    /// A rigid axis-aligned box: kinematic or, with a `mass`, dynamic.
    Box {
        /// Centre at t = 0.
        center: [f64; 3],
        /// Full size.
        size: [f64; 3],
        /// Velocity at t = 0 in m/s. Default 0.
        #[serde(default)]
        velocity: [f64; 3],
        /// Mass in kg. Default: kinematic.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mass: Option<f64>,
        /// Whether gravity acts on a dynamic collider. Default true.
        #[serde(default = "default_true")]
        gravity: bool,
        /// Coulomb friction coefficient. Default 0.2.
        #[serde(default = "default_collider_friction")]
        friction: f64,
    },
    /// A rigid closed triangle mesh (a table, a floor with steps), static or moved
    /// rigidly by `keyframes` or a per-frame `transforms` file (never both).
    Mesh {
        /// The mesh file (`.obj`, `.ply`, `.gltf`, `.glb`), relative to the scene.
        path: PathBuf,
        /// Scale: one factor or one per axis, applied first. Default 1.
        #[serde(default)]
        scale: MeshScale,
        /// Placement rotation in degrees about x, then y, then z. Default 0.
        #[serde(default)]
        rotation: [f64; 3],
        /// Placement translation in m. Default 0.
        #[serde(default)]
        translation: [f64; 3],
        /// Centre of the keyframes' rotations. Default: the centre of the placed
        /// mesh's bounding box.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pivot: Option<[f64; 3]>,
        /// Poses at increasing times, interpolated (translation linearly, rotation
        /// by slerp) and held before the first and after the last. Default: static.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        keyframes: Vec<KeyframeSpec>,
        /// A text file of poses, one line an output frame from frame 1 (t = 0):
        /// `tx ty tz rx ry rz` (m, degrees, as a keyframe); `#` starts a comment.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        transforms: Option<PathBuf>,
        /// Coulomb friction coefficient. Default 0.5.
        #[serde(default = "default_friction")]
        friction: f64,
    },
}

impl ColliderSpec {
    /// The shape of a mesh collider's file as placed in the scene.
    pub fn mesh_shape(&self) -> Option<ShapeSpec> {
        match self {
            ColliderSpec::Mesh {
                path,
                scale,
                rotation,
                translation,
                ..
            } => Some(ShapeSpec::Mesh {
                path: path.clone(),
                scale: *scale,
                rotation: *rotation,
                translation: *translation,
            }),
            _ => None,
        }
    }
}

/// `[contact]`: contact between particles of different bodies and between unbonded
/// particles of one body (fragments, the faces of an initial crack); see
/// `docs/contact.md`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Turns particle contact on or off. Default: on when the scene has more than one
    /// body, a material with a `critical_stretch` or a `[[body.crack]]`; off otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particles: Option<bool>,
    /// The contact spring as a multiple of the bond micromodulus c = 18κ/(πδ⁴).
    /// Default 15 (Silling & Askari 2005, LAMMPS PERI).
    #[serde(default = "default_contact_stiffness")]
    pub stiffness: f64,
    /// The distance, in particle spacings, below which two particles repel. Default 0.9.
    #[serde(default = "default_contact_distance")]
    pub distance: f64,
    /// Damping ratio ζ of each contact spring along the normal. Default 0.1.
    #[serde(default = "default_contact_damping")]
    pub damping: f64,
    /// Coulomb friction coefficient between particles. Default 0.3.
    #[serde(default = "default_contact_friction")]
    pub friction: f64,
}

impl Default for ContactSpec {
    fn default() -> Self {
        ContactSpec {
            particles: None,
            stiffness: default_contact_stiffness(),
            distance: default_contact_distance(),
            damping: default_contact_damping(),
            friction: default_contact_friction(),
        }
    }
}

fn default_contact_stiffness() -> f64 {
    15.0
}
fn default_contact_distance() -> f64 {
    0.9
}
fn default_contact_damping() -> f64 {
    0.1
}
fn default_contact_friction() -> f64 {
    0.3
}

/// A pose of a mesh collider at a time (`[[collider]] keyframes`): its motion from the
/// placed mesh, x ↦ pivot + R (x − pivot) + translation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeSpec {
    /// Time in s.
    pub time: f64,
    /// Translation in m. Default 0.
    #[serde(default)]
    pub translation: [f64; 3],
    /// Rotation about the pivot in degrees about x, then y, then z (fixed axes; R = Rz
    /// Ry Rx), as for mesh placement. Default 0.
    #[serde(default)]
    pub rotation: [f64; 3],
}

fn default_name() -> String {
    "scene".into()
}
fn default_duration() -> f64 {
    1.0
}
fn default_fps() -> f64 {
    24.0
}
fn default_gravity() -> [f64; 3] {
    [0.0, -9.81, 0.0]
}
fn default_dt_safety() -> f64 {
    0.7
}
fn default_true() -> bool {
    true
}
fn default_energy_growth() -> f64 {
    10.0
}
fn default_inf() -> f64 {
    f64::INFINITY
}
fn default_horizon() -> f64 {
    1.45
}
fn default_friction() -> f64 {
    0.5
}
fn default_collider_friction() -> f64 {
    0.2
}

impl Scene {
    /// Reads, resolves and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene> {
        Scene::read(path, false)
    }

    /// Reads the resolved scene of a cache (`OUT/scene.toml`) for the stages that read
    /// the cache: validated as [`Scene::load`] does, except that the mesh and transforms
    /// files it names need not exist any more (those stages read the cache's own copies:
    /// particles, `colliders/mesh_N.ply`).
    pub fn load_cached(path: &Path) -> Result<Scene> {
        Scene::read(path, true)
    }

    fn read(path: &Path, cached: bool) -> Result<Scene> {
        let bytes = std::fs::read(path).map_err(|e| CacheError::io(path, e))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let valid = std::str::from_utf8(&e.as_bytes()[..at]).unwrap_or_default();
            let (line, column) = locate::line_column(valid, at);
            CacheError::Scene {
                file: path.to_path_buf(),
                line,
                column,
                key: locate::key_at(valid, at),
                message: format!(
                    "byte {at} (0x{:02x}) is not UTF-8: a scene file is UTF-8 text; save it \
                     as UTF-8",
                    e.as_bytes()[at]
                ),
            }
        })?;
        let base_dir = path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        Scene::parse_as(&text, path, &base_dir, cached)
    }

    /// Parses and validates scene text; `file` names it in messages and `base_dir`
    /// resolves mesh paths.
    pub fn parse(text: &str, file: &Path, base_dir: &Path) -> Result<Scene> {
        Scene::parse_as(text, file, base_dir, false)
    }

    fn parse_as(text: &str, file: &Path, base_dir: &Path, cached: bool) -> Result<Scene> {
        let mut scene: Scene = toml::from_str(text).map_err(|e| {
            let (line, column) = e
                .span()
                .map(|s| locate::line_column(text, s.start))
                .unwrap_or((1, 1));
            let key = locate::key_at(text, e.span().map_or(0, |s| s.start));
            CacheError::Scene {
                file: file.to_path_buf(),
                line,
                column,
                key: locate::escape_controls(&key),
                message: locate::escape_controls(e.message().trim()),
            }
        })?;
        scene.base_dir = base_dir.to_path_buf();
        scene.cached = cached;
        for (i, body) in scene.bodies.iter_mut().enumerate() {
            if body.name.is_empty() {
                body.name = format!("body{i}");
            }
        }
        validate::validate(&scene).map_err(|issue| {
            let span = locate::span_of(text, &issue.path);
            let (line, column) = locate::line_column(text, span.map_or(0, |s| s.start));
            CacheError::Scene {
                file: file.to_path_buf(),
                line,
                column,
                key: locate::escape_controls(&issue.path.join(".")),
                message: locate::escape_controls(&issue.message),
            }
        })?;
        scene.output.tets = Some(scene.output.writes_tets());
        Ok(scene)
    }

    /// The scene as resolved, with every default written out and mesh paths made
    /// absolute (canonical where the file exists), so that the copy in a cache
    /// directory (`OUT/scene.toml`) still finds its meshes.
    pub fn to_toml(&self) -> String {
        let mut resolved = self.clone();
        let base = &self.base_dir;
        let absolute = |shape: &mut ShapeSpec| shape.resolve_mesh_paths(base);
        for body in &mut resolved.bodies {
            absolute(&mut body.shape);
            for anchor in &mut body.anchors {
                absolute(&mut anchor.region);
            }
            for crack in &mut body.cracks {
                absolute(&mut crack.region);
            }
        }
        for collider in &mut resolved.colliders {
            if let ColliderSpec::Mesh {
                path, transforms, ..
            } = collider
            {
                for file in std::iter::once(path).chain(transforms.as_mut()) {
                    let mut shape = ShapeSpec::Mesh {
                        path: file.clone(),
                        scale: MeshScale::default(),
                        rotation: [0.0; 3],
                        translation: [0.0; 3],
                    };
                    absolute(&mut shape);
                    if let ShapeSpec::Mesh { path: resolved, .. } = shape {
                        *file = resolved;
                    }
                }
            }
        }
        toml::to_string(&resolved).unwrap_or_else(|e| format!("# could not serialize: {e}\n"))
    }

    /// Whether particles of the scene's bodies touch each other: `[contact] particles`,
    /// or by default when there is more than one body, a material that can break or
    /// an initial crack (peridynamic and FEM bodies; MPM and membrane scenes have
    /// none).
    pub fn particle_contact(&self) -> bool {
        self.contact.particles.unwrap_or_else(|| {
            let solid = |b: &BodySpec| !matches!(b.model, ModelKind::Membrane | ModelKind::Mpm);
            if !self.bodies.iter().all(solid) {
                return false;
            }
            self.bodies.len() > 1
                || self.bodies.iter().any(|b| {
                    !b.cracks.is_empty()
                        || self
                            .materials
                            .get(&b.material)
                            .is_some_and(|m| m.critical_stretch.is_some())
                })
        })
    }

    /// Seconds between output frames.
    pub fn frame_time(&self) -> f64 {
        1.0 / self.scene.fps
    }

    /// Number of output frames after the initial one.
    pub fn frame_count(&self) -> usize {
        (self.scene.duration * self.scene.fps).round().max(1.0) as usize
    }
}

#[cfg(test)]
mod value_tests;

#[cfg(test)]
mod tests;
