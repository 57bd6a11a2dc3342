//! The stencils of Labelle & Shewchuk (2007) that fill the inside part of a BCC
//! tetrahedron cut by the surface, and the filler that emits their tetrahedra.

use perifrac_math::signed_volume;

use super::super::sdf::Sdf;
use super::super::{MeshError, TetMesh};
use super::{CutTable, KeyMap, Lattice};

/// A vertex of a stencil's output, in terms of the BCC tetrahedron's local
/// vertices 0–3: a lattice vertex, or the cut point on an edge (inside end first).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Node {
    Vertex(usize),
    Cut(usize, usize),
}

/// Up to three output tetrahedra (unoriented) of one BCC tetrahedron.
pub(super) struct Stencil {
    tets: [[Node; 4]; 3],
    len: usize,
}

impl Stencil {
    fn new(tets: &[[Node; 4]]) -> Self {
        let mut s = Self {
            tets: [[Node::Vertex(0); 4]; 3],
            len: tets.len(),
        };
        s.tets[..tets.len()].copy_from_slice(tets);
        s
    }

    pub(super) fn tets(&self) -> &[[Node; 4]] {
        &self.tets[..self.len]
    }
}

/// For a face with inside vertices `n1`, `n2` and outside vertex `p`, whose
/// inside part is the quadrilateral `n1, n2, cut(n2, p), cut(n1, p)`: which of
/// `n1`, `n2` the splitting diagonal leaves from (it ends at the cut point on
/// the other's edge). Depends only on the face, so the two tetrahedra sharing
/// it agree.
///
/// If `p` shares the face's long edge with one inside vertex, the diagonal
/// joins the cut point on that long edge to the other inside vertex. If the
/// long edge joins `n1` and `n2`, the paper's parity rule decides: from `n1`
/// when the number of axes along which `n1` lies above `p` is odd on a
/// corner-grid edge, or even on a centre-grid edge.
fn diagonal_owner(coords: &[[i64; 3]; 4], n1: usize, n2: usize, p: usize) -> usize {
    if n1 ^ n2 == 1 {
        let corner_edge = n1 >= 2;
        let above = (0..3).filter(|&k| coords[n1][k] > coords[p][k]).count();
        if corner_edge == (above % 2 == 1) {
            n1
        } else {
            n2
        }
    } else if n1 ^ p == 1 {
        n2
    } else {
        n1
    }
}

/// The stencil filling the inside (negative) part of a BCC tetrahedron with
/// vertex signs `signs` and doubled lattice coordinates `coords`, ordered as
/// in [`Lattice::for_each_tet`] (local vertices `v` and `v ^ 1` share a long edge).
pub(super) fn stencil(signs: [i8; 4], coords: &[[i64; 3]; 4]) -> Stencil {
    use Node::{Cut as C, Vertex as V};
    let pick = |s: i8| {
        let mut out = [0usize; 4];
        let mut len = 0;
        for (v, &sv) in signs.iter().enumerate() {
            if sv == s {
                out[len] = v;
                len += 1;
            }
        }
        (out, len)
    };
    let (neg, nn) = pick(-1);
    let (zero, nz) = pick(0);
    let (pos, np) = pick(1);
    if nn == 0 {
        Stencil::new(&[])
    } else if np == 0 {
        Stencil::new(&[[V(0), V(1), V(2), V(3)]])
    } else if nn == 1 {
        // One inside vertex: a corner tetrahedron on the cut points and zeros.
        let n = neg[0];
        let tet = [0, 1, 2, 3].map(|v| if signs[v] > 0 { C(n, v) } else { V(v) });
        Stencil::new(&[tet])
    } else if nn == 2 && nz == 1 {
        // A pyramid on the quadrilateral n1 n2 c2 c1 with apex at the zero.
        let (z, p) = (zero[0], pos[0]);
        let o = diagonal_owner(coords, neg[0], neg[1], p);
        let q = neg[0] + neg[1] - o;
        Stencil::new(&[[V(z), V(o), V(q), C(q, p)], [V(z), V(o), C(q, p), C(o, p)]])
    } else if nn == 2 {
        // A prism between the triangles (n1, c11, c12) and (n2, c21, c22).
        let (n1, n2) = (neg[0], neg[1]);
        if n1 ^ n2 == 1 {
            // Inside vertices on a long edge: the parity rule splits the two
            // side faces from different ends of it.
            let (p1, p2) = (pos[0], pos[1]);
            let (n1, n2) = if diagonal_owner(coords, n1, n2, p1) == n1 {
                (n1, n2)
            } else {
                (n2, n1)
            };
            Stencil::new(&[
                [C(n1, p2), V(n2), C(n2, p1), C(n2, p2)],
                [C(n1, p2), V(n1), C(n1, p1), C(n2, p1)],
                [C(n1, p2), V(n1), C(n2, p1), V(n2)],
            ])
        } else {
            // Inside vertices on a short edge, each sharing a long edge with
            // one outside vertex.
            let (p1, p2) = (n1 ^ 1, n2 ^ 1);
            Stencil::new(&[
                [C(n1, p1), V(n2), C(n2, p1), C(n2, p2)],
                [C(n1, p1), C(n1, p2), V(n1), C(n2, p2)],
                [C(n1, p1), V(n1), V(n2), C(n2, p2)],
            ])
        }
    } else {
        // Three inside vertices: a prism with the cut triangle on top. The
        // vertex `a` shares a long edge with the outside vertex `p`; the
        // parity owner `o` of the other long edge owns two side diagonals.
        let p = pos[0];
        let a = p ^ 1;
        let o = diagonal_owner(coords, p ^ 2, p ^ 3, p);
        let q = (p ^ 2) + (p ^ 3) - o;
        Stencil::new(&[
            [V(o), C(o, p), C(q, p), C(a, p)],
            [V(o), V(q), V(a), C(a, p)],
            [V(o), V(q), C(a, p), C(q, p)],
        ])
    }
}

/// An output vertex before numbering: a lattice point or a cut point.
#[derive(Clone, Copy)]
enum Slot {
    Point(usize),
    Cut(usize),
}

/// Applies the stencils and numbers the output vertices in order of first use.
pub(super) struct Filler<'a> {
    pub(super) sdf: &'a dyn Sdf,
    pub(super) lattice: &'a Lattice,
    pub(super) values: &'a [f64],
    pub(super) warped: &'a KeyMap<[f64; 3]>,
    pub(super) cuts: &'a mut CutTable,
    pub(super) point_vertex: Vec<u32>,
    pub(super) cut_vertex: Vec<u32>,
    pub(super) mesh: TetMesh,
    pub(super) min_volume: f64,
    pub(super) dropped: usize,
}

fn sign_of(x: f64) -> i8 {
    if x < 0.0 {
        -1
    } else if x > 0.0 {
        1
    } else {
        0
    }
}

impl Filler<'_> {
    pub(super) fn fill(
        &mut self,
        ids: &[usize; 4],
        coords: &[[i64; 3]; 4],
    ) -> Result<(), MeshError> {
        let v = self.values;
        let signs = [
            sign_of(v[ids[0]]),
            sign_of(v[ids[1]]),
            sign_of(v[ids[2]]),
            sign_of(v[ids[3]]),
        ];
        if !signs.contains(&-1) {
            return Ok(());
        }
        if !signs.contains(&1) {
            // Entirely inside: the common case, kept off the stencil path.
            let pos = [
                self.point_position(ids[0], coords[0]),
                self.point_position(ids[1], coords[1]),
                self.point_position(ids[2], coords[2]),
                self.point_position(ids[3], coords[3]),
            ];
            let slots = [
                Slot::Point(ids[0]),
                Slot::Point(ids[1]),
                Slot::Point(ids[2]),
                Slot::Point(ids[3]),
            ];
            self.push(slots, pos);
            return Ok(());
        }
        for tet in stencil(signs, coords).tets() {
            let mut slots = [Slot::Point(0); 4];
            let mut pos = [[0.0; 3]; 4];
            for (v, node) in tet.iter().enumerate() {
                (slots[v], pos[v]) = match *node {
                    Node::Vertex(l) => {
                        (Slot::Point(ids[l]), self.point_position(ids[l], coords[l]))
                    }
                    Node::Cut(a, b) => {
                        let c =
                            self.cuts
                                .get(self.sdf, self.lattice, self.values, ids[a], ids[b])?;
                        (Slot::Cut(c), self.cuts.cuts[c].pos)
                    }
                };
            }
            self.push(slots, pos);
        }
        Ok(())
    }

    fn point_position(&self, id: usize, coords: [i64; 3]) -> [f64; 3] {
        let warped = if self.values[id] == 0.0 {
            self.warped.get(&(id as u64)).copied()
        } else {
            None
        };
        warped.unwrap_or_else(|| self.lattice.position(coords))
    }

    /// Adds a tetrahedron, positively oriented, unless it is degenerate.
    fn push(&mut self, slots: [Slot; 4], pos: [[f64; 3]; 4]) {
        let volume = signed_volume(pos[0], pos[1], pos[2], pos[3]);
        if volume.abs() < self.min_volume {
            self.dropped += 1;
            return;
        }
        let mut tet = [
            self.vertex(slots[0], pos[0]),
            self.vertex(slots[1], pos[1]),
            self.vertex(slots[2], pos[2]),
            self.vertex(slots[3], pos[3]),
        ];
        if volume < 0.0 {
            tet.swap(0, 1);
        }
        self.mesh.tets.push(tet);
    }

    /// The output index of a slot, numbering it on first use.
    fn vertex(&mut self, slot: Slot, pos: [f64; 3]) -> u32 {
        let entry = match slot {
            Slot::Point(id) => &mut self.point_vertex[id],
            Slot::Cut(c) => {
                if c >= self.cut_vertex.len() {
                    self.cut_vertex.resize(self.cuts.cuts.len(), u32::MAX);
                }
                &mut self.cut_vertex[c]
            }
        };
        if *entry == u32::MAX {
            // At most 2×10⁸ lattice points and 7 edges per point keep this in range.
            *entry = self.mesh.vertices.len() as u32;
            self.mesh.vertices.push(pos);
        }
        *entry
    }
}
