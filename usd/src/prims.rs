//! The stage's prims other than the colliders: the looks, the particles, the
//! surfaces (one mesh, or a mesh a fragment) and the volume ([`crate::write_stage`]).

use super::*;

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
pub(crate) fn looks(stage: &mut Layer, world: &str) -> Result<[String; 2], String> {
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
pub(crate) fn particle_samples(
    frame: &ParticleFrame,
    widths: &[f32],
    velocity_scale: f32,
) -> Vec<Sample> {
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
pub(crate) const PARTICLE_ATTRIBUTES: [(&str, &str); 9] = [
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
pub(crate) fn particles(
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
pub(crate) fn mesh_samples(mesh: &SurfaceMesh) -> (Vec<Sample>, usize) {
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
pub(crate) const MESH_ATTRIBUTES: [(&str, &str); 9] = [
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
pub(crate) fn define_mesh(
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
pub(crate) fn embedded_surface<'a>(
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
pub(crate) fn fragments<'a>(
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
pub(crate) fn natural(name: &str) -> (String, u64) {
    let digits: String = name.chars().filter(char::is_ascii_digit).collect();
    let text: String = name.chars().filter(|c| !c.is_ascii_digit()).collect();
    (text, digits.parse().unwrap_or(0))
}

/// `/World/Volume`: a `Volume` whose `OpenVDBAsset` fields `surface` (level set) and
/// `v` (velocity, m/s of simulated time) point at `vdb/NNNN.vdb` frame by frame.
pub(crate) fn volume(
    stage: &mut Layer,
    world: &str,
    layout: &Layout,
    frames: usize,
) -> Result<(), String> {
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
