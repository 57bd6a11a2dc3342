//! Mesh file readers: OBJ (`tobj`), PLY (`ply-rs`), glTF 2.0 and GLB (`gltf`).
//! Only positions and triangles are read; polygons are fanned into triangles.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use super::{MeshFileError, TriMesh};

/// Reads `path` by its extension, checking every index.
pub(super) fn read(path: &Path) -> Result<TriMesh, MeshFileError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let unreadable = |reason: String| MeshFileError::Unreadable {
        path: path.to_path_buf(),
        reason,
    };
    let reader: fn(&Path) -> Result<Polygons, String> = match extension.as_str() {
        "obj" => read_obj,
        "ply" => read_ply,
        "gltf" | "glb" => read_gltf,
        _ => {
            return Err(MeshFileError::UnsupportedExtension {
                path: path.to_path_buf(),
                extension,
            });
        }
    };
    // The third-party parsers index their input; a malformed file must give an
    // error, not abort the run, so a panic inside them is turned into one.
    let polygons = catch_unwind(AssertUnwindSafe(|| reader(path)))
        .unwrap_or_else(|_| Err("the parser failed on malformed data".into()))
        .map_err(unreadable)?;
    let vertices = polygons.vertices.len();
    let mut triangles = Vec::new();
    for (face, polygon) in polygons.faces.iter().enumerate() {
        if let Some(&index) = polygon.iter().find(|&&i| i >= vertices as u64) {
            return Err(MeshFileError::IndexOutOfRange {
                path: path.to_path_buf(),
                face,
                index,
                vertices,
            });
        }
        for k in 1..polygon.len().saturating_sub(1) {
            triangles.push([polygon[0], polygon[k], polygon[k + 1]].map(|i| i as u32));
        }
    }
    if triangles.is_empty() {
        return Err(MeshFileError::Empty {
            path: path.to_path_buf(),
            vertices,
        });
    }
    Ok(TriMesh {
        vertices: polygons.vertices,
        triangles,
    })
}

/// Most vertices plus faces a mesh file may hold: 2×10⁷, about 1 GB as read. A
/// surface that fine is far below any resolution the mesher can fill (its lattice
/// stops at 2×10⁸ points), and the bound keeps a damaged or hostile file (a huge
/// count in a header, a node that is its own child) from allocating without limit.
pub const MAX_MESH_ELEMENTS: usize = 20_000_000;

/// The refusal of a mesh above [`MAX_MESH_ELEMENTS`].
fn too_large(format: &str) -> String {
    format!(
        "more than {MAX_MESH_ELEMENTS} vertices and faces: decimate the mesh (a body's \
         surface needs no more detail than its resolution) ({format})"
    )
}

/// Positions and polygons as read, before any check.
struct Polygons {
    vertices: Vec<[f64; 3]>,
    faces: Vec<Vec<u64>>,
}

fn read_obj(path: &Path) -> Result<Polygons, String> {
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut reader = std::io::BufReader::new(file);
    // Materials are not needed: no .mtl file is opened.
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| format!("{e} (OBJ)"))?;
    let mut out = Polygons {
        vertices: Vec::new(),
        faces: Vec::new(),
    };
    let elements = models.iter().fold(0usize, |n, m| {
        n.saturating_add(m.mesh.positions.len() / 3)
            .saturating_add(m.mesh.face_arities.len().max(m.mesh.indices.len() / 3))
    });
    if elements > MAX_MESH_ELEMENTS {
        return Err(too_large("OBJ"));
    }
    for model in models {
        let m = model.mesh;
        let offset = out.vertices.len() as u64;
        out.vertices
            .extend(m.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
        let mut start = 0usize;
        let arities: Vec<u32> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.clone()
        };
        for n in arities {
            let end = start + n as usize;
            let face = m
                .indices
                .get(start..end)
                .ok_or("face list shorter than its arities")?;
            out.faces
                .push(face.iter().map(|&i| i as u64 + offset).collect());
            start = end;
        }
    }
    Ok(out)
}

fn read_ply(path: &Path) -> Result<Polygons, String> {
    use ply_rs::parser::Parser;
    use ply_rs::ply::{DefaultElement, Property};
    check_ply_counts(path)?;
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut reader = std::io::BufReader::new(file);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut reader)
        .map_err(|e| format!("{e} (PLY)"))?;
    let scalar = |p: Option<&Property>| -> Option<f64> {
        Some(match p? {
            Property::Float(x) => *x as f64,
            Property::Double(x) => *x,
            Property::Char(x) => *x as f64,
            Property::UChar(x) => *x as f64,
            Property::Short(x) => *x as f64,
            Property::UShort(x) => *x as f64,
            Property::Int(x) => *x as f64,
            Property::UInt(x) => *x as f64,
            _ => return None,
        })
    };
    let vertex_elements = ply
        .payload
        .get("vertex")
        .ok_or("no 'vertex' element (PLY)")?;
    let mut vertices = Vec::with_capacity(vertex_elements.len());
    for (i, v) in vertex_elements.iter().enumerate() {
        let p = ["x", "y", "z"].map(|k| scalar(v.get(k)));
        match p {
            [Some(x), Some(y), Some(z)] => vertices.push([x, y, z]),
            _ => return Err(format!("vertex {i} lacks numeric x, y, z properties (PLY)")),
        }
    }
    let list = |p: &Property| -> Option<Vec<u64>> {
        fn conv<T: Copy + TryInto<u64>>(v: &[T]) -> Option<Vec<u64>> {
            v.iter().map(|&x| x.try_into().ok()).collect()
        }
        match p {
            Property::ListChar(v) => conv(v),
            Property::ListUChar(v) => conv(v),
            Property::ListShort(v) => conv(v),
            Property::ListUShort(v) => conv(v),
            Property::ListInt(v) => conv(v),
            Property::ListUInt(v) => conv(v),
            _ => None,
        }
    };
    let mut faces = Vec::new();
    for (i, f) in ply.payload.get("face").into_iter().flatten().enumerate() {
        let indices = f
            .get("vertex_indices")
            .or_else(|| f.get("vertex_index"))
            .and_then(list)
            .ok_or_else(|| {
                format!("face {i} lacks a non-negative integer list 'vertex_indices' (PLY)")
            })?;
        faces.push(indices);
    }
    Ok(Polygons { vertices, faces })
}

/// Checks a PLY header's element counts before the parser allocates for them: each
/// element needs at least a byte a property (binary) or two (ASCII: a digit and a
/// separator) after the header, so a count the file cannot hold is refused, and the
/// total is bounded by [`MAX_MESH_ELEMENTS`].
fn check_ply_counts(path: &Path) -> Result<(), String> {
    use std::io::{BufRead, Read};
    let size = std::fs::metadata(path).map_err(|e| e.to_string())?.len();
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut reader = std::io::BufReader::new(file);
    let (mut header, mut line) = (0u64, Vec::new());
    let mut ascii = false;
    let mut elements: Vec<(String, u64, u64)> = Vec::new();
    loop {
        line.clear();
        let n = reader
            .by_ref()
            .take(4096)
            .read_until(b'\n', &mut line)
            .map_err(|e| e.to_string())?;
        if n == 0 || header > 1 << 20 {
            return Err("the header has no end_header line (PLY)".into());
        }
        header += n as u64;
        let text = String::from_utf8_lossy(&line);
        let words: Vec<&str> = text.split_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            ["format", format, ..] => ascii = *format == "ascii",
            ["element", name, count] => {
                let count = count
                    .parse::<u64>()
                    .map_err(|_| format!("element '{name}' has count '{count}' (PLY)"))?;
                elements.push((name.to_string(), count, 0));
            }
            ["property", ..] => {
                if let Some(e) = elements.last_mut() {
                    e.2 += 1;
                }
            }
            _ => {}
        }
    }
    let body = size.saturating_sub(header);
    let mut total = 0u64;
    for (name, count, properties) in &elements {
        let least = properties.max(&1) * if ascii { 2 } else { 1 };
        if count.saturating_mul(least) > body {
            return Err(format!(
                "the header declares {count} '{name}' elements but only {body} bytes follow it: \
                 the file is truncated or its header is damaged (PLY)"
            ));
        }
        total = total.saturating_add(*count);
    }
    if total > MAX_MESH_ELEMENTS as u64 {
        return Err(too_large("PLY"));
    }
    Ok(())
}

fn read_gltf(path: &Path) -> Result<Polygons, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| format!("{e} (glTF)"))?;
    let mut buffers = Vec::new();
    for buffer in gltf.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or("a buffer refers to a missing GLB binary chunk")?,
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, encoded) = rest
                        .split_once(";base64,")
                        .ok_or("data URI buffers must be base64")?;
                    decode_base64(encoded).ok_or("malformed base64 in a data URI")?
                } else {
                    let file = path.parent().unwrap_or(Path::new(".")).join(uri);
                    std::fs::read(&file).map_err(|e| format!("buffer {}: {e}", file.display()))?
                }
            }
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "buffer {} has {} bytes, {} declared",
                buffer.index(),
                data.len(),
                buffer.length()
            ));
        }
        buffers.push(data);
    }
    let mut out = Polygons {
        vertices: Vec::new(),
        faces: Vec::new(),
    };
    let identity = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let roots: Vec<gltf::Node> = match gltf.default_scene().or_else(|| gltf.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => Vec::new(),
    };
    if roots.is_empty() {
        // No scene: every mesh, untransformed.
        for mesh in gltf.meshes() {
            add_mesh(&mesh, identity, &buffers, &mut out)?;
        }
    }
    let mut stack: Vec<(gltf::Node, [[f64; 4]; 4])> =
        roots.into_iter().rev().map(|n| (n, identity)).collect();
    // glTF's node hierarchy is a forest (§3.5.3: no node is the child of two nodes,
    // no cycles): each node is visited once, so neither the walk nor the vertices it
    // adds can grow past the file's own nodes and meshes.
    let mut visited = vec![false; gltf.nodes().len()];
    while let Some((node, parent)) = stack.pop() {
        match visited.get_mut(node.index()) {
            Some(seen) if !*seen => *seen = true,
            _ => {
                return Err(format!(
                    "node {} is reached twice: the node hierarchy has a cycle or a shared \
                     child, and glTF requires a tree (glTF)",
                    node.index()
                ));
            }
        }
        let local = node.transform().matrix().map(|c| c.map(f64::from));
        let world = mat4_mul(parent, local);
        if let Some(mesh) = node.mesh() {
            add_mesh(&mesh, world, &buffers, &mut out)?;
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
    }
    Ok(out)
}

/// Column-major 4×4 product `a·b` (glTF's layout: `m[column][row]`).
fn mat4_mul(a: [[f64; 4]; 4], b: [[f64; 4]; 4]) -> [[f64; 4]; 4] {
    [0, 1, 2, 3].map(|c| [0, 1, 2, 3].map(|r| (0..4).map(|k| a[k][r] * b[c][k]).sum()))
}

fn add_mesh(
    mesh: &gltf::Mesh,
    m: [[f64; 4]; 4],
    buffers: &[Vec<u8>],
    out: &mut Polygons,
) -> Result<(), String> {
    for primitive in mesh.primitives() {
        if primitive.mode() != gltf::mesh::Mode::Triangles {
            return Err(format!(
                "mesh {} has a {:?} primitive; only triangles are supported",
                mesh.index(),
                primitive.mode()
            ));
        }
        // Bound what this primitive adds before reading it (its accessors' counts).
        let count = |a: Option<gltf::Accessor>| a.map_or(0, |a| a.count());
        let adds = count(primitive.get(&gltf::Semantic::Positions))
            .saturating_add(count(primitive.indices()));
        if out
            .vertices
            .len()
            .saturating_add(out.faces.len())
            .saturating_add(adds)
            > MAX_MESH_ELEMENTS
        {
            return Err(too_large("glTF"));
        }
        let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let offset = out.vertices.len() as u64;
        let positions = reader
            .read_positions()
            .ok_or_else(|| format!("mesh {} has a primitive without positions", mesh.index()))?;
        for p in positions {
            let p = p.map(f64::from);
            out.vertices.push(
                [0, 1, 2].map(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r]),
            );
        }
        let count = out.vertices.len() as u64 - offset;
        let indices: Vec<u64> = match reader.read_indices() {
            Some(i) => i.into_u32().map(|i| i as u64 + offset).collect(),
            None => (offset..offset + count).collect(),
        };
        if indices.len() % 3 != 0 {
            return Err(format!(
                "mesh {} has {} indices, not a multiple of 3",
                mesh.index(),
                indices.len()
            ));
        }
        out.faces
            .extend(indices.chunks_exact(3).map(<[u64]>::to_vec));
    }
    Ok(())
}

/// Standard base64 (RFC 4648, with or without padding); `None` if malformed.
fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let digits = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for chunk in digits.chunks(4) {
        if chunk.len() == 1 {
            return None;
        }
        let mut acc = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            acc |= value(c)? << (18 - 6 * i);
        }
        let bytes = acc.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes() {
        assert_eq!(decode_base64("TWFu").unwrap(), b"Man");
        assert_eq!(decode_base64("TWE=").unwrap(), b"Ma");
        assert_eq!(decode_base64("TQ==").unwrap(), b"M");
        assert!(decode_base64("T").is_none());
        assert!(decode_base64("T*==").is_none());
    }
}
