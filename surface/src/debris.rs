//! Debris: the particles of fragments too small to surface, written as a point set
//! (`surface/NNNN_debris.ply`, binary little-endian PLY with float properties
//! `x y z vx vy vz radius fragment material`) that Blender and Houdini import as
//! points with attributes, to instance or render as spheres of `radius`.

use std::path::Path;

use perifrac_cache::ply::encode_points;
use perifrac_cache::write_atomic;

use crate::error::Result;

/// The vertex properties of a debris file, in file order.
pub const PROPERTIES: [&str; 9] = [
    "x", "y", "z", "vx", "vy", "vz", "radius", "fragment", "material",
];

/// Debris points of one frame (structure of arrays).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Debris {
    /// Positions (m).
    pub position: Vec<[f32; 3]>,
    /// Velocities (m/s).
    pub velocity: Vec<[f32; 3]>,
    /// Sphere radius of each point (m), the particle's volume-equivalent radius times
    /// the radius scale.
    pub radius: Vec<f32>,
    /// Fragment id.
    pub fragment: Vec<f32>,
    /// Body (material) index.
    pub material: Vec<f32>,
}

impl Debris {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Encodes the points as PLY bytes (a file with zero points is valid).
    pub fn to_bytes(&self, frame: usize) -> Vec<u8> {
        let values: [&[f32]; 3] = [&self.radius, &self.fragment, &self.material];
        let scalars: Vec<(&str, &[f32])> = PROPERTIES[6..].iter().copied().zip(values).collect();
        encode_points(
            &format!("perifrac debris frame {frame}"),
            &self.position,
            &self.velocity,
            &scalars,
        )
    }

    /// Writes the points atomically.
    pub fn write(&self, path: &Path, frame: usize) -> Result<()> {
        Ok(write_atomic(path, &self.to_bytes(frame))?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_size() {
        let d = Debris {
            position: vec![[1.0, 2.0, 3.0]],
            velocity: vec![[0.0; 3]],
            radius: vec![0.5],
            fragment: vec![7.0],
            material: vec![0.0],
        };
        let bytes = d.to_bytes(3);
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.starts_with("ply\nformat binary_little_endian 1.0\n"));
        assert!(text.contains("element vertex 1\n"));
        let header = text.find("end_header\n").expect("header") + "end_header\n".len();
        assert_eq!(bytes.len() - header, 9 * 4);
        assert_eq!(&bytes[header + 28..header + 32], &7.0f32.to_le_bytes());
    }
}
