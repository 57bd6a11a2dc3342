//! Triangle meshes as the surface stage hands them on: built from the points,
//! triangles and quads a mesher returns (quads split into triangles here), with the
//! measures the tests and the CLI report (volume, open edges, connected parts) and
//! area-weighted vertex normals for export.

use std::collections::HashMap;

use perifrac_math::{UnionFind, cross, dot, norm, sub};

/// An indexed triangle mesh, counter-clockwise seen from outside.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions (m).
    pub positions: Vec<[f32; 3]>,
    /// Three vertex indices a triangle.
    pub indices: Vec<u32>,
}

/// a − b in f64 (the coordinates are stored as f32).
fn sub64(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    sub(a.map(f64::from), b.map(f64::from))
}

impl TriangleMesh {
    /// Builds a mesh from points, triangles and quads, keeping the polygons' winding.
    /// Each quad becomes two triangles split along its shorter diagonal.
    pub fn from_polygons(
        positions: Vec<[f32; 3]>,
        triangles: &[[u32; 3]],
        quads: &[[u32; 4]],
    ) -> TriangleMesh {
        let mut indices = Vec::with_capacity(3 * triangles.len() + 6 * quads.len());
        for t in triangles {
            indices.extend_from_slice(t);
        }
        for &[a, b, c, d] in quads {
            let squared = |i: u32, j: u32| {
                let e = sub64(positions[i as usize], positions[j as usize]);
                dot(e, e)
            };
            if squared(a, c) <= squared(b, d) {
                indices.extend_from_slice(&[a, b, c, a, c, d]);
            } else {
                indices.extend_from_slice(&[a, b, d, b, c, d]);
            }
        }
        TriangleMesh { positions, indices }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Whether the mesh has no triangles.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]])
    }

    /// Reverses every triangle's winding.
    pub fn flip(&mut self) {
        for t in self.indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }

    /// Signed enclosed volume (m³, positive when the triangles face outward), by the
    /// divergence theorem; meaningful for a closed mesh.
    pub fn volume(&self) -> f64 {
        let origin = self.positions.first().copied().unwrap_or_default();
        self.triangles()
            .map(|[a, b, c]| {
                let pa = sub64(self.positions[a as usize], origin);
                let pb = sub64(self.positions[b as usize], origin);
                let pc = sub64(self.positions[c as usize], origin);
                let n = cross(pb, pc);
                dot(pa, n) / 6.0
            })
            .sum()
    }

    /// Edges not shared by exactly two triangles (0 for a closed mesh).
    pub fn open_edges(&self) -> usize {
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        for [a, b, c] in self.triangles() {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                *count.entry((u.min(v), u.max(v))).or_default() += 1;
            }
        }
        count.values().filter(|&&n| n != 2).count()
    }

    /// Whether every edge is shared by exactly two triangles.
    pub fn is_closed(&self) -> bool {
        !self.is_empty() && self.open_edges() == 0
    }

    /// Number of connected parts (triangles sharing vertices are connected).
    pub fn components(&self) -> usize {
        let mut sets = UnionFind::new(self.positions.len());
        let mut used = vec![false; self.positions.len()];
        for [a, b, c] in self.triangles() {
            sets.union(a as usize, b as usize);
            sets.union(b as usize, c as usize);
            for i in [a, b, c] {
                used[i as usize] = true;
            }
        }
        (0..self.positions.len())
            .filter(|&i| used[i] && sets.find(i) == i)
            .count()
    }

    /// Area-weighted vertex normals (unit length; +y for a vertex without area).
    pub fn vertex_normals(&self) -> Vec<[f32; 3]> {
        let mut sum = vec![[0.0f64; 3]; self.positions.len()];
        for [a, b, c] in self.triangles() {
            let pa = self.positions[a as usize];
            let n = cross(
                sub64(self.positions[b as usize], pa),
                sub64(self.positions[c as usize], pa),
            );
            for i in [a, b, c] {
                for k in 0..3 {
                    sum[i as usize][k] += n[k];
                }
            }
        }
        sum.into_iter()
            .map(|n| {
                let len = norm(n);
                if len > 0.0 {
                    [
                        (n[0] / len) as f32,
                        (n[1] / len) as f32,
                        (n[2] / len) as f32,
                    ]
                } else {
                    [0.0, 1.0, 0.0]
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube of 6 quads, counter-clockwise from outside.
    fn cube() -> TriangleMesh {
        let p = (0..8)
            .map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32])
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        TriangleMesh::from_polygons(p, &[], &quads)
    }

    #[test]
    fn a_cube_is_closed_with_unit_volume() {
        let mut m = cube();
        assert_eq!(m.triangle_count(), 12);
        assert!(m.is_closed());
        assert_eq!(m.components(), 1);
        assert!((m.volume() - 1.0).abs() < 1e-12, "{}", m.volume());
        let n = m.vertex_normals();
        let corner = n[7];
        assert!(
            corner.iter().all(|&c| (c - 1.0 / 3f32.sqrt()).abs() < 1e-6),
            "{corner:?}"
        );
        m.flip();
        assert!((m.volume() + 1.0).abs() < 1e-12);
        m.indices.truncate(33);
        assert!(!m.is_closed());
        assert_eq!(m.open_edges(), 3);
    }
}
