//! The whole cache as one USD stage, `OUT/cache.usd` (binary usdc, written with the
//! pure-Rust `openusd` crate), for the tools artists use: Houdini (Solaris, USD
//! Import), Blender (File → Import → USD), Maya and Omniverse read it natively.
//! docs/usd.md describes the stage; [`write_stage`] writes it.
//!
//! Frame by frame: the particles' and surfaces' time samples of frame k are in the
//! value clip `OUT/usd/NNNN.usdc`, which `cache.usd` names in `/World`'s `clips`
//! metadata (clip manifest `OUT/usd/manifest.usdc`), so the export holds a frame a
//! worker thread whatever the cache's length; USD composes the clips into one stage.
//!
//! Time: cache frame k is time code k, and `timeCodesPerSecond` = `framesPerSecond`
//! = `[output] playback_fps`, so frame k plays at (k − 1)/playback_fps s
//! ([`perifrac_cache::playback_time`]); the simulation time of every frame is in the
//! layer's `customLayerData` (`perifrac.simulation_times`). Units are metres
//! (`metersPerUnit = 1`) and +y is up (`upAxis = "Y"`), as everywhere in the cache.
//!
//! Prims, under the default prim `/World`:
//!
//! | prim | type | from |
//! |---|---|---|
//! | `Particles` | `Points`: `points`, `velocities` (playback), `widths`, `ids`, primvars `damage`, `plastic`, `fragment`, `material`, `simulation_velocity` and a model's extra columns | `particles/NNNN.ply` |
//! | `Surface` | `Mesh` with time-sampled topology, `normals`, primvars `damage` (vertex), `crack` and `displayColor` (per face); `GeomSubset`s `surface` and `crack` (family `materialBind`) | `surface/NNNN.glb` (embedded method) |
//! | `Fragments/fragment_N` | one `Mesh` a fragment, `visibility` time-sampled where a frame lacks it | `surface/NNNN.glb` (vdb method) |
//! | `Volume` | `Volume` with `OpenVDBAsset` fields `surface` and `v`, `filePath` time-sampled | `vdb/NNNN.vdb` |
//! | `Colliders/ground` (`ground_N` when there are several), `sphere_N`, `box_N`, `mesh_N` (N: the scene index) | `Xform` with time-sampled `xformOp:translate` (and `xformOp:orient` where the manifest has rotations), a `Sphere`, `Cube`, ground `Mesh` or the mesh collider's `Mesh` child of the same name | `scene.toml`, `manifest.json`, `colliders/mesh_N.ply` |
//! | `Looks/surface`, `Looks/crack` | `Material` with a `UsdPreviewSurface` whose colour is the meshes' `displayColor` | the glTF materials' colours |
//!
//! Velocities: `velocities` are in metres per second of *playback* (the simulation
//! velocity × playback_fps / simulation fps), what renderers' motion blur and USD's
//! velocity extrapolation between time samples read; the simulation velocities (m/s
//! of simulated time) are the primvar `simulation_velocity`.
#![warn(missing_docs)]

mod colliders;
mod layer;
mod prims;

use std::path::PathBuf;
use std::time::Instant;

use openusd::gf;
use openusd::sdf::{AssetPath, Value};
use perifrac_cache::collider::{MovingCollider, mesh_colliders};
use perifrac_cache::manifest::Manifest;
use perifrac_cache::mesh::SurfaceMesh;
use perifrac_cache::ply::ParticleFrame;
use perifrac_cache::scene::{ColliderSpec, Scene};
use perifrac_cache::{CacheError, Layout};
use perifrac_render::RenderError;
use rayon::prelude::*;

use colliders::*;
use layer::{Layer, Samples};
use prims::*;

/// A failure of the USD export.
#[derive(Debug, thiserror::Error)]
pub enum UsdError {
    /// A cache file (scene, manifest, particles) is missing or malformed.
    #[error(transparent)]
    Cache(#[from] CacheError),
    /// A surface file could not be read.
    #[error(transparent)]
    Surface(#[from] RenderError),
    /// The cache is not one the stage can be made of.
    #[error("{path}: {message}")]
    Input {
        /// The file or directory.
        path: PathBuf,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// The stage could not be authored or encoded.
    #[error("{path}: {message}")]
    Encode {
        /// The stage being written.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

impl UsdError {
    /// Whether the failure is the input's (a missing or malformed cache file), not
    /// the writer's.
    pub fn is_bad_input(&self) -> bool {
        !matches!(self, UsdError::Encode { .. })
    }
}

/// What [`write_stage`] wrote.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct UsdReport {
    /// Frames (time codes 1 … frames).
    pub frames: usize,
    /// Particles in the last frame (0 without particle files).
    pub particles: usize,
    /// Meshes (the embedded surface, or the vdb method's fragments).
    pub meshes: usize,
    /// Whether a `Volume` prim points at the `.vdb` files.
    pub volume: bool,
    /// Colliders.
    pub colliders: usize,
    /// Size in bytes of `cache.usd` and its clips (`usd/`).
    pub bytes: usize,
    /// Wall-clock seconds: the frames (reading them, writing their clips), then the
    /// stage (`cache.usd` and the clip manifest).
    pub seconds: (f64, f64),
}

/// Colour and roughness of the preview materials, the glTF files' (render/src/gltf.rs).
const SURFACE_LOOK: ([f32; 3], f32) = ([0.8, 0.8, 0.78], 0.5);
const CRACK_LOOK: ([f32; 3], f32) = ([0.85, 0.45, 0.3], 0.9);

/// Writes `cache.usd` for the cache at `layout` from its `scene.toml`,
/// `manifest.json`, particle, surface and `.vdb` files.
///
/// Frame by frame: each frame's time samples (particles, surfaces) go to a layer of
/// their own, `usd/NNNN.usdc`, written and dropped before the next frames are read,
/// and `cache.usd` ties them together as USD value clips (the `clips` metadata of
/// `/World`, with the clip manifest `usd/manifest.usdc`), so the export holds a few
/// frames at a time however long the cache. `cache.usd` and the old clips are
/// removed first, so a failed export leaves no stage that reads stale frames.
pub fn write_stage(layout: &Layout) -> Result<UsdReport, UsdError> {
    let start = Instant::now();
    let scene = Scene::load_cached(&layout.scene())?;
    let manifest = Manifest::read(&layout.manifest())?;
    let frames = manifest.frame_times.len();
    if frames == 0 {
        return Err(UsdError::Input {
            path: layout.manifest(),
            message: "the cache has no frames; run the scene (or --resume it) first".into(),
        });
    }
    let target = layout.usd();
    let encode = |message: String| UsdError::Encode {
        path: target.clone(),
        message,
    };
    let surface = if layout.surface(1).is_file() {
        let first = perifrac_render::gltf::read_surfaces(&layout.surface(1))?;
        // The vdb method names its meshes `fragment N`; the embedded method writes one
        // mesh a frame (whichever method last surfaced the cache wrote the files).
        let vdb = !first.is_empty() && first.iter().all(|m| m.name.starts_with("fragment "));
        Some(if vdb {
            Method::Fragments
        } else {
            Method::Embedded
        })
    } else {
        None
    };
    let clip = ClipFrames {
        layout,
        frames,
        particles: layout.particles(1).is_file(),
        surface,
        widths: scene.bodies.iter().map(|b| b.resolution as f32).collect(),
        velocity_scale: (scene.output.playback_fps / manifest.fps) as f32,
    };
    remove(&target)?;
    let clips = layout.usd_dir();
    match std::fs::remove_dir_all(&clips) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            return Err(CacheError::io(&clips, e).into());
        }
        _ => {}
    }
    std::fs::create_dir_all(&clips).map_err(|e| CacheError::io(&clips, e))?;
    // Rayon's workers take one frame at a time: at most a frame a thread is in memory.
    // The reduction keeps the frames' order (it is associative, not commutative).
    let written = (1..=frames)
        .into_par_iter()
        .map(|frame| clip.write(frame))
        .try_reduce(Written::default, |a, b| Ok(a.merge(b)))?;
    let authored = start.elapsed().as_secs_f64();

    let playback_fps = scene.output.playback_fps;
    let mut stage = Layer::new(stage_metadata(&manifest, playback_fps));
    let world = stage.def("/", "World", "Xform").map_err(encode)?;
    let looks = looks(&mut stage, &world).map_err(encode)?;
    let declared = &written.prims;
    let mut report = UsdReport {
        frames,
        particles: written.frames.last().map_or(0, |w| w.particles),
        bytes: written.bytes,
        ..UsdReport::default()
    };
    let attributes = |prim: &str| {
        declared
            .iter()
            .find(|(p, _)| p == prim)
            .map_or(&[][..], |(_, a)| a.as_slice())
    };
    if clip.particles {
        particles(
            &mut stage,
            &world,
            attributes("Particles"),
            clip.velocity_scale,
        )
        .map_err(encode)?;
    }
    report.meshes = match surface {
        Some(Method::Embedded) => {
            embedded_surface(&mut stage, &world, &attributes, &looks).map_err(encode)?
        }
        Some(Method::Fragments) => {
            fragments(&mut stage, &world, &written.frames, &attributes, &looks).map_err(encode)?
        }
        None => 0,
    };
    if layout.vdb(1).is_file() {
        volume(&mut stage, &world, layout, frames).map_err(encode)?;
        report.volume = true;
    }
    let meshes = mesh_colliders(layout, &scene, Some(&manifest))?;
    report.colliders = colliders(&mut stage, &world, &scene, &manifest, &meshes).map_err(encode)?;
    let manifest_path = layout.usd_clip_manifest();
    let manifest_bytes = clip_manifest(declared).map_err(|message| UsdError::Encode {
        path: manifest_path.clone(),
        message,
    })?;
    perifrac_cache::write_atomic(&manifest_path, &manifest_bytes)?;
    stage
        .prim_metadata(&world, "clips", clips_metadata(layout, frames))
        .map_err(encode)?;
    let bytes = stage.into_usdc().map_err(encode)?;
    perifrac_cache::write_atomic(&target, &bytes)?;
    report.bytes += bytes.len() + manifest_bytes.len();
    report.seconds = (authored, start.elapsed().as_secs_f64() - authored);
    Ok(report)
}

/// Removes `path` if it is there.
fn remove(path: &std::path::Path) -> Result<(), UsdError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(CacheError::io(path, e).into()),
        _ => Ok(()),
    }
}

/// How the cache was surfaced: one mesh a frame with crack faces, or the vdb
/// method's fragments.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Method {
    Embedded,
    Fragments,
}

/// An attribute whose time samples the clips give: name and USD type.
type Declared = (String, &'static str);

/// One attribute's value in a frame's clip: name, USD type and value.
type Sample = (String, &'static str, Value);

/// What one frame's clip leaves to the stage: its particle count and the vdb
/// method's mesh names.
struct FrameSummary {
    particles: usize,
    names: Vec<String>,
}

/// What the clips of a run of frames wrote: the attributes they authored, prim by
/// prim (the prim's path below `/World`) in the order they first appeared, each
/// frame's [`FrameSummary`] in frame order, and the clips' size in bytes. Frames are
/// merged as they are written, so what is kept grows with the distinct attributes,
/// not with the frames.
#[derive(Default)]
struct Written {
    prims: Vec<(String, Vec<Declared>)>,
    /// Where each prim is in `prims`.
    index: std::collections::HashMap<String, usize>,
    frames: Vec<FrameSummary>,
    bytes: usize,
}

impl Written {
    /// Adds `attributes` of `prim` that are not there yet.
    fn declare(&mut self, prim: String, attributes: Vec<Declared>) {
        let index = match self.index.get(&prim) {
            Some(&index) => index,
            None => {
                self.index.insert(prim.clone(), self.prims.len());
                self.prims.push((prim, Vec::new()));
                self.prims.len() - 1
            }
        };
        for attribute in attributes {
            if !self.prims[index].1.contains(&attribute) {
                self.prims[index].1.push(attribute);
            }
        }
    }

    /// These frames followed by `later`'s.
    fn merge(mut self, later: Written) -> Written {
        for (prim, attributes) in later.prims {
            self.declare(prim, attributes);
        }
        self.frames.extend(later.frames);
        self.bytes += later.bytes;
        self
    }
}

/// What every frame's clip is made of.
struct ClipFrames<'a> {
    layout: &'a Layout,
    frames: usize,
    /// Whether the cache has particle files.
    particles: bool,
    surface: Option<Method>,
    /// Each body's λ, the width of a particle without a volume.
    widths: Vec<f32>,
    /// Playback over simulation fps.
    velocity_scale: f32,
}

impl ClipFrames<'_> {
    /// Reads frame `frame`'s particle and surface files and writes their time samples
    /// as the clip `usd/NNNN.usdc`.
    fn write(&self, frame: usize) -> Result<Written, UsdError> {
        let mut prims: Vec<(String, Vec<Sample>)> = Vec::new();
        let mut particles = 0;
        let mut names = Vec::new();
        if self.particles {
            let path = self.layout.particles(frame);
            if !path.is_file() {
                return Err(UsdError::Input {
                    path,
                    message: format!(
                        "missing, but the manifest lists {} frames: the cache is \
                         incomplete; run the scene again (or --resume it)",
                        self.frames
                    ),
                });
            }
            let p = ParticleFrame::read(&path)?;
            particles = p.len();
            prims.push((
                "Particles".into(),
                particle_samples(&p, &self.widths, self.velocity_scale),
            ));
        }
        if let Some(method) = self.surface {
            let path = self.layout.surface(frame);
            if !path.is_file() {
                return Err(UsdError::Input {
                    path,
                    message: "missing: surface the cache again with `perifrac surface OUT`".into(),
                });
            }
            let meshes = perifrac_render::gltf::read_surfaces(&path)?;
            match method {
                Method::Embedded => {
                    let [mesh] = meshes.as_slice() else {
                        return Err(UsdError::Input {
                            path,
                            message: format!(
                                "{} meshes; the embedded method writes one a frame: surface \
                                 the cache again with `perifrac surface OUT --method embedded`",
                                meshes.len()
                            ),
                        });
                    };
                    let (samples, surface) = mesh_samples(mesh);
                    let surface = surface as i32;
                    let all = mesh.triangle_count() as i32;
                    prims.push(("Surface".into(), samples));
                    for (name, range) in [("surface", 0..surface), ("crack", surface..all)] {
                        let indices = Value::IntVec(range.collect());
                        prims.push((
                            format!("Surface/{name}"),
                            vec![("indices".into(), "int[]", indices)],
                        ));
                    }
                }
                Method::Fragments => {
                    for mesh in &meshes {
                        let prim = format!("Fragments/{}", identifier(&mesh.name));
                        prims.push((prim, mesh_samples(mesh).0));
                        names.push(mesh.name.clone());
                    }
                }
            }
        }
        let path = self.layout.usd_clip(frame);
        let bytes = clip_layer(&prims, frame as f64).map_err(|message| UsdError::Encode {
            path: path.clone(),
            message,
        })?;
        perifrac_cache::write_atomic(&path, &bytes)?;
        let mut written = Written {
            frames: vec![FrameSummary { particles, names }],
            bytes: bytes.len(),
            ..Written::default()
        };
        for (prim, samples) in prims {
            written.declare(prim, samples.into_iter().map(|(n, t, _)| (n, t)).collect());
        }
        Ok(written)
    }
}

/// Creates the `over`s of `/World/PRIM` and its ancestors in `layer` that `made`
/// lacks; returns the prim's path.
fn over_path(layer: &mut Layer, made: &mut Vec<String>, prim: &str) -> Result<String, String> {
    let mut path = "/World".to_string();
    for name in prim.split('/') {
        let child = format!("{path}/{name}");
        if !made.contains(&child) {
            layer.over(&path, name)?;
            made.push(child.clone());
        }
        path = child;
    }
    Ok(path)
}

/// The clip of one frame: `over`s of the prims with one time sample, at `time`, of
/// each attribute.
fn clip_layer(prims: &[(String, Vec<Sample>)], time: f64) -> Result<Vec<u8>, String> {
    let mut layer = Layer::new(vec![]);
    layer.over("/", "World")?;
    let mut made = Vec::new();
    for (prim, samples) in prims {
        let path = over_path(&mut layer, &mut made, prim)?;
        for (name, type_name, value) in samples {
            layer.animated(&path, name, type_name, vec![(time, value.clone())], vec![])?;
        }
    }
    layer.into_usdc()
}

/// The clip manifest, `usd/manifest.usdc`: the attributes the clips give values to,
/// declared without values (USD reads clips only for these).
fn clip_manifest(declared: &[(String, Vec<Declared>)]) -> Result<Vec<u8>, String> {
    let mut layer = Layer::new(vec![]);
    layer.over("/", "World")?;
    let mut made = Vec::new();
    for (prim, attributes) in declared {
        let path = over_path(&mut layer, &mut made, prim)?;
        for (name, type_name) in attributes {
            layer.declare(&path, name, type_name, vec![])?;
        }
    }
    layer.into_usdc()
}

/// `/World`'s `clips` metadata: clip k (`usd/NNNN.usdc` of frame k) active from time
/// code k, its times the stage's, missing values (a fragment in a frame that lacks
/// it) interpolated from the clips around, as USD resolves time samples in one layer.
fn clips_metadata(layout: &Layout, frames: usize) -> Value {
    let relative = |path: PathBuf| -> AssetPath {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
        AssetPath::new(format!("./usd/{}", name.unwrap_or_default()))
    };
    let set: std::collections::HashMap<String, Value> = [
        (
            "assetPaths",
            Value::AssetPathVec((1..=frames).map(|k| relative(layout.usd_clip(k))).collect()),
        ),
        ("primPath", Value::String("/World".into())),
        (
            "active",
            Value::Vec2dVec(
                (0..frames)
                    .map(|i| gf::vec2d((i + 1) as f64, i as f64))
                    .collect(),
            ),
        ),
        (
            "times",
            Value::Vec2dVec(
                (1..=frames)
                    .map(|k| gf::vec2d(k as f64, k as f64))
                    .collect(),
            ),
        ),
        (
            "manifestAssetPath",
            Value::AssetPath(relative(layout.usd_clip_manifest())),
        ),
        ("interpolateMissingClipValues", Value::Bool(true)),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    Value::Dictionary([("default".to_string(), Value::Dictionary(set))].into())
}

/// The metadata of an attribute of the `Points` and `Mesh` prims: per point
/// (interpolation `vertex`) for `widths`, `normals` and the primvars, per face
/// (`uniform`) for `primvars:displayColor` and `primvars:crack`.
fn attribute_metadata(name: &str) -> Vec<(&'static str, Value)> {
    match name {
        "primvars:displayColor" | "primvars:crack" => {
            vec![("interpolation", Value::token("uniform"))]
        }
        "primvars:displayColor:indices" => vec![],
        "widths" | "normals" => vertex(),
        _ if name.starts_with("primvars:") => vertex(),
        _ => vec![],
    }
}

/// Declares on `prim` the attributes whose values the clips give.
fn declare_all(stage: &mut Layer, prim: &str, attributes: &[Declared]) -> Result<(), String> {
    for (name, type_name) in attributes {
        stage.declare(prim, name, type_name, attribute_metadata(name))?;
    }
    Ok(())
}

/// The pseudo-root's metadata: axes, units, time base, and the simulation times.
fn stage_metadata(manifest: &Manifest, playback_fps: f64) -> Vec<(&'static str, Value)> {
    let frames = manifest.frame_times.len();
    let perifrac = [
        ("playback_fps", Value::Double(playback_fps)),
        ("simulation_fps", Value::Double(manifest.fps)),
        (
            "simulation_times",
            Value::DoubleVec(manifest.frame_times.clone()),
        ),
        ("velocity_scale", Value::Double(playback_fps / manifest.fps)),
        ("scene", Value::String(manifest.scene.clone())),
        ("tool_version", Value::String(manifest.tool_version.clone())),
    ];
    let perifrac = perifrac
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
    let custom = [("perifrac".to_string(), Value::Dictionary(perifrac))].into();
    vec![
        ("defaultPrim", Value::token("World")),
        ("upAxis", Value::token("Y")),
        ("metersPerUnit", Value::Double(1.0)),
        ("startTimeCode", Value::Double(1.0)),
        ("endTimeCode", Value::Double(frames as f64)),
        ("timeCodesPerSecond", Value::Double(playback_fps)),
        ("framesPerSecond", Value::Double(playback_fps)),
        (
            "documentation",
            Value::String(format!(
                "perifrac cache '{}': frame k is time code k, played at {playback_fps} fps; \
                 simulation times in customLayerData perifrac.simulation_times",
                manifest.scene
            )),
        ),
        ("customLayerData", Value::Dictionary(custom)),
    ]
}

fn vec3f(v: &[[f32; 3]]) -> Value {
    Value::Vec3fVec(v.iter().map(|p| gf::vec3f(p[0], p[1], p[2])).collect())
}

/// The extent (bounding box) of `points` grown by `margin`, as `float3[2]`.
fn extent(points: &[[f32; 3]], margin: f32) -> Value {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if points.is_empty() {
        (lo, hi) = ([0.0; 3], [0.0; 3]);
    }
    vec3f(&[lo.map(|x| x - margin), hi.map(|x| x + margin)])
}

/// A primvar's metadata: interpolation "vertex".
fn vertex() -> Vec<(&'static str, Value)> {
    vec![("interpolation", Value::token("vertex"))]
}

/// A USD identifier from a column or mesh name (letters, digits, `_`).
fn identifier(name: &str) -> String {
    let mut id: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if id.is_empty() || id.starts_with(|c: char| c.is_ascii_digit()) {
        id.insert(0, '_');
    }
    id
}

#[cfg(test)]
mod tests;
