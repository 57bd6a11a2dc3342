//! The `embedded` surface method: the boundary of the split tet mesh of a frame
//! (`tets/NNNN.vtu`, Chen et al. 2018 §5.2) — the original surface plus the crack
//! faces — with per-face flags, normals split where crack meets original surface and
//! along the original surface's creases (`smoothing_groups`), and
//! the crack-surface smoothing that Chen §7 names as the remedy for the zig-zag
//! artefact of cracks that follow tet faces.
//!
//! Smoothing moves only *crack vertices*: vertices of crack faces, inside the body
//! (free to move), or on the rim where a crack meets a flat part of the original
//! surface (they slide within that plane, along the edge of two such planes, or along
//! a box edge that the stuffing turned into a band of tilted triangles, so the flat
//! faces stay flat; see `constraints`).
//! Vertices on an edge not shared by exactly two boundary faces (a crack front
//! inside the body) stay put. Each pass (Jacobi updates, deterministic) moves every
//! inside crack vertex half way to the mean of its neighbours along crack edges: an
//! umbrella Laplacian, which on a crack surface with a fixed rim converges to the
//! flattest surface spanning the rim; it shrinks a fragment, which the volume
//! correction below undoes, so no Taubin inflation step is needed (with the guard
//! below, Taubin's λ/μ pairs were measured to diverge: inflation steps were cut less
//! often than shrink steps). A rim vertex moves within its face half way to the plane
//! fitted through its ring on the crack surface (`rim_move`): moving it to the mean
//! of its neighbours along the rim, as before, rounds the corner a tilted crack makes
//! where it crosses a box edge (the mean lies on the inner side of the corner), which
//! held the tilted cut of `surface/tests/embedded.rs` at 0.36λ from its plane. After
//! each pass every tet touching a moved vertex must keep at least
//! `MIN_VOLUME_FRACTION` (2%) of its signed volume: a tet mesh whose tets stay
//! positively oriented maps each vertex's neighbourhood one-to-one, so a fragment's
//! surface cannot fold over itself locally; nor may a tet's longest edge grow past
//! `MAX_EDGE_GROWTH` (1.8) times its length before smoothing (no crack needles);
//! where a tet would break either bound, the moves of its vertices are halved (four
//! times, then dropped). Finally each fragment's
//! volume (the sum of its tets' signed volumes, equal to the volume its surface
//! encloses) is restored by moving its crack vertices along their normals (rim
//! vertices along their normals' part within their face) by a common offset
//! h = ΔV / A (three Newton steps), under the same guard.

mod animated;
mod guard;
mod plane;
mod rim;
mod stage;

use guard::Guard;
use perifrac_cache::mesh::SurfaceMesh;
use perifrac_cache::vtu::TetFrame;
use perifrac_math::{TET_FACES, UnionFind, cross, dot, norm, signed_volume, sub};
use plane::roughness;
use rim::{constraints, rim_move};

pub use stage::{EmbeddedReport, stage};

/// Fraction of the way to the neighbours' mean a smoothing pass moves a vertex.
const STEP: f64 = 0.5;
/// Original faces whose unit normals have a larger dot product lie in one plane
/// (about 2°).
const PLANE_COS: f64 = 0.9994;

/// How a crack vertex may move: freely inside the body, within the plane of the
/// flat original surface it lies on, or along the edge of two such planes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Constraint {
    Free,
    Plane([f64; 3]),
    Line([f64; 3]),
}

impl Constraint {
    fn project(self, m: [f64; 3]) -> [f64; 3] {
        match self {
            Constraint::Free => m,
            Constraint::Plane(n) => {
                let d = dot(m, n);
                [0, 1, 2].map(|a| m[a] - d * n[a])
            }
            Constraint::Line(t) => {
                let d = dot(m, t);
                t.map(|c| d * c)
            }
        }
    }
}
/// Original faces whose unit normals have a smaller dot product meet at a hard edge
/// of the render mesh (30°, where a mesh file's feature edges start, `Sdf::features`).
const HARD_EDGE_COS: f64 = 0.866_025_403_784_438_6;
/// Fragments with fewer tets are not smoothed.
pub const MIN_FRAGMENT_TETS: usize = 8;
/// Largest relative volume change of a smoothed fragment; a fragment beyond it is
/// put back unsmoothed.
pub const MAX_VOLUME_CHANGE: f64 = 1e-3;
/// Fraction of its volume below which a tet counts as (nearly) inverted.
/// (10% stopped rim vertices short of the plane of a flat cut; 2% lets them reach it.)
const MIN_VOLUME_FRACTION: f64 = 0.02;

/// The surface of one frame.
#[derive(Debug, Clone, Default)]
pub struct EmbeddedSurface {
    /// Every vertex of the split tet mesh after smoothing (the ids of the .vtu).
    pub points: Vec<[f64; 3]>,
    /// Boundary triangles (vertex ids), counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Whether each triangle is a crack face (inside of the object) or original.
    pub crack: Vec<bool>,
    /// The tet (and particle) each triangle bounds.
    pub owner: Vec<u32>,
    /// Fragment (connected set of tets) of each tet.
    pub fragment: Vec<u32>,
    /// What smoothing did.
    pub stats: SmoothingStats,
}

/// What the smoothing of one frame did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SmoothingStats {
    /// Vertices it was allowed to move.
    pub crack_vertices: usize,
    /// Moves halved or dropped to keep tets from inverting.
    pub backed_off: usize,
    /// Largest relative volume change of a fragment after the volume correction.
    pub volume_error: f64,
    /// Vertices put back unsmoothed because their fragment's volume could not be
    /// restored within [`MAX_VOLUME_CHANGE`].
    pub reverted: usize,
    /// How far the crack surface zig-zags, before and after smoothing (m): the median
    /// distance of a smoothed vertex from the plane fitted through its ring on the
    /// crack surface (vertices with fewer than three neighbours there left out).
    pub roughness: [f64; 2],
}

/// A frame's surface ready for export, with the split-mesh vertex each of its
/// vertices stands for: one vertex per split-mesh vertex, class (original or crack)
/// and smoothing group, so crack and original faces meeting at a vertex, and the
/// faces on either side of a crease of the original surface, get a copy each, with
/// their own normals. The mesh's damage is the mean damage of the tets the vertex's
/// faces bound.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RenderMesh {
    /// The split-mesh vertex of each mesh vertex.
    pub vertex: Vec<u32>,
    /// Positions, area-weighted unit normals per class, damage, and the original
    /// and crack triangles.
    pub mesh: SurfaceMesh,
}

fn tet_volume(x: &[[f64; 3]], t: [u32; 4]) -> f64 {
    let [a, b, c, d] = t.map(|v| x[v as usize]);
    signed_volume(a, b, c, d)
}

/// Area vector (twice the area, along the normal) of a triangle.
fn area_vector(x: &[[f64; 3]], f: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = f.map(|v| x[v as usize]);
    cross(sub(b, a), sub(c, a))
}

/// Sorted keys of `keys`, with how many times each occurs, found by sorting.
fn counts<K: Ord + Copy>(keys: &[K]) -> Vec<(K, usize)> {
    let mut sorted = keys.to_vec();
    sorted.sort_unstable();
    let mut out: Vec<(K, usize)> = Vec::new();
    for k in sorted {
        match out.last_mut() {
            Some((last, n)) if *last == k => *n += 1,
            _ => out.push((k, 1)),
        }
    }
    out
}

fn count_of<K: Ord + Copy>(table: &[(K, usize)], k: K) -> usize {
    table
        .binary_search_by(|e| e.0.cmp(&k))
        .map_or(0, |i| table[i].1)
}

fn sorted3(mut f: [u32; 3]) -> [u32; 3] {
    f.sort_unstable();
    f
}

/// The boundary of a split tet mesh: triangles (outward), crack flags, owners.
/// A face is on the boundary when no other tet has it (by vertex ids); it is a crack
/// face when its original face (by root vertices) was shared by two tets.
pub fn boundary(frame: &TetFrame) -> (Vec<[u32; 3]>, Vec<bool>, Vec<u32>) {
    let mut root: Vec<u32> = Vec::with_capacity(frame.parent.len());
    for (v, &p) in frame.parent.iter().enumerate() {
        root.push(if p < 0 { v as u32 } else { root[p as usize] });
    }
    let faces: Vec<[u32; 3]> = frame
        .tets
        .iter()
        .flat_map(|t| TET_FACES.map(|f| sorted3(f.map(|i| t[i]))))
        .collect();
    let roots: Vec<[u32; 3]> = faces
        .iter()
        .map(|f| sorted3(f.map(|v| root[v as usize])))
        .collect();
    let face_counts = counts(&faces);
    let root_counts = counts(&roots);
    let mut triangles = Vec::new();
    let mut crack = Vec::new();
    let mut owner = Vec::new();
    for (t, tet) in frame.tets.iter().enumerate() {
        for (f, local) in TET_FACES.iter().enumerate() {
            if count_of(&face_counts, faces[4 * t + f]) == 1 {
                triangles.push(local.map(|i| tet[i]));
                crack.push(count_of(&root_counts, roots[4 * t + f]) == 2);
                owner.push(t as u32);
            }
        }
    }
    (triangles, crack, owner)
}

/// Fragments: tets connected through shared vertices, labelled in order of their
/// lowest tet.
pub fn fragments(frame: &TetFrame) -> Vec<u32> {
    let nv = frame.points.len();
    let mut sets = UnionFind::new(nv + frame.tets.len());
    for (t, tet) in frame.tets.iter().enumerate() {
        for &v in tet {
            sets.union(nv + t, v as usize);
        }
    }
    sets.labels_of(nv..nv + frame.tets.len())
}

/// Extracts the surface of a frame and smooths its cracks with `passes` passes.
pub fn surface(frame: &TetFrame, passes: usize) -> EmbeddedSurface {
    let (triangles, crack, owner) = boundary(frame);
    let fragment = fragments(frame);
    let mut points = frame.points.clone();
    let nv = points.len();
    // Vertex classes: on crack faces / an edge not shared by exactly two boundary
    // faces (a crack front inside the body: fixed). Rim edges join a crack face and
    // an original face.
    let mut on_crack = vec![false; nv];
    let mut fixed = vec![false; nv];
    let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * triangles.len());
    for (i, (f, c)) in triangles.iter().zip(&crack).enumerate() {
        for e in 0..3 {
            let (a, b) = (f[e], f[(e + 1) % 3]);
            edges.push((a.min(b), a.max(b), i as u32));
            if *c {
                on_crack[a as usize] = true;
            }
        }
    }
    edges.sort_unstable();
    let mut crack_edges: Vec<(u32, u32)> = Vec::new();
    let mut rim_edges: Vec<(u32, u32)> = Vec::new();
    for run in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        let (a, b) = (run[0].0, run[0].1);
        if let [(_, _, t0), (_, _, t1)] = *run {
            let (c0, c1) = (crack[t0 as usize], crack[t1 as usize]);
            if c0 && c1 {
                crack_edges.push((a, b));
            } else if c0 != c1 {
                rim_edges.push((a, b));
            }
        } else {
            fixed[a as usize] = true;
            fixed[b as usize] = true;
        }
    }
    let constraint = constraints(
        &points,
        &frame.parent,
        &triangles,
        &crack,
        &on_crack,
        &fixed,
    );
    // Fragments of few tets (debris) have no zig-zag at the scale of their size:
    // their vertices stay put.
    let mut fragment_tets =
        vec![0usize; fragment.iter().map(|&f| f as usize + 1).max().unwrap_or(0)];
    for &f in &fragment {
        fragment_tets[f as usize] += 1;
    }
    let mut in_small = vec![false; nv];
    for (t, &f) in frame.tets.iter().zip(&fragment) {
        if fragment_tets[f as usize] < MIN_FRAGMENT_TETS {
            for &v in t {
                in_small[v as usize] = true;
            }
        }
    }
    let movable: Vec<u32> = (0..nv as u32)
        .filter(|&v| constraint[v as usize].is_some() && !in_small[v as usize])
        .collect();
    let mut stats = SmoothingStats {
        crack_vertices: movable.len(),
        ..SmoothingStats::default()
    };
    let mut slot = vec![u32::MAX; nv];
    for (i, &v) in movable.iter().enumerate() {
        slot[v as usize] = i as u32;
    }
    // Rings on the crack surface (along crack edges and the rim): an inside vertex
    // moves towards the mean of its neighbours, a rim vertex towards the plane fitted
    // through its neighbours and theirs.
    let mut adjacent: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for &(a, b) in crack_edges.iter().chain(&rim_edges) {
        adjacent[a as usize].push(b);
        adjacent[b as usize].push(a);
    }
    let rings: Vec<Vec<u32>> = movable
        .iter()
        .map(|&v| {
            let mut ring = adjacent[v as usize].clone();
            if constraint[v as usize] != Some(Constraint::Free) {
                for &w in &adjacent[v as usize] {
                    ring.extend(&adjacent[w as usize]);
                }
            }
            ring.sort_unstable();
            ring.dedup();
            ring.retain(|&w| w != v);
            ring
        })
        .collect();
    stats.roughness = [roughness(&points, &movable, &rings); 2];
    if movable.is_empty() || passes == 0 {
        return EmbeddedSurface {
            points,
            triangles,
            crack,
            owner,
            fragment,
            stats,
        };
    }
    let guard = Guard::new(frame, &points, &movable, &slot);
    let guarded = &guard.tets;
    let fragment_volume = |x: &[[f64; 3]]| -> Vec<f64> {
        let count = fragment.iter().map(|&f| f as usize + 1).max().unwrap_or(0);
        let mut v = vec![0.0; count];
        for &t in guarded {
            v[fragment[t] as usize] += tet_volume(x, frame.tets[t]);
        }
        v
    };
    let before = fragment_volume(&points);
    let mut frag_of = vec![0usize; movable.len()];
    for &t in guarded {
        for &v in &frame.tets[t] {
            if slot[v as usize] != u32::MAX {
                frag_of[slot[v as usize] as usize] = fragment[t] as usize;
            }
        }
    }
    let mut whole = vec![0.0; before.len()];
    for (t, &k) in frame.tets.iter().zip(&fragment) {
        whole[k as usize] += tet_volume(&points, *t);
    }
    for _ in 0..passes {
        let moves: Vec<[f64; 3]> = movable
            .iter()
            .zip(&rings)
            .map(|(&v, ring)| {
                if ring.is_empty() {
                    return [0.0; 3];
                }
                let x = points[v as usize];
                let mut mean = [0.0; 3];
                for &w in ring {
                    let y = points[w as usize];
                    for a in 0..3 {
                        mean[a] += y[a] / ring.len() as f64;
                    }
                }
                match constraint[v as usize] {
                    Some(Constraint::Free) => [0, 1, 2].map(|a| STEP * (mean[a] - x[a])),
                    Some(c) => rim_move(c, x, mean, ring.iter().map(|&w| points[w as usize])),
                    None => [0.0; 3],
                }
            })
            .collect();
        stats.backed_off += guard.apply(&mut points, moves);
    }
    // Restore each fragment's volume with a common normal offset of its vertices.
    for _ in 0..3 {
        let now = fragment_volume(&points);
        let mut normal = crack_normals(&points, &triangles, &crack, &slot, movable.len());
        // Rim vertices move along their normal's part within their plane or line:
        // moving a vertex by h along unit d changes the volume by (n · d) h = |d| h
        // for d the projection of n.
        for (n, &v) in normal.iter_mut().zip(&movable) {
            if let Some(c) = constraint[v as usize] {
                *n = c.project(*n);
            }
        }
        // dV/dh of fragment k = Σ over its vertices of |area vector|/3 along n̂.
        let mut rate = vec![0.0; now.len()];
        for (i, n) in normal.iter().enumerate() {
            rate[frag_of[i]] += norm(*n);
        }
        let moves: Vec<[f64; 3]> = normal
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let k = frag_of[i];
                let len = norm(*n);
                if rate[k] <= 0.0 || len <= 0.0 {
                    return [0.0; 3];
                }
                let h = (before[k] - now[k]) / rate[k];
                n.map(|c| h * c / len)
            })
            .collect();
        stats.backed_off += guard.apply(&mut points, moves);
    }
    // A fragment whose volume could not be restored (the guard held its vertices)
    // is left unsmoothed.
    let after = fragment_volume(&points);
    let failed: Vec<bool> = (0..before.len())
        .map(|k| whole[k] > 0.0 && ((after[k] - before[k]) / whole[k]).abs() > MAX_VOLUME_CHANGE)
        .collect();
    for (i, &v) in movable.iter().enumerate() {
        if failed[frag_of[i]] {
            points[v as usize] = frame.points[v as usize];
            stats.reverted += 1;
        }
    }
    stats.roughness[1] = roughness(&points, &movable, &rings);
    let after = fragment_volume(&points);
    stats.volume_error = (0..before.len())
        .filter(|&k| whole[k] > 0.0)
        .map(|k| ((after[k] - before[k]) / whole[k]).abs())
        .fold(0.0, f64::max);
    EmbeddedSurface {
        points,
        triangles,
        crack,
        owner,
        fragment,
        stats,
    }
}

/// Area vector of the crack faces at each movable vertex (a third of each face's
/// area along its normal: the rate at which moving the vertex along it changes the
/// volume its fragment encloses).
fn crack_normals(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    crack: &[bool],
    slot: &[u32],
    movable: usize,
) -> Vec<[f64; 3]> {
    let mut normal = vec![[0.0; 3]; movable];
    for (f, _) in triangles.iter().zip(crack).filter(|(_, c)| **c) {
        let n = area_vector(points, *f);
        for &v in f {
            let s = slot[v as usize];
            if s != u32::MAX {
                for a in 0..3 {
                    normal[s as usize][a] += n[a] / 6.0;
                }
            }
        }
    }
    normal
}

impl EmbeddedSurface {
    /// Render vertices (one per split-mesh vertex, class and smoothing group), normals, damage and
    /// the two index lists, with positions from `points` (this frame's, or another
    /// frame's positions of the same vertices).
    pub fn render_mesh(&self, damage: &[f32]) -> RenderMesh {
        let group = self.smoothing_groups();
        let corner = |t: usize, k: usize| (self.triangles[t][k], self.crack[t], group[3 * t + k]);
        let mut key: Vec<(u32, bool, u32)> = (0..self.triangles.len())
            .flat_map(|t| (0..3).map(move |k| corner(t, k)))
            .collect();
        key.sort_unstable();
        key.dedup();
        let index = |k: (u32, bool, u32)| key.binary_search(&k).unwrap_or(0) as u32;
        let mut out = RenderMesh {
            vertex: key.iter().map(|k| k.0).collect(),
            ..RenderMesh::default()
        };
        let mut damage_sum = vec![(0.0f64, 0usize); key.len()];
        for (i, (&c, &t)) in self.crack.iter().zip(&self.owner).enumerate() {
            let ids = [0, 1, 2].map(|k| index(corner(i, k)));
            let list = if c {
                &mut out.mesh.crack_indices
            } else {
                &mut out.mesh.surface_indices
            };
            list.extend_from_slice(&ids);
            for i in ids {
                let d = &mut damage_sum[i as usize];
                d.0 += f64::from(damage.get(t as usize).copied().unwrap_or(0.0));
                d.1 += 1;
            }
        }
        out.mesh.damage = damage_sum
            .iter()
            .map(|(s, n)| (s / (*n).max(1) as f64) as f32)
            .collect();
        out.mesh.positions = self.positions_of(&out, &self.points);
        out.mesh.normals = self.normals(&out, &self.points);
        out
    }

    /// The smoothing group of each triangle corner (`3 t + k`): the original faces
    /// around a vertex that meet across edges bent by less than 30°
    /// ([`HARD_EDGE_COS`]) share a group, and so a normal; across a sharper edge of the
    /// original surface (a box's edge, a corner) each side keeps its own, so the
    /// creases of a shape render sharp instead of as soft streaks. Crack faces all
    /// share group 0 (their normals stay averaged over the crack surface). A group is
    /// named by its smallest corner, so it does not depend on the order of the unions.
    fn smoothing_groups(&self) -> Vec<u32> {
        let mut sets = UnionFind::new(3 * self.triangles.len());
        let mut edges: Vec<((u32, u32), usize)> = Vec::new();
        for (t, f) in self.triangles.iter().enumerate() {
            if !self.crack[t] {
                for k in 0..3 {
                    let (a, b) = (f[k], f[(k + 1) % 3]);
                    edges.push(((a.min(b), a.max(b)), t));
                }
            }
        }
        edges.sort_unstable();
        let corner_of =
            |t: usize, v: u32| 3 * t + self.triangles[t].iter().position(|&w| w == v).unwrap_or(0);
        for run in edges.chunk_by(|x, y| x.0 == y.0) {
            if let [(edge, t1), (_, t2)] = *run {
                let (n1, n2) = (
                    area_vector(&self.points, self.triangles[t1]),
                    area_vector(&self.points, self.triangles[t2]),
                );
                // A degenerate face (no normal) joins its neighbours' group.
                if dot(n1, n2) >= HARD_EDGE_COS * norm(n1) * norm(n2) {
                    for v in [edge.0, edge.1] {
                        sets.union(corner_of(t1, v), corner_of(t2, v));
                    }
                }
            }
        }
        (0..3 * self.triangles.len())
            .map(|c| {
                if self.crack[c / 3] {
                    0
                } else {
                    sets.find(c) as u32
                }
            })
            .collect()
    }

    /// Positions of `mesh`'s render vertices in `points`.
    pub fn positions_of(&self, mesh: &RenderMesh, points: &[[f64; 3]]) -> Vec<[f32; 3]> {
        mesh.vertex
            .iter()
            .map(|&v| points[v as usize].map(|c| c as f32))
            .collect()
    }

    /// Area-weighted unit normals of `mesh`'s render vertices at `points`.
    pub fn normals(&self, mesh: &RenderMesh, points: &[[f64; 3]]) -> Vec<[f32; 3]> {
        let mut n = vec![[0.0f64; 3]; mesh.vertex.len()];
        for list in [&mesh.mesh.surface_indices, &mesh.mesh.crack_indices] {
            for tri in list.chunks_exact(3) {
                let f = [0, 1, 2].map(|k| mesh.vertex[tri[k] as usize]);
                let a = area_vector(points, f);
                for &i in tri {
                    for c in 0..3 {
                        n[i as usize][c] += a[c];
                    }
                }
            }
        }
        n.iter()
            .map(|v| {
                let l = norm(*v);
                if l > 0.0 {
                    v.map(|c| (c / l) as f32)
                } else {
                    [0.0, 1.0, 0.0]
                }
            })
            .collect()
    }
}
