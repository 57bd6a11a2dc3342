//! Float PLY, the one reader and writer of point files in the cache: binary
//! little-endian, one `vertex` element, every property a `float`.
//!
//! Particle frames (`particles/NNNN.ply`) have the standard properties
//! `x y z vx vy vz damage plastic material fragment` ([`PROPERTIES`]), which Blender's
//! PLY importer turns into point attributes and Houdini reads as point attributes,
//! followed by the extra columns a model adds: every model writes [`VOLUME`] (each
//! particle's volume in m³, so readers draw it at its own size), some more (e.g.
//! `temperature`). Caches written before the volume column existed lack it; readers
//! fall back to the body's resolution λ ([`ParticleFrame::volume`] is `None`). Debris
//! points (`surface/NNNN_debris.ply`) are written with [`encode_points`] too.

use std::io::Write;
use std::path::Path;

use crate::error::{CacheError, Result};

/// The standard vertex properties of a particle frame, in file order.
pub const PROPERTIES: [&str; 10] = [
    "x", "y", "z", "vx", "vy", "vz", "damage", "plastic", "material", "fragment",
];

/// The extra column every model writes: each particle's volume (m³). A particle's
/// size (spacing) is its cube root.
pub const VOLUME: &str = "volume";

/// The names of the position and velocity columns every point file starts with.
pub const VECTOR_PROPERTIES: [&str; 6] = ["x", "y", "z", "vx", "vy", "vz"];

/// Encodes points as a binary little-endian PLY with one `comment` line: the columns
/// [`VECTOR_PROPERTIES`] from `position` and `velocity`, then the named `scalars`
/// (each one value a point).
pub fn encode_points(
    comment: &str,
    position: &[[f32; 3]],
    velocity: &[[f32; 3]],
    scalars: &[(&str, &[f32])],
) -> Vec<u8> {
    let mut out = Vec::with_capacity(points_len(comment, position.len(), scalars));
    write_points(&mut out, comment, position, velocity, scalars)
        .expect("writing into memory does not fail");
    out
}

/// The header of [`encode_points`]' file.
fn points_header(comment: &str, count: usize, scalars: &[(&str, &[f32])]) -> String {
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment {comment}\nelement vertex {count}\n"
    );
    let names = VECTOR_PROPERTIES
        .into_iter()
        .chain(scalars.iter().map(|c| c.0));
    for name in names {
        header.push_str(&format!("property float {name}\n"));
    }
    header.push_str("end_header\n");
    header
}

/// The length of [`encode_points`]' file.
fn points_len(comment: &str, count: usize, scalars: &[(&str, &[f32])]) -> usize {
    points_header(comment, count, scalars).len() + count * 4 * (6 + scalars.len())
}

/// [`encode_points`]' bytes written to `out`.
fn write_points(
    out: &mut dyn Write,
    comment: &str,
    position: &[[f32; 3]],
    velocity: &[[f32; 3]],
    scalars: &[(&str, &[f32])],
) -> std::io::Result<()> {
    out.write_all(points_header(comment, position.len(), scalars).as_bytes())?;
    let mut row = Vec::with_capacity(4 * (6 + scalars.len()));
    for i in 0..position.len() {
        row.clear();
        let vectors = position[i].into_iter().chain(velocity[i]);
        for v in vectors.chain(scalars.iter().map(|c| c.1[i])) {
            row.extend_from_slice(&v.to_le_bytes());
        }
        out.write_all(&row)?;
    }
    Ok(())
}

/// A decoded float PLY: its comment lines and its columns in file order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FloatPly {
    /// The text of each `comment` line.
    pub comments: Vec<String>,
    /// Number of vertices.
    pub count: usize,
    /// Named columns, in file order.
    pub columns: Vec<(String, Vec<f32>)>,
}

impl FloatPly {
    /// The column `name`, if the file has it.
    pub fn column(&self, name: &str) -> Option<&[f32]> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Takes the column `name` out, failing with a message naming it.
    fn take(&mut self, name: &str) -> std::result::Result<Vec<f32>, String> {
        let c = self
            .columns
            .iter()
            .position(|(n, _)| n == name)
            .ok_or(format!("PLY has no '{name}' property"))?;
        Ok(self.columns.remove(c).1)
    }

    /// Decodes a binary little-endian PLY with float vertex properties.
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<FloatPly, String> {
        let (header, header_len) = split_header(bytes)?;
        let lines = header.lines().skip(1);
        let mut count = None;
        let mut names: Vec<String> = Vec::new();
        let mut comments = Vec::new();
        for line in lines {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["format", "binary_little_endian", _] => {}
                ["format", other, _] => {
                    return Err(format!(
                        "PLY format '{other}' is not supported; expected binary_little_endian"
                    ));
                }
                ["comment", ..] => comments.push(line["comment".len()..].trim().to_string()),
                ["element", "vertex", n] => {
                    count = Some(
                        n.parse::<usize>()
                            .map_err(|_| format!("bad vertex count '{n}'"))?,
                    )
                }
                ["element", other, _] => return Err(format!("unexpected PLY element '{other}'")),
                ["property", "float", name] => names.push(name.to_string()),
                ["property", ty, name] => {
                    return Err(format!("property '{name}' has type {ty}; expected float"));
                }
                _ => {}
            }
        }
        let n = count.ok_or("PLY header has no 'element vertex' line")?;
        let stride = names.len() * 4;
        let body = &bytes[header_len..];
        if body.len() < n * stride {
            return Err(format!(
                "PLY body is truncated: {} bytes for {n} vertices of {stride} bytes",
                body.len()
            ));
        }
        let columns = names
            .into_iter()
            .enumerate()
            .map(|(c, name)| {
                let values = (0..n)
                    .map(|i| {
                        let o = i * stride + c * 4;
                        f32::from_le_bytes([body[o], body[o + 1], body[o + 2], body[o + 3]])
                    })
                    .collect();
                (name, values)
            })
            .collect();
        Ok(FloatPly {
            comments,
            count: n,
            columns,
        })
    }
}

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
    /// Further float columns a model adds (name, one value a particle), written after
    /// the standard ones in this order.
    pub extra: Vec<(String, Vec<f32>)>,
}

/// The text header of a binary PLY (its first line checked to be `ply`) and the
/// offset of the body after it.
pub(crate) fn split_header(bytes: &[u8]) -> std::result::Result<(&str, usize), String> {
    let end = b"end_header\n";
    let header_len = bytes
        .windows(end.len())
        .position(|w| w == end)
        .ok_or("not a PLY file: no end_header line")?
        + end.len();
    let header = std::str::from_utf8(&bytes[..header_len]).map_err(|_| "PLY header is not text")?;
    if header.lines().next() != Some("ply") {
        return Err("not a PLY file: the first line is not 'ply'".into());
    }
    Ok((header, header_len))
}

fn zip3([a, b, c]: [Vec<f32>; 3]) -> Vec<[f32; 3]> {
    a.into_iter()
        .zip(b)
        .zip(c)
        .map(|((a, b), c)| [a, b, c])
        .collect()
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

    /// The extra column `name`, if the frame has it.
    pub fn extra(&self, name: &str) -> Option<&[f32]> {
        self.extra
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Each particle's volume (m³), the [`VOLUME`] column, if the frame has it with
    /// one value a particle (caches written before it existed do not).
    pub fn volume(&self) -> Option<&[f32]> {
        self.extra(VOLUME).filter(|v| v.len() == self.len())
    }

    /// Each particle's size (m): the cube root of its volume where the frame has the
    /// [`VOLUME`] column and the value is positive and finite, else `fallback(i)`
    /// (for old caches, the body's resolution λ).
    pub fn sizes(&self, fallback: impl Fn(usize) -> f32) -> Vec<f32> {
        let volume = self.volume();
        (0..self.len())
            .map(|i| match volume.map(|v| v[i]) {
                Some(v) if v.is_finite() && v > 0.0 => v.cbrt(),
                _ => fallback(i),
            })
            .collect()
    }

    /// Encodes the frame as PLY bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let (comment, scalars) = self.columns();
        encode_points(&comment, &self.position, &self.velocity, &scalars)
    }

    /// The comment line and the scalar columns, in file order.
    fn columns(&self) -> (String, Vec<(&str, &[f32])>) {
        let standard: [&[f32]; 4] = [&self.damage, &self.plastic, &self.material, &self.fragment];
        let scalars: Vec<(&str, &[f32])> = PROPERTIES[6..]
            .iter()
            .copied()
            .zip(standard)
            .chain(self.extra.iter().map(|(n, v)| (n.as_str(), v.as_slice())))
            .collect();
        let comment = format!(
            "perifrac particles frame {} time {:e}",
            self.frame, self.time
        );
        (comment, scalars)
    }

    /// Writes the frame atomically, through a buffer (the file's bytes are never
    /// held whole: 52 bytes a particle and more); refuses columns of the wrong
    /// length. Returns what the manifest records of the file.
    pub fn write(&self, path: &Path) -> Result<crate::manifest::FileRecord> {
        let n = self.len();
        let lengths = [
            ("velocity", self.velocity.len()),
            ("damage", self.damage.len()),
            ("plastic", self.plastic.len()),
            ("material", self.material.len()),
            ("fragment", self.fragment.len()),
        ];
        let extra = self.extra.iter().map(|(name, v)| (name.as_str(), v.len()));
        if let Some((name, len)) = lengths.into_iter().chain(extra).find(|&(_, l)| l != n) {
            return Err(CacheError::format(
                path,
                format!("{n} particles but {len} values of '{name}'"),
            ));
        }
        let (comment, scalars) = self.columns();
        let needed = points_len(&comment, n, &scalars) as u64;
        crate::layout::write_atomic_with(path, needed, |out| {
            write_points(out, &comment, &self.position, &self.velocity, &scalars)
        })
    }

    /// Reads a frame written by [`ParticleFrame::write`] (or any binary little-endian
    /// PLY with float vertex properties including the standard ones, in any order).
    pub fn read(path: &Path) -> Result<ParticleFrame> {
        let bytes = std::fs::read(path).map_err(|e| CacheError::io(path, e))?;
        Self::from_bytes(&bytes).map_err(|message| CacheError::format(path, message))
    }

    /// Decodes PLY bytes; properties other than the standard ones become
    /// [`ParticleFrame::extra`] columns, in file order.
    pub fn from_bytes(bytes: &[u8]) -> std::result::Result<ParticleFrame, String> {
        let mut ply = FloatPly::from_bytes(bytes)?;
        let (mut frame, mut time) = (0, 0.0);
        for comment in &ply.comments {
            let words: Vec<&str> = comment.split_whitespace().collect();
            if let ["perifrac", "particles", "frame", f, "time", t] = words.as_slice() {
                frame = f.parse().unwrap_or(0);
                time = t.parse().unwrap_or(0.0);
            }
        }
        let mut take3 = |names: [&str; 3]| -> std::result::Result<[Vec<f32>; 3], String> {
            Ok([
                ply.take(names[0])?,
                ply.take(names[1])?,
                ply.take(names[2])?,
            ])
        };
        let position = zip3(take3(["x", "y", "z"])?);
        let velocity = zip3(take3(["vx", "vy", "vz"])?);
        Ok(ParticleFrame {
            frame,
            time,
            position,
            velocity,
            damage: ply.take("damage")?,
            plastic: ply.take("plastic")?,
            material: ply.take("material")?,
            fragment: ply.take("fragment")?,
            extra: ply.columns,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_particles() -> ParticleFrame {
        ParticleFrame {
            frame: 3,
            time: 0.125,
            position: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
            velocity: vec![[0.5; 3], [0.25; 3]],
            damage: vec![0.0, 1.0],
            plastic: vec![0.1, 0.2],
            material: vec![0.0, 1.0],
            fragment: vec![0.0, 1.0],
            extra: Vec::new(),
        }
    }

    #[test]
    fn round_trip_and_truncation() {
        let f = two_particles();
        let bytes = f.to_bytes();
        assert_eq!(ParticleFrame::from_bytes(&bytes).unwrap(), f);
        let err = ParticleFrame::from_bytes(&bytes[..bytes.len() - 3]).unwrap_err();
        assert!(err.contains("truncated"), "{err}");
    }

    #[test]
    fn a_frame_written_through_a_buffer_is_its_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("0003.ply");
        let mut f = two_particles();
        // More rows than the writer's buffer holds.
        let n = 40_000;
        f.position = (0..n).map(|i| [i as f32, 0.5, -(i as f32)]).collect();
        f.velocity = vec![[0.25; 3]; n];
        for column in [
            &mut f.damage,
            &mut f.plastic,
            &mut f.material,
            &mut f.fragment,
        ] {
            *column = (0..n).map(|i| (i % 7) as f32).collect();
        }
        f.extra = vec![("region".to_string(), vec![1.0; n])];
        let record = f.write(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes == f.to_bytes());
        assert_eq!(record, crate::manifest::FileRecord::of(&bytes));
        assert_eq!(
            record.bytes as usize,
            points_len(&f.columns().0, n, &f.columns().1)
        );
    }

    #[test]
    fn standard_columns_keep_their_bytes() {
        // The layout before extra columns existed: header, then rows of ten floats.
        let f = two_particles();
        let mut expected = b"ply\nformat binary_little_endian 1.0\n\
            comment perifrac particles frame 3 time 1.25e-1\nelement vertex 2\n"
            .to_vec();
        for p in PROPERTIES {
            expected.extend_from_slice(format!("property float {p}\n").as_bytes());
        }
        expected.extend_from_slice(b"end_header\n");
        for i in 0..2 {
            let row = [
                f.position[i][0],
                f.position[i][1],
                f.position[i][2],
                f.velocity[i][0],
                f.velocity[i][1],
                f.velocity[i][2],
                f.damage[i],
                f.plastic[i],
                f.material[i],
                f.fragment[i],
            ];
            for v in row {
                expected.extend_from_slice(&v.to_le_bytes());
            }
        }
        assert_eq!(f.to_bytes(), expected);
    }

    #[test]
    fn extra_columns_follow_and_come_back() {
        let mut f = two_particles();
        f.extra = vec![
            ("temperature".into(), vec![300.0, 350.0]),
            ("phase".into(), vec![0.0, 1.0]),
        ];
        let bytes = f.to_bytes();
        let text = String::from_utf8_lossy(&bytes);
        assert!(
            text.contains(
                "property float fragment\nproperty float temperature\nproperty float phase\n"
            ),
            "{text}"
        );
        let back = ParticleFrame::from_bytes(&bytes).unwrap();
        assert_eq!(back.extra("temperature"), Some(&[300.0, 350.0][..]));
        assert_eq!(back, f);
    }

    #[test]
    fn sizes_come_from_the_volume_column_or_the_fallback() {
        let mut f = two_particles();
        // An old cache: no volume column, every size from the fallback.
        assert_eq!(f.volume(), None);
        assert_eq!(f.sizes(|i| 0.5 + i as f32), [0.5, 1.5]);
        f.extra = vec![(VOLUME.into(), vec![8e-6, 0.0])];
        let back = ParticleFrame::from_bytes(&f.to_bytes()).unwrap();
        assert_eq!(back.volume(), Some(&[8e-6, 0.0][..]));
        // The cube root of 8e-6 m³ is 0.02 m; a zero volume falls back.
        let sizes = back.sizes(|_| 7.0);
        assert!(
            (sizes[0] - 0.02).abs() < 1e-7 && sizes[1] == 7.0,
            "{sizes:?}"
        );
    }

    #[test]
    fn bad_lengths_are_refused_before_writing() {
        let dir = tempfile::tempdir().unwrap();
        let mut f = two_particles();
        f.extra = vec![("temperature".into(), vec![300.0])];
        let err = f
            .write(&dir.path().join("0003.ply"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("0003.ply") && err.contains("1 values of 'temperature'"),
            "{err}"
        );
    }
}
