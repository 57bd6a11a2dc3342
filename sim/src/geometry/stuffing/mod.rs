//! Tetrahedral meshing of a signed-distance shape by isosurface stuffing.
//!
//! Implements Labelle & Shewchuk (2007), "Isosurface stuffing: fast
//! tetrahedral meshes with good dihedral angles". The shape's bounding box is
//! covered with a body-centred cubic (BCC) lattice whose tetrahedra are all
//! congruent; lattice vertices close to the surface are warped onto it, and
//! every lattice tetrahedron cut by the surface is replaced by a stencil of
//! one to three tetrahedra filling its inside part. The result is a
//! conforming mesh whose boundary vertices lie on the zero set of the SDF and
//! whose dihedral angles are bounded well away from 0° and 180°.
//!
//! Lattice geometry: with spacing `h`, corner points sit at `origin + h·(i, j, k)`
//! and centre points at `origin + h·(i + ½, j + ½, k + ½)`. Both are handled in
//! doubled integer coordinates (corners even, centres odd). Long edges join
//! neighbours on one grid (length `h`), short edges join a centre to the eight
//! corners of its cube (length `h·√3/2`). Each BCC tetrahedron is a long edge
//! of the centre grid plus a crossing long edge of the corner grid.

mod stencil;
mod turned;

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use perifrac_math::{dist, lerp};

use super::sdf::Sdf;
use super::{MeshError, TetMesh, checked_bounds, empty_mesh};
use stencil::Filler;
pub use turned::{random_rotation, stuff_rotated};

/// Mean edge length of a BCC tetrahedron over its lattice spacing:
/// two edges of `h` and four of `h·√3/2` give `(1 + √3) / 3`.
const MEAN_EDGE_PER_SPACING: f64 = 0.910_683_602_522_959_1;

/// Warping threshold on long edges, as a fraction of the edge length.
const ALPHA_LONG: f64 = 0.24999;

/// Warping threshold on short edges, as a fraction of the edge length.
const ALPHA_SHORT: f64 = 0.41189;

/// Largest lattice (corner plus centre points) the mesher will build.
const MAX_LATTICE_POINTS: u64 = 200_000_000;

/// Lattice margin around the shape's bounds, in lattice spacings.
const PADDING: f64 = 2.0;

/// Side, in cubes, of the blocks used to skip SDF evaluations far from the surface.
const BLOCK: usize = 8;

/// Stopping tolerance of the cut-point search, relative to the mesh's length scale
/// (the lattice spacing; the unstructured mesher's sampling radius).
pub(super) const ROOT_TOLERANCE: f64 = 1e-10;

/// Iteration cap of the cut-point search.
const ROOT_MAX_ITERATIONS: usize = 100;

/// Tetrahedra smaller than this times `h³` are dropped.
pub(super) const MIN_VOLUME: f64 = 1e-12;

/// Labelle & Shewchuk 2007, "Isosurface stuffing: fast tetrahedral meshes with good dihedral angles".
///
/// Fills the region where `sdf` is negative with tetrahedra whose mean edge
/// length is about `edge_length` (the lattice spacing is `edge_length / 0.911`,
/// the mean edge of a BCC tetrahedron being `0.911` spacings; cut tetrahedra
/// at the boundary are a little smaller). Boundary vertices lie on the zero
/// set of the SDF (to about `1e-10·edge_length` for an exact SDF), so sharp
/// edges and corners of the shape are bevelled at the scale of the edge
/// length. Every tetrahedron is positively oriented; any of volume below
/// `1e-12` cubed spacings would be dropped, though the stencils produce none.
/// The result is deterministic.
///
/// # Errors
/// - [`MeshError::InvalidEdgeLength`] if `edge_length` is not finite and positive;
/// - [`MeshError::InvalidBounds`] if the shape's bounds are not finite or are empty;
/// - [`MeshError::LatticeTooLarge`] if the lattice would exceed 2×10⁸ points;
/// - [`MeshError::NonFiniteDistance`] if the SDF returns NaN;
/// - [`MeshError::EmptyMesh`] if the shape is too thin to produce any tetrahedron.
pub fn stuff(sdf: &dyn Sdf, edge_length: f64) -> Result<TetMesh, MeshError> {
    stuff_counted(sdf, edge_length).map(|(mesh, _)| mesh)
}

/// The lattice spacing [`stuff`] uses for `edge_length`, and the number of points
/// of its lattice around `sdf`'s bounds (a float: it may be huge), known before
/// anything is allocated. An interior lattice cube of side h holds twelve
/// tetrahedra of volume h³/12.
pub fn lattice_size(sdf: &dyn Sdf, edge_length: f64) -> (f64, f64) {
    let h = edge_length / MEAN_EDGE_PER_SPACING;
    let (min, max) = sdf.bounds();
    (h, Lattice::size(min, max, h).1)
}

/// [`stuff`], also returning how many near-zero-volume tetrahedra were dropped.
fn stuff_counted(sdf: &dyn Sdf, edge_length: f64) -> Result<(TetMesh, usize), MeshError> {
    let (min, max) = checked_bounds(sdf, edge_length)?;
    let lattice = Lattice::covering(min, max, edge_length)?;
    let mut values = evaluate(sdf, &lattice)?;
    let mut cuts = CutTable::default();
    find_cuts(sdf, &lattice, &values, &mut cuts)?;
    let warped = warp(&lattice, &mut values, &cuts);
    let vertex_bound = values.iter().filter(|&&v| v <= 0.0).count() + cuts.cuts.len();
    let inside_centres = values[lattice.corners..]
        .iter()
        .filter(|&&v| v < 0.0)
        .count();
    let mut filler = Filler {
        sdf,
        lattice: &lattice,
        values: &values,
        warped: &warped,
        cuts: &mut cuts,
        point_vertex: vec![u32::MAX; lattice.total],
        cut_vertex: Vec::new(),
        mesh: TetMesh {
            vertices: Vec::with_capacity(vertex_bound),
            // Twelve lattice tets per cube: about right for the inside cubes.
            tets: Vec::with_capacity(12 * inside_centres),
        },
        min_volume: MIN_VOLUME * lattice.h.powi(3),
        dropped: 0,
    };
    lattice.for_each_tet(|ids, coords| filler.fill(ids, coords))?;
    let (mut mesh, dropped) = (filler.mesh, filler.dropped);
    mesh.vertices.shrink_to_fit();
    mesh.tets.shrink_to_fit();
    if mesh.tets.is_empty() {
        return Err(empty_mesh(min, max, edge_length));
    }
    Ok((mesh, dropped))
}

/// Multiplicative hasher for the integer keys of the lattice maps.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, x: u64) {
        let h = (self.0.rotate_left(5) ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        self.0 = h ^ (h >> 29);
    }
}

type KeyMap<V> = HashMap<u64, V, BuildHasherDefault<KeyHasher>>;

/// A BCC lattice: `cells` cubes per axis, `cells + 1` corner points and
/// `cells` centre points per axis. Points are numbered corners first.
struct Lattice {
    origin: [f64; 3],
    h: f64,
    cells: [usize; 3],
    corners: usize,
    total: usize,
}

impl Lattice {
    /// Cells per axis and total point count of the lattice for spacing `h`
    /// covering `[min, max]` with padding, as floats (they may be huge).
    fn size(min: [f64; 3], max: [f64; 3], h: f64) -> ([f64; 3], f64) {
        let cells = [0, 1, 2].map(|k| ((max[k] - min[k]) / h + 2.0 * PADDING).ceil());
        let points =
            (cells[0] + 1.0) * (cells[1] + 1.0) * (cells[2] + 1.0) + cells[0] * cells[1] * cells[2];
        (cells, points)
    }

    /// The lattice for `edge_length` covering `[min, max]` with padding.
    fn covering(min: [f64; 3], max: [f64; 3], edge_length: f64) -> Result<Self, MeshError> {
        let h = edge_length / MEAN_EDGE_PER_SPACING;
        let (cells_f, points_f) = Self::size(min, max, h);
        let limit = MAX_LATTICE_POINTS as f64;
        if points_f > limit || points_f.is_nan() {
            // Points scale like 1/λ³ (estimated factor by factor so that it
            // cannot overflow); step up from there until the lattice fits.
            let estimate = cells_f
                .iter()
                .fold(2f64.cbrt(), |p, c| p * (c + 1.0).cbrt());
            let mut suggested = edge_length * estimate / limit.cbrt();
            for _ in 0..100 {
                if Self::size(min, max, suggested / MEAN_EDGE_PER_SPACING).1 <= limit {
                    break;
                }
                suggested *= 1.02;
            }
            return Err(MeshError::LatticeTooLarge {
                points: if points_f.is_finite() {
                    points_f as u64
                } else {
                    u64::MAX
                },
                limit: MAX_LATTICE_POINTS,
                edge_length,
                suggested_edge_length: suggested,
            });
        }
        // Centred on the shape's bounds: the lattice is then mirror symmetric about the
        // shape's mid-planes, and with the warping order of `warp` so are the tets in
        // all but a few configurations of the stencils' parity rule (which is not
        // mirror symmetric), so a symmetric shape gets a symmetric set of tets
        // (centroid on the axes, no product of inertia), not one shifted by a fraction
        // of a spacing (0.08λ before).
        let origin = [0, 1, 2].map(|k| 0.5 * (min[k] + max[k]) - 0.5 * cells_f[k] * h);
        let far = [0, 1, 2].map(|k| origin[k] + cells_f[k] * h);
        if !origin.iter().chain(&far).all(|x| x.is_finite()) {
            // Only an edge length near the largest float gets here.
            return Err(MeshError::InvalidEdgeLength(edge_length));
        }
        let cells = cells_f.map(|c| c as usize);
        let corners = (cells[0] + 1) * (cells[1] + 1) * (cells[2] + 1);
        Ok(Self {
            origin,
            h,
            cells,
            corners,
            total: corners + cells[0] * cells[1] * cells[2],
        })
    }

    fn corner(&self, c: [usize; 3]) -> usize {
        c[0] + (self.cells[0] + 1) * (c[1] + (self.cells[1] + 1) * c[2])
    }

    fn centre(&self, c: [usize; 3]) -> usize {
        self.corners + c[0] + self.cells[0] * (c[1] + self.cells[1] * c[2])
    }

    /// Doubled integer coordinates of point `id`.
    fn coords(&self, id: usize) -> [i64; 3] {
        let (r, n, odd) = if id < self.corners {
            (id, self.cells.map(|c| c + 1), 0)
        } else {
            (id - self.corners, self.cells, 1)
        };
        let c = [r % n[0], (r / n[0]) % n[1], r / (n[0] * n[1])];
        [
            2 * c[0] as i64 + odd,
            2 * c[1] as i64 + odd,
            2 * c[2] as i64 + odd,
        ]
    }

    fn position(&self, coords: [i64; 3]) -> [f64; 3] {
        let s = 0.5 * self.h;
        [
            self.origin[0] + s * coords[0] as f64,
            self.origin[1] + s * coords[1] as f64,
            self.origin[2] + s * coords[2] as f64,
        ]
    }

    /// Calls `f` with the point ids and doubled coordinates of every BCC
    /// tetrahedron, ordered `[centre, centre, corner, corner]`: entries 0–1
    /// form a long edge of the centre grid and 2–3 one of the corner grid.
    fn for_each_tet<E>(
        &self,
        mut f: impl FnMut(&[usize; 4], &[[i64; 3]; 4]) -> Result<(), E>,
    ) -> Result<(), E> {
        let n = self.cells;
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let m = [i, j, k];
                    let id0 = self.centre(m);
                    let c0 = [2 * i as i64 + 1, 2 * j as i64 + 1, 2 * k as i64 + 1];
                    for a in 0..3 {
                        if m[a] + 1 >= n[a] {
                            continue;
                        }
                        let mut m1 = m;
                        m1[a] += 1;
                        let id1 = self.centre(m1);
                        let mut c1 = c0;
                        c1[a] += 2;
                        // The square face shared by the two cubes, walked around.
                        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                        let mut ids = [0; 4];
                        let mut coords = [[0; 3]; 4];
                        for (s, [db, dc]) in
                            [[0, 0], [1, 0], [1, 1], [0, 1]].into_iter().enumerate()
                        {
                            let mut q = m1;
                            q[b] += db;
                            q[c] += dc;
                            ids[s] = self.corner(q);
                            coords[s] = [2 * q[0] as i64, 2 * q[1] as i64, 2 * q[2] as i64];
                        }
                        for e in 0..4 {
                            let e1 = (e + 1) % 4;
                            f(
                                &[id0, id1, ids[e], ids[e1]],
                                &[c0, c1, coords[e], coords[e1]],
                            )?;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// Evaluates the SDF at every lattice point. Blocks of `BLOCK³` cubes whose
/// centre is far from the surface get a conservative value of the right sign
/// instead (this relies on the SDF being 1-Lipschitz); such points never end
/// an edge crossing the surface.
fn evaluate(sdf: &dyn Sdf, lattice: &Lattice) -> Result<Vec<f64>, MeshError> {
    let mut values = vec![0.0; lattice.total];
    let h = lattice.h;
    let radius = 0.5 * BLOCK as f64 * h * 3f64.sqrt();
    let blocks = lattice.cells.map(|c| c / BLOCK + 1);
    let eval = |coords: [i64; 3]| {
        let p = lattice.position(coords);
        let d = sdf.distance(p);
        if d.is_nan() {
            Err(MeshError::NonFiniteDistance { point: p })
        } else {
            Ok(d)
        }
    };
    for bk in 0..blocks[2] {
        for bj in 0..blocks[1] {
            for bi in 0..blocks[0] {
                let lo = [bi, bj, bk].map(|b| b * BLOCK);
                let middle = lo.map(|x| 2 * x as i64 + BLOCK as i64);
                let d = eval(middle)?;
                let far = d.abs() > radius + 2.0 * h;
                let bound = d.signum() * (d.abs() - radius);
                for grid in 0..2 {
                    let count = lattice.cells.map(|c| c + 1 - grid);
                    let hi = [0, 1, 2].map(|k| (lo[k] + BLOCK).min(count[k]));
                    for k in lo[2]..hi[2] {
                        for j in lo[1]..hi[1] {
                            for i in lo[0]..hi[0] {
                                let q = [i, j, k];
                                let id = if grid == 0 {
                                    lattice.corner(q)
                                } else {
                                    lattice.centre(q)
                                };
                                values[id] = if far {
                                    bound
                                } else {
                                    eval(q.map(|x| 2 * x as i64 + grid as i64))?
                                };
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(values)
}

fn opposite_signs(a: f64, b: f64) -> bool {
    (a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0)
}

/// A point where the surface crosses a lattice edge.
struct Cut {
    /// Lattice points ending the edge, smaller id first.
    ends: [u32; 2],
    /// Position along the edge as a fraction from `ends[0]`.
    t: f64,
    /// The point itself.
    pos: [f64; 3],
}

/// Cut points, found once per lattice edge so that neighbouring tetrahedra share them.
#[derive(Default)]
struct CutTable {
    index: KeyMap<u32>,
    cuts: Vec<Cut>,
}

impl CutTable {
    /// Index of the cut point on the edge `a`–`b`, whose ends have values of
    /// opposite signs, searching for it on first use.
    fn get(
        &mut self,
        sdf: &dyn Sdf,
        lattice: &Lattice,
        values: &[f64],
        a: usize,
        b: usize,
    ) -> Result<usize, MeshError> {
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        let key = ((a as u64) << 32) | b as u64;
        if let Some(&c) = self.index.get(&key) {
            return Ok(c as usize);
        }
        let pa = lattice.position(lattice.coords(a));
        let pb = lattice.position(lattice.coords(b));
        let t = find_zero(
            sdf,
            pa,
            values[a],
            pb,
            values[b],
            ROOT_TOLERANCE * lattice.h,
        )?;
        let c = self.cuts.len();
        self.cuts.push(Cut {
            ends: [a as u32, b as u32],
            t,
            pos: lerp(pa, pb, t),
        });
        self.index.insert(key, c as u32);
        Ok(c)
    }
}

/// Fraction `t` along `a`–`b` where the SDF vanishes, given its values `fa`
/// and `fb` of opposite signs at the ends: regula falsi with the Illinois
/// modification (bisecting where values are infinite), stopping when the
/// value or the bracket drops below `tol`.
pub(super) fn find_zero(
    sdf: &dyn Sdf,
    a: [f64; 3],
    fa: f64,
    b: [f64; 3],
    fb: f64,
    tol: f64,
) -> Result<f64, MeshError> {
    let len = dist(a, b);
    let (mut t0, mut f0, mut t1, mut f1) = (0.0, fa, 1.0, fb);
    let mut t = 0.5;
    let mut last_side = 0;
    for _ in 0..ROOT_MAX_ITERATIONS {
        let secant = (t0 * f1 - t1 * f0) / (f1 - f0);
        t = if secant > t0 && secant < t1 {
            secant
        } else {
            0.5 * (t0 + t1)
        };
        let p = lerp(a, b, t);
        let f = sdf.distance(p);
        if f.is_nan() {
            return Err(MeshError::NonFiniteDistance { point: p });
        }
        if f.abs() <= tol {
            break;
        }
        if (f < 0.0) == (f0 < 0.0) {
            (t0, f0) = (t, f);
            if last_side == -1 {
                f1 *= 0.5;
            }
            last_side = -1;
        } else {
            (t1, f1) = (t, f);
            if last_side == 1 {
                f0 *= 0.5;
            }
            last_side = 1;
        }
        if (t1 - t0) * len <= tol {
            break;
        }
    }
    Ok(t)
}

/// Finds the cut point on every lattice edge whose ends have opposite signs.
fn find_cuts(
    sdf: &dyn Sdf,
    lattice: &Lattice,
    values: &[f64],
    cuts: &mut CutTable,
) -> Result<(), MeshError> {
    let n = lattice.cells;
    let mut cross = |a: usize, b: usize| -> Result<(), MeshError> {
        if opposite_signs(values[a], values[b]) {
            cuts.get(sdf, lattice, values, a, b)?;
        }
        Ok(())
    };
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let q = [i, j, k];
                let id = lattice.corner(q);
                for a in 0..3 {
                    if q[a] < n[a] {
                        let mut r = q;
                        r[a] += 1;
                        cross(id, lattice.corner(r))?;
                    }
                }
                if i < n[0] && j < n[1] && k < n[2] {
                    let id = lattice.centre(q);
                    for a in 0..3 {
                        if q[a] + 1 < n[a] {
                            let mut r = q;
                            r[a] += 1;
                            cross(id, lattice.centre(r))?;
                        }
                    }
                    for octant in 0..8 {
                        let r = [i + (octant & 1), j + ((octant >> 1) & 1), k + (octant >> 2)];
                        cross(id, lattice.corner(r))?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// Snaps lattice points onto nearby cut points (setting their values to zero)
/// and returns their new positions.
///
/// A point is violated by a cut point on one of its edges lying closer than
/// `ALPHA_LONG` (long edges) or `ALPHA_SHORT` (short edges) times the edge
/// length. Violations are visited closest first and each violated point moves to
/// its nearest violating cut point that still exists; cut points on edges of a
/// warped point cease to exist (those edges now end on the surface).
fn warp(lattice: &Lattice, values: &mut [f64], cuts: &CutTable) -> KeyMap<[f64; 3]> {
    let long = lattice.h;
    let short = 0.5 * 3f64.sqrt() * lattice.h;
    // Distances are compared in units of 1e-9 spacings, so that mirror images, whose
    // distances differ by rounding only, tie; ties go to the edge direction in a fixed
    // order (long x, short, long y, long z), which every mirror of the lattice keeps.
    let quantum = 1e-9 * long;
    let mut violations: Vec<(i64, [i64; 3], u32, u32)> = Vec::new();
    for (c, cut) in cuts.cuts.iter().enumerate() {
        let [a, b] = cut.ends;
        let same_grid = ((a as usize) < lattice.corners) == ((b as usize) < lattice.corners);
        let (len, alpha) = if same_grid {
            (long, ALPHA_LONG)
        } else {
            (short, ALPHA_SHORT)
        };
        let (ca, cb) = (lattice.coords(a as usize), lattice.coords(b as usize));
        let direction = [0, 1, 2].map(|k| -(ca[k] - cb[k]).abs());
        if cut.t < alpha {
            let d = (cut.t * len / quantum).round() as i64;
            violations.push((d, direction, a, c as u32));
        } else if 1.0 - cut.t < alpha {
            let d = ((1.0 - cut.t) * len / quantum).round() as i64;
            violations.push((d, direction, b, c as u32));
        }
    }
    // Closest violation first (Labelle & Shewchuk allow any order): unlike an order by
    // point id, it treats mirror images alike, so a symmetric shape warps symmetrically.
    violations.sort_unstable();
    let mut warped = KeyMap::default();
    for (_, _, v, c) in violations {
        let cut = &cuts.cuts[c as usize];
        let other = cut.ends[0] + cut.ends[1] - v;
        if values[v as usize] == 0.0 || values[other as usize] == 0.0 {
            continue;
        }
        values[v as usize] = 0.0;
        warped.insert(u64::from(v), cut.pos);
    }
    warped
}

#[cfg(test)]
mod tests;
