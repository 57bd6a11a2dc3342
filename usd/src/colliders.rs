//! The scene's colliders as prims: an `Xform` each with its time-sampled pose and
//! its shape ([`crate::write_stage`]).

use super::*;

/// `/World/Colliders`: each collider an `Xform` at its centre in each frame
/// (`manifest.json`'s `collider_centers`, else its scene position) with its shape;
/// a mesh collider's shape is its mesh from `meshes` (`colliders/mesh_N.ply`, in
/// the collider's frame).
pub(crate) fn colliders(
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
pub(crate) fn collider_name(colliders: &[ColliderSpec], index: usize) -> String {
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
pub(crate) fn polygon_mesh(
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
