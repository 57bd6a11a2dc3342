//! The embedded tet mesh and vertex splitting (Chen et al. 2018, §5.2, Eq. 20–22).
//!
//! Every particle is a tet of its body's mesh (the particle sits at the barycentre).
//! Two face-adjacent tets are always joined by a bond (their barycentres are at most
//! about λ apart, inside the horizon δ = 1.45λ); when that bond breaks, the shared
//! triangle enters the *crack-face set*. Only the vertices of newly cracked faces are
//! examined: the tets around such a vertex are grouped by connectivity through faces
//! that are not cracked, and a vertex whose tets fall into k groups is split into k
//! copies (k − 1 new vertices, each remembering the vertex it was split from). A
//! crack face is *retired* once its two tets no longer share any of its vertices (it
//! has become two boundary faces of the split mesh). Several vertices of one face can
//! split in the same pass.
//!
//! The groups are a function of the crack-face set alone, and bonds never heal, so
//! splitting once per output frame gives the same topology as splitting every step
//! (only the order in which copies are numbered could differ); the run does it at
//! frame output, where the mesh is needed, so a step pays nothing for it.
//!
//! Vertex positions: Chen Eq. 20–22 move a vertex with the mass-weighted mean
//! velocity of the particles of its tets, ω_v = Σ_p m_p/4, v_v = Σ_p (m_p/4) v_p / ω_v,
//! x_v ← x_v + Δt v_v. Integrated over a run with fixed weights this is the
//! displacement interpolation x_v = X_v + Σ_p w_p u_p (w_p = m_p / 4ω_v), which is exact
//! for translations only: under a rotation R it misses (R − I)(X_v − X̄_v), up to λ/2
//! for a vertex a quarter of an edge from its tets' mass centre X̄_v. We use the
//! same weights on each particle's first-order prediction of the vertex,
//!
//! ```text
//! x_v = Σ_p w_p (x_p + F_p (X_v − X_p)),    w_p = m_p / (4 ω_v)   (Eq. 20–21 weights)
//! ```
//!
//! with F_p the deformation gradient of particle p's intact bonds (the correspondence
//! estimate F = (Σ_j η_ij ⊗ ξ_ij V_j) K⁻¹, K = Σ_j ξ_ij ⊗ ξ_ij V_j) where it can be
//! trusted, else its rotation ([`deformation_gradients`]). It is exact for every
//! affine motion (rigid rotations of fragments included) and needs no per-step work;
//! see the test `affine_motion_is_exact`. Where the particles of a vertex's tets
//! disagree (a sliver hanging on by one face, a tet pushed through its neighbours),
//! neither Chen's average nor ours keeps every tet positively oriented, so tets
//! left below 5% of their rest volume are mended afterwards
//! (`EmbeddedMesh::untangle`, a departure from Chen §5.2); figures in
//! docs/embedded.md.

mod gradient;
mod placement;

pub use gradient::{TRUSTED_CONDITIONING, TRUSTED_STRETCH, deformation_gradients};

use perifrac_math::{TET_FACES, UnionFind, cross, dot, norm, signed_volume, sub};
use rayon::prelude::*;

use crate::error::{Result, SimError};
use crate::family::{BROKEN, Bonds, INDEX};
use crate::geometry::discretize::Discretization;
use crate::model::PieceSurface;

/// No neighbour across a face (a face of the body's surface).
pub const NONE: u32 = u32::MAX;
/// Parent of an original vertex.
pub const NO_PARENT: u32 = u32::MAX;
/// Fraction of its rest volume below which [`EmbeddedMesh::positions`] mends a tet.
pub const MIN_VOLUME_FRACTION: f64 = 0.05;
/// Fraction of their rest volume that `EmbeddedMesh::untangle`'s last resort lets
/// other tets fall to while it turns an inverted tet right side out.
pub const FLOOR_FRACTION: f64 = 0.01;
/// Rounds of `EmbeddedMesh::untangle`'s first stage.
pub const UNTANGLE_ROUNDS: usize = 8;
/// Largest fragment (in tets) that `EmbeddedMesh::untangle` may place rigidly.
pub const SMALL_FRAGMENT: usize = 64;

/// The embedded mesh of all bodies: tet p belongs to particle p.
#[derive(Debug, Clone)]
pub struct EmbeddedMesh {
    /// Reference position X of each vertex (a copy has its parent's).
    pub reference: Vec<[f64; 3]>,
    /// The vertex each copy was split from ([`NO_PARENT`] for original vertices).
    pub parent: Vec<u32>,
    /// The four vertices of each tet (tet p is particle p's), positively oriented.
    pub tets: Vec<[u32; 4]>,
    /// The tet across face f (opposite local vertex f), [`NONE`] on the surface.
    pub adjacent: Vec<[u32; 4]>,
    /// The bond p→q across each interior face (index into the bond arrays).
    face_bond: Vec<[usize; 4]>,
    /// Bit f set: face f is in the crack-face set.
    cracked: Vec<u8>,
    /// Crack faces (tet, face) whose tets still share a vertex of the face, with the
    /// lower tet first.
    active: Vec<(u32, u8)>,
    /// Crack faces retired so far.
    pub retired: usize,
    /// Original vertex → tets around it (CSR rows; fixed).
    star_offsets: Vec<usize>,
    star_tets: Vec<u32>,
    /// Number of original vertices.
    original: usize,
}

/// What one [`EmbeddedMesh::update`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SplitStats {
    /// Faces that entered the crack set.
    pub new_crack_faces: usize,
    /// Vertices examined.
    pub examined: usize,
    /// Vertices that split.
    pub split: usize,
    /// New vertex copies.
    pub new_vertices: usize,
    /// Crack faces retired.
    pub retired: usize,
}

fn same_face(a: [u32; 3], b: [u32; 3]) -> bool {
    let (mut a, mut b) = (a, b);
    a.sort_unstable();
    b.sort_unstable();
    a == b
}

impl EmbeddedMesh {
    /// Builds the mesh of a discretization: all bodies' vertices one after the other,
    /// tet p = particle p, face adjacency, and the bond across every interior face.
    /// Fails, naming the tets, if two face-adjacent tets have no bond (their
    /// barycentres would be farther apart than the horizon).
    pub fn build(disc: &Discretization, bonds: &Bonds, body_names: &[String]) -> Result<Self> {
        let mut first = Vec::with_capacity(disc.meshes.len());
        let mut reference = Vec::new();
        for m in &disc.meshes {
            first.push(reference.len() as u32);
            reference.extend_from_slice(&m.vertices);
        }
        let n = disc.position.len();
        let tets: Vec<[u32; 4]> = (0..n)
            .map(|p| {
                let b = disc.body[p] as usize;
                disc.meshes[b].tets[disc.tet[p] as usize].map(|v| v + first[b])
            })
            .collect();
        // Positively oriented tets, so that faces wound by `TET_FACES` face out.
        let tets: Vec<[u32; 4]> = tets
            .into_iter()
            .map(|mut t| {
                let [a, b, c, d] = t.map(|v| reference[v as usize]);
                if dot(sub(b, a), cross(sub(c, a), sub(d, a))) < 0.0 {
                    t.swap(0, 1);
                }
                t
            })
            .collect();
        let original = reference.len();
        // Faces keyed by sorted vertices; equal keys are the two sides of one face.
        let mut keys: Vec<([u32; 3], u32)> = (0..n)
            .into_par_iter()
            .flat_map_iter(|p| {
                let t = tets[p];
                (0..4).map(move |f| {
                    let mut k = TET_FACES[f].map(|i| t[i]);
                    k.sort_unstable();
                    (k, (4 * p + f) as u32)
                })
            })
            .collect();
        keys.par_sort_unstable();
        let mut adjacent = vec![[NONE; 4]; n];
        let mut i = 0;
        while i < keys.len() {
            let mut j = i + 1;
            while j < keys.len() && keys[j].0 == keys[i].0 {
                j += 1;
            }
            if j - i == 2 {
                let (a, b) = (keys[i].1 as usize, keys[i + 1].1 as usize);
                adjacent[a / 4][a % 4] = (b / 4) as u32;
                adjacent[b / 4][b % 4] = (a / 4) as u32;
            }
            i = j;
        }
        drop(keys);
        let face_bond: Vec<[usize; 4]> = (0..n)
            .into_par_iter()
            .map(|p| {
                let mut out = [usize::MAX; 4];
                for f in 0..4 {
                    let q = adjacent[p][f];
                    if q == NONE {
                        continue;
                    }
                    let r = bonds.range(p);
                    let row = &bonds.neighbours[r.clone()];
                    match row.binary_search_by_key(&q, |&x| x & INDEX) {
                        Ok(k) => out[f] = r.start + k,
                        Err(_) => {
                            let b = disc.body[p] as usize;
                            let (x, y) = (disc.position[p], disc.position[q as usize]);
                            let d = ((x[0] - y[0]).powi(2)
                                + (x[1] - y[1]).powi(2)
                                + (x[2] - y[2]).powi(2))
                            .sqrt();
                            return Err(SimError::Mesh {
                                body: body_names.get(b).cloned().unwrap_or_default(),
                                message: format!(
                                    "tets {p} and {q} share a face but their particles, {d:.4e} m \
                                     apart, have no bond: the embedded mesh needs a horizon of at \
                                     least {d:.4e} m (raise `horizon`)"
                                ),
                            });
                        }
                    }
                }
                Ok(out)
            })
            .collect::<Result<_>>()?;
        let mut star_offsets = vec![0usize; original + 1];
        for t in &tets {
            for &v in t {
                star_offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..original {
            star_offsets[v + 1] += star_offsets[v];
        }
        let mut fill = star_offsets.clone();
        let mut star_tets = vec![0u32; star_offsets[original]];
        for (p, t) in tets.iter().enumerate() {
            for &v in t {
                star_tets[fill[v as usize]] = p as u32;
                fill[v as usize] += 1;
            }
        }
        Ok(EmbeddedMesh {
            parent: vec![NO_PARENT; original],
            reference,
            tets,
            adjacent,
            face_bond,
            cracked: vec![0; n],
            active: Vec::new(),
            retired: 0,
            star_offsets,
            star_tets,
            original,
        })
    }

    /// Number of vertices (original and copies).
    pub fn vertex_count(&self) -> usize {
        self.reference.len()
    }

    /// Number of original vertices.
    pub fn original_vertices(&self) -> usize {
        self.original
    }

    /// Crack faces that have not yet opened fully.
    pub fn active_crack_faces(&self) -> usize {
        self.active.len()
    }

    /// The original vertex a copy descends from.
    pub fn root(&self, mut v: u32) -> u32 {
        while self.parent[v as usize] != NO_PARENT {
            v = self.parent[v as usize];
        }
        v
    }

    fn face_vertices(&self, p: u32, f: usize) -> [u32; 3] {
        let t = self.tets[p as usize];
        TET_FACES[f].map(|i| t[i])
    }

    /// Adds the faces whose bonds broke to the crack-face set, splits the vertices
    /// of those faces whose tets fall apart into groups, and retires the crack faces
    /// that opened fully.
    pub fn update(&mut self, bonds: &Bonds) -> SplitStats {
        let broken = |k: usize| bonds.neighbours[k] & BROKEN != 0;
        let new: Vec<(u32, u8)> = (0..self.tets.len())
            .into_par_iter()
            .flat_map_iter(|p| {
                let (adj, fb, cracked) = (self.adjacent[p], self.face_bond[p], self.cracked[p]);
                (0..4).filter_map(move |f| {
                    let q = adj[f];
                    (q != NONE && (q as usize) > p && cracked & (1 << f) == 0 && broken(fb[f]))
                        .then_some((p as u32, f as u8))
                })
            })
            .collect();
        let mut stats = SplitStats {
            new_crack_faces: new.len(),
            ..SplitStats::default()
        };
        if new.is_empty() {
            return stats;
        }
        // Cracked faces containing the examined vertices (from both sides).
        let mut examine: Vec<u32> = Vec::with_capacity(6 * new.len());
        for &(p, f) in &new {
            let q = self.adjacent[p as usize][f as usize];
            let g = self.back_face(p, f);
            self.cracked[p as usize] |= 1 << f;
            self.cracked[q as usize] |= 1 << g;
            examine.extend(self.face_vertices(p, f as usize));
            examine.extend(self.face_vertices(q, g));
        }
        examine.sort_unstable();
        examine.dedup();
        stats.examined = examine.len();
        for v in examine {
            let added = self.split_vertex(v);
            if added > 0 {
                stats.split += 1;
                stats.new_vertices += added;
            }
        }
        self.active.extend(new);
        let before = self.active.len();
        let tets = &self.tets;
        let adjacent = &self.adjacent;
        self.active.retain(|&(p, f)| {
            let q = adjacent[p as usize][f as usize] as usize;
            let t = tets[p as usize];
            TET_FACES[f as usize]
                .iter()
                .any(|&i| tets[q].contains(&t[i]))
        });
        stats.retired = before - self.active.len();
        self.retired += stats.retired;
        stats
    }

    /// The local face index, in tet q across face f of p, of the same face.
    fn back_face(&self, p: u32, f: u8) -> usize {
        let q = self.adjacent[p as usize][f as usize];
        (0..4)
            .find(|&g| self.adjacent[q as usize][g] == p)
            .unwrap_or(0)
    }

    /// Splits vertex v into one copy per group of its tets (connected through
    /// faces around v that are not cracked); returns how many copies were added.
    fn split_vertex(&mut self, v: u32) -> usize {
        let root = self.root(v) as usize;
        let star: Vec<u32> = self.star_tets[self.star_offsets[root]..self.star_offsets[root + 1]]
            .iter()
            .copied()
            .filter(|&t| self.tets[t as usize].contains(&v))
            .collect();
        // Union-find over the star, through uncracked faces that contain v.
        let mut group = UnionFind::new(star.len());
        for (a, &t) in star.iter().enumerate() {
            let tv = self.tets[t as usize];
            for (f, &w) in tv.iter().enumerate() {
                if w == v || self.cracked[t as usize] & (1 << f) != 0 {
                    continue;
                }
                let s = self.adjacent[t as usize][f];
                if s == NONE {
                    continue;
                }
                if let Some(b) = star.iter().position(|&x| x == s) {
                    group.union(a, b);
                }
            }
        }
        // The group of the lowest tet keeps v; the others get new copies, in the
        // order of their lowest tets (the star is sorted by tet).
        let mut copy_of_root: Vec<(usize, u32)> = Vec::new();
        let mut added = 0;
        for (a, &t) in star.iter().enumerate() {
            let r = group.find(a);
            let id = match copy_of_root.iter().find(|c| c.0 == r) {
                Some(c) => c.1,
                None => {
                    let id = if copy_of_root.is_empty() {
                        v
                    } else {
                        self.reference.push(self.reference[v as usize]);
                        self.parent.push(v);
                        added += 1;
                        (self.reference.len() - 1) as u32
                    };
                    copy_of_root.push((r, id));
                    id
                }
            };
            if id != v {
                for x in self.tets[t as usize].iter_mut() {
                    if *x == v {
                        *x = id;
                    }
                }
            }
        }
        added
    }

    /// The crack-face set for a checkpoint: four bits a tet (bit f: face f), eight
    /// tets a word. It is the set as of the last frame written, which a checkpoint
    /// taken during a frame cannot rebuild from the bonds (bonds broken since that frame
    /// are not in it yet).
    pub fn crack_faces(&self) -> Vec<u32> {
        self.cracked
            .chunks(8)
            .map(|tets| {
                tets.iter()
                    .enumerate()
                    .fold(0, |word, (i, &bits)| word | (bits as u32) << (4 * i))
            })
            .collect()
    }

    /// Words of [`Self::crack_faces`].
    pub fn crack_face_words(&self) -> usize {
        self.tets.len().div_ceil(8)
    }

    /// Sets the crack-face set from [`Self::crack_faces`] of a checkpoint, after checking
    /// that every face in it is an interior face whose bond is broken and that it is in
    /// the set from both sides; the error says which face is not.
    pub fn restore_crack_faces(&mut self, words: &[u32], bonds: &Bonds) -> Result<(), String> {
        if words.len() != self.crack_face_words() {
            return Err(format!(
                "{} words of crack faces for {} tets",
                words.len(),
                self.tets.len()
            ));
        }
        let mut cracked: Vec<u8> = (0..8 * words.len())
            .map(|p| (words[p / 8] >> (4 * (p % 8)) & 0xf) as u8)
            .collect();
        if let Some(p) = (self.tets.len()..cracked.len()).find(|&p| cracked[p] != 0) {
            return Err(format!("crack faces set for tet {p}, past the last tet"));
        }
        for (p, &bits) in cracked.iter().enumerate().take(self.tets.len()) {
            for f in (0..4).filter(|f| bits & (1 << f) != 0) {
                let q = self.adjacent[p][f];
                let valid = q != NONE
                    && bonds.neighbours[self.face_bond[p][f]] & BROKEN != 0
                    && cracked[q as usize] & (1 << self.back_face(p as u32, f as u8)) != 0;
                if !valid {
                    return Err(format!(
                        "face {f} of tet {p} is in the crack-face set but is not a cracked \
                         interior face"
                    ));
                }
            }
        }
        cracked.truncate(self.tets.len());
        self.cracked = cracked;
        Ok(())
    }

    /// Restores the topology written at a frame (tets and parents, from
    /// `tets/NNNN.vtu`); the crack-face set is restored first
    /// ([`Self::restore_crack_faces`]).
    pub fn restore(&mut self, tets: Vec<[u32; 4]>, parent: Vec<u32>) -> Result<()> {
        if tets.len() != self.tets.len() || parent.len() < self.original {
            return Err(SimError::Refused(format!(
                "the split tet mesh to resume from has {} tets and {} vertices; the scene has {} \
                 tets and {} vertices",
                tets.len(),
                parent.len(),
                self.tets.len(),
                self.original
            )));
        }
        if let Some(v) = parent[..self.original].iter().position(|&p| p != NO_PARENT) {
            return Err(SimError::Refused(format!(
                "the split tet mesh to resume from gives original vertex {v} a parent"
            )));
        }
        let vertices = parent.len() as u32;
        let mut reference = self.reference[..self.original].to_vec();
        for (v, &p) in parent.iter().enumerate().skip(self.original) {
            if p >= v as u32 {
                return Err(SimError::Refused(format!(
                    "the split tet mesh to resume from has vertex {v} with parent {p}: a copy's \
                     parent must come before it"
                )));
            }
            reference.push(reference[p as usize]);
        }
        for (p, t) in tets.iter().enumerate() {
            let roots_match = t.iter().zip(&self.tets[p]).all(|(&a, &b)| {
                a < vertices && {
                    let mut r = a;
                    while parent[r as usize] != NO_PARENT {
                        r = parent[r as usize];
                    }
                    r == self.root(b)
                }
            });
            if !roots_match {
                return Err(SimError::Refused(format!(
                    "the split tet mesh to resume from does not match the scene's mesh at tet {p}"
                )));
            }
        }
        self.tets = tets;
        self.parent = parent;
        self.reference = reference;
        for p in 0..self.tets.len() {
            let adjacent = self.adjacent[p];
            for (f, &q) in adjacent.iter().enumerate() {
                if q != NONE && self.cracked[p] & (1 << f) != 0 {
                    let open = {
                        let t = self.tets[p];
                        !TET_FACES[f]
                            .iter()
                            .any(|&i| self.tets[q as usize].contains(&t[i]))
                    };
                    if (q as usize) > p {
                        if open {
                            self.retired += 1;
                        } else {
                            self.active.push((p as u32, f as u8));
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Reference (rest) volume of tet p.
    fn rest_volume(&self, p: usize) -> f64 {
        let [a, b, c, d] = self.tets[p].map(|v| self.reference[v as usize]);
        signed_volume(a, b, c, d)
    }

    /// The surface of the tets `tets` (a fragment's particles) in the reference
    /// configuration: each face on the body's surface or shared with a tet outside the
    /// set, wound outward, over the original vertices (a copy counts as the vertex it
    /// was split from, so faces inside the set stay shut whatever cracked between
    /// them), renumbered from 0 in order of first use; its reach, the largest distance
    /// from a tet's barycentre (its particle) to a vertex of a surface face of it. The
    /// rigid phase's collider of the piece (docs/rigid.md, "Colliders and contact").
    pub fn piece_surface(&self, tets: &[u32]) -> PieceSurface {
        let mut inside = tets.to_vec();
        inside.sort_unstable();
        let member = |q: u32| q != NONE && inside.binary_search(&q).is_ok();
        let mut index = std::collections::HashMap::new();
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        let mut reach: f64 = 0.0;
        for &p in tets {
            let corners = self.tets[p as usize].map(|v| self.reference[v as usize]);
            let centre = [0, 1, 2].map(|k| corners.iter().map(|c| c[k]).sum::<f64>() / 4.0);
            for (f, &q) in self.adjacent[p as usize].iter().enumerate() {
                if member(q) {
                    continue;
                }
                let face = self.face_vertices(p, f).map(|v| {
                    let v = self.root(v);
                    reach = reach.max(norm(sub(self.reference[v as usize], centre)));
                    *index.entry(v).or_insert_with(|| {
                        vertices.push(self.reference[v as usize]);
                        (vertices.len() - 1) as u32
                    })
                });
                triangles.push(face);
            }
        }
        PieceSurface {
            vertices,
            triangles,
            reach,
        }
    }

    /// Boundary faces of the split mesh, wound outward from the tet owning them
    /// (tets are positively oriented), with whether each is a crack face (its
    /// original face was shared by two tets).
    pub fn boundary(&self) -> Vec<([u32; 3], u32, bool)> {
        let mut out = Vec::new();
        for (p, t) in self.tets.iter().enumerate() {
            for (f, &q) in self.adjacent[p].iter().enumerate() {
                let face = self.face_vertices(p as u32, f);
                let open = q == NONE
                    || !same_face(
                        face,
                        self.face_vertices(q, self.back_face(p as u32, f as u8)),
                    );
                if open {
                    out.push((TET_FACES[f].map(|i| t[i]), p as u32, q != NONE));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
