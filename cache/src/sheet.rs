//! `sheet/NNNN.ply`: a membrane's sheet at one frame — its particles as vertices (with
//! the diffused quantity θ and damage) and the lattice triangles whose three bonds are
//! intact as faces. A zero-thickness mesh any tool reads as it is (binary PLY, y up,
//! metres), and what the `sheet` surface method thickens into `surface/NNNN.glb`.

use std::path::Path;

use crate::error::{CacheError, Result};
use crate::layout::write_atomic;
use crate::manifest::FileRecord;

/// One frame of a sheet.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SheetFrame {
    /// Vertex (particle) positions (m).
    pub positions: Vec<[f32; 3]>,
    /// Sheet thickness at each vertex (m), for the surface method's offset.
    pub thickness: Vec<f32>,
    /// θ per vertex.
    pub quantity: Vec<f32>,
    /// Damage φ per vertex.
    pub damage: Vec<f32>,
    /// The intact lattice triangles, counter-clockwise about the sheet's normal.
    pub triangles: Vec<[u32; 3]>,
}

const PROPERTIES: [&str; 6] = ["x", "y", "z", "thickness", "quantity", "damage"];
/// Bytes of one vertex.
const VERTEX: usize = 4 * PROPERTIES.len();

impl SheetFrame {
    /// The binary little-endian PLY bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = format!(
            "ply\nformat binary_little_endian 1.0\ncomment perifrac sheet\nelement vertex {}\n",
            self.positions.len()
        );
        for p in PROPERTIES {
            out += &format!("property float {p}\n");
        }
        out += &format!(
            "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
            self.triangles.len()
        );
        let mut bytes = out.into_bytes();
        for (i, p) in self.positions.iter().enumerate() {
            let v = [
                p[0],
                p[1],
                p[2],
                self.thickness[i],
                self.quantity[i],
                self.damage[i],
            ];
            for v in v {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        for t in &self.triangles {
            bytes.push(3);
            for v in t {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        bytes
    }

    /// Writes `path` atomically; returns its size and checksum for the manifest.
    pub fn write(&self, path: &Path) -> Result<FileRecord> {
        let bytes = self.to_bytes();
        write_atomic(path, &bytes)?;
        Ok(FileRecord::of(&bytes))
    }

    /// Reads `path`; a file not written by [`SheetFrame::write`] (another layout,
    /// truncated, an index out of range) is an error naming the file.
    pub fn read(path: &Path) -> Result<SheetFrame> {
        let bytes = std::fs::read(path).map_err(|e| CacheError::io(path, e))?;
        Self::from_bytes(&bytes).map_err(|message| CacheError::format(path, message))
    }

    /// Decodes the bytes of [`SheetFrame::to_bytes`].
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<SheetFrame, String> {
        const END: &[u8] = b"end_header\n";
        let end = bytes
            .windows(END.len())
            .position(|w| w == END)
            .ok_or("no PLY header (end_header missing)")?;
        let header = std::str::from_utf8(&bytes[..end]).map_err(|_| "the header is not text")?;
        let mut lines = header.lines();
        let mut expect = |what: &str| -> std::result::Result<String, String> {
            lines
                .next()
                .map(str::to_string)
                .ok_or_else(|| format!("the header ends before {what}"))
        };
        let count = |line: String, element: &str| -> std::result::Result<usize, String> {
            line.strip_prefix(&format!("element {element} "))
                .and_then(|n| n.parse().ok())
                .ok_or_else(|| format!("expected 'element {element} N', found '{line}'"))
        };
        if expect("the magic")? != "ply"
            || expect("the format")? != "format binary_little_endian 1.0"
        {
            return Err("not a binary little-endian PLY".into());
        }
        if expect("the comment")? != "comment perifrac sheet" {
            return Err("not a perifrac sheet (its comment is missing)".into());
        }
        let vertices = count(expect("the vertex element")?, "vertex")?;
        for p in PROPERTIES {
            let line = expect("a vertex property")?;
            if line != format!("property float {p}") {
                return Err(format!("expected 'property float {p}', found '{line}'"));
            }
        }
        let faces = count(expect("the face element")?, "face")?;
        if expect("the face property")? != "property list uchar uint vertex_indices" {
            return Err("faces must be 'property list uchar uint vertex_indices'".into());
        }
        let body = &bytes[end + END.len()..];
        let expected = vertices
            .checked_mul(VERTEX)
            .and_then(|v| faces.checked_mul(13).and_then(|f| v.checked_add(f)))
            .ok_or("element counts overflow")?;
        if body.len() != expected {
            return Err(format!(
                "{} bytes of data where {vertices} vertices and {faces} triangles take {expected}",
                body.len()
            ));
        }
        let f32_at = |k: usize| f32::from_le_bytes(body[k..k + 4].try_into().expect("4 bytes"));
        let mut frame = SheetFrame::default();
        for i in 0..vertices {
            let k = VERTEX * i;
            frame
                .positions
                .push([f32_at(k), f32_at(k + 4), f32_at(k + 8)]);
            let thickness = f32_at(k + 12);
            if !(thickness.is_finite() && thickness > 0.0) {
                return Err(format!(
                    "vertex {i} has thickness {thickness}: not a positive number"
                ));
            }
            frame.thickness.push(thickness);
            frame.quantity.push(f32_at(k + 16));
            frame.damage.push(f32_at(k + 20));
        }
        for f in 0..faces {
            let k = VERTEX * vertices + 13 * f;
            if body[k] != 3 {
                return Err(format!("face {f} has {} corners, not 3", body[k]));
            }
            let t = [0, 1, 2].map(|c| {
                u32::from_le_bytes(
                    body[k + 1 + 4 * c..k + 5 + 4 * c]
                        .try_into()
                        .expect("4 bytes"),
                )
            });
            if t.iter().any(|&v| v as usize >= vertices) {
                return Err(format!(
                    "face {f} points past the {vertices} vertices: {t:?}"
                ));
            }
            frame.triangles.push(t);
        }
        Ok(frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet() -> SheetFrame {
        SheetFrame {
            thickness: vec![0.001; 3],
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]],
            quantity: vec![0.0, 0.5, 1.0],
            damage: vec![0.0, 0.25, 0.0],
            triangles: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn a_sheet_reads_back_as_written() {
        let s = sheet();
        assert_eq!(SheetFrame::from_bytes(&s.to_bytes()), Ok(s));
    }

    #[test]
    fn damaged_sheets_are_refused() {
        let bytes = sheet().to_bytes();
        let truncated = &bytes[..bytes.len() - 1];
        assert!(
            SheetFrame::from_bytes(truncated)
                .unwrap_err()
                .contains("bytes of data")
        );
        let mut out_of_range = bytes.clone();
        let n = out_of_range.len();
        out_of_range[n - 4..].copy_from_slice(&7u32.to_le_bytes());
        assert!(
            SheetFrame::from_bytes(&out_of_range)
                .unwrap_err()
                .contains("points past")
        );
        let mut negative = bytes.clone();
        let start = negative.len() - 13 - 2 * VERTEX;
        negative[start + 12..start + 16].copy_from_slice(&(-1f32).to_le_bytes());
        assert!(
            SheetFrame::from_bytes(&negative)
                .unwrap_err()
                .contains("thickness")
        );
    }
}
