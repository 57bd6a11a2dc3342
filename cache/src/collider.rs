//! Mesh colliders' geometry in the cache, `colliders/mesh_N.ply` (N the collider's
//! index in the scene's `[[collider]]` list), written once by the run so that the
//! previews, `cache.usd` and `surface/animated.glb` draw the collider without the
//! scene's mesh file (which may move or change after the run).
//!
//! The file is the placed mesh (after the scene's scale, rotation and translation,
//! welded and wound outward, as the solver collides with it) less its pivot: the
//! collider's own frame. Frame k shows it moved rigidly to x ↦ c + R x, with c =
//! `collider_centers[k − 1][N]` and R the quaternion `collider_rotations[k − 1][N]` of
//! `manifest.json` (the solver's x ↦ centre + R (x − pivot) of the placed mesh).
//!
//! Binary little-endian PLY: `element vertex` with `float x y z`, `element face` with
//! `property list uchar uint vertex_indices` (triangles, counter-clockwise seen from
//! outside), and a `comment pivot X Y Z` line, the pivot (m) in the scene.

use std::path::Path;

use crate::error::{CacheError, Result};
use crate::layout::Layout;
use crate::manifest::{FileRecord, Manifest};
use crate::ply::split_header;
use crate::scene::{ColliderSpec, Scene};

/// A mesh collider's triangles in its own frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ColliderMesh {
    /// Vertex positions (m) in the collider's frame: the placed mesh less the pivot.
    pub positions: Vec<[f32; 3]>,
    /// Three vertex indices a triangle, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// The pivot (m): where the collider's origin sits in the scene at rest.
    pub pivot: [f64; 3],
}

/// The fix for a collider mesh that is missing or damaged.
const RERUN: &str = "the run writes it from the scene's mesh collider: run the scene again \
                     (`perifrac run SCENE -o OUT --force`)";

impl ColliderMesh {
    /// Encodes it as the cache's binary PLY.
    pub fn to_bytes(&self) -> Vec<u8> {
        let [px, py, pz] = self.pivot;
        let header = format!(
            "ply\nformat binary_little_endian 1.0\ncomment perifrac mesh collider: the \
             placed mesh less its pivot\ncomment pivot {px:?} {py:?} {pz:?}\nelement vertex \
             {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\n\
             property list uchar uint vertex_indices\nend_header\n",
            self.positions.len(),
            self.triangles.len()
        );
        let mut out = Vec::with_capacity(
            header.len() + 12 * self.positions.len() + 13 * self.triangles.len(),
        );
        out.extend_from_slice(header.as_bytes());
        for p in &self.positions {
            for v in p {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        for t in &self.triangles {
            out.push(3);
            for v in t {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out
    }

    /// Decodes what [`ColliderMesh::to_bytes`] wrote; refuses anything else (other
    /// properties, faces that are not triangles, indices past the vertices,
    /// non-finite positions, a truncated or overlong body).
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<ColliderMesh, String> {
        let (header, header_len) = split_header(bytes)?;
        let lines = header.lines().skip(1);
        let mut pivot = None;
        let mut counts: Vec<(&str, usize)> = Vec::new();
        let mut properties: Vec<String> = Vec::new();
        for line in lines {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["format", "binary_little_endian", "1.0"] | ["end_header"] => {}
                ["format", ..] => {
                    return Err(format!(
                        "'{line}': expected 'format binary_little_endian 1.0'"
                    ));
                }
                ["comment", "pivot", x, y, z] => {
                    let parse = |w: &str| w.parse::<f64>().ok().filter(|v| v.is_finite());
                    pivot = Some(
                        [parse(x), parse(y), parse(z)]
                            .into_iter()
                            .collect::<Option<Vec<f64>>>()
                            .ok_or(format!("'{line}': the pivot is not three finite numbers"))?,
                    );
                }
                ["comment", ..] => {}
                ["element", name, n] => counts.push((
                    name,
                    n.parse()
                        .map_err(|_| format!("'{line}': bad element count"))?,
                )),
                ["property", ..] => properties.push(words.join(" ")),
                _ => return Err(format!("unexpected PLY header line '{line}'")),
            }
        }
        let expected = [
            "property float x",
            "property float y",
            "property float z",
            "property list uchar uint vertex_indices",
        ];
        let &[("vertex", vertices), ("face", faces)] = counts.as_slice() else {
            return Err("expected the elements 'vertex' then 'face'".into());
        };
        if properties != expected {
            return Err(format!(
                "properties {properties:?}; expected float x, y, z and a uchar/uint list \
                 vertex_indices"
            ));
        }
        let body = &bytes[header_len..];
        let length = vertices
            .checked_mul(12)
            .zip(faces.checked_mul(13))
            .and_then(|(v, f)| v.checked_add(f));
        if length != Some(body.len()) {
            return Err(format!(
                "{} bytes after the header, not the {vertices} vertices and {faces} triangles \
                 it announces (truncated or damaged)",
                body.len()
            ));
        }
        let float = |o: usize| f32::from_le_bytes([body[o], body[o + 1], body[o + 2], body[o + 3]]);
        let positions: Vec<[f32; 3]> = (0..vertices)
            .map(|i| [0, 1, 2].map(|k| float(12 * i + 4 * k)))
            .collect();
        if let Some(i) = positions
            .iter()
            .position(|p| !p.iter().all(|v| v.is_finite()))
        {
            return Err(format!("vertex {i} has a non-finite position"));
        }
        let faces_at = 12 * vertices;
        let mut triangles = Vec::with_capacity(faces);
        for t in 0..faces {
            let o = faces_at + 13 * t;
            if body[o] != 3 {
                return Err(format!("face {t} has {} vertices, not 3", body[o]));
            }
            let index = |k: usize| {
                let a = o + 1 + 4 * k;
                u32::from_le_bytes([body[a], body[a + 1], body[a + 2], body[a + 3]])
            };
            let triangle = [index(0), index(1), index(2)];
            if let Some(&v) = triangle.iter().find(|&&v| v as usize >= vertices) {
                return Err(format!(
                    "face {t} refers to vertex {v}, past the {vertices} vertices"
                ));
            }
            triangles.push(triangle);
        }
        let pivot = pivot.ok_or("no 'comment pivot X Y Z' line")?;
        Ok(ColliderMesh {
            positions,
            triangles,
            pivot: [pivot[0], pivot[1], pivot[2]],
        })
    }

    /// Writes it atomically; returns what the manifest records of the file.
    pub fn write(&self, path: &Path) -> Result<FileRecord> {
        let bytes = self.to_bytes();
        crate::write_atomic(path, &bytes)?;
        Ok(FileRecord::of(&bytes))
    }

    /// Reads `colliders/mesh_N.ply`; a missing or malformed file is an error naming
    /// it and the fix (bad input, exit code 2).
    pub fn read(path: &Path) -> Result<ColliderMesh> {
        let bytes = std::fs::read(path).map_err(|e| {
            CacheError::format(path, format!("cannot read the mesh collider: {e}; {RERUN}"))
        })?;
        Self::from_bytes(&bytes).map_err(|message| {
            CacheError::format(
                path,
                format!("not a perifrac collider mesh (damaged?): {message}; {RERUN}"),
            )
        })
    }
}

/// A mesh collider of a cache: its geometry and its pose at every frame.
#[derive(Debug, Clone, PartialEq)]
pub struct MovingCollider {
    /// The collider's index N in the scene's `[[collider]]` list.
    pub index: usize,
    /// `mesh_N`, N the collider's index in the scene (the file's and the USD prim's name).
    pub name: String,
    /// The geometry in the collider's frame.
    pub mesh: ColliderMesh,
    /// The centre at each frame (frame k at k − 1).
    pub centers: Vec<[f64; 3]>,
    /// The rotation [x, y, z, w] at each frame.
    pub rotations: Vec<[f64; 4]>,
}

impl MovingCollider {
    /// The pose (centre, rotation) at frame `frame` (from 1); the rest pose (the
    /// pivot, no rotation) where the manifest has none.
    pub fn pose(&self, frame: usize) -> ([f64; 3], [f64; 4]) {
        let k = frame.wrapping_sub(1);
        (
            self.centers.get(k).copied().unwrap_or(self.mesh.pivot),
            self.rotations
                .get(k)
                .copied()
                .unwrap_or([0.0, 0.0, 0.0, 1.0]),
        )
    }
}

/// The name of collider `index` when it is a mesh (`mesh_N`).
pub fn mesh_name(index: usize) -> String {
    format!("mesh_{index}")
}

/// The mesh colliders of the cache at `layout` (the scene's `[[collider]] type =
/// "mesh"`, in scene order), each read from `colliders/mesh_N.ply` with its poses from
/// `manifest` (empty without one).
pub fn mesh_colliders(
    layout: &Layout,
    scene: &Scene,
    manifest: Option<&Manifest>,
) -> Result<Vec<MovingCollider>> {
    scene
        .colliders
        .iter()
        .enumerate()
        .filter(|(_, c)| matches!(c, ColliderSpec::Mesh { .. }))
        .map(|(i, _)| {
            let mesh = ColliderMesh::read(&layout.collider_mesh(i))?;
            Ok(MovingCollider {
                index: i,
                name: mesh_name(i),
                centers: column(manifest.map(|m| &m.collider_centers), i, mesh.pivot),
                rotations: column(
                    manifest.map(|m| &m.collider_rotations),
                    i,
                    [0.0, 0.0, 0.0, 1.0],
                ),
                mesh,
            })
        })
        .collect()
}

/// Entry `index` of every frame's row of `rows` (`fallback` where a row is short);
/// empty without rows.
fn column<T: Copy>(rows: Option<&Vec<Vec<T>>>, index: usize, fallback: T) -> Vec<T> {
    rows.map_or_else(Vec::new, |rows| {
        rows.iter()
            .map(|row| row.get(index).copied().unwrap_or(fallback))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> ColliderMesh {
        ColliderMesh {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
            pivot: [0.1, 0.3, -1.0 / 3.0],
        }
    }

    #[test]
    fn round_trip_and_damage_is_named() {
        let mesh = tetrahedron();
        let bytes = mesh.to_bytes();
        assert_eq!(ColliderMesh::from_bytes(&bytes).unwrap(), mesh);
        let text = String::from_utf8_lossy(&bytes);
        assert!(
            text.contains("comment pivot 0.1 0.3 -0.3333333333333333\n"),
            "{text}"
        );
        let err = ColliderMesh::from_bytes(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(err.contains("truncated"), "{err}");
        let mut bad = bytes.clone();
        let last = bad.len() - 4;
        bad[last..].copy_from_slice(&9u32.to_le_bytes());
        let err = ColliderMesh::from_bytes(&bad).unwrap_err();
        assert!(err.contains("face 3 refers to vertex 9"), "{err}");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mesh_0.ply");
        let err = ColliderMesh::read(&path).unwrap_err();
        assert!(err.is_bad_input());
        let text = err.to_string();
        assert!(
            text.contains("mesh_0.ply") && text.contains("--force"),
            "{text}"
        );
        let record = mesh.write(&path).unwrap();
        assert_eq!(record, FileRecord::of(&bytes));
        assert_eq!(ColliderMesh::read(&path).unwrap(), mesh);
    }
}
