//! `surface/animated.glb`'s mesh and its vertices at each frame. The animation has one
//! topology, the last frame's; a crack face that is not open yet at frame k (its
//! tets still bonded there) must show nothing: it is folded to a point of frame k's
//! surface, so it has no area and no vertex of frame k sits off that frame's surface
//! (through a transparent or x-ray material the future cracks would otherwise show
//! inside the intact body from frame 1).
//!
//! A crack face opens at the first frame from which its tets' face is on the boundary
//! of every later frame's split mesh. Its corners get their own vertices per opening
//! frame (a vertex shared by faces opening at different frames is copied), so that
//! the faces opening at frame o can be folded before o while those open already keep
//! their place. Before o, each connected patch of them folds to one point: one of its
//! own vertices that is on frame k's surface, else the surface vertex of frame k
//! nearest to it.

use std::collections::HashMap;

use perifrac_math::UnionFind;

use super::{EmbeddedSurface, RenderMesh};

/// What the animation needs of one frame's surface.
pub struct FrameView {
    /// Position of each vertex of the final mesh at this frame (the split-mesh vertex
    /// it was copied from where it does not exist yet).
    pub positions: Vec<[f32; 3]>,
    /// Whether each final vertex's split-mesh vertex is on this frame's surface.
    pub on_surface: Vec<bool>,
    /// Whether each crack triangle of the final mesh is a boundary face here.
    pub open: Vec<bool>,
    /// This frame's surface vertices (for the nearest one).
    pub surface_points: Vec<[f32; 3]>,
}

/// The view of `final_mesh` (of the last frame, whose split mesh has the vertex
/// parents `parent`) from the surface `surf` of one frame.
pub fn view(final_mesh: &RenderMesh, parent: &[i32], surf: &EmbeddedSurface) -> FrameView {
    let count = surf.points.len();
    let here = |v: u32| {
        let mut v = v as usize;
        while v >= count && parent[v] >= 0 {
            v = parent[v] as usize;
        }
        v
    };
    let map: Vec<usize> = final_mesh.vertex.iter().map(|&v| here(v)).collect();
    let mut boundary: Vec<[u32; 3]> = surf.triangles.iter().map(|&f| sorted(f)).collect();
    boundary.sort_unstable();
    let mut on = vec![false; count];
    for f in &surf.triangles {
        for &v in f {
            on[v as usize] = true;
        }
    }
    let open = final_mesh
        .mesh
        .crack_indices
        .chunks_exact(3)
        .map(|t| {
            let f = sorted([0, 1, 2].map(|k| map[t[k] as usize] as u32));
            f[0] != f[1] && f[1] != f[2] && boundary.binary_search(&f).is_ok()
        })
        .collect();
    FrameView {
        positions: map
            .iter()
            .map(|&v| surf.points.get(v).map_or([0.0; 3], |p| p.map(|c| c as f32)))
            .collect(),
        on_surface: map
            .iter()
            .map(|&v| on.get(v).copied().unwrap_or(false))
            .collect(),
        open,
        surface_points: (0..count)
            .filter(|&v| on[v])
            .map(|v| surf.points[v].map(|c| c as f32))
            .collect(),
    }
}

fn sorted(mut f: [u32; 3]) -> [u32; 3] {
    f.sort_unstable();
    f
}

/// The animated mesh (`final_mesh` with the crack corners copied per opening frame)
/// and its positions at every frame of `views`.
pub fn animate(final_mesh: &RenderMesh, views: &[FrameView]) -> (RenderMesh, Vec<Vec<[f32; 3]>>) {
    let crack = &final_mesh.mesh.crack_indices;
    // The frame (index into `views`) from which each crack triangle stays open.
    let opens: Vec<usize> = (0..crack.len() / 3)
        .map(|t| {
            views
                .iter()
                .rposition(|v| !v.open[t])
                .map_or(0, |closed| closed + 1)
        })
        .collect();
    // Vertices: (final vertex, opening frame), original faces' corners at frame 0.
    let mut keys: Vec<(u32, usize)> = final_mesh
        .mesh
        .surface_indices
        .iter()
        .map(|&r| (r, 0))
        .chain(crack.iter().enumerate().map(|(c, &r)| (r, opens[c / 3])))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    let index = |key: (u32, usize)| keys.binary_search(&key).unwrap_or(0) as u32;
    let mut mesh = final_mesh.clone();
    mesh.vertex = keys
        .iter()
        .map(|&(r, _)| final_mesh.vertex[r as usize])
        .collect();
    mesh.mesh.surface_indices = final_mesh
        .mesh
        .surface_indices
        .iter()
        .map(|&r| index((r, 0)))
        .collect();
    mesh.mesh.crack_indices = crack
        .iter()
        .enumerate()
        .map(|(c, &r)| index((r, opens[c / 3])))
        .collect();
    let copy = |values: &[f32]| -> Vec<f32> {
        match values.is_empty() {
            true => Vec::new(),
            false => keys.iter().map(|&(r, _)| values[r as usize]).collect(),
        }
    };
    mesh.mesh.damage = copy(&final_mesh.mesh.damage);
    mesh.mesh.quantity = copy(&final_mesh.mesh.quantity);
    mesh.mesh.normals = keys
        .iter()
        .map(|&(r, _)| final_mesh.mesh.normals[r as usize])
        .collect();
    // Patches of crack faces that open at the same frame, joined by shared vertices.
    let mut patches = UnionFind::new(keys.len());
    for tri in mesh.mesh.crack_indices.chunks_exact(3) {
        patches.union(tri[0] as usize, tri[1] as usize);
        patches.union(tri[0] as usize, tri[2] as usize);
    }
    let patch: Vec<usize> = (0..keys.len()).map(|v| patches.find(v)).collect();
    let positions = views
        .iter()
        .enumerate()
        .map(|(k, view)| {
            let at = |v: usize| view.positions[keys[v].0 as usize];
            // Where each closed patch folds at this frame: its first vertex on the
            // surface, else the surface point nearest its first vertex.
            let mut fold: HashMap<usize, [f32; 3]> = HashMap::new();
            for v in 0..keys.len() {
                if keys[v].1 > k && view.on_surface[keys[v].0 as usize] {
                    fold.entry(patch[v]).or_insert_with(|| at(v));
                }
            }
            let nearest = Nearest::new(&view.surface_points);
            (0..keys.len())
                .map(|v| match keys[v].1 > k {
                    false => at(v),
                    true => *fold
                        .entry(patch[v])
                        .or_insert_with(|| nearest.to(at(patch[v]))),
                })
                .collect()
        })
        .collect();
    (mesh, positions)
}

/// The nearest of a set of points, through a grid of cells.
struct Nearest<'a> {
    points: &'a [[f32; 3]],
    cell: f32,
    cells: HashMap<[i32; 3], Vec<u32>>,
}

impl<'a> Nearest<'a> {
    /// A grid of about two points a cell over `points`.
    fn new(points: &'a [[f32; 3]]) -> Nearest<'a> {
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in points {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let volume: f32 = (0..3).map(|c| (hi[c] - lo[c]).max(1e-6)).product();
        let cell = (2.0 * volume / points.len().max(1) as f32).cbrt().max(1e-6);
        let mut cells: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
        for (i, p) in points.iter().enumerate() {
            cells.entry(key(*p, cell)).or_default().push(i as u32);
        }
        Nearest {
            points,
            cell,
            cells,
        }
    }

    /// The point nearest `q` (the lowest index among equally near ones); `q` itself
    /// when there are no points.
    fn to(&self, q: [f32; 3]) -> [f32; 3] {
        if self.points.is_empty() {
            return q;
        }
        let centre = key(q, self.cell);
        let mut best: Option<(f32, u32)> = None;
        let mut ring = 0i32;
        loop {
            for dx in -ring..=ring {
                for dy in -ring..=ring {
                    for dz in -ring..=ring {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != ring {
                            continue;
                        }
                        let cell = [centre[0] + dx, centre[1] + dy, centre[2] + dz];
                        for &i in self.cells.get(&cell).into_iter().flatten() {
                            let p = self.points[i as usize];
                            let d: f32 = (0..3).map(|c| (p[c] - q[c]).powi(2)).sum();
                            if best.is_none_or(|b| (d, i) < b) {
                                best = Some((d, i));
                            }
                        }
                    }
                }
            }
            // Points of later rings are at least `ring` cells away.
            if let Some((d, i)) = best
                && d.sqrt() <= ring as f32 * self.cell
            {
                return self.points[i as usize];
            }
            ring += 1;
        }
    }
}

fn key(p: [f32; 3], cell: f32) -> [i32; 3] {
    p.map(|c| (c / cell).floor() as i32)
}
