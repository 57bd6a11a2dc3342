//! `tets/NNNN.vtu`: the split tet mesh of a frame (Chen §5.2) as a VTK XML
//! UnstructuredGrid (ParaView, meshio and VTK read it).
//!
//! One piece; points as Float64 ×3; cells are VTK_TETRA (10) with Int32
//! connectivity and offsets; CellData `particle` (UInt32, the particle of the tet)
//! and `damage` (Float32); PointData `parent` (Int32, the vertex a copy was split
//! from, −1 for an original vertex). Vertices only ever get added: the first N
//! vertices of a frame are the vertices of every earlier frame with N vertices or
//! more. Data arrays are appended raw binary (`<AppendedData encoding="raw">`), each
//! block a UInt64 byte count and the little-endian values.

use std::path::Path;

use crate::error::{CacheError, Result};

/// Writes `tets/tets.pvd`, the ParaView collection of the tet frames 1 … `frames`:
/// frame k (file `NNNN.vtu`) at `timestep` (k − 1)/`playback_fps`, the playback time
/// base of every file of the cache that carries time, with its simulation time
/// `simulation_times[k − 1]` (s) kept in the attribute `simulation_time` (which
/// ParaView ignores).
pub fn write_collection(path: &Path, simulation_times: &[f64], playback_fps: f64) -> Result<()> {
    use std::fmt::Write as _;
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
         byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for (k, time) in simulation_times.iter().enumerate() {
        let frame = k + 1;
        let _ = writeln!(
            text,
            "<DataSet timestep=\"{}\" simulation_time=\"{time:e}\" group=\"\" part=\"0\" \
             file=\"{frame:04}.vtu\"/>",
            crate::playback_time(frame, playback_fps)
        );
    }
    text.push_str("</Collection>\n</VTKFile>\n");
    crate::write_atomic(path, text.as_bytes())
}

/// VTK's cell type of a linear tetrahedron.
pub const VTK_TETRA: u8 = 10;

/// The split tet mesh of one frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TetFrame {
    /// Vertex positions (m).
    pub points: Vec<[f64; 3]>,
    /// The four vertices of each tet.
    pub tets: Vec<[u32; 4]>,
    /// The particle of each tet.
    pub particle: Vec<u32>,
    /// Damage φ of each tet's particle (Chen §5.1).
    pub damage: Vec<f32>,
    /// The vertex each copy was split from (−1: an original vertex).
    pub parent: Vec<i32>,
}

struct Array {
    name: &'static str,
    kind: &'static str,
    components: usize,
    bytes: Vec<u8>,
}

fn le<T: Copy, const N: usize>(values: &[T], f: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| f(v)).collect()
}

impl TetFrame {
    fn check(&self) -> std::result::Result<(), String> {
        let (nv, nt) = (self.points.len(), self.tets.len());
        if self.particle.len() != nt || self.damage.len() != nt {
            return Err(format!(
                "{nt} tets but {} particle ids and {} damage values",
                self.particle.len(),
                self.damage.len()
            ));
        }
        if self.parent.len() != nv {
            return Err(format!(
                "{nv} points but {} parent indices",
                self.parent.len()
            ));
        }
        if let Some(t) = self
            .tets
            .iter()
            .position(|t| t.iter().any(|&v| v as usize >= nv))
        {
            return Err(format!("tet {t} has a vertex past the {nv} points"));
        }
        if let Some(v) = (0..nv).find(|&v| self.parent[v] >= v as i32 || self.parent[v] < -1) {
            return Err(format!(
                "vertex {v} has parent {}: a copy's parent must come before it",
                self.parent[v]
            ));
        }
        Ok(())
    }

    /// Encodes the frame as a .vtu file.
    pub fn to_bytes(&self) -> Vec<u8> {
        let flat: Vec<i32> = self.tets.iter().flatten().map(|&v| v as i32).collect();
        let offsets: Vec<i32> = (1..=self.tets.len()).map(|t| 4 * t as i32).collect();
        let points: Vec<f64> = self.points.iter().flatten().copied().collect();
        let arrays = [
            Array {
                name: "parent",
                kind: "Int32",
                components: 1,
                bytes: le(&self.parent, i32::to_le_bytes),
            },
            Array {
                name: "particle",
                kind: "UInt32",
                components: 1,
                bytes: le(&self.particle, u32::to_le_bytes),
            },
            Array {
                name: "damage",
                kind: "Float32",
                components: 1,
                bytes: le(&self.damage, f32::to_le_bytes),
            },
            Array {
                name: "Points",
                kind: "Float64",
                components: 3,
                bytes: le(&points, f64::to_le_bytes),
            },
            Array {
                name: "connectivity",
                kind: "Int32",
                components: 1,
                bytes: le(&flat, i32::to_le_bytes),
            },
            Array {
                name: "offsets",
                kind: "Int32",
                components: 1,
                bytes: le(&offsets, i32::to_le_bytes),
            },
            Array {
                name: "types",
                kind: "UInt8",
                components: 1,
                bytes: vec![VTK_TETRA; self.tets.len()],
            },
        ];
        let mut offset = 0usize;
        let mut tags = Vec::new();
        for a in &arrays {
            tags.push(format!(
                "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" offset=\"{offset}\"/>",
                a.kind, a.name, a.components
            ));
            offset += 8 + a.bytes.len();
        }
        let header = format!(
            "<?xml version=\"1.0\"?>\n\
             <VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
             <UnstructuredGrid>\n\
             <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n\
             <PointData Scalars=\"parent\">\n{}\n</PointData>\n\
             <CellData Scalars=\"damage\">\n{}\n{}\n</CellData>\n\
             <Points>\n{}\n</Points>\n\
             <Cells>\n{}\n{}\n{}\n</Cells>\n\
             </Piece>\n\
             </UnstructuredGrid>\n\
             <AppendedData encoding=\"raw\">\n_",
            self.points.len(),
            self.tets.len(),
            tags[0],
            tags[1],
            tags[2],
            tags[3],
            tags[4],
            tags[5],
            tags[6]
        );
        let mut out = header.into_bytes();
        for a in &arrays {
            out.extend_from_slice(&(a.bytes.len() as u64).to_le_bytes());
            out.extend_from_slice(&a.bytes);
        }
        out.extend_from_slice(b"\n</AppendedData>\n</VTKFile>\n");
        out
    }

    /// Writes the frame atomically; refuses inconsistent data.
    pub fn write(&self, path: &Path) -> Result<crate::manifest::FileRecord> {
        self.check().map_err(|message| CacheError::Format {
            path: path.to_path_buf(),
            message,
        })?;
        let bytes = self.to_bytes();
        crate::write_atomic(path, &bytes)?;
        Ok(crate::manifest::FileRecord::of(&bytes))
    }

    /// Reads a frame written by [`TetFrame::write`].
    pub fn read(path: &Path) -> Result<TetFrame> {
        let bytes = std::fs::read(path).map_err(|e| CacheError::io(path, e))?;
        let frame = Self::parse(&bytes).map_err(|message| CacheError::Format {
            path: path.to_path_buf(),
            message,
        })?;
        frame.check().map_err(|message| CacheError::Format {
            path: path.to_path_buf(),
            message,
        })?;
        Ok(frame)
    }

    fn parse(bytes: &[u8]) -> std::result::Result<TetFrame, String> {
        let marker = b"<AppendedData encoding=\"raw\">";
        let start = bytes
            .windows(marker.len())
            .position(|w| w == marker)
            .ok_or("no raw appended data: not a perifrac .vtu file")?;
        let header =
            std::str::from_utf8(&bytes[..start]).map_err(|_| "the XML header is not UTF-8")?;
        let underscore = bytes[start..]
            .iter()
            .position(|&b| b == b'_')
            .ok_or("no '_' opening the appended data")?;
        let data = &bytes[start + underscore + 1..];
        let attribute = |tag: &str, key: &str| -> Option<String> {
            let k = format!("{key}=\"");
            let s = tag.find(&k)? + k.len();
            let e = tag[s..].find('"')? + s;
            Some(tag[s..e].to_string())
        };
        let piece = header
            .find("<Piece")
            .map(|s| &header[s..])
            .ok_or("no <Piece>")?;
        let count = |key: &str| -> std::result::Result<usize, String> {
            attribute(piece, key)
                .and_then(|v| v.parse().ok())
                .ok_or(format!("no {key} in <Piece>"))
        };
        let (nv, nt) = (count("NumberOfPoints")?, count("NumberOfCells")?);
        let block = |name: &str, kind: &str, len: usize| -> std::result::Result<&[u8], String> {
            let tag = header
                .split("<DataArray")
                .skip(1)
                .find(|t| attribute(t, "Name").as_deref() == Some(name))
                .ok_or(format!("no data array '{name}'"))?;
            if attribute(tag, "type").as_deref() != Some(kind) {
                return Err(format!("data array '{name}' is not {kind}"));
            }
            let offset: usize = attribute(tag, "offset")
                .and_then(|v| v.parse().ok())
                .ok_or(format!("data array '{name}' has no offset"))?;
            let size = data
                .get(offset..offset + 8)
                .map(|b| u64::from_le_bytes(b.try_into().unwrap_or_default()) as usize)
                .ok_or(format!(
                    "data array '{name}' starts past the end of the file"
                ))?;
            if size != len {
                return Err(format!(
                    "data array '{name}' has {size} bytes, expected {len}"
                ));
            }
            data.get(offset + 8..offset + 8 + size)
                .ok_or(format!("data array '{name}' is cut short"))
        };
        let words = |b: &[u8]| -> Vec<[u8; 4]> {
            b.chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect()
        };
        let points: Vec<f64> = block("Points", "Float64", 24 * nv)?
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap_or_default()))
            .collect();
        let flat: Vec<i32> = words(block("connectivity", "Int32", 16 * nt)?)
            .into_iter()
            .map(i32::from_le_bytes)
            .collect();
        let types = block("types", "UInt8", nt)?;
        if let Some(t) = types.iter().position(|&t| t != VTK_TETRA) {
            return Err(format!(
                "cell {t} is not a tetrahedron (VTK type {})",
                types[t]
            ));
        }
        if flat.iter().any(|&v| v < 0) {
            return Err("negative vertex index".into());
        }
        Ok(TetFrame {
            points: points.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            tets: flat
                .chunks_exact(4)
                .map(|c| [c[0] as u32, c[1] as u32, c[2] as u32, c[3] as u32])
                .collect(),
            particle: words(block("particle", "UInt32", 4 * nt)?)
                .into_iter()
                .map(u32::from_le_bytes)
                .collect(),
            damage: words(block("damage", "Float32", 4 * nt)?)
                .into_iter()
                .map(f32::from_le_bytes)
                .collect(),
            parent: words(block("parent", "Int32", 4 * nv)?)
                .into_iter()
                .map(i32::from_le_bytes)
                .collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_tets() -> TetFrame {
        TetFrame {
            points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
                [1.0, 0.0, 0.0],
            ],
            tets: vec![[0, 1, 2, 3], [5, 2, 4, 3]],
            particle: vec![7, 3],
            damage: vec![0.25, 0.5],
            parent: vec![-1, -1, -1, -1, -1, 1],
        }
    }

    #[test]
    fn collection_gives_playback_and_simulation_times() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("tets.pvd");
        write_collection(&path, &[0.0, 1.0 / 7500.0, 2.0 / 7500.0], 24.0).expect("write");
        let text = std::fs::read_to_string(&path).expect("read");
        assert_eq!(text.matches("<DataSet ").count(), 3, "{text}");
        assert!(text.contains("timestep=\"0\"") && text.contains("file=\"0001.vtu\""));
        assert!(
            text.contains(
                "timestep=\"0.08333333333333333\" simulation_time=\"2.666666666666667e-4\""
            ),
            "{text}"
        );
    }

    #[test]
    fn round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("0001.vtu");
        let frame = two_tets();
        frame.write(&path).unwrap();
        assert_eq!(TetFrame::read(&path).unwrap(), frame);
    }

    #[test]
    fn bad_files_name_what_is_wrong() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.vtu");
        let mut frame = two_tets();
        frame.parent[5] = 5;
        let err = frame.write(&path).unwrap_err().to_string();
        assert!(err.contains("vertex 5 has parent 5"), "{err}");
        let mut bytes = two_tets().to_bytes();
        bytes.truncate(bytes.len() - 60);
        std::fs::write(&path, &bytes).unwrap();
        let err = TetFrame::read(&path).unwrap_err().to_string();
        assert!(
            err.contains("bad.vtu") && err.contains("cut short"),
            "{err}"
        );
    }
}
