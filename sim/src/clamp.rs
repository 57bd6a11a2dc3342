//! A clamp at a plane: u = 0 on a surface of a peridynamic body (an anchor's `clamp`),
//! instead of u = 0 throughout a held slab.
//!
//! A held slab is a clamp for a local model but not for a nonlocal one: the free
//! particles within δ of its face keep bonds into material that does not move, a kink
//! in the displacement their bonds see where the continuum's strain does not vanish at
//! the wall. A cantilever held that way is 6–10% too soft at 4–8 particles across
//! (docs/lattice.md, "Bending"), where the same beams with both ends free are within
//! 1.7% of the FEM.
//!
//! Here the anchor's particles within δ behind the plane are *ghosts* that continue
//! the free field smoothly through u = 0 at the plane. A ghost at distance s behind it
//! takes the quadratic through u(0) = 0, u(s) and u(2s) along the normal n,
//!
//! ```text
//! u_g = u(x_g + 3s n) − 3 u(x_g + 2s n),
//! ```
//!
//! each u(p) the linear least-squares fit a + g·(x − p) of the free particles (those of
//! the body in front of the plane and in no anchor) within 1.5λ of p: u_g = Σ_k w_gk u_k,
//! weights fixed at set-up from the reference positions. Ghosts' velocities are
//! extrapolated the same way. The particles farther than δ behind the plane have no
//! bond to a free particle and are held at rest.
//!
//! The clamp is variational: with the ghosts a linear map P of the free particles, the
//! strain energy is W(u_f, P u_f) and its gradient carries each ghost's internal force
//! back to the particles it is made from, F_k += Σ_g w_gk F_g (Pᵀ). The stiffness seen by
//! the free particles stays symmetric and the clamp does no work; the ghosts are part
//! of the wall (no mass, no gravity in the free particles' equations). Dropping that
//! transfer (ghosts placed, their forces lost) measured +3.2% / −1.4% where the
//! variational clamp has −3.0% / +1.7% (L/h = 5, 6 across): about as close, but not
//! conservative.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::{Matrix4, Vector4};
use perifrac_math::{dot, normalize, sub};
use rayon::prelude::*;

/// The plane of a clamp: through `point`, unit `normal` into the free body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// A point of the plane.
    pub point: [f64; 3],
    /// The unit normal, pointing into the free body.
    pub normal: [f64; 3],
}

impl Plane {
    /// The plane through `point` with normal along `normal` (non-zero).
    pub fn new(point: [f64; 3], normal: [f64; 3]) -> Plane {
        Plane {
            point,
            normal: normalize(normal),
        }
    }

    /// Signed distance of `x` in front of the plane (negative behind it).
    pub fn distance(&self, x: [f64; 3]) -> f64 {
        dot(sub(x, self.point), self.normal)
    }
}

/// The ghost layer of a clamp: each ghost's displacement as fixed weights of free
/// particles' displacements, in CSR arrays (ghost `g`'s sources are
/// `source[offsets[g]..offsets[g + 1]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Ghosts {
    /// The ghost particles.
    pub ghost: Vec<u32>,
    /// Start of each ghost's sources; one more entry than ghosts.
    offsets: Vec<u32>,
    /// The free particles each ghost is made from.
    source: Vec<u32>,
    /// The weights w_gk of the sources.
    weight: Vec<f64>,
}

/// Radius of the least-squares fits, in λ.
const FIT_RADIUS: f64 = 1.5;

impl Ghosts {
    /// The weights of the ghosts `ghost` (particles behind `plane`) from the `free`
    /// particles (in front of it), at reference positions `position`, for a body of
    /// resolution `lambda`. Fails, naming the first ghost that cannot be extrapolated,
    /// when the free particles near its mirror images are too few or flat to fit.
    pub fn build(
        position: &[[f64; 3]],
        ghost: Vec<u32>,
        free: &[u32],
        plane: Plane,
        lambda: f64,
    ) -> std::result::Result<Ghosts, String> {
        let free_position: Vec<[f64; 3]> = free.iter().map(|&k| position[k as usize]).collect();
        let tree = (!free.is_empty())
            .then(|| ImmutableKdTree::new_from_slice(&free_position))
            .transpose()
            .map_err(|e| format!("could not build the search tree of the clamp: {e:?}"))?;
        let n = plane.normal;
        let fits: Vec<std::result::Result<Vec<(u32, f64)>, String>> = ghost
            .par_iter()
            .map(|&g| {
                let x = position[g as usize];
                let s = -plane.distance(x);
                let at = |k: f64| [0, 1, 2].map(|a| x[a] + k * s * n[a]);
                let fail = || {
                    format!(
                        "the free particles in front of the plane near the ghost at {x:?} \
                         ({s:.3e} m behind the plane) are too few to extrapolate from"
                    )
                };
                let tree = tree.as_ref().ok_or_else(fail)?;
                let near = fit(tree, free, &free_position, at(2.0), lambda).ok_or_else(fail)?;
                let far = fit(tree, free, &free_position, at(3.0), lambda).ok_or_else(fail)?;
                let mut w: Vec<(u32, f64)> = far
                    .into_iter()
                    .chain(near.into_iter().map(|(k, c)| (k, -3.0 * c)))
                    .collect();
                w.sort_by_key(|&(k, _)| k);
                w.dedup_by(|b, a| {
                    let same = a.0 == b.0;
                    if same {
                        a.1 += b.1;
                    }
                    same
                });
                Ok(w)
            })
            .collect();
        let mut out = Ghosts {
            ghost,
            offsets: vec![0],
            source: Vec::new(),
            weight: Vec::new(),
        };
        for w in fits {
            for (k, c) in w? {
                out.source.push(k);
                out.weight.push(c);
            }
            out.offsets.push(out.source.len() as u32);
        }
        Ok(out)
    }

    /// The sources and weights of ghost number `g`.
    fn sources(&self, g: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.offsets[g] as usize..self.offsets[g + 1] as usize;
        self.source[range.clone()]
            .iter()
            .zip(&self.weight[range])
            .map(|(&k, &w)| (k as usize, w))
    }

    /// Places the ghosts: y_g = X_g + Σ_k w_gk (y_k − X_k), v_g = Σ_k w_gk v_k.
    pub fn place(&self, rest: &[[f64; 3]], position: &mut [[f64; 3]], velocity: &mut [[f64; 3]]) {
        for (g, &i) in self.ghost.iter().enumerate() {
            let (mut u, mut v) = ([0.0; 3], [0.0; 3]);
            for (k, w) in self.sources(g) {
                for a in 0..3 {
                    u[a] += w * (position[k][a] - rest[k][a]);
                    v[a] += w * velocity[k][a];
                }
            }
            let i = i as usize;
            position[i] = [0, 1, 2].map(|a| rest[i][a] + u[a]);
            velocity[i] = v;
        }
    }

    /// Carries the ghosts' internal forces F_g = m_g (a_g − g) back to their sources,
    /// a_k += Σ_g w_gk F_g / m_k, and sets the ghosts' accelerations to zero (they are
    /// placed, not integrated). Sequential in ghost order: the same bytes on any
    /// number of threads.
    pub fn carry(&self, mass: &[f64], gravity: [f64; 3], acceleration: &mut [[f64; 3]]) {
        for (g, &i) in self.ghost.iter().enumerate() {
            let i = i as usize;
            let force = [0, 1, 2].map(|a| mass[i] * (acceleration[i][a] - gravity[a]));
            for (k, w) in self.sources(g) {
                for a in 0..3 {
                    acceleration[k][a] += w * force[a] / mass[k];
                }
            }
            acceleration[i] = [0.0; 3];
        }
    }
}

/// The weights c_k of the linear least-squares fit u(p) ≈ Σ c_k u_k of the free
/// particles within 1.5λ of `p` (`None` when they do not determine a linear field).
fn fit(
    tree: &ImmutableKdTree<f64, 3>,
    free: &[u32],
    free_position: &[[f64; 3]],
    p: [f64; 3],
    lambda: f64,
) -> Option<Vec<(u32, f64)>> {
    let r = FIT_RADIUS * lambda;
    let mut near: Vec<usize> = tree
        .query(&p)
        .within::<SquaredEuclidean<f64>>(r * r)
        .unsorted()
        .execute()
        .into_iter()
        .map(|item| item.item as usize)
        .filter(|&j| dot(sub(free_position[j], p), sub(free_position[j], p)) < r * r)
        .collect();
    near.sort_unstable();
    let rows: Vec<[f64; 4]> = near
        .iter()
        .map(|&j| {
            let d = sub(free_position[j], p);
            [1.0, d[0] / lambda, d[1] / lambda, d[2] / lambda]
        })
        .collect();
    let z = least_squares(&rows, &[1.0, 0.0, 0.0, 0.0])?;
    Some(
        near.iter()
            .zip(&rows)
            .map(|(&j, row)| (free[j], dot4(row, &z)))
            .collect(),
    )
}

fn dot4(a: &[f64; 4], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// z = (ΦᵀΦ)⁻¹ e for the rows φ_k of Φ, so that c_k = φ_k · z are the weights of the
/// least-squares fit's eᵀ(coefficients); `None` when ΦᵀΦ is singular (its smallest
/// eigenvalue below 10⁻⁹ of its largest).
fn least_squares(rows: &[[f64; 4]], e: &[f64; 4]) -> Option<Vec<f64>> {
    let normal = Matrix4::<f64>::from_fn(|i, j| rows.iter().map(|r| r[i] * r[j]).sum());
    let eigen = normal.symmetric_eigen();
    let largest = eigen.eigenvalues.max();
    if !(largest > 0.0 && eigen.eigenvalues.min() > 1e-9 * largest) {
        return None;
    }
    let v = eigen.eigenvectors;
    let inverse = Matrix4::from_diagonal(&eigen.eigenvalues.map(|l| 1.0 / l));
    let z: Vector4<f64> = v * inverse * v.transpose() * Vector4::from_row_slice(e);
    Some(z.iter().copied().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cubic lattice of spacing 1 in x ∈ [−3, 6], y, z ∈ [−3, 3]; the plane x = 0.
    fn lattice() -> (Vec<[f64; 3]>, Vec<u32>, Vec<u32>) {
        let mut x = Vec::new();
        for i in -3..=6 {
            for j in -3..=3 {
                for k in -3..=3 {
                    x.push([f64::from(i) - 0.5, f64::from(j), f64::from(k)]);
                }
            }
        }
        let ghost = (0..x.len() as u32)
            .filter(|&i| (-2.0..0.0).contains(&x[i as usize][0]))
            .collect();
        let free = (0..x.len() as u32)
            .filter(|&i| x[i as usize][0] > 0.0)
            .collect();
        (x, ghost, free)
    }

    /// A displacement that grows linearly away from the plane is continued exactly
    /// through it (the fits reproduce linear fields, the extrapolation quadratics).
    #[test]
    fn a_linear_field_through_zero_is_continued_exactly() {
        let (x, ghost, free) = lattice();
        let plane = Plane::new([0.0; 3], [2.0, 0.0, 0.0]);
        let ghosts = Ghosts::build(&x, ghost, &free, plane, 1.0).expect("fits");
        let field = |p: [f64; 3]| [0.01 * p[0], 0.02 * p[0], -0.005 * p[0]];
        let mut y: Vec<[f64; 3]> = x
            .iter()
            .map(|p| [0, 1, 2].map(|a| p[a] + field(*p)[a]))
            .collect();
        let mut v = vec![[0.0; 3]; x.len()];
        for &g in &ghosts.ghost {
            y[g as usize] = x[g as usize];
        }
        ghosts.place(&x, &mut y, &mut v);
        for &g in &ghosts.ghost {
            let (got, want) = (y[g as usize], field(x[g as usize]));
            for a in 0..3 {
                assert!(
                    (got[a] - x[g as usize][a] - want[a]).abs() < 1e-12,
                    "ghost {g} at {:?}: {got:?}",
                    x[g as usize]
                );
            }
        }
    }

    /// The transfer is the transpose of the placement: Σ_g F_g · u_g = Σ_k F'_k · u_k
    /// (the clamp does no work).
    #[test]
    fn the_force_transfer_is_the_placements_transpose() {
        let (x, ghost, free) = lattice();
        let plane = Plane::new([0.0; 3], [1.0, 0.0, 0.0]);
        let ghosts = Ghosts::build(&x, ghost, &free, plane, 1.0).expect("fits");
        let n = x.len();
        let mass: Vec<f64> = (0..n).map(|i| 1.0 + 0.1 * (i % 7) as f64).collect();
        let u: Vec<[f64; 3]> = (0..n)
            .map(|i| [0.3 * (i % 5) as f64, -0.2 * (i % 3) as f64, 0.1])
            .collect();
        let mut y: Vec<[f64; 3]> = (0..n)
            .map(|i| [0, 1, 2].map(|a| x[i][a] + u[i][a]))
            .collect();
        ghosts.place(&x, &mut y, &mut vec![[0.0; 3]; n]);
        let gravity = [0.0, -9.81, 0.0];
        let acceleration: Vec<[f64; 3]> = (0..n)
            .map(|i| [(i % 4) as f64, 0.5 * (i % 9) as f64, -1.0])
            .collect();
        let mut carried = acceleration.clone();
        ghosts.carry(&mass, gravity, &mut carried);
        let work_ghosts: f64 = ghosts
            .ghost
            .iter()
            .map(|&g| {
                let g = g as usize;
                let f = [0, 1, 2].map(|a| mass[g] * (acceleration[g][a] - gravity[a]));
                dot(f, sub(y[g], x[g]))
            })
            .sum();
        let work_sources: f64 = (0..n)
            .filter(|&k| x[k][0] > 0.0)
            .map(|k| {
                let df = [0, 1, 2].map(|a| mass[k] * (carried[k][a] - acceleration[k][a]));
                dot(df, u[k])
            })
            .sum();
        assert!(
            (work_ghosts - work_sources).abs() < 1e-9 * work_ghosts.abs(),
            "{work_ghosts} {work_sources}"
        );
        assert!(
            ghosts
                .ghost
                .iter()
                .all(|&g| carried[g as usize] == [0.0; 3])
        );
    }

    /// A ghost with nothing in front of the plane to extrapolate from is an error.
    #[test]
    fn a_plane_facing_away_from_the_body_is_refused() {
        let (x, ghost, _) = lattice();
        let plane = Plane::new([0.0; 3], [1.0, 0.0, 0.0]);
        let message = Ghosts::build(&x, ghost, &[], plane, 1.0).expect_err("no free particles");
        assert!(message.contains("too few"), "{message}");
    }
}
