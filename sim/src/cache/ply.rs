//! Particle frames as binary little-endian PLY: one vertex per particle with float
//! properties `x y z vx vy vz damage plastic material fragment`, which Blender's PLY
//! importer turns into point attributes and Houdini reads as point attributes.

use std::path::Path;

use crate::error::{Result, SimError};

/// The vertex properties of a particle frame, in file order.
pub const PROPERTIES: [&str; 10] = [
    "x", "y", "z", "vx", "vy", "vz", "damage", "plastic", "material", "fragment",
];

/// One frame of particles (structure of arrays).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParticleFrame {
    /// Frame number (from 1).
    pub frame: usize,
    /// Simulation time (s).
    pub time: f64,
    /// Positions.
    pub position: Vec<[f32; 3]>,
    /// Velocities.
    pub velocity: Vec<[f32; 3]>,
    /// Damage φ in [0, 1].
    pub damage: Vec<f32>,
    /// Plastic strain measure.
    pub plastic: Vec<f32>,
    /// Body (material) index.
    pub material: Vec<f32>,
    /// Fragment id (connected component of intact bonds).
    pub fragment: Vec<f32>,
}

impl ParticleFrame {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether the frame has no particles.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Encodes the frame as PLY bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let n = self.len();
        let mut header = format!(
            "ply\nformat binary_little_endian 1.0\ncomment perifrac particles frame {} time {:e}\nelement vertex {n}\n",
            self.frame, self.time
        );
        for p in PROPERTIES {
            header.push_str(&format!("property float {p}\n"));
        }
        header.push_str("end_header\n");
        let mut out = Vec::with_capacity(header.len() + n * 4 * PROPERTIES.len());
        out.extend_from_slice(header.as_bytes());
        for i in 0..n {
            let row = [
                self.position[i][0],
                self.position[i][1],
                self.position[i][2],
                self.velocity[i][0],
                self.velocity[i][1],
                self.velocity[i][2],
                self.damage[i],
                self.plastic[i],
                self.material[i],
                self.fragment[i],
            ];
            for v in row {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out
    }

    /// Writes the frame atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        super::write_atomic(path, &self.to_bytes())
    }

    /// Reads a frame written by [`ParticleFrame::write`] (or any binary little-endian
    /// PLY with float vertex properties including these names, in any order).
    pub fn read(path: &Path) -> Result<ParticleFrame> {
        let bytes = std::fs::read(path).map_err(|e| SimError::io(path, e))?;
        Self::from_bytes(&bytes).map_err(|message| SimError::Cache {
            path: path.to_path_buf(),
            message,
        })
    }

    /// Decodes PLY bytes.
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<ParticleFrame, String> {
        let end = b"end_header\n";
        let header_len = bytes
            .windows(end.len())
            .position(|w| w == end)
            .ok_or("not a PLY file: no end_header line")?
            + end.len();
        let header =
            std::str::from_utf8(&bytes[..header_len]).map_err(|_| "PLY header is not text")?;
        let mut lines = header.lines();
        if lines.next() != Some("ply") {
            return Err("not a PLY file: the first line is not 'ply'".into());
        }
        let mut count = None;
        let mut props: Vec<String> = Vec::new();
        let mut frame = 0;
        let mut time = 0.0;
        for line in lines {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["format", "binary_little_endian", _] => {}
                ["format", other, _] => {
                    return Err(format!(
                        "PLY format '{other}' is not supported; expected binary_little_endian"
                    ));
                }
                ["comment", "perifrac", "particles", "frame", f, "time", t] => {
                    frame = f.parse().unwrap_or(0);
                    time = t.parse().unwrap_or(0.0);
                }
                ["element", "vertex", n] => {
                    count = Some(
                        n.parse::<usize>()
                            .map_err(|_| format!("bad vertex count '{n}'"))?,
                    )
                }
                ["element", other, _] => return Err(format!("unexpected PLY element '{other}'")),
                ["property", "float", name] => props.push(name.to_string()),
                ["property", ty, name] => {
                    return Err(format!("property '{name}' has type {ty}; expected float"));
                }
                _ => {}
            }
        }
        let n = count.ok_or("PLY header has no 'element vertex' line")?;
        let stride = props.len() * 4;
        let body = &bytes[header_len..];
        if body.len() < n * stride {
            return Err(format!(
                "PLY body is truncated: {} bytes for {n} vertices of {stride} bytes",
                body.len()
            ));
        }
        let column = |name: &str| -> std::result::Result<Vec<f32>, String> {
            let c = props
                .iter()
                .position(|p| p == name)
                .ok_or(format!("PLY has no '{name}' property"))?;
            Ok((0..n)
                .map(|i| {
                    let o = i * stride + c * 4;
                    f32::from_le_bytes([body[o], body[o + 1], body[o + 2], body[o + 3]])
                })
                .collect())
        };
        let zip3 = |a: Vec<f32>, b: Vec<f32>, c: Vec<f32>| -> Vec<[f32; 3]> {
            a.into_iter()
                .zip(b)
                .zip(c)
                .map(|((a, b), c)| [a, b, c])
                .collect()
        };
        Ok(ParticleFrame {
            frame,
            time,
            position: zip3(column("x")?, column("y")?, column("z")?),
            velocity: zip3(column("vx")?, column("vy")?, column("vz")?),
            damage: column("damage")?,
            plastic: column("plastic")?,
            material: column("material")?,
            fragment: column("fragment")?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_truncation() {
        let f = ParticleFrame {
            frame: 3,
            time: 0.125,
            position: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
            velocity: vec![[0.5; 3], [0.25; 3]],
            damage: vec![0.0, 1.0],
            plastic: vec![0.1, 0.2],
            material: vec![0.0, 1.0],
            fragment: vec![0.0, 1.0],
        };
        let bytes = f.to_bytes();
        assert_eq!(ParticleFrame::from_bytes(&bytes).unwrap(), f);
        let err = ParticleFrame::from_bytes(&bytes[..bytes.len() - 3]).unwrap_err();
        assert!(err.contains("truncated"), "{err}");
    }
}
