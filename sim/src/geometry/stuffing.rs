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

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use perifrac_math::{dist, dot, lerp, signed_volume, sub};

use super::sdf::Sdf;
use super::{MeshError, TetMesh};

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

/// Stopping tolerance of the cut-point search, relative to the lattice spacing.
const ROOT_TOLERANCE: f64 = 1e-10;

/// Iteration cap of the cut-point search.
const ROOT_MAX_ITERATIONS: usize = 100;

/// Tetrahedra smaller than this times `h³` are dropped.
const MIN_VOLUME: f64 = 1e-12;

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

/// [`stuff`] with the lattice turned by `rotation` (a proper rotation matrix, rows)
/// about the centre of the shape's bounds: the mesh of the shape turned by Rᵀ, turned
/// back by R. Boundary vertices still lie on the zero set and every tetrahedron stays
/// positively oriented (det R = 1); the lattice's axes, and so the directions along
/// which a mesh is weakest, are those of R instead of the scene's.
///
/// # Errors
/// As [`stuff`].
pub fn stuff_rotated(
    sdf: &dyn Sdf,
    edge_length: f64,
    rotation: [[f64; 3]; 3],
) -> Result<TetMesh, MeshError> {
    let turned = Turned::new(sdf, rotation);
    let mut mesh = stuff(&turned, edge_length)?;
    for v in &mut mesh.vertices {
        *v = turned.to_shape(*v);
    }
    Ok(mesh)
}

/// The shape of `inner` turned by Rᵀ about the centre c of its bounds:
/// d(p) = d_inner(c + R (p − c)).
struct Turned<'a> {
    inner: &'a dyn Sdf,
    centre: [f64; 3],
    rotation: [[f64; 3]; 3],
}

impl<'a> Turned<'a> {
    fn new(inner: &'a dyn Sdf, rotation: [[f64; 3]; 3]) -> Self {
        let (lo, hi) = inner.bounds();
        let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        Self {
            inner,
            centre,
            rotation,
        }
    }

    /// c + R (p − c): a point of the turned shape to the shape.
    fn to_shape(&self, p: [f64; 3]) -> [f64; 3] {
        let d = sub(p, self.centre);
        [0, 1, 2].map(|k| self.centre[k] + dot(self.rotation[k], d))
    }
}

impl Sdf for Turned<'_> {
    fn distance(&self, p: [f64; 3]) -> f64 {
        self.inner.distance(self.to_shape(p))
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        // The box around the turned corners of the inner bounds: c + Rᵀ (q − c).
        let (lo, hi) = self.inner.bounds();
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for corner in 0..8 {
            let q = [0, 1, 2].map(|k| if corner >> k & 1 == 0 { lo[k] } else { hi[k] });
            let d = sub(q, self.centre);
            for k in 0..3 {
                let x = self.centre[k] + (0..3).map(|r| self.rotation[r][k] * d[r]).sum::<f64>();
                min[k] = min[k].min(x);
                max[k] = max[k].max(x);
            }
        }
        (min, max)
    }
}

/// A uniformly distributed random rotation (rows of the matrix) from `seed` and
/// `stream` (e.g. a body index): the unit quaternion of Shoemake (1992), "Uniform
/// random rotations", from three uniform numbers.
pub fn random_rotation(seed: u64, stream: u64) -> [[f64; 3]; 3] {
    use std::f64::consts::TAU;
    let mut rng = perifrac_math::SplitMix64::new(seed ^ stream.wrapping_mul(0xd1b5_4a32_d192_ed03));
    let (u1, u2, u3) = (rng.next_f64(), rng.next_f64(), rng.next_f64());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (w, x, y, z) = (
        a * (TAU * u2).sin(),
        a * (TAU * u2).cos(),
        b * (TAU * u3).sin(),
        b * (TAU * u3).cos(),
    );
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
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
    if !(edge_length.is_finite() && edge_length > 0.0) {
        return Err(MeshError::InvalidEdgeLength(edge_length));
    }
    let (min, max) = sdf.bounds();
    let finite = (0..3).all(|k| (max[k] - min[k]).is_finite());
    if !finite || (0..3).any(|k| min[k] >= max[k]) {
        return Err(MeshError::InvalidBounds { min, max });
    }
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
        let thinnest = (0..3)
            .map(|k| max[k] - min[k])
            .fold(f64::INFINITY, f64::min);
        return Err(MeshError::EmptyMesh {
            edge_length,
            suggested_edge_length: (0.25 * thinnest).min(0.5 * edge_length),
        });
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
fn find_zero(
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

/// A vertex of a stencil's output, in terms of the BCC tetrahedron's local
/// vertices 0–3: a lattice vertex, or the cut point on an edge (inside end first).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Node {
    Vertex(usize),
    Cut(usize, usize),
}

/// Up to three output tetrahedra (unoriented) of one BCC tetrahedron.
struct Stencil {
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

    fn tets(&self) -> &[[Node; 4]] {
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
fn stencil(signs: [i8; 4], coords: &[[i64; 3]; 4]) -> Stencil {
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
struct Filler<'a> {
    sdf: &'a dyn Sdf,
    lattice: &'a Lattice,
    values: &'a [f64],
    warped: &'a KeyMap<[f64; 3]>,
    cuts: &'a mut CutTable,
    point_vertex: Vec<u32>,
    cut_vertex: Vec<u32>,
    mesh: TetMesh,
    min_volume: f64,
    dropped: usize,
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
    fn fill(&mut self, ids: &[usize; 4], coords: &[[i64; 3]; 4]) -> Result<(), MeshError> {
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

#[cfg(test)]
mod tests {
    use std::collections::HashMap;
    use std::f64::consts::PI;

    use super::super::{Ball, Cuboid, Cylinder, Difference, Union};
    use super::*;

    /// Small deterministic generator for test data.
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Everything measured by [`check`].
    struct Report {
        volume: f64,
        min_dihedral: f64,
        max_dihedral: f64,
        mean_edge: f64,
        tets: usize,
        vertices: usize,
        surface_error: f64,
    }

    /// Asserts that `mesh` is a valid stuffing of `sdf`: positive tetrahedra,
    /// no unused vertices, every face shared by at most two tetrahedra lying
    /// on opposite sides of it, and (if `closed`) a boundary that is a closed
    /// oriented manifold surface whose vertices lie within `surface_tol` of
    /// the zero set.
    fn check(mesh: &TetMesh, sdf: &dyn Sdf, closed: bool, surface_tol: f64) -> Report {
        let mut used = vec![false; mesh.vertices.len()];
        for (t, tet) in mesh.tets.iter().enumerate() {
            assert!(mesh.volume(t) > 0.0, "tet {t} {tet:?} not positive");
            for &v in tet {
                used[v as usize] = true;
            }
        }
        assert!(used.iter().all(|&u| u), "unused vertices");

        let mut faces: HashMap<[u32; 3], Vec<u32>> = HashMap::new();
        for tet in &mesh.tets {
            for skip in 0..4 {
                let mut f = [0u32; 3];
                let mut n = 0;
                for (v, &x) in tet.iter().enumerate() {
                    if v != skip {
                        f[n] = x;
                        n += 1;
                    }
                }
                f.sort_unstable();
                faces.entry(f).or_default().push(tet[skip]);
            }
        }
        let p = |v: u32| mesh.vertices[v as usize];
        for (f, opposite) in &faces {
            assert!(
                opposite.len() <= 2,
                "face {f:?} shared by {}",
                opposite.len()
            );
            if let [u, w] = opposite[..] {
                let su = signed_volume(p(f[0]), p(f[1]), p(f[2]), p(u));
                let sw = signed_volume(p(f[0]), p(f[1]), p(f[2]), p(w));
                assert!(su * sw < 0.0, "tets on face {f:?} overlap");
            }
        }

        let boundary = mesh.boundary_faces();
        let mut surface_error = 0.0f64;
        let expected = faces.values().filter(|o| o.len() == 1).count();
        assert_eq!(boundary.len(), expected);
        if closed {
            let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
            for f in &boundary {
                for e in 0..3 {
                    *directed.entry((f[e], f[(e + 1) % 3])).or_default() += 1;
                }
            }
            for (&(a, b), &n) in &directed {
                assert_eq!(n, 1, "directed boundary edge {a}-{b} used {n} times");
                assert_eq!(
                    directed.get(&(b, a)),
                    Some(&1),
                    "boundary edge {a}-{b} not shared by two faces"
                );
            }
            // The divergence theorem on the boundary gives the total volume.
            let enclosed: f64 = boundary
                .iter()
                .map(|f| signed_volume([0.0; 3], p(f[0]), p(f[1]), p(f[2])))
                .sum();
            let total = mesh.total_volume();
            assert!(
                (enclosed - total).abs() < 1e-9 * total,
                "{enclosed} vs {total}"
            );
            for f in &boundary {
                for &v in f {
                    let d = sdf.distance(p(v));
                    assert!(
                        d.abs() <= surface_tol,
                        "boundary vertex {v} at distance {d}"
                    );
                    surface_error = surface_error.max(d.abs());
                }
            }
        }
        let q = mesh.quality();
        Report {
            volume: mesh.total_volume(),
            min_dihedral: q.min_dihedral_deg,
            max_dihedral: q.max_dihedral_deg,
            mean_edge: q.mean_edge,
            tets: q.tets,
            vertices: mesh.vertices.len(),
            surface_error,
        }
    }

    /// Meshes `sdf`, checks it with [`check`] and the dihedral bounds, and
    /// returns the report after asserting no tetrahedron was dropped.
    fn mesh_and_check(name: &str, sdf: &dyn Sdf, lambda: f64, exact_volume: f64) -> Report {
        let (mesh, dropped) = stuff_counted(sdf, lambda).expect("meshing failed");
        assert_eq!(dropped, 0, "{name}: dropped degenerate tets");
        let r = check(&mesh, sdf, true, 1e-6);
        let err = r.volume / exact_volume - 1.0;
        println!(
            "{name:>10} λ={lambda}: {} tets, {} vertices, volume error {:+.3}%, \
             dihedral [{:.2}°, {:.2}°], mean edge {:.4}, surface error {:.1e}",
            r.tets,
            r.vertices,
            100.0 * err,
            r.min_dihedral,
            r.max_dihedral,
            r.mean_edge,
            r.surface_error
        );
        assert!(
            r.min_dihedral >= 8.0,
            "{name}: min dihedral {}",
            r.min_dihedral
        );
        assert!(
            r.max_dihedral <= 165.0,
            "{name}: max dihedral {}",
            r.max_dihedral
        );
        r
    }

    fn volume_error(r: &Report, exact: f64) -> f64 {
        (r.volume / exact - 1.0).abs()
    }

    fn unit_cube() -> Cuboid {
        Cuboid {
            center: [0.5; 3],
            half_extents: [0.5; 3],
        }
    }

    #[test]
    fn cube_meshes_with_good_quality() {
        let cube = unit_cube();
        let coarse = mesh_and_check("cube", &cube, 0.1, 1.0);
        assert!(volume_error(&coarse, 1.0) < 0.01);
        let fine = mesh_and_check("cube", &cube, 0.05, 1.0);
        assert!(volume_error(&fine, 1.0) < 0.005);
        assert!(
            (fine.mean_edge / 0.05 - 1.0).abs() < 0.15,
            "mean edge {}",
            fine.mean_edge
        );
    }

    #[test]
    fn ball_meshes_with_good_quality() {
        let r = 0.5;
        let ball = Ball {
            center: [0.1, -0.2, 0.3],
            radius: r,
        };
        let exact = 4.0 / 3.0 * PI * r * r * r;
        let report = mesh_and_check("ball", &ball, 0.05, exact);
        assert!(volume_error(&report, exact) < 0.02);
    }

    #[test]
    fn cylinder_union_and_difference_have_right_volumes() {
        let cyl = Cylinder {
            center: [0.0, 0.0, 0.0],
            axis: 2,
            radius: 0.3,
            half_height: 0.5,
        };
        let exact = PI * 0.3 * 0.3 * 1.0;
        let r = mesh_and_check("cylinder", &cyl, 0.05, exact);
        assert!(volume_error(&r, exact) < 0.02);

        // A box with a ball bulging out of its +x face (the ball crosses no
        // other face): one box plus a half ball.
        let union = Union(vec![
            Box::new(Cuboid {
                center: [0.0; 3],
                half_extents: [0.5; 3],
            }),
            Box::new(Ball {
                center: [0.5, 0.0, 0.0],
                radius: 0.3,
            }),
        ]);
        let exact = 1.0 + 2.0 / 3.0 * PI * 0.3f64.powi(3);
        let r = mesh_and_check("union", &union, 0.05, exact);
        assert!(volume_error(&r, exact) < 0.02);

        // A 1 × 0.5 × 0.5 bar with a 0.1-wide, 0.125-deep slot through it.
        let bar = Cuboid {
            center: [0.0; 3],
            half_extents: [0.5, 0.25, 0.25],
        };
        let notch = Cuboid {
            center: [0.0, 0.25, 0.0],
            half_extents: [0.05, 0.125, 0.3],
        };
        let difference = Difference(Box::new(bar), Box::new(notch));
        let exact = 0.25 - 0.1 * 0.125 * 0.5;
        let r = mesh_and_check("difference", &difference, 0.025, exact);
        assert!(volume_error(&r, exact) < 0.02);
    }

    #[test]
    fn thin_slab_is_resolved() {
        let slab = Cuboid {
            center: [0.0; 3],
            half_extents: [0.5, 0.01, 0.25],
        };
        let r = mesh_and_check("slab", &slab, 0.0125, 0.01);
        assert!(r.tets > 0);
        assert!(volume_error(&r, 0.01) < 0.03);
    }

    #[test]
    fn bad_input_gives_errors() {
        let ball = Ball {
            center: [0.0; 3],
            radius: 0.5,
        };
        assert_eq!(stuff(&ball, 0.0), Err(MeshError::InvalidEdgeLength(0.0)));
        assert_eq!(stuff(&ball, -1.0), Err(MeshError::InvalidEdgeLength(-1.0)));
        assert!(matches!(
            stuff(&ball, f64::NAN),
            Err(MeshError::InvalidEdgeLength(x)) if x.is_nan()
        ));
        assert!(matches!(
            stuff(&ball, f64::INFINITY),
            Err(MeshError::InvalidEdgeLength(_))
        ));
        assert!(matches!(
            stuff(&ball, f64::MAX),
            Err(MeshError::InvalidEdgeLength(_))
        ));
        assert!(matches!(
            stuff(&ball, 1e300),
            Err(MeshError::EmptyMesh { suggested_edge_length, .. }) if suggested_edge_length == 0.25
        ));

        let speck = Ball {
            center: [0.3, 0.2, 0.1],
            radius: 1e-4,
        };
        match stuff(&speck, 0.1) {
            Err(MeshError::EmptyMesh {
                edge_length,
                suggested_edge_length,
            }) => {
                assert_eq!(edge_length, 0.1);
                assert!(suggested_edge_length > 0.0 && suggested_edge_length <= 1e-4);
            }
            other => panic!("expected EmptyMesh, got {other:?}"),
        }

        match stuff(&unit_cube(), 1e-300) {
            Err(MeshError::LatticeTooLarge {
                points,
                suggested_edge_length,
                ..
            }) => {
                assert_eq!(points, u64::MAX);
                assert!(suggested_edge_length.is_finite());
                assert!(Lattice::covering([0.0; 3], [1.0; 3], suggested_edge_length).is_ok());
            }
            other => panic!("expected LatticeTooLarge, got {other:?}"),
        }
        match stuff(&unit_cube(), 1e-4) {
            Err(MeshError::LatticeTooLarge {
                points,
                suggested_edge_length,
                ..
            }) => {
                assert!(points > MAX_LATTICE_POINTS);
                assert!(suggested_edge_length > 1e-4);
                let lattice = Lattice::covering([0.0; 3], [1.0; 3], suggested_edge_length);
                assert!(lattice.is_ok(), "suggestion still too fine");
            }
            other => panic!("expected LatticeTooLarge, got {other:?}"),
        }

        let bad_axis = Cylinder {
            center: [0.0; 3],
            axis: 7,
            radius: 1.0,
            half_height: 1.0,
        };
        assert!(matches!(
            stuff(&bad_axis, 0.1),
            Err(MeshError::InvalidBounds { .. })
        ));
        assert!(matches!(
            stuff(&Union(Vec::new()), 0.1),
            Err(MeshError::InvalidBounds { .. })
        ));
        let inverted = Cuboid {
            center: [0.0; 3],
            half_extents: [0.5, -0.5, 0.5],
        };
        assert!(matches!(
            stuff(&inverted, 0.1),
            Err(MeshError::InvalidBounds { .. })
        ));

        struct Broken;
        impl Sdf for Broken {
            fn distance(&self, p: [f64; 3]) -> f64 {
                if p[0] > 0.2 {
                    f64::NAN
                } else {
                    p[0].abs() - 0.5
                }
            }
            fn bounds(&self) -> ([f64; 3], [f64; 3]) {
                ([-0.5; 3], [0.5; 3])
            }
        }
        assert!(matches!(
            stuff(&Broken, 0.1),
            Err(MeshError::NonFiniteDistance { .. })
        ));
    }

    #[test]
    fn meshing_is_deterministic() {
        let shape = Difference(
            Box::new(Ball {
                center: [0.0; 3],
                radius: 0.5,
            }),
            Box::new(Cylinder {
                center: [0.0; 3],
                axis: 1,
                radius: 0.15,
                half_height: 1.0,
            }),
        );
        let a = stuff(&shape, 0.06).expect("mesh");
        let b = stuff(&shape, 0.06).expect("mesh");
        assert!(!a.tets.is_empty());
        assert_eq!(a, b);
    }

    /// Volume-weighted centroid and products of inertia (I_xy, I_yz, I_zx) about it of
    /// the tets of `mesh`.
    fn centroid_and_products(mesh: &TetMesh) -> ([f64; 3], [f64; 3]) {
        let mut m = 0.0;
        let mut c = [0.0; 3];
        for t in 0..mesh.tets.len() {
            let (v, x) = (mesh.volume(t), mesh.barycentre(t));
            m += v;
            (0..3).for_each(|k| c[k] += v * x[k]);
        }
        c = c.map(|x| x / m);
        let mut p = [0.0; 3];
        for t in 0..mesh.tets.len() {
            let (v, x) = (mesh.volume(t), mesh.barycentre(t));
            let d = sub(x, c);
            (0..3).for_each(|k| p[k] += v * d[k] * d[(k + 1) % 3]);
        }
        (c, p)
    }

    /// Issue 13: the lattice sat 0.08λ off the axis of a centred box, so a cantilever
    /// loaded straight down bent sideways (7.4% of its deflection at 4 particles across).
    #[test]
    fn a_centred_box_gets_a_symmetric_mesh() {
        let shape = Cuboid {
            center: [0.3, -0.2, 0.1],
            half_extents: [0.5, 0.1, 0.1],
        };
        for lambda in [0.05, 0.0333, 0.025] {
            let mesh = stuff(&shape, lambda).expect("mesh");
            let (c, p) = centroid_and_products(&mesh);
            let inertia = 0.2 * 0.2 * 0.2 * 0.2 * 1.0 / 12.0;
            let unmatched = [1, 2].map(|k| mirror_mismatch(&mesh, k, shape.center[k]));
            println!(
                "λ {lambda}: centroid {c:?}, products {p:?} (of {inertia:e}), tets without a mirror image {unmatched:?}"
            );
            for k in 0..3 {
                assert!((c[k] - shape.center[k]).abs() < 1e-9, "centroid {c:?}");
                assert!(p[k].abs() < 1e-9 * inertia, "products of inertia {p:?}");
            }
            assert_eq!(unmatched, [0; 2], "tets without a mirror image in y and z");
        }
    }

    /// Tets whose barycentre has no mirror image in the plane `x[axis] = at` (to 1e-7 m).
    fn mirror_mismatch(mesh: &TetMesh, axis: usize, at: f64) -> usize {
        let key = |x: [f64; 3]| x.map(|v| (v * 1e7).round() as i64);
        let set: std::collections::HashSet<[i64; 3]> = (0..mesh.tets.len())
            .map(|t| key(mesh.barycentre(t)))
            .collect();
        (0..mesh.tets.len())
            .filter(|&t| {
                let mut x = mesh.barycentre(t);
                x[axis] = 2.0 * at - x[axis];
                !set.contains(&key(x))
            })
            .count()
    }

    /// A sphere wrinkled at the lattice scale (up to one spacing high): many
    /// cut configurations, warps and stencil cases per mesh.
    struct Wrinkled {
        ball: Ball,
        waves: Vec<([f64; 3], f64)>,
        amplitude: f64,
    }

    impl Wrinkled {
        fn new(rng: &mut Lcg, h: f64) -> Self {
            let ball = Ball {
                center: [rng.next(), rng.next(), rng.next()],
                radius: 0.2 + 0.2 * rng.next(),
            };
            let waves = (0..6)
                .map(|_| {
                    let dir = [0, 1, 2].map(|_| rng.next() - 0.5);
                    let len = dir.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
                    let k = (0.3 + 0.7 * rng.next()) * PI / h;
                    (dir.map(|x| x * k / len), 2.0 * PI * rng.next())
                })
                .collect();
            Self {
                ball,
                waves,
                amplitude: (0.25 + 0.75 * rng.next()) * h,
            }
        }
    }

    impl Sdf for Wrinkled {
        fn distance(&self, p: [f64; 3]) -> f64 {
            let wave: f64 = self
                .waves
                .iter()
                .map(|(k, phase)| (k[0] * p[0] + k[1] * p[1] + k[2] * p[2] + phase).sin())
                .sum();
            self.ball.distance(p) + self.amplitude * wave / self.waves.len() as f64
        }
        fn bounds(&self) -> ([f64; 3], [f64; 3]) {
            let (lo, hi) = self.ball.bounds();
            (
                lo.map(|x| x - self.amplitude),
                hi.map(|x| x + self.amplitude),
            )
        }
    }

    #[test]
    fn random_shapes_keep_dihedral_bounds() {
        let mut rng = Lcg(7);
        let (mut lo, mut hi) = (180.0f64, 0.0f64);
        let mut tets = 0;
        for trial in 0..24 {
            let lambda = 0.03 + 0.03 * rng.next();
            let h = lambda / MEAN_EDGE_PER_SPACING;
            let (mesh, dropped) = if trial % 2 == 0 {
                let shape = Wrinkled::new(&mut rng, h);
                let m = stuff_counted(&shape, lambda).expect("mesh");
                check(&m.0, &shape, false, 0.0);
                m
            } else {
                let shape = Ball {
                    center: [rng.next(), rng.next(), rng.next()],
                    radius: 0.1 + 0.3 * rng.next(),
                };
                let m = stuff_counted(&shape, lambda).expect("mesh");
                check(&m.0, &shape, true, 1e-9);
                m
            };
            assert_eq!(dropped, 0);
            let q = mesh.quality();
            lo = lo.min(q.min_dihedral_deg);
            hi = hi.max(q.max_dihedral_deg);
            tets += q.tets;
        }
        println!("random shapes: {tets} tets, dihedral angles in [{lo:.2}°, {hi:.2}°]");
        assert!(lo >= 8.0, "min dihedral {lo}");
        assert!(hi <= 165.0, "max dihedral {hi}");
    }

    fn unit_lattice(n: usize) -> Lattice {
        let corners = (n + 1).pow(3);
        Lattice {
            origin: [0.0; 3],
            h: 1.0,
            cells: [n; 3],
            corners,
            total: corners + n.pow(3),
        }
    }

    #[test]
    fn lattice_tets_are_congruent_and_positive_or_negative() {
        let lattice = unit_lattice(3);
        let mut count = 0;
        lattice
            .for_each_tet(|ids, coords| -> Result<(), ()> {
                for (id, c) in ids.iter().zip(coords) {
                    assert_eq!(lattice.coords(*id), *c);
                }
                let p = coords.map(|c| lattice.position(c));
                assert!((signed_volume(p[0], p[1], p[2], p[3]).abs() - 1.0 / 12.0).abs() < 1e-12);
                assert!((dist(p[0], p[1]) - 1.0).abs() < 1e-12);
                assert!((dist(p[2], p[3]) - 1.0).abs() < 1e-12);
                count += 1;
                Ok(())
            })
            .expect("visit");
        // 3 directions × (n - 1) · n² centre edges, 4 tets each.
        assert_eq!(count, 3 * 2 * 9 * 4);
    }

    /// Barycentric containment test (strict, with a tiny tolerance).
    fn contains(t: &[[f64; 3]; 4], x: [f64; 3]) -> bool {
        let v = signed_volume(t[0], t[1], t[2], t[3]);
        (0..4).all(|i| {
            let mut u = *t;
            u[i] = x;
            signed_volume(u[0], u[1], u[2], u[3]) / v > 1e-12
        })
    }

    #[test]
    fn stencils_tile_the_inside_of_every_lattice_tet() {
        // Every orientation and parity of BCC tet, every sign pattern, random
        // cut positions from a linear field: the stencil tets must be
        // non-degenerate and cover {field < 0} exactly once.
        let lattice = unit_lattice(3);
        let mut rng = Lcg(99);
        lattice
            .for_each_tet(|_, coords| -> Result<(), ()> {
                let p = coords.map(|c| lattice.position(c));
                for code in 0..81 {
                    let signs = [1, 3, 9, 27].map(|d| ((code / d) % 3) as i8 - 1);
                    let values = signs.map(|s| f64::from(s) * (0.2 + 0.8 * rng.next()));
                    let at = |n: Node| match n {
                        Node::Vertex(l) => p[l],
                        Node::Cut(a, b) => lerp(p[a], p[b], values[a] / (values[a] - values[b])),
                    };
                    let stencil = stencil(signs, coords);
                    let tets: Vec<[[f64; 3]; 4]> =
                        stencil.tets().iter().map(|t| t.map(at)).collect();
                    for t in &tets {
                        assert!(signed_volume(t[0], t[1], t[2], t[3]).abs() > 1e-6);
                    }
                    for _ in 0..60 {
                        let w = [0, 1, 2, 3].map(|_| -rng.next().max(1e-300).ln());
                        let sum: f64 = w.iter().sum();
                        let w = w.map(|x| x / sum);
                        let x = [0, 1, 2].map(|k| (0..4).map(|i| w[i] * p[i][k]).sum());
                        let phi: f64 = (0..4).map(|i| w[i] * values[i]).sum();
                        if phi.abs() < 1e-9 {
                            continue;
                        }
                        let hits = tets.iter().filter(|t| contains(t, x)).count();
                        assert_eq!(
                            hits,
                            usize::from(phi < 0.0),
                            "signs {signs:?} coords {coords:?}"
                        );
                    }
                }
                Ok(())
            })
            .expect("visit");
    }

    #[test]
    fn neighbouring_stencils_agree_on_shared_faces() {
        // Random signs on a small lattice: every output face is shared by at
        // most two tets, and faces used once lie on the surface (cut points
        // and zero vertices only).
        let n = 4;
        let lattice = unit_lattice(n);
        let mut rng = Lcg(2024);
        for _ in 0..400 {
            let signs: Vec<i8> = (0..lattice.total)
                .map(|id| {
                    let c = lattice.coords(id);
                    // The outer layer of both grids stays outside, as padding does.
                    if c.iter().any(|&x| x <= 1 || x >= 2 * n as i64 - 1) {
                        1
                    } else {
                        (rng.next() * 3.0) as i8 - 1
                    }
                })
                .collect();
            const CUT: u64 = 1 << 62;
            let mut faces: HashMap<[u64; 3], usize> = HashMap::new();
            lattice
                .for_each_tet(|ids, coords| -> Result<(), ()> {
                    let s = ids.map(|id| signs[id]);
                    for t in stencil(s, coords).tets() {
                        let keys = t.map(|node| match node {
                            Node::Vertex(l) => ids[l] as u64,
                            Node::Cut(a, b) => {
                                let (a, b) = (ids[a].min(ids[b]), ids[a].max(ids[b]));
                                CUT | ((a as u64) << 20) | b as u64
                            }
                        });
                        for skip in 0..4 {
                            let mut f = [0u64; 3];
                            let mut m = 0;
                            for (v, &k) in keys.iter().enumerate() {
                                if v != skip {
                                    f[m] = k;
                                    m += 1;
                                }
                            }
                            f.sort_unstable();
                            *faces.entry(f).or_default() += 1;
                        }
                    }
                    Ok(())
                })
                .expect("visit");
            for (f, &count) in &faces {
                assert!(count <= 2, "face {f:?} used {count} times");
                if count == 1 {
                    for &k in f {
                        assert!(
                            k & CUT != 0 || signs[k as usize] == 0,
                            "non-surface boundary face {f:?}"
                        );
                    }
                }
            }
        }
    }
}
