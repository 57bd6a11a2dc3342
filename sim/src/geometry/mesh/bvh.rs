//! A bounding-volume hierarchy over triangles: closest-point queries (for the
//! signed distance and the conformity measure) and box-overlap queries (for the
//! self-intersection check).

use perifrac_math::{add, dot, scale, sub};

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;

/// Which feature of a triangle a closest point lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// The interior of the face.
    Face,
    /// The edge from local corner `i` to `(i + 1) % 3`.
    Edge(usize),
    /// Local corner `i`.
    Vertex(usize),
}

#[derive(Debug, Clone)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Leaf: range `start..start + count` of `order`; inner: children at
    /// `start` and `start + 1`, with `count == 0`.
    start: u32,
    count: u32,
}

/// Median-split BVH over a set of triangles.
#[derive(Debug, Clone)]
pub struct Bvh {
    triangles: Vec<[[f64; 3]; 3]>,
    nodes: Vec<Node>,
    order: Vec<u32>,
}

/// The result of a closest-point query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Closest {
    /// Index of the triangle (as given to [`Bvh::new`]).
    pub triangle: usize,
    /// The closest point.
    pub point: [f64; 3],
    /// Squared distance to it.
    pub distance_squared: f64,
    /// The feature of the triangle it lies on.
    pub feature: Feature,
}

impl Bvh {
    /// Builds the hierarchy over `triangles` (corner positions).
    pub fn new(triangles: Vec<[[f64; 3]; 3]>) -> Bvh {
        let mut bvh = Bvh {
            order: (0..triangles.len() as u32).collect(),
            triangles,
            nodes: Vec::new(),
        };
        if !bvh.triangles.is_empty() {
            let centroids: Vec<[f64; 3]> = bvh
                .triangles
                .iter()
                .map(|t| scale(add(add(t[0], t[1]), t[2]), 1.0 / 3.0))
                .collect();
            bvh.nodes.push(Node {
                lo: [0.0; 3],
                hi: [0.0; 3],
                start: 0,
                count: 0,
            });
            bvh.build(0, 0, bvh.triangles.len(), &centroids);
        }
        bvh
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Whether there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The corners of triangle `t`.
    pub fn triangle(&self, t: usize) -> [[f64; 3]; 3] {
        self.triangles[t]
    }

    fn build(&mut self, node: usize, start: usize, end: usize, centroids: &[[f64; 3]]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &t in &self.order[start..end] {
            for p in self.triangles[t as usize] {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            let c = centroids[t as usize];
            for k in 0..3 {
                clo[k] = clo[k].min(c[k]);
                chi[k] = chi[k].max(c[k]);
            }
        }
        self.nodes[node].lo = lo;
        self.nodes[node].hi = hi;
        if end - start <= LEAF_SIZE {
            self.nodes[node].start = start as u32;
            self.nodes[node].count = (end - start) as u32;
            return;
        }
        let mut axis = 0;
        for k in 1..3 {
            if chi[k] - clo[k] > chi[axis] - clo[axis] {
                axis = k;
            }
        }
        let mid = (start + end) / 2;
        self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
            centroids[a as usize][axis]
                .total_cmp(&centroids[b as usize][axis])
                .then(a.cmp(&b))
        });
        let left = self.nodes.len();
        for _ in 0..2 {
            self.nodes.push(Node {
                lo: [0.0; 3],
                hi: [0.0; 3],
                start: 0,
                count: 0,
            });
        }
        self.nodes[node].start = left as u32;
        self.build(left, start, mid, centroids);
        self.build(left + 1, mid, end, centroids);
    }

    /// The closest point of any triangle to `p` (ties go to the lowest
    /// triangle index); `None` without triangles.
    pub fn closest(&self, p: [f64; 3]) -> Option<Closest> {
        let mut best: Option<Closest> = None;
        let mut stack = vec![0usize];
        if self.nodes.is_empty() {
            return None;
        }
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            let bound = box_distance_squared(p, node.lo, node.hi);
            if best.is_some_and(|b| bound > b.distance_squared) {
                continue;
            }
            if node.count > 0 {
                for &t in &self.order[node.start as usize..(node.start + node.count) as usize] {
                    let (point, feature) = closest_on_triangle(p, self.triangles[t as usize]);
                    let d = sub(point, p);
                    let d2 = dot(d, d);
                    let better = match best {
                        None => true,
                        Some(b) => {
                            d2 < b.distance_squared
                                || (d2 == b.distance_squared && (t as usize) < b.triangle)
                        }
                    };
                    if better {
                        best = Some(Closest {
                            triangle: t as usize,
                            point,
                            distance_squared: d2,
                            feature,
                        });
                    }
                }
            } else {
                let (a, b) = (node.start as usize, node.start as usize + 1);
                let da = box_distance_squared(p, self.nodes[a].lo, self.nodes[a].hi);
                let db = box_distance_squared(p, self.nodes[b].lo, self.nodes[b].hi);
                // Visit the nearer child first (pushed last).
                if da <= db {
                    stack.push(b);
                    stack.push(a);
                } else {
                    stack.push(a);
                    stack.push(b);
                }
            }
        }
        best
    }

    /// Calls `visit` with every triangle whose bounding box overlaps `[lo, hi]`.
    pub fn overlapping(&self, lo: [f64; 3], hi: [f64; 3], mut visit: impl FnMut(usize)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            if (0..3).any(|k| node.lo[k] > hi[k] || node.hi[k] < lo[k]) {
                continue;
            }
            if node.count > 0 {
                for &t in &self.order[node.start as usize..(node.start + node.count) as usize] {
                    let tri = self.triangles[t as usize];
                    let overlaps = (0..3).all(|k| {
                        let tlo = tri[0][k].min(tri[1][k]).min(tri[2][k]);
                        let thi = tri[0][k].max(tri[1][k]).max(tri[2][k]);
                        tlo <= hi[k] && thi >= lo[k]
                    });
                    if overlaps {
                        visit(t as usize);
                    }
                }
            } else {
                stack.push(node.start as usize + 1);
                stack.push(node.start as usize);
            }
        }
    }
}

fn box_distance_squared(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let d = (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0);
            d * d
        })
        .sum()
}

/// Closest point of triangle `abc` to `p` and the feature it lies on
/// (Ericson 2005, *Real-Time Collision Detection*, §5.1.5).
pub fn closest_on_triangle(p: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> ([f64; 3], Feature) {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(0));
    }
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (add(a, scale(ab, v)), Feature::Edge(0));
    }
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (add(a, scale(ac, w)), Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (add(b, scale(sub(c, b), w)), Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (add(a, add(scale(ab, v), scale(ac, w))), Feature::Face)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_regions() {
        let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let (p, feature) = closest_on_triangle([0.2, 0.2, 1.0], t);
        assert_eq!(feature, Feature::Face);
        assert!(dot(sub(p, [0.2, 0.2, 0.0]), sub(p, [0.2, 0.2, 0.0])) < 1e-30);
        assert_eq!(
            closest_on_triangle([-1.0, -1.0, 0.0], t).1,
            Feature::Vertex(0)
        );
        assert_eq!(
            closest_on_triangle([2.0, -0.1, 0.0], t).1,
            Feature::Vertex(1)
        );
        assert_eq!(closest_on_triangle([0.5, -1.0, 0.0], t).1, Feature::Edge(0));
        assert_eq!(closest_on_triangle([1.0, 1.0, 0.0], t).1, Feature::Edge(1));
        assert_eq!(closest_on_triangle([-1.0, 0.5, 0.0], t).1, Feature::Edge(2));
    }

    #[test]
    fn bvh_closest_matches_brute_force() {
        let mut s = 7u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let tris: Vec<[[f64; 3]; 3]> = (0..200)
            .map(|_| {
                let c = [rnd(), rnd(), rnd()];
                [0, 1, 2].map(|_| [0, 1, 2].map(|k| c[k] + 0.1 * rnd()))
            })
            .collect();
        let bvh = Bvh::new(tris.clone());
        for _ in 0..200 {
            let p = [0, 1, 2].map(|_| 2.0 * rnd() - 0.5);
            let got = bvh.closest(p).expect("non-empty");
            let want = tris
                .iter()
                .map(|&t| {
                    let q = closest_on_triangle(p, t).0;
                    dot(sub(q, p), sub(q, p))
                })
                .fold(f64::INFINITY, f64::min);
            assert!((got.distance_squared - want).abs() < 1e-15);
        }
    }
}
