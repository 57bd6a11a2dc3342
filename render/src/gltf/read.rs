//! Reading the .glb files the surface stage wrote back: into a frame's geometry for
//! the previews ([`read_glb`]) and into the cache's surface type ([`read_surfaces`]).

use std::path::Path;

use perifrac_cache::mesh::SurfaceMesh;

use crate::RenderError;
use crate::cache::{ColorBy, NO_RANGE, Ranges, widen};
use crate::geometry::{self, FrameGeometry, Shading};

/// Appends the triangle meshes of a .glb file: primitives of the material named
/// "crack" are crack faces; with `ColorBy::Damage` a `_DAMAGE` vertex attribute colours
/// the vertices, with `ColorBy::Quantity` a `_QUANTITY` one (θ, on the map over
/// `ranges.quantity`; a primitive without it is an error). Points and lines (debris)
/// are skipped. Returns the range of the `_QUANTITY` values read (empty, +∞ > −∞,
/// unless `color_by` is `Quantity`).
pub fn read_glb(
    path: &Path,
    color_by: ColorBy,
    ranges: &Ranges,
    g: &mut FrameGeometry,
) -> Result<[f32; 2], RenderError> {
    let bad = |message: String| input(path, message);
    let gltf = open(path)?;
    let blob = gltf.blob.as_deref();
    let buffer = |b: gltf::Buffer<'_>| embedded(blob, b);
    let damage_semantic = gltf::Semantic::Extras("DAMAGE".into());
    let quantity_semantic = gltf::Semantic::Extras("QUANTITY".into());
    let mut range = NO_RANGE;
    for mesh in gltf.meshes() {
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let reader = primitive.reader(buffer);
            let Some(positions) = reader.read_positions() else {
                return Err(bad(format!(
                    "mesh '{}' has a primitive without positions (or external buffers)",
                    mesh.name().unwrap_or("?")
                )));
            };
            let positions: Vec<[f32; 3]> = positions.collect();
            let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            let crack = primitive.material().name() == Some("crack");
            let shading = if crack {
                Shading::Crack
            } else {
                Shading::Surface
            };
            let base = if crack {
                geometry::crack_color()
            } else {
                geometry::surface_color()
            };
            let values = |semantic: &gltf::Semantic| -> Option<Vec<f32>> {
                primitive
                    .get(semantic)
                    .and_then(|a| gltf::accessor::Iter::<f32>::new(a, buffer))
                    .map(|it| it.collect())
            };
            let damage = (color_by == ColorBy::Damage)
                .then(|| values(&damage_semantic))
                .flatten();
            let quantity = match color_by {
                ColorBy::Quantity => Some(values(&quantity_semantic).ok_or_else(|| {
                    bad(format!(
                        "mesh '{}' has no _QUANTITY attribute (only membranes' sheet surfaces                          carry θ); use --color-by damage, or run `perifrac surface OUT --method                          sheet` on a membrane cache",
                        mesh.name().unwrap_or("?")
                    ))
                })?),
                _ => None,
            };
            if let Some(q) = &quantity {
                range = widen(range, q);
            }
            let colors = |i: usize| match (&damage, &quantity) {
                (Some(d), _) => geometry::damage_color(d.get(i).copied().unwrap_or(0.0)),
                (_, Some(q)) => {
                    geometry::quantity_color(q.get(i).copied().unwrap_or(0.0), ranges.quantity)
                }
                _ => base,
            };
            g.push_mesh(&positions, normals.as_deref(), &colors, &indices, shading);
        }
    }
    Ok(range)
}

/// Reads the meshes of a .glb file the surface stage wrote (`surface/NNNN.glb`) back
/// into the cache's surface type, one [`SurfaceMesh`] a glTF mesh, named like it:
/// primitives of the material named "crack" give the crack triangles, the others the
/// original surface's; primitives that share their position accessor share vertices;
/// `_DAMAGE` is read when every primitive carries it. Points and lines are skipped.
pub fn read_surfaces(path: &Path) -> Result<Vec<SurfaceMesh>, RenderError> {
    let bad = |message: String| input(path, message);
    let gltf = open(path)?;
    let blob = gltf.blob.as_deref();
    let buffer = |b: gltf::Buffer<'_>| embedded(blob, b);
    let damage_semantic = gltf::Semantic::Extras("DAMAGE".into());
    let mut meshes = Vec::new();
    for mesh in gltf.meshes() {
        let name = mesh.name().unwrap_or("").to_string();
        let mut out = SurfaceMesh {
            name: name.clone(),
            ..SurfaceMesh::default()
        };
        let mut with_damage = true;
        // (position accessor, first vertex) of the primitives read so far.
        let mut shared: Vec<(usize, u32)> = Vec::new();
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let Some(accessor) = primitive.get(&gltf::Semantic::Positions) else {
                return Err(bad(format!(
                    "mesh '{name}' has a primitive without positions"
                )));
            };
            let reader = primitive.reader(buffer);
            let base = match shared.iter().find(|(a, _)| *a == accessor.index()) {
                Some(&(_, base)) => base,
                None => {
                    let base = out.positions.len() as u32;
                    let positions: Vec<[f32; 3]> = reader
                        .read_positions()
                        .ok_or_else(|| {
                            bad(format!("mesh '{name}': positions in an external buffer"))
                        })?
                        .collect();
                    let normals: Vec<[f32; 3]> = match reader.read_normals() {
                        Some(n) => n.collect(),
                        None => vec![[0.0; 3]; positions.len()],
                    };
                    let damage = primitive
                        .get(&damage_semantic)
                        .and_then(|a| gltf::accessor::Iter::<f32>::new(a, buffer));
                    match damage {
                        Some(d) if with_damage => out.damage.extend(d),
                        _ => with_damage = false,
                    }
                    out.positions.extend(positions);
                    out.normals.extend(normals);
                    shared.push((accessor.index(), base));
                    base
                }
            };
            let count = accessor.count() as u32;
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..count).collect(),
            };
            if let Some(&i) = indices.iter().find(|&&i| i >= count) {
                return Err(bad(format!(
                    "mesh '{name}': index {i} past its {count} vertices"
                )));
            }
            let list = if primitive.material().name() == Some("crack") {
                &mut out.crack_indices
            } else {
                &mut out.surface_indices
            };
            list.extend(indices.iter().map(|i| i + base));
        }
        if !with_damage || out.damage.len() != out.positions.len() {
            out.damage.clear();
        }
        meshes.push(out);
    }
    Ok(meshes)
}

/// The error of a .glb file `path` that is not what the cache writes.
fn input(path: &Path, message: String) -> RenderError {
    RenderError::Input {
        path: path.to_path_buf(),
        message,
    }
}

/// The glTF binary at `path`, read whole.
fn open(path: &Path) -> Result<gltf::Gltf, RenderError> {
    let bytes = std::fs::read(path).map_err(|e| RenderError::io(path, e))?;
    gltf::Gltf::from_slice(&bytes).map_err(|e| input(path, format!("not a glTF binary: {e}")))
}

/// The data of buffer `b` when it is the file's own binary chunk `blob` (the cache
/// writes no external buffers).
fn embedded<'a>(blob: Option<&'a [u8]>, b: gltf::Buffer<'_>) -> Option<&'a [u8]> {
    match b.source() {
        gltf::buffer::Source::Bin => blob,
        gltf::buffer::Source::Uri(_) => None,
    }
}
