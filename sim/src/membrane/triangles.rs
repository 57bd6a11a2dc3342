//! The sheet's triangles and fragments, what its surface (`surface = "sheet"`) is
//! drawn from: the lattice's or the mesh's triangles, those whose three edge bonds
//! are intact, their area, and the connected components of intact bonds.

use perifrac_math::{cross, det_sum, dot, norm, sub};

use super::MembraneModel;
use crate::family::{BROKEN, INDEX};

impl MembraneModel {
    /// Every sheet's triangles: the lattice triangles of the lattice sheets
    /// ([`MembraneModel::lattice_triangles`]), then the mesh sheets' own.
    pub fn sheet_triangles(&self) -> Vec<[u32; 3]> {
        let mut triangles = self.lattice_triangles();
        triangles.extend_from_slice(&self.mesh_triangles);
        triangles
    }

    /// The lattice sheets' triangles: every triple of particles of one body bonded
    /// pairwise at the lattice spacing (each particle's shortest bond, to 0.1%),
    /// wound so that their reference normals agree with the first one's along the
    /// sheet's normal, in increasing order of their smallest index. Particles of mesh
    /// sheets (in [`MembraneModel::mesh_triangles`]) are left out.
    pub fn lattice_triangles(&self) -> Vec<[u32; 3]> {
        let bonds = &self.bonds;
        let mut meshed = vec![false; self.len()];
        for &v in self.mesh_triangles.iter().flatten() {
            meshed[v as usize] = true;
        }
        let nearest = |i: usize| -> Vec<usize> {
            if meshed[i] {
                return Vec::new();
            }
            let shortest = bonds
                .range(i)
                .map(|k| self.rest_length[k])
                .fold(f64::INFINITY, f64::min);
            let mut near: Vec<usize> = bonds
                .range(i)
                .filter(|&k| self.rest_length[k] <= 1.001 * shortest)
                .map(|k| (bonds.neighbours[k] & INDEX) as usize)
                .filter(|&j| j > i)
                .collect();
            near.sort_unstable();
            near
        };
        let near: Vec<Vec<usize>> = (0..self.len()).map(nearest).collect();
        let x = &self.reference;
        let normal = |t: [usize; 3]| cross(sub(x[t[1]], x[t[0]]), sub(x[t[2]], x[t[0]]));
        let mut triangles = Vec::new();
        let mut up: Option<[f64; 3]> = None;
        for (i, near_i) in near.iter().enumerate() {
            for (a, &j) in near_i.iter().enumerate() {
                for &k in &near_i[a + 1..] {
                    if near[j].binary_search(&k).is_ok() {
                        let n = normal([i, j, k]);
                        let reference = *up.get_or_insert(n);
                        triangles.push(if dot(n, reference) >= 0.0 {
                            [i as u32, j as u32, k as u32]
                        } else {
                            [i as u32, k as u32, j as u32]
                        });
                    }
                }
            }
        }
        triangles
    }

    /// Whether the three bonds of lattice triangle `t` are intact.
    pub fn triangle_intact(&self, t: [u32; 3]) -> bool {
        let intact = |i: u32, j: u32| {
            self.bonds.range(i as usize).any(|k| {
                let nb = self.bonds.neighbours[k];
                nb & INDEX == j && nb & BROKEN == 0
            })
        };
        intact(t[0], t[1]) && intact(t[1], t[2]) && intact(t[2], t[0])
    }

    /// The current area (m²) of the lattice triangles `triangles` whose three bonds
    /// are intact, in 3D (wrinkles and folds count at their true area).
    pub fn sheet_area(&self, triangles: &[[u32; 3]]) -> f64 {
        let y = &self.position;
        det_sum(triangles.len(), |t| {
            if self.triangle_intact(triangles[t]) {
                let [i, j, k] = triangles[t].map(|v| v as usize);
                0.5 * norm(cross(sub(y[j], y[i]), sub(y[k], y[i])))
            } else {
                0.0
            }
        })
    }

    /// Connected components of intact bonds, numbered by their smallest particle
    /// index in increasing order (deterministic).
    pub fn fragments(&self) -> Vec<u32> {
        self.bonds.fragments()
    }
}
