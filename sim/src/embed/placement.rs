//! Placing the split mesh's vertices from the particles (Chen Eq. 20–22 on first-order
//! predictions, [`EmbeddedMesh::positions`]) and mending the tets that the average
//! leaves inverted or flattened (a departure from Chen §5.2: `EmbeddedMesh::untangle`).

use perifrac_math::{TET_FACES, UnionFind, add, cross, dot, norm, rigid_fit, signed_volume, sub};
use rayon::prelude::*;

use super::{EmbeddedMesh, FLOOR_FRACTION, MIN_VOLUME_FRACTION, SMALL_FRAGMENT, UNTANGLE_ROUNDS};

/// The particles, for placing a fragment rigidly ([`EmbeddedMesh::untangle`]).
pub(super) struct Rigid<'a> {
    pub(super) reference: &'a [[f64; 3]],
    pub(super) position: &'a [[f64; 3]],
    pub(super) mass: &'a [f64],
}

impl EmbeddedMesh {
    /// Vertex positions for particles at `position`, from their reference positions
    /// `reference`, masses `mass` and gradients `gradient` (from
    /// [`super::deformation_gradients`]): Chen Eq. 20–21 weights on first-order predictions
    /// (see the module doc), then the untangling of tets below
    /// [`MIN_VOLUME_FRACTION`] of their rest volume (`untangle`).
    pub fn positions(
        &self,
        reference: &[[f64; 3]],
        position: &[[f64; 3]],
        mass: &[f64],
        gradient: &[[[f64; 3]; 3]],
    ) -> Vec<[f64; 3]> {
        let nv = self.reference.len();
        let mut offsets = vec![0usize; nv + 1];
        for t in &self.tets {
            for &v in t {
                offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..nv {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut incident = vec![0u32; offsets[nv]];
        for (p, t) in self.tets.iter().enumerate() {
            for &v in t {
                incident[fill[v as usize]] = p as u32;
                fill[v as usize] += 1;
            }
        }
        let predict = |p: usize, v: usize| -> [f64; 3] {
            let d = sub(self.reference[v], reference[p]);
            let f = &gradient[p];
            [0, 1, 2].map(|a| position[p][a] + f[a][0] * d[0] + f[a][1] * d[1] + f[a][2] * d[2])
        };
        let mut points: Vec<[f64; 3]> = (0..nv)
            .into_par_iter()
            .map(|v| {
                let mut sum = [0.0; 3];
                let mut omega = 0.0;
                for &p in &incident[offsets[v]..offsets[v + 1]] {
                    let p = p as usize;
                    // ω_v = Σ_p m_p/4 (Eq. 20).
                    let w = 0.25 * mass[p];
                    let pred = predict(p, v);
                    for a in 0..3 {
                        sum[a] += w * pred[a];
                    }
                    omega += w;
                }
                if omega > 0.0 {
                    sum.map(|s| s / omega)
                } else {
                    self.reference[v]
                }
            })
            .collect();
        let star = |v: usize| &incident[offsets[v]..offsets[v + 1]];
        let rigid = Rigid {
            reference,
            position,
            mass,
        };
        self.untangle(&mut points, &predict, &star, &rigid);
        points
    }

    /// Puts right the tets that the averaged vertices leave below
    /// [`MIN_VOLUME_FRACTION`] of their rest volume V_p (a departure from Chen §5.2,
    /// whose Eq. 20–22 average can turn a tet inside out where the particles of a
    /// vertex's tets disagree: a sliver hanging on by one face, a tet pushed through
    /// its neighbours).
    ///
    /// 1. [`UNTANGLE_ROUNDS`] rounds: each vertex of a tet below the bound moves to the
    ///    mean of where those tets' own particles put it, x_p + G_p (X_v − X_p); a tet
    ///    placed by its own particle alone has volume det G_p V_p > 0 (G_p is a trusted
    ///    F or a rotation), so a tet whose vertices are its alone is mended in one
    ///    round, and a vertex shared by disagreeing tets takes their compromise.
    /// 2. A tet still below the bound in a fragment (tets joined through shared
    ///    vertices) of at most [`SMALL_FRAGMENT`] tets places its whole fragment
    ///    rigidly: x_v = c + R (X_v − C), with C, c the mass centres of the fragment's
    ///    particles then and now and R the rotation of the best rigid fit of the
    ///    particles (the polar rotation of Σ_p m_p (x_p − c) ⊗ (X_p − C), Kabsch).
    ///    Every tet of the fragment then keeps its rest volume.
    /// 3. A tet still below the bound lifts one of its vertices off the plane of the
    ///    opposite face to the height that gives it the bound's volume: a vertex of its
    ///    own (in no other tet) if it has one, else the vertex in fewest tets whose
    ///    other tets all stay at or above the bound after the move (a tet hanging by
    ///    two faces in a large fragment, as in the demo); if none can, it stays. A tet
    ///    still inside out after that gets a last resort: the same lift, with the
    ///    vertex's other tets allowed down to [`FLOOR_FRACTION`] of their rest volume
    ///    (a pair of tets folded over their shared face among slivers, on an
    ///    unstructured mesh).
    ///
    /// Deterministic: every round reads the positions of the previous one, and step 3
    /// takes the tets in order.
    pub(super) fn untangle<'a>(
        &self,
        points: &mut [[f64; 3]],
        predict: &(dyn Fn(usize, usize) -> [f64; 3] + Sync),
        star: &(dyn Fn(usize) -> &'a [u32] + Sync),
        rigid: &Rigid<'_>,
    ) {
        let volume = |points: &[[f64; 3]], q: usize| {
            let [a, b, c, d] = self.tets[q].map(|v| points[v as usize]);
            signed_volume(a, b, c, d)
        };
        let low = |points: &[[f64; 3]]| -> Vec<usize> {
            (0..self.tets.len())
                .into_par_iter()
                .filter(|&p| volume(points, p) < MIN_VOLUME_FRACTION * self.rest_volume(p))
                .collect()
        };
        let mut bad = low(points);
        for _ in 0..UNTANGLE_ROUNDS {
            if bad.is_empty() {
                return;
            }
            let mut target: Vec<(u32, [f64; 3])> = bad
                .par_iter()
                .flat_map_iter(|&p| self.tets[p].map(|v| (v, predict(p, v as usize))))
                .collect();
            target.sort_by_key(|t| t.0);
            let mut i = 0;
            while i < target.len() {
                let v = target[i].0;
                let mut j = i;
                let mut sum = [0.0; 3];
                while j < target.len() && target[j].0 == v {
                    sum = add(sum, target[j].1);
                    j += 1;
                }
                let n = (j - i) as f64;
                points[v as usize] = sum.map(|c| c / n);
                i = j;
            }
            bad = low(points);
        }
        if bad.is_empty() {
            return;
        }
        self.place_small_fragments(points, &bad, rigid);
        // Step 3, then its last resort for the tets it leaves inside out: the other
        // tets of the lifted vertex may then fall to FLOOR_FRACTION of their rest
        // volume (flat, not inverted).
        for p in low(points) {
            self.lift(points, p, MIN_VOLUME_FRACTION, &volume, star);
        }
        let inverted: Vec<usize> = low(points)
            .into_iter()
            .filter(|&p| volume(points, p) <= 0.0)
            .collect();
        for p in inverted {
            self.lift(points, p, FLOOR_FRACTION, &volume, star);
        }
    }

    /// Step 3 of [`Self::untangle`] for tet `p`: lifts one of its vertices (fewest
    /// tets first) off the plane of the opposite face to the height that gives `p` the
    /// bound's volume, if the vertex's other tets all keep `floor` of their rest
    /// volume; else no vertex moves.
    fn lift<'a>(
        &self,
        points: &mut [[f64; 3]],
        p: usize,
        floor: f64,
        volume: &impl Fn(&[[f64; 3]], usize) -> f64,
        star: &(dyn Fn(usize) -> &'a [u32] + Sync),
    ) {
        let t = self.tets[p];
        let mut corners = [0, 1, 2, 3];
        corners.sort_by_key(|&i| star(t[i] as usize).len());
        for own in corners {
            let v = t[own] as usize;
            // The face opposite vertex `own`, wound so that its normal points to
            // the side a positively oriented tet has the vertex on.
            let face = TET_FACES[own].map(|i| points[t[i] as usize]);
            let area = cross(sub(face[1], face[0]), sub(face[2], face[0]));
            let twice = norm(area);
            if twice <= 0.0 {
                continue;
            }
            let n = area.map(|c| -c / twice);
            let x = points[v];
            let height = dot(sub(x, face[0]), n);
            let wanted = 6.0 * MIN_VOLUME_FRACTION * self.rest_volume(p) / twice;
            points[v] = [0, 1, 2].map(|a| x[a] + (wanted - height) * n[a]);
            let kept = star(v).iter().all(|&q| {
                let q = q as usize;
                q == p || volume(points, q) >= floor * self.rest_volume(q)
            });
            if kept {
                return;
            }
            points[v] = x;
        }
    }

    /// Step 2 of [`Self::untangle`]: the fragments of at most [`SMALL_FRAGMENT`] tets
    /// that hold a tet of `bad` are placed rigidly.
    fn place_small_fragments(&self, points: &mut [[f64; 3]], bad: &[usize], rigid: &Rigid<'_>) {
        let nv = points.len();
        let n = self.tets.len();
        let mut sets = UnionFind::new(nv + n);
        for (p, t) in self.tets.iter().enumerate() {
            for &v in t {
                sets.union(nv + p, v as usize);
            }
        }
        let label = sets.labels_of(nv..nv + n);
        // The tets of each fragment holding a bad tet, gathered in one pass (in tet
        // order, fragments in label order: deterministic).
        let mut fragments: std::collections::BTreeMap<u32, Vec<usize>> =
            bad.iter().map(|&p| (label[p], Vec::new())).collect();
        for (p, k) in label.iter().enumerate() {
            if let Some(members) = fragments.get_mut(k) {
                members.push(p);
            }
        }
        for members in fragments.into_values() {
            if members.len() > SMALL_FRAGMENT {
                continue;
            }
            let members_fit = members
                .iter()
                .map(|&p| (rigid.mass[p], rigid.reference[p], rigid.position[p]));
            let Some(fit) = rigid_fit(members_fit) else {
                continue;
            };
            let (c0, c, rotation) = (fit.rest, fit.centre, fit.rotation);
            for &p in &members {
                for &v in &self.tets[p] {
                    let d = sub(self.reference[v as usize], c0);
                    points[v as usize] = [0, 1, 2].map(|a| c[a] + dot(rotation[a], d));
                }
            }
        }
    }
}
