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

mod layer;

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

use layer::{Layer, Samples};

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
        let first = perifrac_render::cache::read_surfaces(&layout.surface(1))?;
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
            let meshes = perifrac_render::cache::read_surfaces(&path)?;
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

/// `/World/Looks` with a preview material for the original surface and one for the
/// crack faces; returns their paths.
///
/// Both read their diffuse colour from the meshes' per-face primvar `displayColor`
/// (a `UsdPrimvarReader_float3`, falling back to the material's own colour), which
/// [`mesh_samples`] makes [`SURFACE_LOOK`]'s colour on original faces and
/// [`CRACK_LOOK`]'s on crack faces, frame by frame. So a crack face shows the crack
/// colour whichever of the two materials it is bound to: through the `GeomSubset`s in
/// the tools that play their time-sampled indices, and in Blender, which applies
/// subsets once, at import (frame 1, before any crack opens), but imports the
/// primvar reader as an Attribute node and `displayColor` as a colour attribute that
/// its mesh cache updates every frame. `inputs:diffuseColor` keeps the material's
/// colour as a value too, for readers that do not follow connections (Blender's
/// viewport colour).
fn looks(stage: &mut Layer, world: &str) -> Result<[String; 2], String> {
    let scope = stage.def(world, "Looks", "Scope")?;
    let mut paths = [String::new(), String::new()];
    for (slot, (name, (colour, roughness))) in [("surface", SURFACE_LOOK), ("crack", CRACK_LOOK)]
        .into_iter()
        .enumerate()
    {
        let material = stage.def(&scope, name, "Material")?;
        let [r, g, b] = colour;
        let reader = stage.def(&material, "DisplayColor", "Shader")?;
        stage.attribute(
            &reader,
            "info:id",
            "token",
            true,
            Value::token("UsdPrimvarReader_float3"),
            vec![],
        )?;
        stage.attribute(
            &reader,
            "inputs:varname",
            "string",
            false,
            Value::String("displayColor".into()),
            vec![],
        )?;
        stage.attribute(
            &reader,
            "inputs:fallback",
            "float3",
            false,
            Value::Vec3f(gf::vec3f(r, g, b)),
            vec![],
        )?;
        stage.declare(&reader, "outputs:result", "float3", vec![])?;
        let shader = stage.def(&material, "PreviewSurface", "Shader")?;
        stage.attribute(
            &shader,
            "info:id",
            "token",
            true,
            Value::token("UsdPreviewSurface"),
            vec![],
        )?;
        stage.connection(
            &shader,
            "inputs:diffuseColor",
            "color3f",
            &format!("{reader}.outputs:result"),
            Some(Value::Vec3f(gf::vec3f(r, g, b))),
        )?;
        stage.attribute(
            &shader,
            "inputs:roughness",
            "float",
            false,
            Value::Float(roughness),
            vec![],
        )?;
        stage.attribute(
            &shader,
            "inputs:metallic",
            "float",
            false,
            Value::Float(0.0),
            vec![],
        )?;
        stage.declare(&shader, "outputs:surface", "token", vec![])?;
        stage.connection(
            &material,
            "outputs:surface",
            "token",
            &format!("{shader}.outputs:surface"),
            None,
        )?;
        paths[slot] = material;
    }
    Ok(paths)
}

/// One particle frame as the samples of the `Points` prim's attributes: those of
/// [`PARTICLE_ATTRIBUTES`], the extra columns as primvars, then the extent.
fn particle_samples(frame: &ParticleFrame, widths: &[f32], velocity_scale: f32) -> Vec<Sample> {
    let scaled: Vec<[f32; 3]> = frame
        .velocity
        .iter()
        .map(|v| v.map(|c| c * velocity_scale))
        .collect();
    let width = |m: f32| {
        let body = if m.is_finite() && m >= 0.0 {
            m as usize
        } else {
            0
        };
        widths.get(body).or(widths.first()).copied().unwrap_or(0.01)
    };
    // Each particle's own size, the cube root of its volume; λ for caches written
    // before the volume column.
    let widths = frame.sizes(|i| width(frame.material[i]));
    let largest = widths.iter().copied().fold(0.0f32, f32::max);
    let ints = |v: &[f32]| Value::IntVec(v.iter().map(|&x| x as i32).collect());
    let values = [
        vec3f(&frame.position),
        vec3f(&scaled),
        Value::FloatVec(widths),
        Value::Int64Vec((0..frame.len() as i64).collect()),
        Value::FloatVec(frame.damage.clone()),
        Value::FloatVec(frame.plastic.clone()),
        ints(&frame.fragment),
        ints(&frame.material),
        vec3f(&frame.velocity),
    ];
    let mut samples: Vec<Sample> = PARTICLE_ATTRIBUTES
        .iter()
        .zip(values)
        .map(|((name, type_name), value)| (name.to_string(), *type_name, value))
        .collect();
    for (name, v) in &frame.extra {
        let attribute = format!("primvars:{}", identifier(name));
        samples.push((attribute, "float[]", Value::FloatVec(v.clone())));
    }
    let extent = extent(&frame.position, 0.5 * largest);
    samples.push(("extent".into(), "float3[]", extent));
    samples
}

/// Name and USD type of each attribute of the `Points` prim, in the order
/// [`particle_samples`] gives them (see [`attribute_metadata`] for which are per point).
const PARTICLE_ATTRIBUTES: [(&str, &str); 9] = [
    ("points", "point3f[]"),
    ("velocities", "vector3f[]"),
    ("widths", "float[]"),
    ("ids", "int64[]"),
    ("primvars:damage", "float[]"),
    ("primvars:plastic", "float[]"),
    ("primvars:fragment", "int[]"),
    ("primvars:material", "int[]"),
    ("primvars:simulation_velocity", "vector3f[]"),
];

/// `/World/Particles`, the `Points` prim whose `attributes` the clips give.
fn particles(
    stage: &mut Layer,
    world: &str,
    attributes: &[Declared],
    velocity_scale: f32,
) -> Result<(), String> {
    let prim = stage.def(world, "Particles", "Points")?;
    declare_all(stage, &prim, attributes)?;
    stage.prim_metadata(
        &prim,
        "documentation",
        Value::String(format!(
            "velocities are m/s of playback (simulation velocity x {velocity_scale:e} = \
             playback_fps / simulation fps); primvars:simulation_velocity is m/s of \
             simulated time"
        )),
    )
}

/// One frame of `mesh` as the samples of a `Mesh` prim's attributes (see
/// [`MESH_ATTRIBUTES`]), and the number of original-surface triangles.
fn mesh_samples(mesh: &SurfaceMesh) -> (Vec<Sample>, usize) {
    let surface = mesh.surface_indices.len() / 3;
    let triangles = surface + mesh.crack_indices.len() / 3;
    let indices: Vec<i32> = mesh
        .surface_indices
        .iter()
        .chain(&mesh.crack_indices)
        .map(|&i| i as i32)
        .collect();
    // Per face: the crack flag, and the colour the looks read (see [`looks`]), an
    // indexed primvar whose indices are the flag: colour 0 the surface's, 1 the crack's.
    let crack: Vec<i32> = (0..triangles).map(|t| i32::from(t >= surface)).collect();
    let mut values = vec![
        vec3f(&mesh.positions),
        Value::IntVec(vec![3; triangles]),
        Value::IntVec(indices),
        vec3f(&mesh.normals),
        extent(&mesh.positions, 0.0),
        vec3f(&[SURFACE_LOOK.0, CRACK_LOOK.0]),
        Value::IntVec(crack.clone()),
        Value::IntVec(crack),
    ];
    if !mesh.damage.is_empty() {
        values.push(Value::FloatVec(mesh.damage.clone()));
    }
    let samples = MESH_ATTRIBUTES
        .iter()
        .zip(values)
        .map(|((name, type_name), value)| (name.to_string(), *type_name, value))
        .collect();
    (samples, surface)
}

/// Name and USD type of the time-sampled attributes of a `Mesh` prim, in the order
/// [`mesh_samples`] gives them (`primvars:damage` last: only surfaces that carry it).
/// `primvars:displayColor` and `primvars:crack` are per face (interpolation
/// `uniform`): the colour of the face's look (indexed: the two looks' colours, and
/// per face the index of its look), and 1 on crack faces, 0 on the original surface.
const MESH_ATTRIBUTES: [(&str, &str); 9] = [
    ("points", "point3f[]"),
    ("faceVertexCounts", "int[]"),
    ("faceVertexIndices", "int[]"),
    ("normals", "normal3f[]"),
    ("extent", "float3[]"),
    ("primvars:displayColor", "color3f[]"),
    ("primvars:displayColor:indices", "int[]"),
    ("primvars:crack", "int[]"),
    ("primvars:damage", "float[]"),
];

/// Defines a `Mesh` prim under `parent` whose `attributes` the clips give.
fn define_mesh(
    stage: &mut Layer,
    parent: &str,
    name: &str,
    attributes: &[Declared],
) -> Result<String, String> {
    let prim = stage.def(parent, name, "Mesh")?;
    stage.attribute(
        &prim,
        "subdivisionScheme",
        "token",
        true,
        Value::token("none"),
        vec![],
    )?;
    declare_all(stage, &prim, attributes)?;
    Ok(prim)
}

/// `/World/Surface`, the embedded method's surface with its crack faces in a
/// `GeomSubset` family bound to the crack material; `attributes` gives the
/// attributes the clips authored on a prim below `/World`.
fn embedded_surface<'a>(
    stage: &mut Layer,
    world: &str,
    attributes: &dyn Fn(&str) -> &'a [Declared],
    looks: &[String; 2],
) -> Result<usize, String> {
    let prim = define_mesh(stage, world, "Surface", attributes("Surface"))?;
    stage.attribute(
        &prim,
        "subsetFamily:materialBind:familyType",
        "token",
        true,
        Value::token("partition"),
        vec![],
    )?;
    stage.apply_schema(&prim, "MaterialBindingAPI")?;
    stage.relationship(&prim, "material:binding", &[&looks[0]])?;
    for (name, look) in ["surface", "crack"].into_iter().zip(looks) {
        let subset = stage.def(&prim, name, "GeomSubset")?;
        stage.attribute(
            &subset,
            "elementType",
            "token",
            true,
            Value::token("face"),
            vec![],
        )?;
        stage.attribute(
            &subset,
            "familyName",
            "token",
            true,
            Value::token("materialBind"),
            vec![],
        )?;
        declare_all(stage, &subset, attributes(&format!("Surface/{name}")))?;
        stage.apply_schema(&subset, "MaterialBindingAPI")?;
        stage.relationship(&subset, "material:binding", &[look])?;
    }
    Ok(1)
}

/// `/World/Fragments`, the vdb method's meshes: one `Mesh` a fragment name, whose
/// `visibility` (in `cache.usd` itself) is `invisible` in the frames that lack it.
fn fragments<'a>(
    stage: &mut Layer,
    world: &str,
    written: &[FrameSummary],
    attributes: &dyn Fn(&str) -> &'a [Declared],
    looks: &[String; 2],
) -> Result<usize, String> {
    let mut names: Vec<&String> = written.iter().flat_map(|w| &w.names).collect();
    names.sort_by_key(|a| natural(a));
    names.dedup();
    let group = stage.def(world, "Fragments", "Xform")?;
    stage.apply_schema(&group, "MaterialBindingAPI")?;
    stage.relationship(&group, "material:binding", &[&looks[0]])?;
    for name in &names {
        let id = identifier(name);
        let prim = define_mesh(stage, &group, &id, attributes(&format!("Fragments/{id}")))?;
        let visibility: Samples = written
            .iter()
            .enumerate()
            .map(|(k, w)| {
                let shown = if w.names.contains(name) {
                    "inherited"
                } else {
                    "invisible"
                };
                ((k + 1) as f64, Value::token(shown))
            })
            .collect();
        stage.animated(&prim, "visibility", "token", visibility, vec![])?;
    }
    Ok(names.len())
}

/// Sort key of a mesh name: its text without digits, then its number.
fn natural(name: &str) -> (String, u64) {
    let digits: String = name.chars().filter(char::is_ascii_digit).collect();
    let text: String = name.chars().filter(|c| !c.is_ascii_digit()).collect();
    (text, digits.parse().unwrap_or(0))
}

/// `/World/Volume`: a `Volume` whose `OpenVDBAsset` fields `surface` (level set) and
/// `v` (velocity, m/s of simulated time) point at `vdb/NNNN.vdb` frame by frame.
fn volume(stage: &mut Layer, world: &str, layout: &Layout, frames: usize) -> Result<(), String> {
    let prim = stage.def(world, "Volume", "Volume")?;
    let relative = |frame: usize| -> String {
        let path = layout.vdb(frame);
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
        format!("./vdb/{}", name.unwrap_or_default())
    };
    for (grid, data_type, class) in [("surface", "float", "levelSet"), ("v", "float3", "unknown")] {
        let field = stage.def(&prim, grid, "OpenVDBAsset")?;
        let files: Samples = (1..=frames)
            .map(|f| (f as f64, Value::AssetPath(AssetPath::new(relative(f)))))
            .collect();
        stage.animated(&field, "filePath", "asset", files, vec![])?;
        stage.attribute(
            &field,
            "fieldName",
            "token",
            false,
            Value::token(grid),
            vec![],
        )?;
        stage.attribute(
            &field,
            "fieldDataType",
            "token",
            false,
            Value::token(data_type),
            vec![],
        )?;
        stage.attribute(
            &field,
            "fieldClass",
            "token",
            false,
            Value::token(class),
            vec![],
        )?;
        stage.relationship(&prim, &format!("field:{grid}"), &[&field])?;
    }
    Ok(())
}

/// `/World/Colliders`: each collider an `Xform` at its centre in each frame
/// (`manifest.json`'s `collider_centers`, else its scene position) with its shape;
/// a mesh collider's shape is its mesh from `meshes` (`colliders/mesh_N.ply`, in
/// the collider's frame).
fn colliders(
    stage: &mut Layer,
    world: &str,
    scene: &Scene,
    manifest: &Manifest,
    meshes: &[MovingCollider],
) -> Result<usize, String> {
    if scene.colliders.is_empty() {
        return Ok(0);
    }
    let group = stage.def(world, "Colliders", "Xform")?;
    let frames = manifest.frame_times.len();
    for (i, collider) in scene.colliders.iter().enumerate() {
        let start = match collider {
            ColliderSpec::Ground { height, .. } => [0.0, *height, 0.0],
            ColliderSpec::Sphere { center, .. } | ColliderSpec::Box { center, .. } => *center,
            ColliderSpec::Mesh { translation, .. } => *translation,
        };
        let translate: Samples = manifest
            .frame_times
            .iter()
            .enumerate()
            .map(|(k, _)| {
                let c = manifest
                    .collider_centers
                    .get(k)
                    .and_then(|centres| centres.get(i))
                    .copied()
                    .unwrap_or(start);
                ((k + 1) as f64, Value::Vec3d(gf::vec3d(c[0], c[1], c[2])))
            })
            .collect();
        let name = collider_name(&scene.colliders, i);
        let xform = stage.def(&group, &name, "Xform")?;
        stage.animated(&xform, "xformOp:translate", "double3", translate, vec![])?;
        // The manifest's rotations (written when the scene has a mesh collider): a
        // mesh collider is x ↦ centre + R (x − pivot), so translate then orient.
        let mut order = vec!["xformOp:translate"];
        if !manifest.collider_rotations.is_empty() {
            let orient: Samples = (0..frames)
                .map(|k| {
                    let [x, y, z, w] = manifest
                        .collider_rotations
                        .get(k)
                        .and_then(|rotations| rotations.get(i))
                        .copied()
                        .unwrap_or([0.0, 0.0, 0.0, 1.0]);
                    ((k + 1) as f64, Value::Quatd(gf::quatd(w, x, y, z)))
                })
                .collect();
            stage.animated(&xform, "xformOp:orient", "quatd", orient, vec![])?;
            order.push("xformOp:orient");
        }
        stage.attribute(
            &xform,
            "xformOpOrder",
            "token[]",
            true,
            Value::token_vec(order),
            vec![],
        )?;
        match collider {
            ColliderSpec::Sphere { radius, .. } => {
                let shape = stage.def(&xform, &name, "Sphere")?;
                stage.attribute(
                    &shape,
                    "radius",
                    "double",
                    false,
                    Value::Double(*radius),
                    vec![],
                )?;
                let r = *radius as f32;
                stage.attribute(
                    &shape,
                    "extent",
                    "float3[]",
                    false,
                    extent(&[[0.0; 3]], r),
                    vec![],
                )?;
            }
            ColliderSpec::Box { size, .. } => {
                let shape = stage.def(&xform, &name, "Cube")?;
                stage.attribute(&shape, "size", "double", false, Value::Double(1.0), vec![])?;
                stage.attribute(
                    &shape,
                    "extent",
                    "float3[]",
                    false,
                    extent(&[[0.0; 3]], 0.5),
                    vec![],
                )?;
                stage.attribute(
                    &shape,
                    "xformOp:scale",
                    "double3",
                    false,
                    Value::Vec3d(gf::vec3d(size[0], size[1], size[2])),
                    vec![],
                )?;
                stage.attribute(
                    &shape,
                    "xformOpOrder",
                    "token[]",
                    true,
                    Value::token_vec(["xformOp:scale"]),
                    vec![],
                )?;
            }
            ColliderSpec::Mesh { .. } => {
                let Some(collider) = meshes.iter().find(|m| m.index == i) else {
                    return Err(format!("mesh collider {i} has no colliders/mesh_{i}.ply"));
                };
                let triangles = &collider.mesh.triangles;
                polygon_mesh(
                    stage,
                    &xform,
                    &name,
                    &collider.mesh.positions,
                    vec![3; triangles.len()],
                    triangles.iter().flatten().map(|&v| v as i32).collect(),
                )?;
            }
            ColliderSpec::Ground { .. } => {
                // A square 20 m on a side at the plane's height (the plane is infinite).
                let h = 10.0f32;
                let corners = [[-h, 0.0, -h], [-h, 0.0, h], [h, 0.0, h], [h, 0.0, -h]];
                polygon_mesh(stage, &xform, &name, &corners, vec![4], vec![0, 1, 2, 3])?;
            }
        }
    }
    Ok(scene.colliders.len())
}

/// The name of collider `index` of `colliders`, its `Xform` prim's and its shape's:
/// `ground` for a scene's only ground plane, else the kind and the scene index
/// (`sphere_1`, `box_2`, `ground_0`, `mesh_3`, as `colliders/mesh_3.ply`). The shape
/// child carries the name too, because importers that fold an `Xform` with a single
/// child into one object (Blender) name the object after the child.
fn collider_name(colliders: &[ColliderSpec], index: usize) -> String {
    match &colliders[index] {
        ColliderSpec::Ground { .. } => {
            let grounds = colliders
                .iter()
                .filter(|c| matches!(c, ColliderSpec::Ground { .. }))
                .count();
            match grounds {
                1 => "ground".to_string(),
                _ => format!("ground_{index}"),
            }
        }
        ColliderSpec::Sphere { .. } => format!("sphere_{index}"),
        ColliderSpec::Box { .. } => format!("box_{index}"),
        ColliderSpec::Mesh { .. } => format!("mesh_{index}"),
    }
}

/// The `Mesh` child `name` of a collider's `Xform`: polygons of `counts` corners
/// (`indices` into `positions`) in the collider's frame (the `Xform` poses them).
fn polygon_mesh(
    stage: &mut Layer,
    xform: &str,
    name: &str,
    positions: &[[f32; 3]],
    counts: Vec<i32>,
    indices: Vec<i32>,
) -> Result<(), String> {
    let shape = stage.def(xform, name, "Mesh")?;
    let values = [
        ("points", "point3f[]", vec3f(positions)),
        ("faceVertexCounts", "int[]", Value::IntVec(counts)),
        ("faceVertexIndices", "int[]", Value::IntVec(indices)),
        ("extent", "float3[]", extent(positions, 0.0)),
    ];
    for (name, type_name, value) in values {
        stage.attribute(&shape, name, type_name, false, value, vec![])?;
    }
    stage.attribute(
        &shape,
        "subdivisionScheme",
        "token",
        true,
        Value::token("none"),
        vec![],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cache of two particle frames and one collider, written by hand.
    fn small_cache(root: &std::path::Path) -> Layout {
        let layout = Layout::new(root);
        layout.create().unwrap();
        let scene = "[scene]\nname = \"t\"\nfps = 1000.0\n\n[materials.m]\ndensity = 1000.0\n\
                     bulk_modulus = 1e5\nshear_modulus = 1e5\n\n[[body]]\nmaterial = \"m\"\n\
                     resolution = 0.02\nshape = { type = \"box\", center = [0, 0, 0], size = [0.1, 0.1, 0.1] }\n\n\
                     [[collider]]\ntype = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nradius = 0.1\n\n\
                     [output]\nplayback_fps = 30\n";
        std::fs::write(layout.scene(), scene).unwrap();
        let manifest = Manifest {
            scene: "t".into(),
            fps: 1000.0,
            frame_times: vec![0.0, 0.001],
            collider_centers: vec![vec![[0.0, 1.0, 0.0]], vec![[0.0, 0.9, 0.0]]],
            collider_rotations: vec![vec![[0.0, 0.0, 0.0, 1.0]], vec![[0.6, 0.0, 0.0, 0.8]]],
            ..Manifest::default()
        };
        manifest.write(&layout.manifest()).unwrap();
        for frame in 1..=2 {
            ParticleFrame {
                frame,
                time: manifest.frame_times[frame - 1],
                position: vec![[0.0, frame as f32, 0.0], [1.0, 0.0, 0.0]],
                velocity: vec![[0.0, 3.0, 0.0], [0.0, 0.0, 0.0]],
                damage: vec![0.0, 0.5],
                plastic: vec![0.0, 0.0],
                material: vec![0.0, 0.0],
                fragment: vec![0.0, 1.0],
                extra: vec![
                    ("volume".into(), vec![1e-6, 0.0]),
                    ("quantity".into(), vec![1.0, 2.0]),
                ],
            }
            .write(&layout.particles(frame))
            .unwrap();
        }
        layout
    }

    #[test]
    fn a_small_cache_reads_back_through_the_usdc_reader() {
        let dir = tempfile::tempdir().unwrap();
        let layout = small_cache(dir.path());
        let report = write_stage(&layout).unwrap();
        assert_eq!(
            (report.frames, report.particles, report.colliders),
            (2, 2, 1)
        );
        let data = openusd::usdc::read_file(layout.usd()).unwrap();
        let root = openusd::sdf::Path::abs_root();
        let field = |path: &openusd::sdf::Path, key: &str| data.get_field(path, key).unwrap();
        assert_eq!(*field(&root, "upAxis"), Value::token("Y"));
        assert_eq!(*field(&root, "timeCodesPerSecond"), Value::Double(30.0));
        assert_eq!(*field(&root, "endTimeCode"), Value::Double(2.0));
        // Each frame's particle samples are in its clip, usd/NNNN.usdc, at its time code.
        let clips: Vec<_> = (1..=2)
            .map(|k| openusd::usdc::read_file(layout.usd_clip(k)).unwrap())
            .collect();
        let sample = |frame: usize, attribute: &str| -> Value {
            let path = openusd::sdf::Path::new(attribute).unwrap();
            let field = clips[frame - 1].get_field(&path, "timeSamples").unwrap();
            let Value::TimeSamples(samples) = field.into_owned() else {
                panic!("{attribute} is not time-sampled");
            };
            assert_eq!(samples.len(), 1, "{attribute}: one sample a clip");
            assert_eq!(
                samples[0].0, frame as f64,
                "{attribute}: at the frame's time code"
            );
            samples[0].1.clone()
        };
        assert_eq!(
            sample(2, "/World/Particles.points"),
            vec3f(&[[0.0, 2.0, 0.0], [1.0, 0.0, 0.0]])
        );
        // Velocities in m/s of playback: 3 m/s × 30 / 1000.
        assert_eq!(
            sample(1, "/World/Particles.velocities"),
            vec3f(&[[0.0, 3.0 * 0.03, 0.0], [0.0; 3]])
        );
        // Widths: the cube root of the volume (1e-6 m³ → 0.01 m), not the body's λ
        // (0.02 m), which the particle without a volume falls back to.
        let Value::FloatVec(w) = sample(1, "/World/Particles.widths") else {
            panic!("widths are not floats");
        };
        assert!((w[0] - 0.01).abs() < 1e-7 && w[1] == 0.02, "{w:?}");
        // The stage declares what the clips give, and names the clips frame by frame.
        let points = openusd::sdf::Path::new("/World/Particles.points").unwrap();
        assert_eq!(*field(&points, "typeName"), Value::token("point3f[]"));
        let world = openusd::sdf::Path::new("/World").unwrap();
        let Value::Dictionary(clips_field) = field(&world, "clips").into_owned() else {
            panic!("/World has no clips");
        };
        let Some(Value::Dictionary(set)) = clips_field.get("default") else {
            panic!("no default clip set: {clips_field:?}");
        };
        assert_eq!(
            set.get("assetPaths"),
            Some(&Value::AssetPathVec(vec![
                AssetPath::new("./usd/0001.usdc"),
                AssetPath::new("./usd/0002.usdc")
            ]))
        );
        let quantity = openusd::sdf::Path::new("/World/Particles.primvars:quantity").unwrap();
        assert!(data.has_spec(&quantity), "the extra column is a primvar");
        let sphere =
            openusd::sdf::Path::new("/World/Colliders/sphere_0.xformOp:translate").unwrap();
        let Value::TimeSamples(samples) = field(&sphere, "timeSamples").into_owned() else {
            panic!("the collider does not move");
        };
        assert_eq!(samples[1].1, Value::Vec3d(gf::vec3d(0.0, 0.9, 0.0)));
        let orient = openusd::sdf::Path::new("/World/Colliders/sphere_0.xformOp:orient").unwrap();
        let Value::TimeSamples(samples) = field(&orient, "timeSamples").into_owned() else {
            panic!("the collider's rotations are not time-sampled");
        };
        // [x, y, z, w] in the manifest, (w, x, y, z) in USD.
        assert_eq!(samples[1].1, Value::Quatd(gf::quatd(0.8, 0.6, 0.0, 0.0)));
        // The looks read the per-face colour primvar (Blender follows it per frame).
        let varname =
            openusd::sdf::Path::new("/World/Looks/crack/DisplayColor.inputs:varname").unwrap();
        assert_eq!(
            *field(&varname, "default"),
            Value::String("displayColor".into())
        );
        // The same cache gives the same bytes, the stage's and the clips'.
        let files = [layout.usd(), layout.usd_clip(1), layout.usd_clip(2)];
        let first: Vec<_> = files.iter().map(|f| std::fs::read(f).unwrap()).collect();
        write_stage(&layout).unwrap();
        for (file, bytes) in files.iter().zip(first) {
            assert_eq!(bytes, std::fs::read(file).unwrap(), "{}", file.display());
        }
        // A cache of fewer frames leaves no clip of the old export behind.
        let mut manifest = Manifest::read(&layout.manifest()).unwrap();
        manifest.frame_times.truncate(1);
        manifest.collider_centers.truncate(1);
        manifest.collider_rotations.truncate(1);
        manifest.write(&layout.manifest()).unwrap();
        write_stage(&layout).unwrap();
        assert!(layout.usd_clip(1).is_file() && !layout.usd_clip(2).exists());
    }

    #[test]
    fn a_missing_frame_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let layout = small_cache(dir.path());
        std::fs::remove_file(layout.particles(2)).unwrap();
        let err = write_stage(&layout).unwrap_err();
        assert!(err.is_bad_input());
        let text = err.to_string();
        assert!(
            text.contains("0002.ply") && text.contains("--resume"),
            "{text}"
        );
    }
}
