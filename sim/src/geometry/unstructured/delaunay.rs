//! Delaunay tetrahedralization of a point set by incremental insertion (Bowyer 1981,
//! Watson 1981): each point removes the tetrahedra whose circumsphere holds it (the
//! cavity, found from the tetrahedron containing it by a visibility walk) and joins
//! the cavity's boundary faces to itself. Orientation and in-sphere tests are exact
//! (Shewchuk's adaptive predicates, the `robust` crate), so the result is a valid
//! triangulation whatever the input's rounding.

use robust::Coord3D;

use super::super::discretize::{bounds, morton};

/// No neighbour across a face (the hull of the enclosing tetrahedron).
const NONE: u32 = u32::MAX;

/// Size of the enclosing tetrahedron's vertices' offsets from the points' centre, in
/// multiples of the points' bounding-box diagonal.
const ENCLOSING_SCALE: f64 = 1000.0;

fn coord(p: [f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Six times the signed volume of `a b c d`, exactly signed: positive when
/// (b − a)·((c − a) × (d − a)) > 0, the orientation of [`TetMesh`](super::super::TetMesh).
pub fn orient(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    // Shewchuk's orient3d is positive for the opposite orientation.
    -robust::orient3d(coord(a), coord(b), coord(c), coord(d))
}

/// Whether `e` lies strictly inside the circumsphere of the positively oriented
/// tetrahedron `a b c d`.
fn in_sphere(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], e: [f64; 3]) -> bool {
    // Swapping a and b gives Shewchuk's positive orientation.
    robust::insphere(coord(b), coord(a), coord(c), coord(d), coord(e)) > 0.0
}

/// A Delaunay tetrahedralization under construction.
struct Triangulation {
    /// The input points followed by the enclosing tetrahedron's four vertices.
    points: Vec<[f64; 3]>,
    /// Vertices of each tetrahedron, positively oriented.
    tets: Vec<[u32; 4]>,
    /// Neighbour across the face opposite each vertex, or [`NONE`].
    adjacent: Vec<[u32; 4]>,
    /// Whether a tetrahedron has been removed (its slot is in `free`).
    dead: Vec<bool>,
    free: Vec<u32>,
}

impl Triangulation {
    fn point(&self, tet: u32, corner: usize) -> [f64; 3] {
        self.points[self.tets[tet as usize][corner] as usize]
    }

    /// The tetrahedron holding `p` (in it or on its boundary), by a visibility walk
    /// from `start`: step across a face that has `p` on its far side. The face tried
    /// first turns with every step, which keeps the walk from cycling (Devillers, Pion
    /// & Teillaud 2002).
    fn locate(&self, start: u32, p: [f64; 3]) -> u32 {
        let mut tet = start;
        let mut turn = 0;
        'walk: loop {
            for k in 0..4 {
                let face = (k + turn) % 4;
                let mut corners = [0; 4].map(|_| [0.0; 3]);
                for (c, corner) in corners.iter_mut().enumerate() {
                    *corner = if c == face { p } else { self.point(tet, c) };
                }
                if orient(corners[0], corners[1], corners[2], corners[3]) < 0.0 {
                    let next = self.adjacent[tet as usize][face];
                    if next != NONE {
                        tet = next;
                        turn += 1;
                        continue 'walk;
                    }
                }
            }
            return tet;
        }
    }

    fn add(&mut self, vertices: [u32; 4], adjacent: [u32; 4]) -> u32 {
        match self.free.pop() {
            Some(slot) => {
                let s = slot as usize;
                self.tets[s] = vertices;
                self.adjacent[s] = adjacent;
                self.dead[s] = false;
                slot
            }
            None => {
                self.tets.push(vertices);
                self.adjacent.push(adjacent);
                self.dead.push(false);
                (self.tets.len() - 1) as u32
            }
        }
    }

    /// Inserts point `v`, found in or on tetrahedron `start`; returns a new tetrahedron.
    fn insert(&mut self, v: u32, start: u32) -> u32 {
        let p = self.points[v as usize];
        // The cavity: tetrahedra whose circumsphere holds p, connected to `start`.
        let mut cavity = vec![start];
        self.dead[start as usize] = true;
        let mut boundary = Vec::new();
        let mut next = 0;
        while next < cavity.len() {
            let tet = cavity[next];
            next += 1;
            for face in 0..4 {
                let across = self.adjacent[tet as usize][face];
                if across != NONE && !self.dead[across as usize] {
                    let [a, b, c, d] = [0, 1, 2, 3].map(|k| self.point(across, k));
                    if in_sphere(a, b, c, d, p) {
                        self.dead[across as usize] = true;
                        cavity.push(across);
                        continue;
                    }
                }
                if across == NONE || !self.dead[across as usize] {
                    boundary.push((tet, face, across));
                }
            }
        }
        // Faces seen from inside the cavity whose far side later joined it are not
        // boundary faces. Each boundary face joined to p: the old tetrahedron with p in
        // place of the corner opposite the face keeps its orientation. The cavity's
        // slots are reused, so the new tetrahedra are read off before any is written.
        let joined: Vec<([u32; 4], usize, u32)> = boundary
            .iter()
            .filter(|&&(_, _, across)| across == NONE || !self.dead[across as usize])
            .map(|&(tet, face, across)| {
                let mut vertices = self.tets[tet as usize];
                vertices[face] = v;
                (vertices, face, across)
            })
            .collect();
        self.free.extend(cavity.iter().copied());
        let mut first = NONE;
        let mut edges: std::collections::HashMap<(u32, u32), (u32, usize)> =
            std::collections::HashMap::with_capacity(joined.len() * 3);
        for (vertices, face, across) in joined {
            let mut adjacent = [NONE; 4];
            adjacent[face] = across;
            let created = self.add(vertices, adjacent);
            if across != NONE {
                // The neighbour's corner off the shared face (the face's vertices are
                // the new tetrahedron's but p).
                let back = self.tets[across as usize]
                    .iter()
                    .position(|w| !vertices.contains(w))
                    .expect("a neighbour has one corner off the shared face");
                self.adjacent[across as usize][back] = created;
            }
            // Faces through p, keyed by their two other vertices.
            for k in (0..4).filter(|&k| k != face) {
                let others: Vec<u32> = (0..4)
                    .filter(|&m| m != face && m != k)
                    .map(|m| vertices[m])
                    .collect();
                let key = (others[0].min(others[1]), others[0].max(others[1]));
                match edges.remove(&key) {
                    Some((twin, twin_face)) => {
                        self.adjacent[created as usize][k] = twin;
                        self.adjacent[twin as usize][twin_face] = created;
                    }
                    None => {
                        edges.insert(key, (created, k));
                    }
                }
            }
            first = first.min(created);
        }
        debug_assert!(edges.is_empty(), "the cavity's boundary is closed");
        first
    }
}

/// The Delaunay tetrahedralization of `points`: positively oriented tetrahedra as
/// indices into `points`, covering their convex hull. Points are inserted along a
/// Morton curve, so each walk starts near its point. Duplicate points are skipped.
pub fn tetrahedralize(points: &[[f64; 3]]) -> Vec<[u32; 4]> {
    if points.len() < 4 {
        return Vec::new();
    }
    let (lo, hi) = bounds(points.iter());
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let size = ENCLOSING_SCALE * perifrac_math::dist(lo, hi).max(f64::MIN_POSITIVE);
    let n = points.len() as u32;
    let mut all = points.to_vec();
    for s in [
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ] {
        all.push([0, 1, 2].map(|k| centre[k] + size * s[k]));
    }
    let mut enclosing = [n, n + 1, n + 2, n + 3];
    if orient(
        all[n as usize],
        all[n as usize + 1],
        all[n as usize + 2],
        all[n as usize + 3],
    ) < 0.0
    {
        enclosing.swap(0, 1);
    }
    let mut t = Triangulation {
        points: all,
        tets: vec![enclosing],
        adjacent: vec![[NONE; 4]],
        dead: vec![false],
        free: Vec::new(),
    };
    let mut last = 0;
    for v in morton_order(points, lo, hi) {
        let tet = t.locate(last, t.points[v as usize]);
        let p = t.points[v as usize];
        if t.tets[tet as usize]
            .iter()
            .any(|&w| t.points[w as usize] == p)
        {
            continue;
        }
        last = t.insert(v, tet);
    }
    t.tets
        .iter()
        .zip(&t.dead)
        .filter(|(tet, dead)| !**dead && tet.iter().all(|&v| v < n))
        .map(|(tet, _)| *tet)
        .collect()
}

/// Indices of `points` sorted along a Morton (Z-order) curve over their bounds.
fn morton_order(points: &[[f64; 3]], lo: [f64; 3], hi: [f64; 3]) -> Vec<u32> {
    let mut keyed: Vec<(u64, u32)> = points
        .iter()
        .enumerate()
        .map(|(i, &p)| (morton(p, lo, hi), i as u32))
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use perifrac_math::SplitMix64;

    fn random_points(n: usize, seed: u64) -> Vec<[f64; 3]> {
        let mut rng = SplitMix64::new(seed);
        (0..n)
            .map(|_| [rng.next_f64(), rng.next_f64(), rng.next_f64()])
            .collect()
    }

    #[test]
    fn the_predicates_follow_the_tet_mesh_orientation() {
        let (a, b, c, d) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert!(orient(a, b, c, d) > 0.0);
        assert!(orient(b, a, c, d) < 0.0);
        assert!(in_sphere(a, b, c, d, [0.2, 0.2, 0.2]));
        assert!(!in_sphere(a, b, c, d, [1.0, 1.0, 1.0]));
    }

    /// Every tetrahedron positive, their volumes summing to the hull's, and no point
    /// strictly inside any tetrahedron's circumsphere (the Delaunay property, checked
    /// against every point).
    #[test]
    fn random_points_give_a_delaunay_tetrahedralization_of_their_hull() {
        let mut points = random_points(300, 7);
        // The unit cube's corners make the hull the cube, of volume 1.
        for corner in 0..8 {
            points.push([0, 1, 2].map(|k| f64::from(corner >> k & 1)));
        }
        let tets = tetrahedralize(&points);
        let mut volume = 0.0;
        for t in &tets {
            let [a, b, c, d] = t.map(|v| points[v as usize]);
            let six = orient(a, b, c, d);
            assert!(six > 0.0, "tet {t:?} not positive");
            volume += six / 6.0;
            for (i, &e) in points.iter().enumerate() {
                if !t.contains(&(i as u32)) {
                    assert!(
                        !in_sphere(a, b, c, d, e),
                        "point {i} inside the circumsphere of {t:?}"
                    );
                }
            }
        }
        assert!((volume - 1.0).abs() < 1e-12, "volume {volume}");
        // Every point is a vertex.
        let mut used = vec![false; points.len()];
        for t in &tets {
            for &v in t {
                used[v as usize] = true;
            }
        }
        assert!(used.iter().all(|&u| u));
    }

    /// A lattice's points are co-spherical in every cube: the exact predicates still
    /// give a valid tetrahedralization filling the hull.
    #[test]
    fn lattice_points_with_cospherical_sets_are_tetrahedralized() {
        let points: Vec<[f64; 3]> = (0..64)
            .map(|i| [f64::from(i % 4), f64::from(i / 4 % 4), f64::from(i / 16)])
            .collect();
        let tets = tetrahedralize(&points);
        let volume: f64 = tets
            .iter()
            .map(|t| {
                let [a, b, c, d] = t.map(|v| points[v as usize]);
                let six = orient(a, b, c, d);
                assert!(six > 0.0);
                six / 6.0
            })
            .sum();
        assert!((volume - 27.0).abs() < 1e-9, "volume {volume}");
    }
}
