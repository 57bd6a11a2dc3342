//! Signed distance functions (SDFs) describing solid shapes to mesh.
//!
//! A shape is the set where its SDF is negative. Primitives ([`Cuboid`],
//! [`Ball`], [`Cylinder`]) are exact; the combinators [`Union`] and
//! [`Difference`] give conservative bounds, which is all the mesher needs.
//! Shapes also report their sharp features ([`Sdf::features`], module `features`).

mod features;

use perifrac_math::{dist, norm, sub};

pub(crate) use self::features::mesh as mesh_features;
pub use self::features::{Features, MESH_CREASE_ANGLE_DEG};

/// A solid shape described by a signed distance function.
pub trait Sdf: Send + Sync {
    /// Signed distance (negative inside) at p. Exact or a conservative bound (|grad| <= 1).
    fn distance(&self, p: [f64; 3]) -> f64;

    /// Axis-aligned bounds (min, max) of the inside region.
    fn bounds(&self) -> ([f64; 3], [f64; 3]);

    /// Gradient by central differences by default (override where closed-form is cheap).
    ///
    /// Where the distance is not differentiable, returns one of the one-sided
    /// gradients (or zero).
    fn gradient(&self, p: [f64; 3]) -> [f64; 3] {
        let scale = p.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        let step = 1e-6 * scale;
        [0, 1, 2].map(|k| {
            let (mut a, mut b) = (p, p);
            a[k] += step;
            b[k] -= step;
            (self.distance(a) - self.distance(b)) / (a[k] - b[k])
        })
    }

    /// The surface's sharp features (corners, creases, planar faces), curved creases
    /// as polylines with vertices at most `resolution` apart; none by default (a
    /// smooth surface, such as a [`Ball`]'s, or features not known).
    fn features(&self, _resolution: f64) -> Features {
        Features::default()
    }
}

/// An axis-aligned box (exact SDF).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cuboid {
    /// Centre of the box.
    pub center: [f64; 3],
    /// Half of the box's size along each axis.
    pub half_extents: [f64; 3],
}

/// A solid sphere (exact SDF).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    /// Centre of the ball.
    pub center: [f64; 3],
    /// Radius of the ball.
    pub radius: f64,
}

/// A solid capped cylinder along a coordinate axis (exact SDF).
///
/// An `axis` other than 0, 1 or 2 gives NaN distances and bounds, which the
/// mesher reports as an error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// Centre of the cylinder (midway between its caps).
    pub center: [f64; 3],
    /// Axis the cylinder runs along: 0 for x, 1 for y, 2 for z.
    pub axis: usize,
    /// Radius of the cylinder.
    pub radius: f64,
    /// Half of the cylinder's length along its axis.
    pub half_height: f64,
}

/// The union of shapes: the minimum of their distances. Its bounds are the
/// union of theirs; an empty union has empty (non-finite) bounds.
pub struct Union(pub Vec<Box<dyn Sdf>>);

/// The first shape with the second removed: `max(a, -b)`, for cutting notches.
/// Its bounds are those of the first shape.
pub struct Difference(pub Box<dyn Sdf>, pub Box<dyn Sdf>);

fn sign(x: f64) -> f64 {
    if x < 0.0 { -1.0 } else { 1.0 }
}

impl Sdf for Cuboid {
    fn distance(&self, p: [f64; 3]) -> f64 {
        let mut outside = 0.0;
        let mut inside = f64::NEG_INFINITY;
        for ((x, c), half) in p.iter().zip(&self.center).zip(&self.half_extents) {
            let q = (x - c).abs() - half;
            outside += q.max(0.0).powi(2);
            inside = inside.max(q);
        }
        outside.sqrt() + inside.min(0.0)
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        (
            [0, 1, 2].map(|k| self.center[k] - self.half_extents[k]),
            [0, 1, 2].map(|k| self.center[k] + self.half_extents[k]),
        )
    }

    fn gradient(&self, p: [f64; 3]) -> [f64; 3] {
        let d = [0, 1, 2].map(|k| p[k] - self.center[k]);
        let q = [0, 1, 2].map(|k| d[k].abs() - self.half_extents[k]);
        let outside = q.map(|x| x.max(0.0));
        let len = outside.iter().map(|x| x * x).sum::<f64>().sqrt();
        if len > 0.0 {
            [0, 1, 2].map(|k| sign(d[k]) * outside[k] / len)
        } else {
            let mut axis = 0;
            for k in 1..3 {
                if q[k] > q[axis] {
                    axis = k;
                }
            }
            let mut g = [0.0; 3];
            g[axis] = sign(d[axis]);
            g
        }
    }

    /// The 8 corners, 12 edges and 6 faces.
    fn features(&self, _resolution: f64) -> Features {
        features::cuboid(self.center, self.half_extents)
    }
}

impl Sdf for Ball {
    fn distance(&self, p: [f64; 3]) -> f64 {
        dist(p, self.center) - self.radius
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        (
            self.center.map(|c| c - self.radius),
            self.center.map(|c| c + self.radius),
        )
    }

    fn gradient(&self, p: [f64; 3]) -> [f64; 3] {
        let d = sub(p, self.center);
        let len = norm(d);
        if len > 0.0 {
            d.map(|x| x / len)
        } else {
            [0.0; 3]
        }
    }
}

impl Cylinder {
    /// The two axes across the cylinder, or `None` for an invalid `axis`.
    fn cross_axes(&self) -> Option<(usize, usize)> {
        match self.axis {
            0 => Some((1, 2)),
            1 => Some((2, 0)),
            2 => Some((0, 1)),
            _ => None,
        }
    }
}

impl Sdf for Cylinder {
    fn distance(&self, p: [f64; 3]) -> f64 {
        let Some((u, v)) = self.cross_axes() else {
            return f64::NAN;
        };
        let (du, dv) = (p[u] - self.center[u], p[v] - self.center[v]);
        let radial = (du * du + dv * dv).sqrt() - self.radius;
        let axial = (p[self.axis] - self.center[self.axis]).abs() - self.half_height;
        let (r, a) = (radial.max(0.0), axial.max(0.0));
        (r * r + a * a).sqrt() + radial.max(axial).min(0.0)
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        if self.cross_axes().is_none() {
            return ([f64::NAN; 3], [f64::NAN; 3]);
        }
        let half = [0, 1, 2].map(|k| {
            if k == self.axis {
                self.half_height
            } else {
                self.radius
            }
        });
        (
            [0, 1, 2].map(|k| self.center[k] - half[k]),
            [0, 1, 2].map(|k| self.center[k] + half[k]),
        )
    }

    fn gradient(&self, p: [f64; 3]) -> [f64; 3] {
        let Some((u, v)) = self.cross_axes() else {
            return [f64::NAN; 3];
        };
        let (du, dv) = (p[u] - self.center[u], p[v] - self.center[v]);
        let rho = (du * du + dv * dv).sqrt();
        let dz = p[self.axis] - self.center[self.axis];
        let radial = rho - self.radius;
        let axial = dz.abs() - self.half_height;
        // Components (radial, axial) of the gradient in the cylinder's frame.
        let (gr, ga) = if radial > 0.0 && axial > 0.0 {
            let len = (radial * radial + axial * axial).sqrt();
            (radial / len, axial / len)
        } else if radial > axial {
            (1.0, 0.0)
        } else {
            (0.0, 1.0)
        };
        let mut g = [0.0; 3];
        if rho > 0.0 {
            g[u] = gr * du / rho;
            g[v] = gr * dv / rho;
        }
        g[self.axis] = ga * sign(dz);
        g
    }

    /// The two rim circles and the two caps.
    fn features(&self, resolution: f64) -> Features {
        match self.cross_axes() {
            Some(across) => features::cylinder(
                self.center,
                self.axis,
                across,
                self.radius,
                self.half_height,
                resolution,
            ),
            None => Features::default(),
        }
    }
}

impl Sdf for Union {
    fn distance(&self, p: [f64; 3]) -> f64 {
        self.0
            .iter()
            .map(|s| s.distance(p))
            .fold(f64::INFINITY, f64::min)
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        self.0.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(lo, hi), s| {
                let (a, b) = s.bounds();
                (
                    [0, 1, 2].map(|k| lo[k].min(a[k])),
                    [0, 1, 2].map(|k| hi[k].max(b[k])),
                )
            },
        )
    }

    fn gradient(&self, p: [f64; 3]) -> [f64; 3] {
        let mut best: Option<(f64, &dyn Sdf)> = None;
        for s in &self.0 {
            let d = s.distance(p);
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, s.as_ref()));
            }
        }
        best.map_or([0.0; 3], |(_, s)| s.gradient(p))
    }

    /// Each part's features where no other part covers them (outside every other
    /// part: the others' least distance is not negative), and the creases where two
    /// parts' planar faces meet outside the rest.
    fn features(&self, resolution: f64) -> Features {
        let parts: Vec<Features> = self.0.iter().map(|s| s.features(resolution)).collect();
        let outside_others = |skip: [usize; 2]| {
            move |p: [f64; 3]| {
                self.0
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| !skip.contains(j))
                    .map(|(_, s)| s.distance(p))
                    .fold(f64::INFINITY, f64::min)
            }
        };
        let mut out = Features::default();
        for (i, part) in parts.iter().enumerate() {
            features::restrict(part, &outside_others([i, i]), resolution, &mut out);
        }
        for i in 0..parts.len() {
            for j in i + 1..parts.len() {
                let keep = outside_others([i, j]);
                features::meeting_faces(&parts[i], &parts[j], &keep, resolution, &mut out);
            }
        }
        out
    }
}

impl Sdf for Difference {
    fn distance(&self, p: [f64; 3]) -> f64 {
        self.0.distance(p).max(-self.1.distance(p))
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        self.0.bounds()
    }

    fn gradient(&self, p: [f64; 3]) -> [f64; 3] {
        if self.0.distance(p) >= -self.1.distance(p) {
            self.0.gradient(p)
        } else {
            self.1.gradient(p).map(|x| -x)
        }
    }

    /// The first shape's features outside the second, the second's inside the first
    /// (a notch's edges are creases of the result), and the creases where a planar
    /// face of one meets a planar face of the other.
    fn features(&self, resolution: f64) -> Features {
        let (base, cut) = (self.0.features(resolution), self.1.features(resolution));
        let mut out = Features::default();
        features::restrict(&base, &|p| self.1.distance(p), resolution, &mut out);
        features::restrict(&cut, &|p| -self.0.distance(p), resolution, &mut out);
        features::meeting_faces(&base, &cut, &|_| 0.0, resolution, &mut out);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences, for comparison with closed-form gradients.
    struct Numeric<'a>(&'a dyn Sdf);

    impl Sdf for Numeric<'_> {
        fn distance(&self, p: [f64; 3]) -> f64 {
            self.0.distance(p)
        }
        fn bounds(&self) -> ([f64; 3], [f64; 3]) {
            self.0.bounds()
        }
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
    }

    fn probe_points() -> Vec<[f64; 3]> {
        // Deterministic scatter over [-1.5, 1.5]^3.
        let mut s = 12345u64;
        (0..400)
            .map(|_| {
                [0, 1, 2].map(|_| {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    ((s >> 11) as f64 / (1u64 << 53) as f64) * 3.0 - 1.5
                })
            })
            .collect()
    }

    #[test]
    fn cuboid_distance_is_exact() {
        let c = Cuboid {
            center: [1.0, 2.0, 3.0],
            half_extents: [0.5, 1.0, 2.0],
        };
        assert_eq!(c.distance([1.0, 2.0, 3.0]), -0.5);
        assert!((c.distance([2.0, 2.0, 3.0]) - 0.5).abs() < 1e-15);
        assert!((c.distance([2.5, 4.0, 3.0]) - 2f64.sqrt()).abs() < 1e-15);
        assert!((c.distance([1.2, 2.0, 4.9]) + 0.1).abs() < 1e-12);
        assert_eq!(c.bounds(), ([0.5, 1.0, 1.0], [1.5, 3.0, 5.0]));
    }

    #[test]
    fn ball_and_cylinder_distances_are_exact() {
        let b = Ball {
            center: [0.0, 0.0, 1.0],
            radius: 2.0,
        };
        assert_eq!(b.distance([0.0, 0.0, 1.0]), -2.0);
        assert!((b.distance([3.0, 4.0, 1.0]) - 3.0).abs() < 1e-15);
        assert_eq!(b.bounds(), ([-2.0, -2.0, -1.0], [2.0, 2.0, 3.0]));
        let c = Cylinder {
            center: [0.0; 3],
            axis: 1,
            radius: 1.0,
            half_height: 2.0,
        };
        assert_eq!(c.distance([0.0; 3]), -1.0);
        assert!((c.distance([0.0, 1.9, 0.0]) + 0.1).abs() < 1e-12);
        assert!((c.distance([3.0, 0.0, 0.0]) - 2.0).abs() < 1e-15);
        assert!((c.distance([0.0, 3.0, 4.0]) - 10f64.sqrt()).abs() < 1e-12);
        assert_eq!(c.bounds(), ([-1.0, -2.0, -1.0], [1.0, 2.0, 1.0]));
    }

    #[test]
    fn invalid_cylinder_axis_gives_nan_not_panic() {
        let c = Cylinder {
            center: [0.0; 3],
            axis: 3,
            radius: 1.0,
            half_height: 1.0,
        };
        assert!(c.distance([0.0; 3]).is_nan());
        assert!(c.bounds().0[0].is_nan());
        assert!(c.gradient([0.0; 3])[0].is_nan());
    }

    #[test]
    fn combinators_combine_distances_and_bounds() {
        let u = Union(vec![
            Box::new(Ball {
                center: [0.0; 3],
                radius: 1.0,
            }),
            Box::new(Ball {
                center: [3.0, 0.0, 0.0],
                radius: 1.0,
            }),
        ]);
        assert!((u.distance([1.5, 0.0, 0.0]) - 0.5).abs() < 1e-15);
        assert_eq!(u.distance([3.0, 0.0, 0.0]), -1.0);
        assert_eq!(u.bounds(), ([-1.0, -1.0, -1.0], [4.0, 1.0, 1.0]));
        assert_eq!(u.gradient([3.5, 0.0, 0.0]), [1.0, 0.0, 0.0]);
        let empty = Union(Vec::new());
        assert!(!empty.bounds().0[0].is_finite());

        let d = Difference(
            Box::new(Cuboid {
                center: [0.0; 3],
                half_extents: [1.0; 3],
            }),
            Box::new(Ball {
                center: [1.0, 0.0, 0.0],
                radius: 0.5,
            }),
        );
        assert!((d.distance([0.75, 0.0, 0.0]) - 0.25).abs() < 1e-15);
        assert_eq!(d.distance([0.0; 3]), -0.5);
        assert_eq!(d.bounds(), ([-1.0; 3], [1.0; 3]));
        assert!(close(d.gradient([0.75, 0.0, 0.0]), [1.0, 0.0, 0.0], 0.0));
    }

    #[test]
    fn closed_form_gradients_match_central_differences() {
        let shapes: Vec<Box<dyn Sdf>> = vec![
            Box::new(Cuboid {
                center: [0.1, -0.2, 0.05],
                half_extents: [0.5, 0.7, 0.3],
            }),
            Box::new(Ball {
                center: [0.2, 0.1, -0.3],
                radius: 0.6,
            }),
            Box::new(Cylinder {
                center: [0.0, 0.1, 0.2],
                axis: 0,
                radius: 0.4,
                half_height: 0.8,
            }),
            Box::new(Cylinder {
                center: [0.3, 0.0, -0.1],
                axis: 2,
                radius: 0.7,
                half_height: 0.5,
            }),
        ];
        for s in &shapes {
            let numeric = Numeric(s.as_ref());
            let mut checked = 0;
            for p in probe_points() {
                let g = s.gradient(p);
                let n = numeric.gradient(p);
                // Skip points near a kink, where the one-sided gradients differ.
                let shifted = [0, 1, 2].map(|k| p[k] + 1e-4);
                if !close(s.gradient(shifted), g, 1e-2) {
                    continue;
                }
                assert!(close(g, n, 1e-5), "gradient {g:?} vs {n:?} at {p:?}");
                let len = g.iter().map(|x| x * x).sum::<f64>().sqrt();
                assert!((len - 1.0).abs() < 1e-9);
                checked += 1;
            }
            assert!(checked > 300, "only {checked} points checked");
        }
    }
}
