//! A glTF 2.0 binary (.glb) writer for triangle meshes, on `gltf-json`'s types.
//!
//! Every function takes the cache's one surface type, [`SurfaceMesh`], and [`Glb`]
//! offers them to the surface stage as its [`SurfaceEncoder`].
//!
//! [`to_glb`] writes plain meshes (the `vdb` method); [`crack_glb`] and
//! [`animated_glb`] write the `embedded` method's fractured surfaces: one mesh with a
//! "surface" and a "crack" primitive (the inside of the object, its own material)
//! sharing vertices, damage as the float attribute `_DAMAGE` (and, with
//! [`Glb::damage_colour`], as the vertex colour `COLOR_0`, which viewers multiply
//! into the base colour), and, for the animation, one morph target a frame with a
//! step-keyed weights animation (Blender imports it as one object with shape keys).
//! The animation is keyed at the playback time base: cache frame k at
//! k/[`Glb::playback_fps`] s, where Blender's glTF importer puts timeline frame k
//! (it maps t to frame t·fps; its exporter writes the same), so played from frame 1
//! cache frame k shows (k − 1)/playback_fps s in; its morph target is named `frame_NNNN`
//! (`mesh.extras.targetNames`, which Blender reads), the frames' simulation times in
//! `mesh.extras.simulation_times` and the time bases in the animation's `extras`.
//!
//! One glTF mesh (and one node, named like it) per input mesh, all in one scene.
//! Each mesh has a position accessor (with the bounds the format requires), a
//! normal accessor and a `u32` index accessor, each in its own buffer view with its
//! target (`ARRAY_BUFFER` for vertices, `ELEMENT_ARRAY_BUFFER` for indices), every
//! view starting on a 4-byte boundary, all in the file's one binary chunk. Units are
//! metres and +y is up, as in the cache and in glTF.

use gltf_json as json;
use json::validation::{Checked, USize64};
use perifrac_cache::collider::MovingCollider;
use perifrac_cache::mesh::{EncodeError, SurfaceEncoder, SurfaceMesh};
use perifrac_cache::scene::OutputSpec;

use crate::RenderError;
use crate::geometry::quantity_color;

/// The glTF binary writer as the surface stage's [`SurfaceEncoder`], with the
/// scene's `[output]` settings it needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Glb {
    /// Frames per second of playback: the animation keys cache frame k at
    /// k/`playback_fps` s, timeline frame k (`[output] playback_fps`).
    pub playback_fps: f64,
    /// Also write damage as the vertex colour `COLOR_0` (`[output] gltf_damage_colour`).
    pub damage_colour: bool,
}

impl Default for Glb {
    fn default() -> Glb {
        Glb::new(&OutputSpec::default())
    }
}

impl Glb {
    /// The writer with a scene's `[output]` settings.
    pub fn new(output: &OutputSpec) -> Glb {
        Glb {
            playback_fps: output.playback_fps,
            damage_colour: output.gltf_damage_colour,
        }
    }
}

impl SurfaceEncoder for Glb {
    fn fractured(&self, mesh: &SurfaceMesh) -> Result<Vec<u8>, EncodeError> {
        Ok(crack_glb(mesh, self)?)
    }

    fn animated(
        &self,
        mesh: &SurfaceMesh,
        times: &[f32],
        frames: &[Vec<[f32; 3]>],
        quantities: &[Vec<f32>],
        colliders: &[MovingCollider],
    ) -> Result<Vec<u8>, EncodeError> {
        Ok(animated_glb(
            mesh, times, frames, quantities, colliders, self,
        )?)
    }

    fn meshes(&self, meshes: &[SurfaceMesh]) -> Result<Vec<u8>, EncodeError> {
        Ok(to_glb(meshes)?)
    }
}

const GLB_MAGIC: &[u8; 4] = b"glTF";
const GLB_VERSION: u32 = 2;
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn invalid(message: impl Into<String>) -> RenderError {
    RenderError::Gltf(message.into())
}

/// The vertex arrays and one index list of a mesh, checked together.
struct Triangles<'a> {
    name: &'a str,
    positions: &'a [[f32; 3]],
    normals: &'a [[f32; 3]],
    indices: &'a [u32],
}

fn check(mesh: &Triangles<'_>) -> Result<(), RenderError> {
    let name = mesh.name;
    if mesh.positions.is_empty() || mesh.indices.is_empty() {
        return Err(invalid(format!("mesh '{name}' is empty")));
    }
    if mesh.normals.len() != mesh.positions.len() {
        return Err(invalid(format!(
            "mesh '{name}' has {} positions but {} normals",
            mesh.positions.len(),
            mesh.normals.len()
        )));
    }
    if mesh.indices.len() % 3 != 0 {
        return Err(invalid(format!(
            "mesh '{name}' has {} indices, not a multiple of 3",
            mesh.indices.len()
        )));
    }
    if let Some(&i) = mesh
        .indices
        .iter()
        .find(|&&i| i as usize >= mesh.positions.len())
    {
        return Err(invalid(format!(
            "mesh '{name}' has index {i} past its {} vertices",
            mesh.positions.len()
        )));
    }
    let finite = |v: &[f32; 3]| v.iter().all(|x| x.is_finite());
    if !mesh.positions.iter().all(finite) || !mesh.normals.iter().all(finite) {
        return Err(invalid(format!(
            "mesh '{name}' has a non-finite position or normal"
        )));
    }
    Ok(())
}

/// Appends `bytes` to the binary chunk at a 4-byte boundary and adds a buffer view
/// for them.
fn push_view(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    bytes: impl Iterator<Item = [u8; 4]>,
    target: json::buffer::Target,
) -> json::Index<json::buffer::View> {
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let offset = bin.len();
    for b in bytes {
        bin.extend_from_slice(&b);
    }
    root.push(json::buffer::View {
        buffer: json::Index::new(0),
        byte_length: USize64::from(bin.len() - offset),
        byte_offset: Some(USize64::from(offset)),
        byte_stride: None,
        name: None,
        target: Some(Checked::Valid(target)),
        extensions: None,
        extras: Default::default(),
    })
}

/// Appends `points` as a vertex buffer of f32 triples and adds its accessor, with
/// the bounds glTF requires of positions (and morph-target positions).
fn push_points(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    points: &[[f32; 3]],
) -> json::Index<json::Accessor> {
    use json::accessor::{ComponentType, Type};
    let view = push_view(
        root,
        bin,
        vec3_bytes(points),
        json::buffer::Target::ArrayBuffer,
    );
    root.push(accessor(
        view,
        points.len(),
        ComponentType::F32,
        Type::Vec3,
        Some(bounds(points)),
    ))
}

fn accessor(
    view: json::Index<json::buffer::View>,
    count: usize,
    component: json::accessor::ComponentType,
    type_: json::accessor::Type,
    bounds: Option<([f32; 3], [f32; 3])>,
) -> json::Accessor {
    json::Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64(0)),
        count: USize64::from(count),
        component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
        extensions: None,
        extras: Default::default(),
        type_: Checked::Valid(type_),
        min: bounds.map(|(lo, _)| json::Value::from(lo.to_vec())),
        max: bounds.map(|(_, hi)| json::Value::from(hi.to_vec())),
        name: None,
        normalized: false,
        sparse: None,
    }
}

/// Vertex colour of damage φ: white when intact, towards red when broken (it
/// multiplies the material's base colour).
pub fn damage_colour(phi: f32) -> [f32; 3] {
    let d = phi.clamp(0.0, 1.0);
    [1.0, 1.0 - 0.8 * d, 1.0 - 0.9 * d]
}

fn bounds(v: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in v {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

fn vec3_bytes(v: &[[f32; 3]]) -> impl Iterator<Item = [u8; 4]> + '_ {
    v.iter().flat_map(|p| p.map(f32::to_le_bytes))
}

fn check_crack(s: &SurfaceMesh) -> Result<(), RenderError> {
    let n = s.positions.len();
    for (what, len) in [
        ("normals", s.normals.len()),
        ("damage values", s.damage.len()),
    ] {
        if len != n {
            return Err(invalid(format!(
                "mesh '{}' has {n} positions but {len} {what}",
                s.name
            )));
        }
    }
    if !s.quantity.is_empty() {
        if s.quantity.len() != n {
            return Err(invalid(format!(
                "mesh '{}' has {n} positions but {} quantity values",
                s.name,
                s.quantity.len()
            )));
        }
        let [lo, hi] = s.quantity_range;
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(invalid(format!(
                "mesh '{}': the quantity's colour range [{lo}, {hi}] is not a finite interval",
                s.name
            )));
        }
    }
    for (what, list) in [
        ("surface", s.surface_indices.as_slice()),
        ("crack", s.crack_indices.as_slice()),
    ] {
        check(&Triangles {
            name: &format!("{} ({what})", s.name),
            positions: &s.positions,
            normals: &s.normals,
            indices: if list.is_empty() { &[0, 0, 0] } else { list },
        })
        .map_err(|e| match n {
            0 => invalid(format!("mesh '{}' is empty", s.name)),
            _ => e,
        })?;
    }
    if s.surface_indices.is_empty() && s.crack_indices.is_empty() {
        return Err(invalid(format!("mesh '{}' has no triangles", s.name)));
    }
    Ok(())
}

fn material(name: &str, colour: [f32; 4], roughness: f32) -> json::Material {
    json::Material {
        name: Some(name.to_string()),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(colour),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(roughness),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The vertex colours `COLOR_0` of a fractured surface, if it gets any: damage
/// ([`damage_colour`]) when [`Glb::damage_colour`] asks for it, else the quantity θ
/// on the map [`quantity_color`] over the mesh's `quantity_range` when it carries
/// one.
fn vertex_colours(s: &SurfaceMesh, options: &Glb) -> Option<Vec<[f32; 3]>> {
    if options.damage_colour {
        Some(s.damage.iter().map(|&d| damage_colour(d)).collect())
    } else if !s.quantity.is_empty() {
        Some(
            s.quantity
                .iter()
                .map(|&q| quantity_color(q, s.quantity_range))
                .collect(),
        )
    } else {
        None
    }
}

/// One frame of an animated surface as a morph target: its deltas from the base
/// mesh in position, and in colour and θ when the mesh carries θ.
struct MorphFrame {
    positions: Vec<[f32; 3]>,
    colours: Option<Vec<[f32; 3]>>,
    quantity: Option<Vec<f32>>,
}

/// Appends `values` as a vertex buffer of f32 scalars and adds its accessor.
fn push_scalars(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    values: &[f32],
) -> json::Index<json::Accessor> {
    use json::accessor::{ComponentType, Type};
    let view = push_view(
        root,
        bin,
        values.iter().map(|v| v.to_le_bytes()),
        json::buffer::Target::ArrayBuffer,
    );
    root.push(accessor(
        view,
        values.len(),
        ComponentType::F32,
        Type::Scalar,
        None,
    ))
}

/// Appends `values` as a vertex buffer of f32 triples (no bounds) and adds its
/// accessor.
fn push_vectors(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    values: &[[f32; 3]],
) -> json::Index<json::Accessor> {
    use json::accessor::{ComponentType, Type};
    let view = push_view(
        root,
        bin,
        vec3_bytes(values),
        json::buffer::Target::ArrayBuffer,
    );
    root.push(accessor(
        view,
        values.len(),
        ComponentType::F32,
        Type::Vec3,
        None,
    ))
}

/// Writes the mesh, node and scene of a fractured surface, with `targets` morph
/// targets when given and the mesh's `extras` (to which the quantity's colour map and
/// range are added when it carries θ); returns the node and the morph-target
/// attributes [`finish`] must add.
fn push_crack_surface(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    s: &SurfaceMesh,
    targets: &[MorphFrame],
    options: &Glb,
    extras: Option<serde_json::Value>,
) -> (json::Index<json::Node>, Vec<TargetPatch>) {
    use json::accessor::{ComponentType, Type};
    use json::buffer::Target;
    use json::mesh::Semantic;

    let positions = push_points(root, bin, &s.positions);
    let normals = push_vectors(root, bin, &s.normals);
    let colours = vertex_colours(s, options).map(|c| push_vectors(root, bin, &c));
    let damage = push_scalars(root, bin, &s.damage);
    let quantity = (!s.quantity.is_empty()).then(|| push_scalars(root, bin, &s.quantity));
    let mut extra_attributes = Vec::new();
    let morph: Vec<json::mesh::MorphTarget> = targets
        .iter()
        .enumerate()
        .map(|(k, frame)| {
            let positions = push_points(root, bin, &frame.positions);
            if let Some(c) = &frame.colours {
                extra_attributes.push((k, "COLOR_0", push_vectors(root, bin, c)));
            }
            if let Some(q) = &frame.quantity {
                extra_attributes.push((k, "_QUANTITY", push_scalars(root, bin, q)));
            }
            json::mesh::MorphTarget {
                positions: Some(positions),
                normals: None,
                tangents: None,
            }
        })
        .collect();
    let surface_material = root.push(material("surface", [0.8, 0.8, 0.78, 1.0], 0.5));
    let crack_material = root.push(material("crack", [0.85, 0.45, 0.3, 1.0], 0.9));
    let mut primitives = Vec::new();
    for (list, mat) in [
        (&s.surface_indices, surface_material),
        (&s.crack_indices, crack_material),
    ] {
        if list.is_empty() {
            continue;
        }
        let view = push_view(
            root,
            bin,
            list.iter().map(|i| i.to_le_bytes()),
            Target::ElementArrayBuffer,
        );
        let indices = root.push(accessor(
            view,
            list.len(),
            ComponentType::U32,
            Type::Scalar,
            None,
        ));
        primitives.push(json::mesh::Primitive {
            attributes: [
                (Checked::Valid(Semantic::Positions), Some(positions)),
                (Checked::Valid(Semantic::Normals), Some(normals)),
                (Checked::Valid(Semantic::Colors(0)), colours),
                (
                    Checked::Valid(Semantic::Extras("DAMAGE".into())),
                    Some(damage),
                ),
                (
                    Checked::Valid(Semantic::Extras("QUANTITY".into())),
                    quantity,
                ),
            ]
            .into_iter()
            .filter_map(|(semantic, accessor)| Some((semantic, accessor?)))
            .collect(),
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: Some(mat),
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets: (!morph.is_empty()).then(|| morph.clone()),
        });
    }
    let mut extras = extras.unwrap_or_else(|| serde_json::json!({}));
    if !s.quantity.is_empty() {
        extras["quantity"] = serde_json::json!({
            "attribute": "_QUANTITY",
            "colour": if options.damage_colour { "none (COLOR_0 is damage)" } else { "COLOR_0" },
            "colour_map": "viridis-like, linear RGB: dark purple at range[0], yellow at range[1], clamped",
            "range": s.quantity_range,
            "range_is": "the smallest and largest θ over every frame of the run, the same in every file",
        });
    }
    let mesh = root.push(json::Mesh {
        extensions: None,
        extras: extras
            .as_object()
            .is_some_and(|o| !o.is_empty())
            .then(|| serde_json::value::to_raw_value(&extras).ok())
            .flatten(),
        name: Some(s.name.to_string()),
        primitives,
        weights: (!targets.is_empty()).then(|| vec![0.0; targets.len()]),
    });
    let patches = extra_attributes
        .into_iter()
        .map(|(target, name, accessor)| TargetPatch {
            mesh: mesh.value(),
            target,
            name,
            accessor: accessor.value(),
        })
        .collect();
    let node = root.push(json::Node {
        mesh: Some(mesh),
        name: Some(s.name.to_string()),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);
    (node, patches)
}

/// A morph-target attribute that gltf-json's `MorphTarget` has no field for (it
/// names POSITION, NORMAL and TANGENT only): `name` → `accessor` in target `target`
/// of every primitive of mesh `mesh`, added to the JSON by [`finish`].
struct TargetPatch {
    mesh: usize,
    target: usize,
    name: &'static str,
    accessor: usize,
}

/// Encodes a fractured surface as a .glb file (one mesh, two materials).
pub fn crack_glb(surface: &SurfaceMesh, options: &Glb) -> Result<Vec<u8>, RenderError> {
    check_crack(surface)?;
    let mut root = new_root();
    let mut bin = Vec::new();
    push_crack_surface(&mut root, &mut bin, surface, &[], options, None);
    finish(root, bin, &[])
}

/// Encodes a fractured surface animated by morph targets: `frames[k]` are the
/// vertex positions of cache frame k + 1, at simulation time `times[k]` (s), one
/// morph target each (its deltas from `surface.positions`, named `frame_NNNN` in
/// `mesh.extras.targetNames`), and a step-interpolated weights animation that shows
/// target k alone from playback time (k + 1)/`options.playback_fps` on (cache frame
/// k + 1 on timeline frame k + 1). The simulation
/// times go to `mesh.extras.simulation_times`.
///
/// When the surface carries θ, `quantities[k]` is its θ in cache frame k + 1 and
/// each target also holds the frame's deltas of `COLOR_0` and `_QUANTITY` from the
/// base mesh's (glTF 2.0 §3.7.2.2: clients MAY morph `COLOR_n`; a viewer that does —
/// three.js — plays the colours with the motion, one that does not — Blender's
/// importer, which makes shape keys of positions only — shows the base mesh's colours
/// throughout; `surface/NNNN.glb` has each frame's own).
///
/// Each of `colliders` is a mesh (its triangles in its own frame, material
/// "collider", no normals: viewers shade it flat) on a node named like it whose
/// translation and rotation are keyed at the same times, linearly (slerp for the
/// rotation), from the collider's pose at each frame.
pub fn animated_glb(
    surface: &SurfaceMesh,
    times: &[f32],
    frames: &[Vec<[f32; 3]>],
    quantities: &[Vec<f32>],
    colliders: &[MovingCollider],
    options: &Glb,
) -> Result<Vec<u8>, RenderError> {
    use json::accessor::{ComponentType, Type};

    check_crack(surface)?;
    let n = frames.len();
    if n == 0 || times.len() != n {
        return Err(invalid(format!(
            "mesh '{}': {} frames and {} times (at least one frame, one time each)",
            surface.name,
            n,
            times.len()
        )));
    }
    if !times.iter().all(|t| t.is_finite()) || times.windows(2).any(|w| w[1] <= w[0]) {
        return Err(invalid(format!(
            "mesh '{}': frame times must be finite and increasing",
            surface.name
        )));
    }
    if !(options.playback_fps.is_finite() && options.playback_fps > 0.0) {
        return Err(invalid(format!(
            "mesh '{}': playback_fps must be a positive finite number, got {}",
            surface.name, options.playback_fps
        )));
    }
    let base = &surface.positions;
    let mut targets = Vec::with_capacity(n);
    for (k, frame) in frames.iter().enumerate() {
        if frame.len() != base.len() || !frame.iter().flatten().all(|x| x.is_finite()) {
            return Err(invalid(format!(
                "mesh '{}': frame {} has {} positions (or non-finite ones), the mesh {}",
                surface.name,
                k + 1,
                frame.len(),
                base.len()
            )));
        }
        let quantity = match (surface.quantity.is_empty(), quantities.get(k)) {
            (true, _) => None,
            (false, Some(q)) if q.len() == base.len() && q.iter().all(|x| x.is_finite()) => Some(q),
            (false, q) => {
                return Err(invalid(format!(
                    "mesh '{}': frame {} has {} quantity values (or non-finite ones), the mesh {}",
                    surface.name,
                    k + 1,
                    q.map_or(0, Vec::len),
                    base.len()
                )));
            }
        };
        targets.push(MorphFrame {
            positions: frame
                .iter()
                .zip(base)
                .map(|(p, b)| [p[0] - b[0], p[1] - b[1], p[2] - b[2]])
                .collect(),
            // COLOR_0 is θ unless damage took it (whose frames are not animated).
            colours: quantity.filter(|_| !options.damage_colour).map(|q| {
                let range = surface.quantity_range;
                q.iter()
                    .zip(&surface.quantity)
                    .map(|(&q, &b)| {
                        let (c, b) = (quantity_color(q, range), quantity_color(b, range));
                        [c[0] - b[0], c[1] - b[1], c[2] - b[2]]
                    })
                    .collect()
            }),
            quantity: quantity.map(|q| {
                q.iter()
                    .zip(&surface.quantity)
                    .map(|(q, b)| q - b)
                    .collect()
            }),
        });
    }
    let mut root = new_root();
    let mut bin = Vec::new();
    let extras = serde_json::json!({
        "targetNames": (1..=n).map(|frame| format!("frame_{frame:04}")).collect::<Vec<_>>(),
        "simulation_times": times,
    });
    let (node, patches) = push_crack_surface(
        &mut root,
        &mut bin,
        surface,
        &targets,
        options,
        Some(extras),
    );
    drop(targets);
    // Keyframes at the playback time base, cache frame k at k/playback_fps s (timeline
    // frame k), and one-hot weights (target k at key k).
    let playback: Vec<f32> = (1..=n)
        .map(|frame| (frame as f64 / options.playback_fps) as f32)
        .collect();
    let view = push_view_plain(
        &mut root,
        &mut bin,
        playback.iter().map(|t| t.to_le_bytes()),
    );
    let mut input = accessor(view, n, ComponentType::F32, Type::Scalar, None);
    input.min = Some(json::Value::from(vec![playback[0]]));
    input.max = Some(json::Value::from(vec![playback[n - 1]]));
    let input = root.push(input);
    let weights = (0..n * n).map(|i| if i / n == i % n { 1.0f32 } else { 0.0 });
    let view = push_view_plain(&mut root, &mut bin, weights.map(|w| w.to_le_bytes()));
    let output = root.push(accessor(
        view,
        n * n,
        ComponentType::F32,
        Type::Scalar,
        None,
    ));
    let animation_extras = serde_json::json!({
        "playback_fps": options.playback_fps,
        "time_base": "cache frame k (from 1) is keyed at k / playback_fps s, timeline \
                      frame k; its simulation time is mesh.extras.simulation_times[k - 1]",
    });
    let mut channels = vec![(
        node,
        json::animation::Property::MorphTargetWeights,
        json::animation::Interpolation::Step,
        output,
    )];
    for collider in colliders {
        channels.extend(push_collider(&mut root, &mut bin, collider, n)?);
    }
    let (channels, samplers) = channels
        .into_iter()
        .enumerate()
        .map(|(c, (node, property, interpolation, output))| {
            let channel = json::animation::Channel {
                sampler: json::Index::new(c as u32),
                target: json::animation::Target {
                    extensions: None,
                    extras: Default::default(),
                    node,
                    path: Checked::Valid(property),
                },
                extensions: None,
                extras: Default::default(),
            };
            let sampler = json::animation::Sampler {
                extensions: None,
                extras: Default::default(),
                input,
                interpolation: Checked::Valid(interpolation),
                output,
            };
            (channel, sampler)
        })
        .unzip();
    root.push(json::Animation {
        extensions: None,
        extras: serde_json::value::to_raw_value(&animation_extras).ok(),
        channels,
        name: Some("frames".into()),
        samplers,
    });
    finish(root, bin, &patches)
}

/// An animation channel's node, property, interpolation and output accessor.
type Channel = (
    json::Index<json::Node>,
    json::animation::Property,
    json::animation::Interpolation,
    json::Index<json::Accessor>,
);

/// Writes a mesh collider's mesh and node (added to the scene) at its pose of frame
/// 1, and the outputs of its translation and rotation over `frames` frames; returns
/// the two animation channels.
fn push_collider(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    collider: &MovingCollider,
    frames: usize,
) -> Result<[Channel; 2], RenderError> {
    use json::accessor::{ComponentType, Type};
    use json::animation::{Interpolation, Property};
    use json::buffer::Target;

    let mesh = &collider.mesh;
    let name = &collider.name;
    let count = mesh.positions.len();
    if mesh.triangles.is_empty() || !mesh.positions.iter().flatten().all(|x| x.is_finite()) {
        return Err(invalid(format!(
            "collider '{name}' has no triangles or a non-finite position"
        )));
    }
    if let Some(&i) = mesh
        .triangles
        .iter()
        .flatten()
        .find(|&&i| i as usize >= count)
    {
        return Err(invalid(format!(
            "collider '{name}' has index {i} past its {count} vertices"
        )));
    }
    let poses: Vec<([f64; 3], [f64; 4])> = (1..=frames).map(|k| collider.pose(k)).collect();
    if !poses
        .iter()
        .all(|(c, r)| c.iter().chain(r).all(|x| x.is_finite()))
    {
        return Err(invalid(format!("collider '{name}' has a non-finite pose")));
    }
    let positions = push_points(root, bin, &mesh.positions);
    let view = push_view(
        root,
        bin,
        mesh.triangles.iter().flatten().map(|i| i.to_le_bytes()),
        Target::ElementArrayBuffer,
    );
    let indices = root.push(accessor(
        view,
        3 * mesh.triangles.len(),
        ComponentType::U32,
        Type::Scalar,
        None,
    ));
    let material = root.push(material("collider", [0.36, 0.40, 0.46, 1.0], 0.4));
    let gltf_mesh = root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some(name.clone()),
        primitives: vec![json::mesh::Primitive {
            attributes: [(Checked::Valid(json::mesh::Semantic::Positions), positions)]
                .into_iter()
                .collect(),
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: Some(material),
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets: None,
        }],
        weights: None,
    });
    let translations: Vec<[f32; 3]> = poses.iter().map(|(c, _)| c.map(|x| x as f32)).collect();
    let rotations: Vec<[f32; 4]> = poses.iter().map(|(_, r)| r.map(|x| x as f32)).collect();
    let node = root.push(json::Node {
        mesh: Some(gltf_mesh),
        name: Some(name.clone()),
        translation: Some(translations[0]),
        rotation: Some(json::scene::UnitQuaternion(rotations[0])),
        ..Default::default()
    });
    if let Some(scene) = root.scenes.first_mut() {
        scene.nodes.push(node);
    }
    let view = push_view_plain(root, bin, vec3_bytes(&translations));
    let translation = root.push(accessor(view, frames, ComponentType::F32, Type::Vec3, None));
    let view = push_view_plain(
        root,
        bin,
        rotations.iter().flat_map(|q| q.map(f32::to_le_bytes)),
    );
    let rotation = root.push(accessor(view, frames, ComponentType::F32, Type::Vec4, None));
    Ok([
        (
            node,
            Property::Translation,
            Interpolation::Linear,
            translation,
        ),
        (node, Property::Rotation, Interpolation::Linear, rotation),
    ])
}

/// A buffer view without a target (animation data), at a 4-byte boundary.
fn push_view_plain(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    bytes: impl Iterator<Item = [u8; 4]>,
) -> json::Index<json::buffer::View> {
    let view = push_view(root, bin, bytes, json::buffer::Target::ArrayBuffer);
    if let Some(v) = root.buffer_views.last_mut() {
        v.target = None;
    }
    view
}

fn new_root() -> json::Root {
    json::Root {
        asset: json::Asset {
            generator: Some(format!("perifrac {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Adds the buffer and packs the JSON and binary chunks into a .glb.
fn finish(
    mut root: json::Root,
    mut bin: Vec<u8>,
    patches: &[TargetPatch],
) -> Result<Vec<u8>, RenderError> {
    if !bin.is_empty() {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        root.push(json::Buffer {
            byte_length: USize64::from(bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
    }
    let encode = |e: serde_json::Error| invalid(format!("could not encode the JSON chunk: {e}"));
    let mut text = if patches.is_empty() {
        root.to_vec().map_err(encode)?
    } else {
        let mut doc = serde_json::to_value(&root).map_err(encode)?;
        for p in patches {
            let primitives = doc["meshes"][p.mesh]["primitives"].as_array_mut();
            for primitive in primitives.into_iter().flatten() {
                primitive["targets"][p.target][p.name] = serde_json::json!(p.accessor);
            }
        }
        serde_json::to_vec(&doc).map_err(encode)?
    };
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let total = u32::try_from(total)
        .map_err(|_| invalid(format!("{total} bytes is over the 4 GiB a .glb can hold")))?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(GLB_MAGIC);
    out.extend_from_slice(&GLB_VERSION.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    Ok(out)
}

/// Encodes meshes as a .glb file (an asset with no scene when `meshes` is empty):
/// one primitive a mesh, of its original-surface then its crack triangles, without
/// materials; a mesh's damage, when it has any, as the float attribute `_DAMAGE`.
pub fn to_glb(meshes: &[SurfaceMesh]) -> Result<Vec<u8>, RenderError> {
    use json::accessor::{ComponentType, Type};
    use json::buffer::Target;

    let mut root = new_root();
    let mut bin: Vec<u8> = Vec::new();
    let mut nodes = Vec::with_capacity(meshes.len());
    for surface in meshes {
        let all: Vec<u32>;
        let indices = if surface.crack_indices.is_empty() {
            &surface.surface_indices
        } else {
            all = [surface.surface_indices.as_slice(), &surface.crack_indices].concat();
            &all
        };
        let mesh = Triangles {
            name: &surface.name,
            positions: &surface.positions,
            normals: &surface.normals,
            indices,
        };
        check(&mesh)?;
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in mesh.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let floats = |v: &'_ [[f32; 3]]| {
            v.iter()
                .flat_map(|p| p.iter().map(|x| x.to_le_bytes()).collect::<Vec<_>>())
                .collect::<Vec<_>>()
        };
        let count = mesh.positions.len();
        let view = push_view(
            &mut root,
            &mut bin,
            floats(mesh.positions).into_iter(),
            Target::ArrayBuffer,
        );
        let positions = root.push(accessor(
            view,
            count,
            ComponentType::F32,
            Type::Vec3,
            Some((lo, hi)),
        ));
        let view = push_view(
            &mut root,
            &mut bin,
            floats(mesh.normals).into_iter(),
            Target::ArrayBuffer,
        );
        let normals = root.push(accessor(view, count, ComponentType::F32, Type::Vec3, None));
        let view = push_view(
            &mut root,
            &mut bin,
            mesh.indices.iter().map(|i| i.to_le_bytes()),
            Target::ElementArrayBuffer,
        );
        let indices = root.push(accessor(
            view,
            mesh.indices.len(),
            ComponentType::U32,
            Type::Scalar,
            None,
        ));
        let damage = if surface.damage.is_empty() {
            None
        } else if surface.damage.len() == count {
            Some(push_scalars(&mut root, &mut bin, &surface.damage))
        } else {
            return Err(invalid(format!(
                "mesh '{}' has {count} positions but {} damage values",
                surface.name,
                surface.damage.len()
            )));
        };
        let primitive = json::mesh::Primitive {
            attributes: [
                (
                    Checked::Valid(json::mesh::Semantic::Positions),
                    Some(positions),
                ),
                (Checked::Valid(json::mesh::Semantic::Normals), Some(normals)),
                (
                    Checked::Valid(json::mesh::Semantic::Extras("DAMAGE".into())),
                    damage,
                ),
            ]
            .into_iter()
            .filter_map(|(semantic, accessor)| Some((semantic, accessor?)))
            .collect(),
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: None,
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets: None,
        };
        let gltf_mesh = root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(mesh.name.to_string()),
            primitives: vec![primitive],
            weights: None,
        });
        nodes.push(root.push(json::Node {
            mesh: Some(gltf_mesh),
            name: Some(mesh.name.to_string()),
            ..Default::default()
        }));
    }
    if !nodes.is_empty() {
        let scene = root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes,
        });
        root.scene = Some(scene);
    }
    finish(root, bin, &[])
}

#[cfg(test)]
mod tests {
    use super::*;

    use std::path::Path;
    use std::process::Command;

    /// A tetrahedron, counter-clockwise from outside, with face-averaged normals.
    fn tetrahedron() -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let n = p
            .iter()
            .map(|q: &[f32; 3]| {
                let c = [q[0] - 0.25, q[1] - 0.25, q[2] - 0.25];
                let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
                [c[0] / l, c[1] / l, c[2] / l]
            })
            .collect();
        (p, n, vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3])
    }

    /// Runs the Khronos validator (tools/gltf-validator, installed by scripts/setup.sh)
    /// and returns its report.
    fn validate(file: &Path) -> serde_json::Value {
        let script =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/gltf-validator/validate.mjs");
        let out = Command::new("node")
            .arg(&script)
            .arg(file)
            .output()
            .expect("node runs (scripts/setup.sh installs it and the validator)");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            !stdout.trim().is_empty(),
            "the validator printed nothing: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_str(stdout.trim()).expect("a JSON report")
    }

    #[test]
    fn layout_of_the_binary() {
        let (p, n, i) = tetrahedron();
        let glb = to_glb(&[plain("tet", &p, &n, &i)]).expect("valid mesh");
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(
            u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize,
            glb.len()
        );
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        assert_eq!(json_len % 4, 0);
        let doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
        assert_eq!(
            doc["accessors"][0]["min"],
            serde_json::json!([0.0, 0.0, 0.0])
        );
        assert_eq!(
            doc["accessors"][0]["max"],
            serde_json::json!([1.0, 1.0, 1.0])
        );
        assert_eq!(doc["bufferViews"][2]["target"], 34963);
        for view in doc["bufferViews"].as_array().unwrap() {
            assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0);
        }
        let bin_len = u32::from_le_bytes(glb[20 + json_len..24 + json_len].try_into().unwrap());
        assert_eq!(doc["buffers"][0]["byteLength"], bin_len);
    }

    #[test]
    fn bad_input_is_an_error() {
        let (p, n, mut i) = tetrahedron();
        i[0] = 9;
        let err = to_glb(&[plain("bad", &p, &n, &i)]).unwrap_err();
        assert!(err.to_string().contains("index 9"), "{err}");
        let err = to_glb(&[plain("short", &p, &n[..2], &i)]).unwrap_err();
        assert!(err.to_string().contains("normals"), "{err}");
        let (p, n, i) = tetrahedron();
        let short = SurfaceMesh {
            damage: vec![0.5; 3],
            ..plain("short damage", &p, &n, &i)
        };
        let err = to_glb(&[short]).unwrap_err();
        assert!(err.to_string().contains("3 damage values"), "{err}");
    }

    #[test]
    fn the_khronos_validator_finds_no_errors() {
        let dir = tempfile::tempdir().unwrap();
        let (p, n, i) = tetrahedron();
        // Two meshes, so that the second's views start after the first's; the second
        // with damage, as the vdb method's meshes carry it.
        let damaged = SurfaceMesh {
            damage: vec![0.0, 0.5, 1.0, 0.25],
            ..plain("tet", &p, &n, &i)
        };
        let glb = to_glb(&[plain("one triangle", &p[..3], &n[..3], &i[..3]), damaged]).unwrap();
        let file = dir.path().join("tet.glb");
        std::fs::write(&file, glb).unwrap();
        let report = validate(&file);
        assert_eq!(report["numErrors"], 0, "{report:#}");
        let empty = dir.path().join("empty.glb");
        std::fs::write(&empty, to_glb(&[]).unwrap()).unwrap();
        let report = validate(&empty);
        assert_eq!(report["numErrors"], 0, "{report:#}");
    }

    /// A mesh of original-surface triangles only.
    fn plain(name: &str, p: &[[f32; 3]], n: &[[f32; 3]], i: &[u32]) -> SurfaceMesh {
        SurfaceMesh {
            name: name.into(),
            positions: p.to_vec(),
            normals: n.to_vec(),
            surface_indices: i.to_vec(),
            ..SurfaceMesh::default()
        }
    }

    fn crack_tet(p: &[[f32; 3]], n: &[[f32; 3]], d: &[f32], i: &[u32]) -> SurfaceMesh {
        SurfaceMesh {
            name: "tet".into(),
            positions: p.to_vec(),
            normals: n.to_vec(),
            damage: d.to_vec(),
            surface_indices: i[..9].to_vec(),
            crack_indices: i[9..].to_vec(),
            ..SurfaceMesh::default()
        }
    }

    /// Reads accessor `index` of a .glb as f32 scalars.
    fn floats(glb: &[u8], doc: &serde_json::Value, index: u64) -> Vec<f32> {
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let bin = &glb[20 + json_len + 8..];
        let acc = &doc["accessors"][index as usize];
        let view = &doc["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap() as usize;
        let components = if acc["type"] == "VEC3" { 3 } else { 1 };
        (0..components * acc["count"].as_u64().unwrap() as usize)
            .map(|k| f32::from_le_bytes(bin[start + 4 * k..start + 4 * k + 4].try_into().unwrap()))
            .collect()
    }

    #[test]
    fn the_quantity_is_an_attribute_a_colour_and_animated_targets() {
        let dir = tempfile::tempdir().unwrap();
        let (p, n, i) = tetrahedron();
        let s = SurfaceMesh {
            quantity: vec![0.0, 1.0, 2.0, 3.0],
            quantity_range: [0.0, 4.0],
            ..crack_tet(&p, &n, &[0.0; 4], &i)
        };
        let glb = crack_glb(&s, &Glb::default()).unwrap();
        let doc = json_chunk(&glb);
        let attributes = &doc["meshes"][0]["primitives"][0]["attributes"];
        assert_eq!(
            floats(&glb, &doc, attributes["_QUANTITY"].as_u64().unwrap()),
            s.quantity
        );
        let colours = floats(&glb, &doc, attributes["COLOR_0"].as_u64().unwrap());
        // θ = 0 is the map's dark end, θ = 3 of [0, 4] three quarters up it: the
        // colours follow the documented map over the declared range, not the mesh's own.
        assert_eq!(colours[..3], quantity_color(0.0, [0.0, 4.0]));
        assert_eq!(colours[9..], quantity_color(3.0, [0.0, 4.0]));
        assert!(
            colours[9] > colours[0] && colours[10] > colours[1],
            "{colours:?}"
        );
        assert_eq!(
            doc["meshes"][0]["extras"]["quantity"]["range"],
            serde_json::json!([0.0, 4.0])
        );
        let file = dir.path().join("frame.glb");
        std::fs::write(&file, &glb).unwrap();
        let report = validate(&file);
        assert_eq!(report["numErrors"], 0, "{report:#}");

        // Three frames in which θ rises by 1 a frame: each target's deltas take the
        // base colour and θ to the frame's own.
        let frames: Vec<Vec<[f32; 3]>> = (0..3).map(|_| p.clone()).collect();
        let quantities: Vec<Vec<f32>> = (0..3)
            .map(|k| s.quantity.iter().map(|q| (q + k as f32).min(4.0)).collect())
            .collect();
        let glb = animated_glb(
            &s,
            &[0.0, 0.1, 0.2],
            &frames,
            &quantities,
            &[],
            &Glb::default(),
        )
        .unwrap();
        let doc = json_chunk(&glb);
        let target = &doc["meshes"][0]["primitives"][1]["targets"][2];
        let dq = floats(&glb, &doc, target["_QUANTITY"].as_u64().unwrap());
        assert_eq!(dq, [2.0, 2.0, 2.0, 1.0]);
        let dc = floats(&glb, &doc, target["COLOR_0"].as_u64().unwrap());
        let expected = quantity_color(4.0, [0.0, 4.0]);
        assert!((0..3).all(|k| (colours[9 + k] + dc[9 + k] - expected[k]).abs() < 1e-6));
        std::fs::write(&file, &glb).unwrap();
        let report = validate(&file);
        assert_eq!(report["numErrors"], 0, "{report:#}");
        assert_eq!(report["numWarnings"], 0, "{report:#}");

        // Damage asked for as COLOR_0 takes the colour; θ stays an attribute.
        let coloured = Glb {
            damage_colour: true,
            ..Glb::default()
        };
        let glb = animated_glb(&s, &[0.0, 0.1, 0.2], &frames, &quantities, &[], &coloured);
        let doc = json_chunk(&glb.unwrap());
        let target = &doc["meshes"][0]["primitives"][0]["targets"][2];
        assert!(target.get("COLOR_0").is_none() && target["_QUANTITY"].is_u64());
        let short = animated_glb(
            &s,
            &[0.0, 0.1, 0.2],
            &frames,
            &quantities[..2],
            &[],
            &coloured,
        );
        assert!(
            short
                .unwrap_err()
                .to_string()
                .contains("frame 3 has 0 quantity values")
        );
    }

    #[test]
    fn animated_crack_surface_passes_the_validator() {
        let dir = tempfile::tempdir().unwrap();
        let (p, n, i) = tetrahedron();
        let d = [0.0, 0.5, 1.0, 0.25];
        let s = crack_tet(&p, &n, &d, &i);
        let frames: Vec<Vec<[f32; 3]>> = (0..3)
            .map(|k| p.iter().map(|q| [q[0] + k as f32, q[1], q[2]]).collect())
            .collect();
        let file = dir.path().join("animated.glb");
        std::fs::write(
            &file,
            animated_glb(&s, &[0.0, 1e-4, 2e-4], &frames, &[], &[], &Glb::default()).unwrap(),
        )
        .unwrap();
        let report = validate(&file);
        assert_eq!(report["numErrors"], 0, "{report:#}");
        // With a mesh collider turning and moving beside it.
        let table = table();
        let glb = animated_glb(
            &s,
            &[0.0, 1e-4, 2e-4],
            &frames,
            &[],
            &[table],
            &Glb::default(),
        );
        std::fs::write(&file, glb.unwrap()).unwrap();
        let report = validate(&file);
        assert_eq!(report["numErrors"], 0, "{report:#}");
        let file = dir.path().join("frame.glb");
        std::fs::write(&file, crack_glb(&s, &Glb::default()).unwrap()).unwrap();
        let report = validate(&file);
        assert_eq!(report["numErrors"], 0, "{report:#}");
        let options = Glb {
            damage_colour: true,
            ..Glb::default()
        };
        std::fs::write(&file, crack_glb(&s, &options).unwrap()).unwrap();
        let report = validate(&file);
        assert_eq!(report["numErrors"], 0, "{report:#}");
    }

    /// A tetrahedron collider that moves along x and turns about y over three frames.
    fn table() -> MovingCollider {
        let (p, _, i) = tetrahedron();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        MovingCollider {
            index: 1,
            name: "mesh_1".into(),
            mesh: perifrac_cache::collider::ColliderMesh {
                positions: p,
                triangles: i.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
                pivot: [0.0, 0.3, 0.0],
            },
            centers: vec![[0.0, 0.3, 0.0], [0.1, 0.3, 0.0], [0.2, 0.3, 0.0]],
            rotations: vec![
                [0.0, 0.0, 0.0, 1.0],
                [0.0, 0.38268343236508984, 0.0, 0.9238795325112867],
                [0.0, h, 0.0, h],
            ],
        }
    }

    #[test]
    fn a_mesh_collider_is_a_node_keyed_at_each_frame() {
        let (p, n, i) = tetrahedron();
        let s = crack_tet(&p, &n, &[0.0; 4], &i);
        let frames: Vec<Vec<[f32; 3]>> = (0..3).map(|_| p.clone()).collect();
        let glb = animated_glb(
            &s,
            &[0.0, 1e-4, 2e-4],
            &frames,
            &[],
            &[table()],
            &Glb::default(),
        );
        let doc = json_chunk(&glb.unwrap());
        assert_eq!(doc["scenes"][0]["nodes"], serde_json::json!([0, 1]));
        let node = &doc["nodes"][1];
        assert_eq!(node["name"], "mesh_1");
        assert_eq!(node["translation"][1].as_f64().unwrap() as f32, 0.3);
        let primitive = &doc["meshes"][1]["primitives"][0];
        assert!(primitive["attributes"]["POSITION"].is_u64() && primitive["indices"].is_u64());
        let animation = &doc["animations"][0];
        let paths: Vec<&str> = animation["channels"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["target"]["path"].as_str().unwrap())
            .collect();
        assert_eq!(paths, ["weights", "translation", "rotation"]);
        let samplers = animation["samplers"].as_array().unwrap();
        assert!(samplers.iter().all(|s| s["input"] == samplers[0]["input"]));
        assert_eq!(samplers[2]["interpolation"], "LINEAR");
        let mut short = table();
        short.mesh.triangles[0][1] = 7;
        let err = animated_glb(
            &s,
            &[0.0, 1e-4, 2e-4],
            &frames,
            &[],
            &[short],
            &Glb::default(),
        );
        assert!(err.unwrap_err().to_string().contains("index 7"));
    }

    /// The JSON chunk of a .glb.
    fn json_chunk(glb: &[u8]) -> serde_json::Value {
        let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        serde_json::from_slice(&glb[20..20 + len]).unwrap()
    }

    #[test]
    fn animation_is_keyed_at_the_playback_time_base_with_named_targets() {
        let (p, n, i) = tetrahedron();
        let s = crack_tet(&p, &n, &[0.0, 0.5, 1.0, 0.25], &i);
        let frames: Vec<Vec<[f32; 3]>> = (0..3).map(|_| p.clone()).collect();
        let options = Glb {
            playback_fps: 25.0,
            damage_colour: false,
        };
        let glb = animated_glb(&s, &[0.0, 1e-4, 2e-4], &frames, &[], &[], &options).unwrap();
        let doc = json_chunk(&glb);
        let input = &doc["accessors"][doc["animations"][0]["samplers"][0]["input"]
            .as_u64()
            .unwrap() as usize];
        assert_eq!(input["min"][0].as_f64().unwrap() as f32, 1.0 / 25.0);
        assert_eq!(input["max"][0].as_f64().unwrap() as f32, 3.0 / 25.0);
        let extras = &doc["meshes"][0]["extras"];
        assert_eq!(
            extras["targetNames"],
            serde_json::json!(["frame_0001", "frame_0002", "frame_0003"])
        );
        assert_eq!(extras["simulation_times"][2].as_f64().unwrap() as f32, 2e-4);
        assert_eq!(doc["animations"][0]["extras"]["playback_fps"], 25.0);
        let attributes = &doc["meshes"][0]["primitives"][0]["attributes"];
        assert!(attributes.get("COLOR_0").is_none() && attributes["_DAMAGE"].is_u64());
        let coloured = Glb {
            damage_colour: true,
            ..options
        };
        let doc = json_chunk(&crack_glb(&s, &coloured).unwrap());
        assert!(doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"].is_u64());
    }

    #[test]
    fn bad_animations_are_errors() {
        let (p, n, i) = tetrahedron();
        let d = [0.0; 4];
        let s = crack_tet(&p, &n, &d, &i);
        let frames = vec![p.clone(), p[..3].to_vec()];
        let err = animated_glb(&s, &[0.0, 0.1], &frames, &[], &[], &Glb::default()).unwrap_err();
        assert!(err.to_string().contains("frame 2 has 3 positions"), "{err}");
        let err = animated_glb(
            &s,
            &[0.1, 0.1],
            &[p.clone(), p.clone()],
            &[],
            &[],
            &Glb::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("increasing"), "{err}");
        let err = crack_glb(
            &SurfaceMesh {
                damage: d[..2].to_vec(),
                ..s
            },
            &Glb::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("damage values"), "{err}");
    }
}
