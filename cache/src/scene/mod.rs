//! The scene file: TOML in SI units (m, kg, s, Pa), y up.
//!
//! [`Scene::load`] reads a file, fills in defaults, checks every value and returns
//! a [`Scene`]; any problem is a [`CacheError::Scene`] naming the file, the line and
//! the dotted key. Unknown keys are errors. The resolved scene (defaults filled in)
//! is written next to the cache by [`Scene::to_toml`].

mod clamp;
mod collider;
mod color;
mod exact;
mod locate;
mod material;
mod membrane;
mod mpm;
mod output;
mod rigid;
mod shape;
mod validate;

pub use clamp::{Clamp, ClampSpec};
pub use collider::{ColliderSpec, ContactSpec, KeyframeSpec};
pub use color::{ColorSpec, PALETTE};
pub use material::{DilatationForm, MaterialSpec, ModelKind};
pub use membrane::{
    MembraneFormulation, MembraneLaw, MembraneMaterialSpec, MembraneSpec, ScatterSpec, SourceSpec,
};
pub use mpm::{MpmBonds, MpmElasticity, MpmPlasticity, MpmSettings, MpmSpec, MpmTransfer};
pub use output::{EmbeddedSpec, OutputSpec, ScheduleSpec, SurfaceMethod, VdbFilter, VdbSpec};
pub use rigid::RigidSpec;
pub use shape::{Axis, MeshScale, ShapeSpec};
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
    /// The rigid phase of fragments that stopped breaking (`[rigid]`).
    #[serde(default)]
    pub rigid: RigidSpec,
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
    #[serde(default = "default_gravity", deserialize_with = "exact::array")]
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
    #[serde(default, deserialize_with = "exact::array")]
    pub velocity: [f64; 3],
    /// Initial angular velocity in rad/s about the body's centroid. Default 0.
    #[serde(default, deserialize_with = "exact::array")]
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
    /// Default: `"unstructured"` for a peridynamic body whose material breaks
    /// (`critical_stretch`), `"aligned"` otherwise.
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
    /// The body's meshing lattice: its `lattice` key, by default unstructured for a
    /// peridynamic body whose `material` breaks (its cracks then follow no lattice,
    /// issue 13) and aligned otherwise (symmetric particles for symmetric shapes).
    pub fn lattice(&self, material: &MaterialSpec) -> LatticeOrientation {
        match self.lattice {
            Some(orientation) => orientation,
            None if self.model == ModelKind::Peridynamics
                && material.critical_stretch.is_some() =>
            {
                LatticeOrientation::Unstructured
            }
            None => LatticeOrientation::Aligned,
        }
    }

    /// The horizon δ in metres: `horizon` (δ/λ) × `resolution` (λ).
    pub fn delta(&self) -> f64 {
        self.horizon * self.resolution
    }
}

/// `[[body.anchor]]`: particles inside `region` move rigidly with the given velocity.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnchorSpec {
    /// The region (a shape; particles with signed distance ≤ 0 are held).
    pub region: ShapeSpec,
    /// Linear velocity in m/s. Default 0 (fixed).
    #[serde(default, deserialize_with = "exact::array")]
    pub velocity: [f64; 3],
    /// Angular velocity in rad/s about `center`. Default 0.
    #[serde(default, deserialize_with = "exact::array")]
    pub angular_velocity: [f64; 3],
    /// Centre of rotation. Default: the region's particles' centroid.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "exact::option_array"
    )]
    pub center: Option<[f64; 3]>,
    /// Time in s after which the anchor releases. Default: never.
    #[serde(default = "default_inf")]
    pub until: f64,
    /// Where the body is clamped (peridynamic bodies only). A clamp puts the body's
    /// displacement to zero *at a plane*, not throughout a held slab: of the region's
    /// particles, those behind the plane and farther than the horizon δ from it are
    /// held at rest; those within δ behind it are a ghost layer that continues the free
    /// particles' displacement smoothly through zero at the plane (recomputed each
    /// step), and the forces on the ghosts act on the particles they are made from; the
    /// region's particles in front of the plane are free.
    ///
    /// Default (no key): a fixed anchor (`velocity` and `angular_velocity` zero) of a
    /// peridynamic body whose material does not break, whose region is a `box` or
    /// `slab` meeting the body's free particles across exactly one face, is clamped at
    /// that face, its normal out of the box (`perifrac check` lists these anchors);
    /// every other anchor holds its whole region. `clamp = false` holds the whole
    /// region (a clamp about λ/2 inside its face, softer by an O(δ) boundary layer:
    /// docs/lattice.md, "Bending"). `clamp = { point, normal }` clamps at that plane;
    /// `velocity` and `angular_velocity` must then be zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clamp: Option<Clamp>,
}

/// `[[body.crack]]`: bonds crossing the plane through `point` with `normal`, whose
/// midpoints lie in `region`, are broken before the first step.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrackSpec {
    /// A point on the crack plane.
    #[serde(deserialize_with = "exact::array")]
    pub point: [f64; 3],
    /// The crack plane's normal.
    #[serde(deserialize_with = "exact::array")]
    pub normal: [f64; 3],
    /// Where on the plane the crack is.
    pub region: ShapeSpec,
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

    /// Seconds between the first output frames (the first segment's frame length).
    pub fn frame_time(&self) -> f64 {
        self.frame_segments()[0].1
    }

    /// The display colour (sRGB, in [0, 1]) of each body, in body order: its material's
    /// `color`, else the [`PALETTE`] colour of the material's place in the materials
    /// table, so bodies of different materials differ and bodies of one material match.
    /// A colour that does not parse (refused by validation) takes the palette's.
    pub fn body_colors(&self) -> Vec<[f32; 3]> {
        self.bodies
            .iter()
            .map(|b| {
                let index = self
                    .materials
                    .keys()
                    .position(|name| *name == b.material)
                    .unwrap_or(0);
                let palette = PALETTE[index % PALETTE.len()];
                self.materials
                    .get(&b.material)
                    .and_then(|m| m.color.as_ref())
                    .and_then(|c| c.srgb().ok())
                    .unwrap_or(palette)
            })
            .collect()
    }

    /// Number of output frames after the initial one.
    pub fn frame_count(&self) -> usize {
        self.frame_segments().iter().map(|s| s.0).sum()
    }

    /// The frame segments of the shot, each (frames, seconds a frame): `[output]
    /// schedule`'s segments, then `[scene] fps` to `duration`. A segment's frames
    /// divide it evenly (their count rounded from its length times its rate), so each
    /// ends on its `until`; without a schedule, `duration × fps` frames of 1/`fps` s.
    pub fn frame_segments(&self) -> Vec<(usize, f64)> {
        let whole = |length: f64, fps: f64| (length * fps).round().max(1.0);
        if self.output.schedule.is_empty() {
            let frames = whole(self.scene.duration, self.scene.fps);
            return vec![(frames as usize, 1.0 / self.scene.fps)];
        }
        let mut out = Vec::new();
        let mut start = 0.0;
        for s in &self.output.schedule {
            let frames = whole(s.until - start, s.fps);
            out.push((frames as usize, (s.until - start) / frames));
            start = s.until;
        }
        if self.scene.duration > start {
            let frames = whole(self.scene.duration - start, self.scene.fps);
            out.push((frames as usize, (self.scene.duration - start) / frames));
        }
        out
    }

    /// Seconds from the frame before `frame` (from 2) to `frame`.
    pub fn frame_length(&self, frame: usize) -> f64 {
        let mut first = 2;
        let segments = self.frame_segments();
        for &(frames, length) in &segments {
            if frame < first + frames {
                return length;
            }
            first += frames;
        }
        segments.last().map_or(1.0 / self.scene.fps, |s| s.1)
    }
}

#[cfg(test)]
mod value_tests;

#[cfg(test)]
mod tests;
