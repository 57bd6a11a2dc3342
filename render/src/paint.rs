//! Colour by material: each body's display colour (its material's `color`, or the
//! scene's default palette, [`perifrac_cache::scene::Scene::body_colors`]) on its
//! particles and on the original surface of the meshes drawn for it (embedded
//! surfaces, VDB fragment meshes, sheets). A mesh does not say which body a vertex
//! belongs to, so a vertex takes the body of the nearest particle of its frame, found
//! in a uniform grid; crack faces keep their own colour. Scenes whose bodies all look
//! alike skip the search.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::geometry::{MESH_STRIDE, Shading};

/// Particles of one frame binned in a uniform grid, to find the body nearest a point.
#[derive(Debug)]
pub struct NearestBody<'a> {
    position: &'a [[f32; 3]],
    body: &'a [f32],
    cell: f32,
    bins: HashMap<[i32; 3], Vec<u32>>,
}

impl<'a> NearestBody<'a> {
    /// Bins `position` (with the body index of each particle, as the PLY's `material`
    /// column holds it) in cells of `cell` metres (about the particle spacing).
    pub fn new(position: &'a [[f32; 3]], body: &'a [f32], cell: f32) -> NearestBody<'a> {
        let cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            1.0
        };
        let mut bins: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
        for (i, p) in position.iter().enumerate() {
            if p.iter().all(|v| v.is_finite()) {
                bins.entry(key(*p, cell)).or_default().push(i as u32);
            }
        }
        NearestBody {
            position,
            body,
            cell,
            bins,
        }
    }

    /// The body of the particle nearest `p` within two cells (the lowest index among
    /// equally near ones), if any.
    pub fn body(&self, p: [f32; 3]) -> Option<usize> {
        let c = key(p, self.cell);
        for reach in 1..=2 {
            let mut best: Option<(f32, u32)> = None;
            for dx in -reach..=reach {
                for dy in -reach..=reach {
                    for dz in -reach..=reach {
                        let Some(bin) = self.bins.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                            continue;
                        };
                        for &i in bin {
                            let q = self.position[i as usize];
                            let d = (0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f32>();
                            if best.is_none_or(|(bd, bi)| d < bd || (d == bd && i < bi)) {
                                best = Some((d, i));
                            }
                        }
                    }
                }
            }
            if let Some((_, i)) = best {
                let b = self.body[i as usize];
                return (b.is_finite() && b >= 0.0).then_some(b as usize);
            }
        }
        None
    }
}

fn key(p: [f32; 3], cell: f32) -> [i32; 3] {
    p.map(|v| (v / cell).floor() as i32)
}

/// Paints the original-surface vertices of `mesh_vertices` (interleaved,
/// [`MESH_STRIDE`] floats each) in their body's colour from `colors` (linear): every
/// vertex in `colors[0]` when `nearest` is `None`, else the colour of the body of the
/// nearest particle (`colors[0]` where none is near). Crack faces and colliders keep
/// their colour.
pub fn paint_surfaces(
    mesh_vertices: &mut [f32],
    colors: &[[f32; 3]],
    nearest: Option<&NearestBody<'_>>,
) {
    let Some(&first) = colors.first() else {
        return;
    };
    mesh_vertices
        .par_chunks_exact_mut(MESH_STRIDE)
        .filter(|v| v[9] == Shading::Surface as u32 as f32)
        .for_each(|v| {
            let color = nearest
                .and_then(|n| n.body([v[0], v[1], v[2]]))
                .and_then(|b| colors.get(b).copied())
                .unwrap_or(first);
            v[6..9].copy_from_slice(&color);
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertex_takes_the_body_of_the_nearest_particle() {
        let position = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.45, 0.0, 0.0]];
        let body = [0.0, 1.0, 2.0];
        let near = NearestBody::new(&position, &body, 0.25);
        assert_eq!(near.body([0.9, 0.1, 0.0]), Some(1));
        assert_eq!(near.body([0.5, 0.0, 0.0]), Some(2));
        assert_eq!(near.body([-0.1, 0.0, 0.0]), Some(0));
        assert_eq!(near.body([5.0, 0.0, 0.0]), None, "nothing within two cells");
        // Surface vertices take the colour, crack vertices keep theirs.
        let mut vertices = vec![0.0; 2 * MESH_STRIDE];
        vertices[0] = 0.95;
        vertices[MESH_STRIDE] = 0.95;
        vertices[MESH_STRIDE + 9] = Shading::Crack as u32 as f32;
        let colors = [[0.1; 3], [0.2; 3], [0.3; 3]];
        paint_surfaces(&mut vertices, &colors, Some(&near));
        assert_eq!(&vertices[6..9], &[0.2; 3]);
        assert_eq!(&vertices[MESH_STRIDE + 6..MESH_STRIDE + 9], &[0.0; 3]);
        paint_surfaces(&mut vertices, &colors, None);
        assert_eq!(&vertices[6..9], &[0.1; 3]);
    }
}
