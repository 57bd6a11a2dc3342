//! The whole shot as one glTF: the fractured surface with a morph target a frame and a
//! stepped weights animation, and the moving colliders keyed along (see the module doc
//! of [`super`]).

use gltf_json as json;
use json::validation::Checked;
use perifrac_cache::collider::MovingCollider;
use perifrac_cache::mesh::SurfaceMesh;

use super::{
    Glb, MorphFrame, accessor, check_crack, finish, invalid, material, new_root,
    push_crack_surface, push_points, push_view, vec3_bytes,
};
use crate::RenderError;
use crate::geometry::quantity_color;

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
