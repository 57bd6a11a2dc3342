//! A clamp at a plane: u = 0 on a surface of a peridynamic body (an anchor's `clamp`),
//! instead of u = 0 throughout a held slab.
//!
//! A held slab is a clamp for a local model but not for a nonlocal one: the free
//! particles within δ of its face keep bonds into material that does not move, a kink
//! in the displacement their bonds see where the continuum's strain does not vanish at
//! the wall. A cantilever held that way is 5–10% too soft at 4–8 particles across
//! (docs/lattice.md, "Bending"), where the same beams with both ends free are within
//! 1.7% of the FEM.
//!
//! Here the anchor's particles within δ behind the plane are *ghosts* that continue
//! the free field smoothly through u = 0 at the plane. For a ghost at distance s behind
//! it, the free particles (those of the body in front of the plane and in no anchor)
//! within 1.5λ of its mirror image x_g + 2s n are fitted by least squares with a field
//! that vanishes on the plane, in the distance d in front of it and the offset t along
//! it (both in λ; n the plane's unit normal),
//!
//! ```text
//! u(d, t) = d (a + b·t) + d² (c + e·t)        (6 coefficients a component),
//! ```
//!
//! and the ghost takes its value u(−s, 0) = −s a + s² c: u_g = Σ_k w_gk u_k, weights
//! fixed at set-up from the reference positions. Ghosts' velocities are extrapolated
//! the same way. The particles farther than δ behind the plane have no bond to a free
//! particle and are held at rest. (The constraint u = 0 on the plane inside the fit,
//! rather than a quadratic through u(0) = 0 and two linear fits at s and 2s in front,
//! halves the error at 4 across: docs/lattice.md.)
//!
//! The clamp is variational: with the ghosts a linear map P of the free particles, the
//! strain energy is W(u_f, P u_f) and its gradient carries each ghost's internal force
//! back to the particles it is made from, F_k += Σ_g w_gk F_g (Pᵀ). The stiffness seen by
//! the free particles stays symmetric and the clamp does no work; the ghosts are part
//! of the wall (no mass, no gravity in the free particles' equations). Dropping that
//! transfer (ghosts placed, their forces lost) is not conservative.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::{Matrix6, Vector6};
use perifrac_math::{cross, dot, normalize, sub};
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

/// `x = 0.5 m, normal +x` for a plane normal to a scene axis (to the micrometre), else
/// the point and the normal.
impl std::fmt::Display for Plane {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let axis = (0..3).find(|&a| self.normal[a].abs() == 1.0);
        match axis {
            Some(a) => write!(
                f,
                "{} = {} m, normal {}{}",
                ["x", "y", "z"][a],
                // To the micrometre: −0.1 + 0.01 reads −0.09, not −0.09000000000000001.
                format!("{:.6}", self.point[a])
                    .trim_end_matches('0')
                    .trim_end_matches('.'),
                if self.normal[a] > 0.0 { '+' } else { '-' },
                ["x", "y", "z"][a]
            ),
            None => write!(f, "through {:?} m, normal {:?}", self.point, self.normal),
        }
    }
}

/// The ghost layer of a clamp: each ghost's displacement as fixed weights of free
/// particles' displacements, in CSR arrays (ghost `g`'s sources are
/// `source[offsets[g]..offsets[g + 1]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Ghosts {
    /// The clamp's plane.
    pub plane: Plane,
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
                let fail = || {
                    format!(
                        "the free particles in front of the plane near the ghost at {x:?} \
                         ({s:.3e} m behind the plane) are too few to extrapolate from"
                    )
                };
                let tree = tree.as_ref().ok_or_else(fail)?;
                let mirror = [0, 1, 2].map(|a| x[a] + 2.0 * s * n[a]);
                fit(tree, free, &free_position, mirror, s, plane, lambda).ok_or_else(fail)
            })
            .collect();
        let mut out = Ghosts {
            plane,
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

/// The weights c_k of u_g ≈ Σ c_k u_k: the value at distance `s` behind `plane` of the
/// least-squares fit of the module doc through the free particles within 1.5λ of `p`
/// (`None` when they do not determine it).
fn fit(
    tree: &ImmutableKdTree<f64, 3>,
    free: &[u32],
    free_position: &[[f64; 3]],
    p: [f64; 3],
    s: f64,
    plane: Plane,
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
    let n = plane.normal;
    let across = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = normalize(cross(n, across));
    let e2 = cross(n, e1);
    let rows: Vec<[f64; 6]> = near
        .iter()
        .map(|&j| {
            let x = free_position[j];
            let d = plane.distance(x) / lambda;
            let t = sub(x, p);
            let (t1, t2) = (dot(t, e1) / lambda, dot(t, e2) / lambda);
            [d, d * t1, d * t2, d * d, d * d * t1, d * d * t2]
        })
        .collect();
    let sigma = s / lambda;
    let z = least_squares(&rows, &[-sigma, 0.0, 0.0, sigma * sigma, 0.0, 0.0])?;
    Some(
        near.iter()
            .zip(&rows)
            .map(|(&j, row)| (free[j], row.iter().zip(&z).map(|(a, b)| a * b).sum()))
            .collect(),
    )
}

/// z = (ΦᵀΦ)⁻¹ e for the rows φ_k of Φ, so that c_k = φ_k · z are the weights of
/// eᵀ(the least-squares coefficients); `None` when ΦᵀΦ is singular (its smallest
/// eigenvalue below 10⁻⁹ of its largest).
fn least_squares(rows: &[[f64; 6]], e: &[f64; 6]) -> Option<Vector6<f64>> {
    let normal = Matrix6::<f64>::from_fn(|i, j| rows.iter().map(|r| r[i] * r[j]).sum());
    let eigen = normal.symmetric_eigen();
    let largest = eigen.eigenvalues.max();
    if !(largest > 0.0 && eigen.eigenvalues.min() > 1e-9 * largest) {
        return None;
    }
    let v = eigen.eigenvectors;
    let inverse = Matrix6::from_diagonal(&eigen.eigenvalues.map(|l: f64| 1.0 / l));
    Some(v * inverse * v.transpose() * Vector6::from_row_slice(e))
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

    /// A displacement of the fit's form (zero on the plane, quadratic away from it,
    /// varying linearly along it) is continued exactly through the plane.
    #[test]
    fn a_field_of_the_fits_form_is_continued_exactly() {
        let (x, ghost, free) = lattice();
        let plane = Plane::new([0.0; 3], [2.0, 0.0, 0.0]);
        let ghosts = Ghosts::build(&x, ghost, &free, plane, 1.0).expect("fits");
        let field = |p: [f64; 3]| {
            let (d, d2) = (p[0], p[0] * p[0]);
            [
                0.01 * d * (1.0 + 0.2 * p[1]),
                0.02 * d + 0.003 * d2 * (1.0 - 0.1 * p[2]),
                -0.005 * d2,
            ]
        };
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
