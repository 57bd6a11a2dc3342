//! Isotropic remeshing of a triangle surface (open or closed) to a target edge length
//! h, for a membrane's sheet given by a mesh file (issue 14): the vertices become the
//! sheet's particles at spacing ≈ h and the triangles the sheet's own, so the `sheet`
//! surface method and the particle areas work as for the built-in lattices.
//!
//! Botsch & Kobbelt 2004 ("A remeshing approach to multiresolution modeling", §4),
//! repeated [`ITERATIONS`] times: split every edge longer than 4/3 L at its midpoint,
//! collapse every edge shorter than 4/5 L (keeping the surface a manifold, no
//! triangle turned over, no new edge above 4/3 L), flip edges where that brings the
//! valences closer to 6 (4 on the boundary), move every vertex to the area-weighted
//! mean of its neighbours within its tangent plane, and project it back onto the
//! input surface. The band alone leaves the mean edge some 8% below L, so L starts at
//! h and is rescaled by h over the mean edge after each round: the mean edge ends
//! within a few % of h, the particle density of the triangular lattice of spacing h,
//! to which Han's R = 1.5 h family is sensitive (a mean edge of 0.93 h made a flat
//! sheet 10% softer than the lattice). L settles near 1.09 h, so the band's top is
//! about 1.45 h, below the default cutoff 1.5 h: every edge is a bond. A last split
//! of the few edges the last relaxation stretched past the band keeps them in it.
//! Boundary vertices move only along the boundary and are projected onto the input's
//! boundary; the input's boundary corners (turning by more than 30°) never move. The
//! result keeps the input's winding. Every step visits edges and vertices in a fixed
//! order: the same mesh gives the same particles.

use std::collections::BTreeMap;

use perifrac_math::{add, cross, dist, dot, norm, scale, sub};

use super::{Bvh, TriMesh};

/// Remeshing iterations (Botsch & Kobbelt use 5–10; 10 leaves the edge lengths
/// within the [4/5, 4/3] h band and the valences settled on the meshes of the tests).
pub const ITERATIONS: usize = 10;

/// Boundary vertices of the input where the boundary turns by more than this (rad)
/// are corners, which stay put (a square sheet keeps its corners).
const CORNER_ANGLE: f64 = std::f64::consts::PI / 6.0;

/// A surface remeshed to spacing h: vertices, triangles (the input's winding) and
/// each vertex's area, a third of its triangles' (they sum to the surface's area).
#[derive(Debug, Clone, PartialEq)]
pub struct Remeshed {
    /// Vertex positions (m), on the input surface.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles, three vertex indices each.
    pub triangles: Vec<[u32; 3]>,
    /// Area A_i of each vertex (m²).
    pub area: Vec<f64>,
}

/// The input surface to project onto: its triangles (a BVH) and its boundary
/// segments.
struct Target {
    bvh: Bvh,
    boundary: Vec<[[f64; 3]; 2]>,
}

impl Target {
    fn closest(&self, p: [f64; 3]) -> [f64; 3] {
        self.bvh.closest(p).map_or(p, |c| c.point)
    }

    fn closest_on_boundary(&self, p: [f64; 3]) -> [f64; 3] {
        let mut best = (f64::INFINITY, p);
        for &[a, b] in &self.boundary {
            let ab = sub(b, a);
            let t = (dot(sub(p, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
            let q = add(a, scale(ab, t));
            let d = dist(p, q);
            if d < best.0 {
                best = (d, q);
            }
        }
        best.1
    }
}

/// The mesh being remeshed: positions (vertices are never renumbered until the end;
/// a collapsed vertex is simply left unused) and triangles.
struct Work {
    p: Vec<[f64; 3]>,
    t: Vec<[u32; 3]>,
    corner: Vec<bool>,
}

/// Triangles of each undirected edge (smaller vertex first), in a fixed order.
fn edge_map(t: &[[u32; 3]]) -> BTreeMap<(u32, u32), Vec<usize>> {
    let mut map: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for (k, tri) in t.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            map.entry((a.min(b), a.max(b))).or_default().push(k);
        }
    }
    map
}

/// Sorted neighbours of every vertex.
fn rings(n: usize, t: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let mut ring = vec![Vec::new(); n];
    for tri in t {
        for i in 0..3 {
            ring[tri[i] as usize].push(tri[(i + 1) % 3]);
            ring[tri[i] as usize].push(tri[(i + 2) % 3]);
        }
    }
    for r in &mut ring {
        r.sort_unstable();
        r.dedup();
    }
    ring
}

/// Triangles of every vertex.
fn fans(n: usize, t: &[[u32; 3]]) -> Vec<Vec<usize>> {
    let mut fan = vec![Vec::new(); n];
    for (k, tri) in t.iter().enumerate() {
        for &v in tri {
            fan[v as usize].push(k);
        }
    }
    fan
}

/// Whether each vertex is on the boundary (has an edge of one triangle).
fn boundary_vertices(n: usize, edges: &BTreeMap<(u32, u32), Vec<usize>>) -> Vec<bool> {
    let mut on = vec![false; n];
    for (&(a, b), tris) in edges {
        if tris.len() == 1 {
            on[a as usize] = true;
            on[b as usize] = true;
        }
    }
    on
}

fn normal(p: &[[f64; 3]], tri: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = tri.map(|v| p[v as usize]);
    cross(sub(b, a), sub(c, a))
}

impl Work {
    /// Splits every edge longer than `high` at its midpoint, a pass at a time (edges
    /// that share no triangle, longest first), until none is.
    fn split_long_edges(&mut self, high: f64) {
        loop {
            let edges = edge_map(&self.t);
            let mut long: Vec<(f64, (u32, u32))> = edges
                .keys()
                .map(|&(a, b)| (dist(self.p[a as usize], self.p[b as usize]), (a, b)))
                .filter(|&(l, _)| l > high)
                .collect();
            if long.is_empty() {
                return;
            }
            long.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
            let mut used = vec![false; self.t.len()];
            for (_, (a, b)) in long {
                let tris = &edges[&(a, b)];
                if tris.iter().any(|&k| used[k]) {
                    continue;
                }
                let m = self.p.len() as u32;
                self.p
                    .push(scale(add(self.p[a as usize], self.p[b as usize]), 0.5));
                self.corner.push(false);
                for &k in tris {
                    used[k] = true;
                    let tri = self.t[k];
                    let i = (0..3)
                        .find(|&i| {
                            let (u, v) = (tri[i], tri[(i + 1) % 3]);
                            (u, v) == (a, b) || (u, v) == (b, a)
                        })
                        .unwrap_or(0);
                    let (u, v, w) = (tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]);
                    self.t[k] = [u, m, w];
                    self.t.push([m, v, w]);
                }
            }
        }
    }

    /// Collapses edges shorter than `low` (shortest first; a pass at a time, each
    /// collapse locking the two vertices' neighbourhoods) where the result stays a
    /// manifold with the same boundary, turns no triangle over and makes no edge
    /// longer than `high`; until none can be.
    fn collapse_short_edges(&mut self, low: f64, high: f64) {
        loop {
            let n = self.p.len();
            let edges = edge_map(&self.t);
            let ring = rings(n, &self.t);
            let fan = fans(n, &self.t);
            let on_boundary = boundary_vertices(n, &edges);
            let mut short: Vec<(f64, (u32, u32))> = edges
                .keys()
                .map(|&(a, b)| (dist(self.p[a as usize], self.p[b as usize]), (a, b)))
                .filter(|&(l, _)| l < low)
                .collect();
            short.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            let mut locked = vec![false; n];
            let mut alive = vec![true; self.t.len()];
            let mut collapsed = false;
            for (_, (a, b)) in short {
                let (ua, ub) = (a as usize, b as usize);
                if locked[ua] || locked[ub] {
                    continue;
                }
                let tris = &edges[&(a, b)];
                let boundary_edge = tris.len() == 1;
                if on_boundary[ua] && on_boundary[ub] && !boundary_edge {
                    continue;
                }
                // Keep the corner, else the boundary vertex, else a.
                let (k, r) = if self.corner[ub] || (on_boundary[ub] && !on_boundary[ua]) {
                    (ub, ua)
                } else {
                    (ua, ub)
                };
                if self.corner[r] {
                    continue;
                }
                // Link condition: the common neighbours are the edge's opposite vertices.
                let common = ring[ua]
                    .iter()
                    .filter(|v| ring[ub].binary_search(v).is_ok());
                if common.count() != tris.len() {
                    continue;
                }
                if boundary_edge {
                    // An ear (both other edges on the boundary) would leave a dangling
                    // vertex.
                    let tri = self.t[tris[0]];
                    let c = tri.iter().copied().find(|&v| v != a && v != b).unwrap_or(a);
                    let key = |x: u32, y: u32| (x.min(y), x.max(y));
                    let ear = [key(a, c), key(b, c)]
                        .iter()
                        .all(|e| edges.get(e).is_some_and(|f| f.len() == 1));
                    if ear {
                        continue;
                    }
                }
                if ring[r]
                    .iter()
                    .any(|&v| v as usize != k && dist(self.p[k], self.p[v as usize]) > high)
                {
                    continue;
                }
                let turns_over = fan[r].iter().any(|&f| {
                    let tri = self.t[f];
                    if tri.contains(&(k as u32)) {
                        return false;
                    }
                    let moved = tri.map(|v| if v as usize == r { k as u32 } else { v });
                    let (before, after) = (normal(&self.p, tri), normal(&self.p, moved));
                    dot(before, after) <= 0.0 || norm(after) <= 1e-3 * norm(before)
                });
                if turns_over {
                    continue;
                }
                for &f in &fan[r] {
                    if self.t[f].contains(&(k as u32)) {
                        alive[f] = false;
                    } else {
                        for v in &mut self.t[f] {
                            if *v as usize == r {
                                *v = k as u32;
                            }
                        }
                    }
                }
                for &v in ring[r].iter().chain(&ring[k]) {
                    locked[v as usize] = true;
                }
                locked[r] = true;
                locked[k] = true;
                collapsed = true;
            }
            let mut keep = alive.iter();
            self.t.retain(|_| *keep.next().unwrap_or(&true));
            if !collapsed {
                return;
            }
        }
    }

    /// Flips interior edges where that brings the four vertices' valences closer to 6
    /// (4 on the boundary), without folding the two triangles; a few passes.
    fn equalize_valences(&mut self) {
        for _ in 0..4 {
            let n = self.p.len();
            let edges = edge_map(&self.t);
            let ring = rings(n, &self.t);
            let on_boundary = boundary_vertices(n, &edges);
            let mut valence: Vec<i64> = ring.iter().map(|r| r.len() as i64).collect();
            let target = |v: usize| if on_boundary[v] { 4 } else { 6 };
            let mut locked = vec![false; n];
            let mut flipped = false;
            for (&(a, b), tris) in &edges {
                if tris.len() != 2 {
                    continue;
                }
                // tri1 runs a → b, tri2 runs b → a.
                let runs = |k: usize, x: u32, y: u32| {
                    let tri = self.t[k];
                    (0..3).any(|i| tri[i] == x && tri[(i + 1) % 3] == y)
                };
                let (k1, k2) = if runs(tris[0], a, b) {
                    (tris[0], tris[1])
                } else {
                    (tris[1], tris[0])
                };
                if !runs(k1, a, b) || !runs(k2, b, a) {
                    continue;
                }
                let third = |k: usize| {
                    self.t[k]
                        .iter()
                        .copied()
                        .find(|&v| v != a && v != b)
                        .unwrap_or(a)
                };
                let (c, d) = (third(k1), third(k2));
                let quad = [a, b, c, d].map(|v| v as usize);
                if c == d
                    || quad.iter().any(|&v| locked[v])
                    || ring[c as usize].binary_search(&d).is_ok()
                {
                    continue;
                }
                let deviation = |delta: [i64; 4]| -> i64 {
                    (0..4)
                        .map(|i| (valence[quad[i]] + delta[i] - target(quad[i])).abs())
                        .sum()
                };
                if deviation([-1, -1, 1, 1]) >= deviation([0; 4]) {
                    continue;
                }
                let (new1, new2) = ([a, d, c], [d, b, c]);
                let old = add(normal(&self.p, self.t[k1]), normal(&self.p, self.t[k2]));
                let (n1, n2) = (normal(&self.p, new1), normal(&self.p, new2));
                let folds = dot(n1, old) <= 0.0
                    || dot(n2, old) <= 0.0
                    || dot(n1, n2) <= 0.5 * norm(n1) * norm(n2);
                if folds {
                    continue;
                }
                self.t[k1] = new1;
                self.t[k2] = new2;
                for (i, &v) in quad.iter().enumerate() {
                    locked[v] = true;
                    valence[v] += [-1, -1, 1, 1][i];
                }
                flipped = true;
            }
            if !flipped {
                return;
            }
        }
    }

    /// Moves every vertex (corners aside) to the mean of its neighbours: an interior
    /// vertex within its tangent plane and then onto the input surface, a boundary
    /// vertex to the mean of its two boundary neighbours and then onto the input's
    /// boundary.
    fn relax(&mut self, target: &Target) {
        let n = self.p.len();
        let edges = edge_map(&self.t);
        let ring = rings(n, &self.t);
        let mut along_boundary: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (&(a, b), tris) in &edges {
            if tris.len() == 1 {
                along_boundary[a as usize].push(b);
                along_boundary[b as usize].push(a);
            }
        }
        let mut vertex_normal = vec![[0.0; 3]; n];
        let mut area = vec![0.0; n];
        for &tri in &self.t {
            let m = normal(&self.p, tri);
            for v in tri {
                vertex_normal[v as usize] = add(vertex_normal[v as usize], m);
                area[v as usize] += norm(m);
            }
        }
        // The neighbours' mean weighted by their areas (Botsch & Kobbelt's area-weighted
        // relaxation, which evens out the areas as well as the spacing).
        let mean = |of: &[u32]| {
            let (sum, weight) = of.iter().fold(([0.0; 3], 0.0), |(s, w), &v| {
                let a = area[v as usize];
                (add(s, scale(self.p[v as usize], a)), w + a)
            });
            if weight > 0.0 {
                scale(sum, 1.0 / weight)
            } else {
                self.p[of[0] as usize]
            }
        };
        let moved: Vec<[f64; 3]> = (0..n)
            .map(|v| {
                let p = self.p[v];
                if ring[v].is_empty() || self.corner[v] {
                    p
                } else if !along_boundary[v].is_empty() {
                    target.closest_on_boundary(mean(&along_boundary[v]))
                } else {
                    let m = vertex_normal[v];
                    let length = norm(m);
                    let mut d = sub(mean(&ring[v]), p);
                    if length > 0.0 {
                        let unit = scale(m, 1.0 / length);
                        d = sub(d, scale(unit, dot(unit, d)));
                    }
                    target.closest(add(p, d))
                }
            })
            .collect();
        self.p = moved;
    }
}

/// Boundary segments and corners of `mesh`: the edges of one triangle, and the
/// vertices where the boundary turns by more than [`CORNER_ANGLE`].
fn boundary_of(mesh: &TriMesh) -> (Vec<[[f64; 3]; 2]>, Vec<bool>) {
    let edges = edge_map(&mesh.triangles);
    let mut segments = Vec::new();
    let mut along: Vec<Vec<u32>> = vec![Vec::new(); mesh.vertices.len()];
    for (&(a, b), tris) in &edges {
        if tris.len() == 1 {
            segments.push([mesh.vertices[a as usize], mesh.vertices[b as usize]]);
            along[a as usize].push(b);
            along[b as usize].push(a);
        }
    }
    let corner = (0..mesh.vertices.len())
        .map(|v| match along[v].as_slice() {
            [] => false,
            &[x, y] => {
                let p = mesh.vertices[v];
                let (u, w) = (
                    sub(p, mesh.vertices[x as usize]),
                    sub(mesh.vertices[y as usize], p),
                );
                let cos = dot(u, w) / (norm(u) * norm(w));
                cos < CORNER_ANGLE.cos()
            }
            _ => true,
        })
        .collect();
    (segments, corner)
}

/// Remeshes `mesh` (a manifold surface, open or closed, consistently wound) to edge
/// length `spacing` (m); see the module docs.
pub fn remesh(mesh: &TriMesh, spacing: f64) -> Remeshed {
    let (boundary, corner) = boundary_of(mesh);
    let target = Target {
        bvh: Bvh::new((0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect()),
        boundary,
    };
    let mut work = Work {
        p: mesh.vertices.clone(),
        t: mesh.triangles.clone(),
        corner,
    };
    // The band's target L starts at h and is rescaled after each round by h over the
    // mean edge, which the band alone leaves some 8% short of L.
    let mut length = spacing;
    for _ in 0..ITERATIONS {
        let (low, high) = (0.8 * length, 4.0 / 3.0 * length);
        work.split_long_edges(high);
        work.collapse_short_edges(low, high);
        work.equalize_valences();
        work.relax(&target);
        let edges = edge_map(&work.t);
        let mean = edges
            .keys()
            .map(|&(a, b)| dist(work.p[a as usize], work.p[b as usize]))
            .sum::<f64>()
            / edges.len().max(1) as f64;
        if mean > 0.0 {
            length *= (spacing / mean).clamp(0.8, 1.25);
        }
    }
    // Split what the last relaxation stretched past the band; the new vertices go
    // onto the surface (or its boundary) too.
    let before = work.p.len();
    work.split_long_edges(4.0 / 3.0 * length);
    let on_boundary = boundary_vertices(work.p.len(), &edge_map(&work.t));
    for (p, &boundary) in work.p.iter_mut().zip(&on_boundary).skip(before) {
        *p = if boundary {
            target.closest_on_boundary(*p)
        } else {
            target.closest(*p)
        };
    }
    // Drop the vertices no triangle uses, keeping the others' order.
    let mut index = vec![u32::MAX; work.p.len()];
    let mut vertices = Vec::new();
    for tri in &work.t {
        for &v in tri {
            if index[v as usize] == u32::MAX {
                index[v as usize] = 0;
            }
        }
    }
    for (v, slot) in index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = vertices.len() as u32;
            vertices.push(work.p[v]);
        }
    }
    let triangles: Vec<[u32; 3]> = work
        .t
        .iter()
        .map(|t| t.map(|v| index[v as usize]))
        .collect();
    let mut area = vec![0.0; vertices.len()];
    for &tri in &triangles {
        let a = 0.5 * norm(normal(&vertices, tri)) / 3.0;
        for v in tri {
            area[v as usize] += a;
        }
    }
    Remeshed {
        vertices,
        triangles,
        area,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square of side `side` in the y = 0 plane as two triangles, wound +y.
    fn square(side: f64) -> TriMesh {
        let s = side / 2.0;
        TriMesh {
            vertices: vec![[-s, 0.0, -s], [s, 0.0, -s], [s, 0.0, s], [-s, 0.0, s]],
            triangles: vec![[0, 2, 1], [0, 3, 2]],
        }
    }

    #[test]
    fn a_square_keeps_its_corners_area_and_winding_at_the_spacing() {
        let h = 0.05;
        let r = remesh(&square(1.0), h);
        let total: f64 = r.area.iter().sum();
        assert!((total - 1.0).abs() < 1e-9, "area {total}");
        for c in [[-0.5, 0.0, -0.5], [0.5, 0.0, 0.5]] {
            assert!(
                r.vertices.iter().any(|&v| dist(v, c) < 1e-12),
                "corner {c:?}"
            );
        }
        assert!(r.vertices.iter().all(|v| v[1].abs() < 1e-12));
        assert!(
            r.triangles.iter().all(|&t| normal(&r.vertices, t)[1] > 0.0),
            "the input's winding (+y)"
        );
        let edges = edge_map(&r.triangles);
        let lengths: Vec<f64> = edges
            .keys()
            .map(|&(a, b)| dist(r.vertices[a as usize], r.vertices[b as usize]))
            .collect();
        let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
        assert!((mean / h - 1.0).abs() < 0.1, "mean edge {mean}");
        assert!(edges.values().all(|t| t.len() <= 2));
    }

    #[test]
    fn the_same_mesh_gives_the_same_vertices() {
        assert_eq!(remesh(&square(0.3), 0.02), remesh(&square(0.3), 0.02));
    }
}
