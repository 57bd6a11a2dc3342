//! Contact between particles: of different bodies, and of one body where no intact
//! bond joins them (fragments, the faces of an initial crack). The short-range force
//! of Silling & Askari 2005 §5 (as in LAMMPS PERI), with normal damping and Coulomb
//! friction; the derivation and the choices are in `docs/contact.md`.
//!
//! For particles i, j at distance r = |y_i − y_j| below their contact distance d_ij the
//! force on i is
//!
//! ```text
//! F_ij = (k_ij (d_ij − r) − c_n v_n) n + F_t,      n = (y_i − y_j)/r,  v_n = (v_i − v_j)·n
//! k_ij = s · min(c_i/δ_i, c_j/δ_j) V_i V_j,        c = 18κ/(πδ⁴) (the bond micromodulus)
//! c_n  = 2ζ √(k_ij m_ij),                          m_ij = m_i m_j/(m_i + m_j)
//! F_t  = −min(μ |F_n|, √(k_ij m_ij) |v_t|) v_t/|v_t|   (Coulomb, regularised at slip onset)
//! d_ij = ϱ (l_i + l_j)/2,  l = V^{1/3};   one body: min(d_ij, min(ϱ, 1)|x_i − x_j|)
//! ```
//!
//! with s = `[contact] stiffness` (15), ϱ = `distance` (0.9), ζ = `damping`, μ =
//! `friction`; the normal force never pulls (F_n ≥ 0). F_ji = −F_ij bit for bit, so
//! momentum is conserved to rounding. Two points of one body never touch beyond their
//! reference distance, even at ϱ > 1: unbonded, they stand there at rest.
//!
//! The faces of a cut made before the first step (a `[[body.crack]]`, a slot narrower
//! than δ that no bond crosses) touch only once they have **come apart**: a pair of
//! one body, no intact bond joining it at set-up, closer than [`PRECUT_RANGE`] mean
//! spacings, touches only after it has been farther apart than |x_i − x_j| + (|x_i −
//! x_j| − d_ij) (opened by as much as it must close to touch). Until then its faces
//! slide past each other freely: sheared, diagonal pairs across a cut come within d_ij
//! and their springs carried the shear across it, which bent the Kalthoff–Winkler
//! cracks by 8–10° (issue 33 item 7, `docs/contact.md`). The velocity constraint of
//! [`apart`] still holds them at half their distance. These pairs stay in the list
//! until they come apart, and which have not is saved in checkpoints.
//!
//! After the forces, [`apart`] keeps every such pair at least half a spacing apart
//! with pairwise impulses (a velocity-level constraint, no stiffer spring).
//!
//! Candidates come from a cell list over every participating point, kept as a Verlet
//! list with a skin: it is rebuilt only when some point has moved more than half the
//! skin since the last build. Each point gathers its own pairs in increasing index
//! order, so the forces are the same bytes with any thread count.

use std::collections::HashMap;
use std::f64::consts::PI;

use perifrac_math::{dot, sub};
use rayon::prelude::*;

use crate::cache::checkpoint::{Decoder, Encoder};
use crate::error::Result;
use crate::family::{BROKEN, Bonds, INDEX};
use crate::material::Material;
use crate::model::Model;
use crate::scene::Scene;

mod precut;

pub mod apart;

/// A candidate pair has no bond joining it.
const NO_BOND: u32 = u32::MAX;

/// The skin of the Verlet list, as a fraction of the largest contact distance.
const SKIN: f64 = 0.3;

/// The faces of a pre-existing cut: pairs of one body closer than this many mean
/// spacings at set-up, no intact bond joining them (module doc).
pub const PRECUT_RANGE: f64 = 2.0;

/// A candidate partner of a point.
#[derive(Debug, Clone, Copy)]
struct Pair {
    /// The partner's global index.
    j: u32,
    /// The bond i→j in the point's model, or [`NO_BOND`].
    bond: u32,
    /// The bond j→i, or [`NO_BOND`]: the pair is excluded while either is intact, so
    /// that i and j agree.
    reverse: u32,
    /// Contact distance d_ij (m).
    reach: f64,
    /// The closest the pair may come, r_min (m): [`apart`].
    limit: f64,
    /// Faces of a pre-existing cut that have not come apart: no spring (module doc).
    closed: bool,
    /// The distance beyond which such a pair has come apart (m).
    open: f64,
}

/// The particle-contact settings of `[contact]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSettings {
    /// Damping ratio ζ of the normal spring.
    pub damping: f64,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
    /// Contact distance ϱ in particle spacings.
    pub distance: f64,
}

/// Particle contact over the parts of a world: the points' fixed data, the Verlet
/// list and its scratch arrays (nothing here is saved in checkpoints: the list is
/// rebuilt on the first step after a resume).
#[derive(Debug, Clone)]
pub struct ParticleContact {
    settings: ContactSettings,
    /// First global index of each part's points; a part that takes no part has an
    /// empty range.
    offsets: Vec<usize>,
    /// Part of each global point.
    part: Vec<u32>,
    /// Scene body of each point.
    body: Vec<u32>,
    /// Particle spacing l = V^{1/3} (m).
    spacing: Vec<f64>,
    /// Particle spacing l̄ = (V̄)^{1/3} of each scene body, V̄ its points' mean volume
    /// (m), for the limit of [`apart`].
    body_spacing: Vec<f64>,
    /// s c/δ (N/m⁷): k_ij = min(modulus_i, modulus_j) V_i V_j.
    modulus: Vec<f64>,
    /// Volume V (m³).
    volume: Vec<f64>,
    /// Mass (kg).
    mass: Vec<f64>,
    /// Reference position x (m).
    reference: Vec<[f64; 3]>,
    /// Whether unbonded points of one body of this part touch.
    self_contact: Vec<bool>,
    /// The largest contact distance (m).
    max_reach: f64,
    /// Positions at the last build of the list.
    built_at: Vec<[f64; 3]>,
    /// The Verlet list: pairs of point i are `pairs[pair_offsets[i]..pair_offsets[i + 1]]`.
    pair_offsets: Vec<usize>,
    pairs: Vec<Pair>,
    /// Scratch: gathered positions, velocities and the contact forces.
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    force: Vec<[f64; 3]>,
    /// Scratch: whether a point has a partner closer than [`apart::WATCH`] limits
    /// (set with the forces).
    near: Vec<bool>,
    /// What keeping pairs apart has done so far.
    pub apart: apart::Counters,
    /// Scratch: whether each point is in the rigid phase (empty while none is); two
    /// rigid points meet through the rigid solver, not here.
    frozen: Vec<bool>,
    /// Wall time spent (s).
    pub time: f64,
    /// Builds of the Verlet list so far.
    pub builds: u64,
    /// The faces of pre-existing cuts that have not come apart, (i, j) and (j, i) in
    /// increasing order; found at the first build, then read from the list before each
    /// build (or from a checkpoint: `restored`).
    closed: Vec<(u32, u32)>,
    /// Whether `closed` has been found or restored.
    closed_known: bool,
    /// Whether `closed` was just read from a checkpoint (the next build takes it as is).
    restored: bool,
}

impl ParticleContact {
    /// Contact over the points of `models` whose [`Model::contact_points`] is given,
    /// with each scene body's bond micromodulus (the body's κ and δ).
    pub fn new(scene: &Scene, models: &[&dyn Model]) -> ParticleContact {
        let c = &scene.contact;
        // s c/δ = s · 18κ/(πδ⁵), per scene body.
        let modulus: Vec<f64> = scene
            .bodies
            .iter()
            .map(|b| {
                let kappa = Material::from_spec(&scene.materials[&b.material]).bulk_modulus;
                let delta = b.delta();
                c.stiffness * 18.0 * kappa / (PI * delta.powi(5))
            })
            .collect();
        let mut out = ParticleContact {
            settings: ContactSettings {
                damping: c.damping,
                friction: c.friction,
                distance: c.distance,
            },
            offsets: Vec::with_capacity(models.len() + 1),
            part: Vec::new(),
            body: Vec::new(),
            spacing: Vec::new(),
            body_spacing: vec![0.0; scene.bodies.len()],
            modulus: Vec::new(),
            volume: Vec::new(),
            mass: Vec::new(),
            reference: Vec::new(),
            self_contact: Vec::new(),
            max_reach: 0.0,
            built_at: Vec::new(),
            pair_offsets: Vec::new(),
            pairs: Vec::new(),
            position: Vec::new(),
            velocity: Vec::new(),
            force: Vec::new(),
            near: Vec::new(),
            apart: apart::Counters::default(),
            frozen: Vec::new(),
            time: 0.0,
            builds: 0,
            closed: Vec::new(),
            closed_known: false,
            restored: false,
        };
        for (p, model) in models.iter().enumerate() {
            out.offsets.push(out.part.len());
            let contact = model.contact_points();
            out.self_contact
                .push(contact.as_ref().is_some_and(|c| c.self_contact));
            let Some(contact) = contact else { continue };
            let points = model.points();
            let bodies = model.point_bodies();
            for i in 0..points.position.len() {
                let v = contact.volume[i];
                out.part.push(p as u32);
                out.body.push(bodies[i]);
                out.spacing.push(v.cbrt());
                out.modulus.push(modulus[bodies[i] as usize]);
                out.volume.push(v);
                out.mass.push(points.mass[i]);
                out.reference.push(points.reference[i]);
            }
        }
        out.offsets.push(out.part.len());
        let n = out.part.len();
        out.position = vec![[0.0; 3]; n];
        out.velocity = vec![[0.0; 3]; n];
        out.force = vec![[0.0; 3]; n];
        out.near = vec![false; n];
        let mut count = vec![0usize; out.body_spacing.len()];
        for (&b, &v) in out.body.iter().zip(&out.volume) {
            out.body_spacing[b as usize] += v;
            count[b as usize] += 1;
        }
        for (l, &k) in out.body_spacing.iter_mut().zip(&count) {
            *l = (*l / k.max(1) as f64).cbrt();
        }
        // The list holds every pair within max(d_ij, WATCH r_min) (plus the skin).
        let widest = out.spacing.iter().fold(0.0f64, |m, &l| m.max(l));
        let widest_mean = out.body_spacing.iter().fold(0.0f64, |m, &l| m.max(l));
        out.max_reach = (c.distance * widest).max(apart::WATCH * apart::LIMIT * widest_mean);
        out
    }

    /// How many points take part.
    pub fn len(&self) -> usize {
        self.part.len()
    }

    /// Whether no point takes part.
    pub fn is_empty(&self) -> bool {
        self.part.is_empty()
    }

    /// The stable time step of the contact springs alone, and the point that limits
    /// it. A point is assumed to touch N = (4π/3) ϱ³ + 1 partners as stiff as itself
    /// (the points of an overlapping body of its density inside its contact sphere,
    /// plus one): λ_max ≤ N k_ii/m_i by Gershgorin; the damped step is
    /// (2/ω)(√(1 + ζ²) − ζ).
    pub fn stable_time_step(&self) -> (f64, usize) {
        let partners = 4.0 * PI / 3.0 * self.settings.distance.powi(3) + 1.0;
        let zeta = self.settings.damping;
        let (worst, rate) = (0..self.len())
            .map(|i| {
                let k = self.modulus[i] * self.volume[i] * self.volume[i];
                (i, partners * k / self.mass[i])
            })
            .fold((0, 0.0f64), |a, b| if b.1 > a.1 { b } else { a });
        if rate <= 0.0 {
            return (f64::INFINITY, worst);
        }
        let local = worst - self.offsets[self.part[worst] as usize];
        (
            2.0 / rate.sqrt() * ((1.0 + zeta * zeta).sqrt() - zeta),
            local,
        )
    }

    /// The global range of part `p`'s points.
    pub fn range(&self, p: usize) -> std::ops::Range<usize> {
        self.offsets[p]..self.offsets[p + 1]
    }

    /// Computes the contact forces at the models' current positions and velocities;
    /// [`ParticleContact::force`] then gives them part by part.
    pub fn compute(&mut self, models: &[&dyn Model]) {
        for (p, model) in models.iter().enumerate() {
            let range = self.range(p);
            if range.is_empty() {
                continue;
            }
            let points = model.points();
            self.position[range.clone()].copy_from_slice(points.position);
            self.velocity[range.clone()].copy_from_slice(points.velocity);
            if let Some(frozen) = model.frozen() {
                self.frozen.resize(self.position.len(), false);
                self.frozen[range].copy_from_slice(frozen);
            }
        }
        if self.needs_build() {
            self.build(models);
        }
        let bonds: Vec<Option<&Bonds>> = models
            .iter()
            .map(|m| m.contact_points().and_then(|c| c.bonds))
            .collect();
        if !self.closed.is_empty() {
            self.mark_opened();
        }
        let mut force = std::mem::take(&mut self.force);
        let mut near = std::mem::take(&mut self.near);
        let this = &*self;
        force
            .par_iter_mut()
            .zip(near.par_iter_mut())
            .enumerate()
            .with_min_len(512)
            .for_each(|(i, (f, close))| (*f, *close) = this.force_on(i, &bonds));
        self.force = force;
        self.near = near;
    }

    /// The contact forces (N) on part `p`'s points after [`ParticleContact::compute`].
    pub fn force(&self, p: usize) -> &[[f64; 3]] {
        &self.force[self.range(p)]
    }

    /// Drops the Verlet list (after a resume): the next step rebuilds it.
    pub fn invalidate(&mut self) {
        self.built_at.clear();
    }

    /// Whether the list is missing or some point moved more than half the skin since
    /// it was built.
    fn needs_build(&self) -> bool {
        if self.built_at.len() != self.len() {
            return true;
        }
        let half_skin = 0.5 * SKIN * self.max_reach;
        let limit = half_skin * half_skin;
        self.position
            .par_iter()
            .zip(self.built_at.par_iter())
            .with_min_len(4096)
            .any(|(y, y0)| {
                let d = sub(*y, *y0);
                dot(d, d) > limit
            })
    }

    /// Rebuilds the Verlet list from a cell list of cell size d_max + skin: every
    /// pair closer than its contact distance plus the skin, in increasing partner
    /// order, with the bond joining it if any.
    fn build(&mut self, models: &[&dyn Model]) {
        let bonds: Vec<Option<&Bonds>> = models
            .iter()
            .map(|m| m.contact_points().and_then(|c| c.bonds))
            .collect();
        if !self.closed_known {
            self.closed = self.precut_faces(&bonds);
            self.closed_known = true;
        } else if !self.restored {
            self.closed = self.closed_in_list();
        }
        self.restored = false;
        let n = self.len();
        let skin = SKIN * self.max_reach;
        let cell = self.max_reach + skin;
        let key = |y: [f64; 3]| y.map(|x| (x / cell).floor() as i64);
        let mut sorted: Vec<([i64; 3], u32)> = (0..n as u32)
            .into_par_iter()
            .map(|i| (key(self.position[i as usize]), i))
            .collect();
        sorted.par_sort_unstable();
        let mut cells: HashMap<[i64; 3], (usize, usize)> = HashMap::new();
        let mut start = 0;
        for k in 1..=sorted.len() {
            if k == sorted.len() || sorted[k].0 != sorted[start].0 {
                cells.insert(sorted[start].0, (start, k));
                start = k;
            }
        }
        let this = &*self;
        let lists: Vec<Vec<Pair>> = (0..n)
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let y = this.position[i];
                let c = key(y);
                let mut out = Vec::new();
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let Some(&(a, b)) = cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                            else {
                                continue;
                            };
                            for &(_, j) in &sorted[a..b] {
                                if let Some(pair) =
                                    this.candidate(i, j as usize, skin, &bonds, false)
                                {
                                    out.push(pair);
                                }
                            }
                        }
                    }
                }
                // Closed faces stay in the list, however far they are, until they
                // have come apart.
                let first = this.closed.partition_point(|&(a, _)| (a as usize) < i);
                for &(_, j) in this.closed[first..]
                    .iter()
                    .take_while(|&&(a, _)| a as usize == i)
                {
                    if !out.iter().any(|p| p.j == j) {
                        out.extend(this.candidate(i, j as usize, skin, &bonds, true));
                    }
                }
                out.sort_unstable_by_key(|p| p.j);
                out
            })
            .collect();
        self.pair_offsets.clear();
        self.pair_offsets.push(0);
        self.pairs.clear();
        for list in lists {
            self.pairs.extend(list);
            self.pair_offsets.push(self.pairs.len());
        }
        self.built_at.clone_from(&self.position);
        self.builds += 1;
    }

    /// The pair (i, j) if it belongs in the list (`force`: whatever its distance).
    fn candidate(
        &self,
        i: usize,
        j: usize,
        skin: f64,
        bonds: &[Option<&Bonds>],
        force: bool,
    ) -> Option<Pair> {
        if i == j {
            return None;
        }
        let part = self.part[i] as usize;
        let one_body = self.part[j] as usize == part && self.body[i] == self.body[j];
        if one_body && !self.self_contact[part] {
            return None;
        }
        let spacing = 0.5 * (self.spacing[i] + self.spacing[j]);
        let mut reach = self.settings.distance * spacing;
        let mean = 0.5
            * (self.body_spacing[self.body[i] as usize] + self.body_spacing[self.body[j] as usize]);
        let mut limit = apart::LIMIT * mean;
        let mut rest = 0.0;
        if one_body {
            let xi = sub(self.reference[i], self.reference[j]);
            rest = dot(xi, xi).sqrt();
            reach = reach.min(self.settings.distance.min(1.0) * rest);
            limit = limit.min(apart::LIMIT * rest);
        }
        let d = sub(self.position[i], self.position[j]);
        let cutoff = reach.max(apart::WATCH * limit) + skin;
        if !force && dot(d, d) >= cutoff * cutoff {
            return None;
        }
        let (mut bond, mut reverse) = (NO_BOND, NO_BOND);
        if self.part[j] as usize == part {
            if let Some(b) = bonds[part] {
                let local = |x: usize| x - self.offsets[part];
                bond = bond_index(b, local(i), local(j));
                reverse = bond_index(b, local(j), local(i));
            }
        }
        let closed = one_body && self.closed.binary_search(&(i as u32, j as u32)).is_ok();
        Some(Pair {
            j: j as u32,
            bond,
            reverse,
            reach,
            limit,
            closed,
            open: 2.0 * rest - reach,
        })
    }

    /// The contact force on point i, its pairs summed in list order, and whether a
    /// pair that no intact bond joins is closer than [`apart::WATCH`] times its limit.
    fn force_on(&self, i: usize, bonds: &[Option<&Bonds>]) -> ([f64; 3], bool) {
        let mut total = [0.0; 3];
        let mut near = false;
        let (yi, vi) = (self.position[i], self.velocity[i]);
        let part_bonds = bonds[self.part[i] as usize];
        for pair in &self.pairs[self.pair_offsets[i]..self.pair_offsets[i + 1]] {
            let j = pair.j as usize;
            if !self.frozen.is_empty() && self.frozen[i] && self.frozen[j] {
                continue;
            }
            let d = sub(yi, self.position[j]);
            let r2 = dot(d, d);
            let watch = apart::WATCH * pair.limit;
            let touches = r2 < pair.reach * pair.reach;
            if !touches && r2 >= watch * watch || r2 == 0.0 {
                continue;
            }
            let intact = |k: u32| {
                k != NO_BOND && part_bonds.is_some_and(|b| b.neighbours[k as usize] & BROKEN == 0)
            };
            if intact(pair.bond) || intact(pair.reverse) {
                continue;
            }
            near |= r2 < watch * watch;
            if !touches || pair.closed {
                continue;
            }
            let r = r2.sqrt();
            let f = self.pair_force(i, j, pair.reach, d, r, vi);
            for a in 0..3 {
                total[a] += f[a];
            }
        }
        (total, near)
    }

    /// The force on i from j (module doc), written so that swapping i and j gives
    /// exactly the opposite vector.
    fn pair_force(
        &self,
        i: usize,
        j: usize,
        reach: f64,
        d: [f64; 3],
        r: f64,
        vi: [f64; 3],
    ) -> [f64; 3] {
        let s = &self.settings;
        let n = d.map(|x| x / r);
        let k = self.modulus[i].min(self.modulus[j]) * (self.volume[i] * self.volume[j]);
        let m = self.mass[i] * self.mass[j] / (self.mass[i] + self.mass[j]);
        let critical = (k * m).sqrt();
        let rel = sub(vi, self.velocity[j]);
        let vn = dot(rel, n);
        let normal = (k * (reach - r) - 2.0 * s.damping * critical * vn).max(0.0);
        let tangential = [rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]];
        let vt = dot(tangential, tangential).sqrt();
        let friction = if vt > 0.0 {
            (s.friction * normal).min(critical * vt) / vt
        } else {
            0.0
        };
        [0, 1, 2].map(|a| normal * n[a] - friction * tangential[a])
    }
}

/// The index of the bond i→j in `bonds` (rows are sorted by neighbour), or [`NO_BOND`].
fn bond_index(bonds: &Bonds, i: usize, j: usize) -> u32 {
    let row = bonds.range(i);
    bonds.neighbours[row.clone()]
        .binary_search_by_key(&(j as u32), |&x| x & INDEX)
        .map_or(NO_BOND, |k| (row.start + k) as u32)
}
