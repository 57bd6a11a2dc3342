//! A glTF 2.0 binary (.glb) writer for triangle meshes, on `gltf-json`'s types, and
//! the reader of what it wrote ([`read_glb`], [`read_surfaces`]).
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

mod animated;
mod plain;
mod read;
pub use animated::animated_glb;
pub use plain::to_glb;
pub use read::{read_glb, read_surfaces};

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

#[cfg(test)]
mod tests;
