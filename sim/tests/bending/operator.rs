//! The linearised peridynamic operator of `bending.rs` (its module doc: K v by central
//! differences of the world's accelerations, conjugate gradients) and the free-free
//! beams' inverse iteration.

use perifrac_sim::contact;
use perifrac_sim::run::{self, Prepared};
use perifrac_sim::world::Part;

use super::{Beam, H};

pub(super) type Field = Vec<[f64; 3]>;

pub(super) fn dot(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x[0] * y[0] + x[1] * y[1] + x[2] * y[2])
        .sum()
}

/// The one part (the peridynamic body) of a prepared cantilever.
pub(super) fn part(p: &mut Prepared) -> &mut Part {
    assert_eq!(p.world.parts.len(), 1);
    &mut p.world.parts[0]
}

/// The particles no anchor holds or places.
pub(super) fn free_particles(part: &Part) -> Vec<bool> {
    let mut anchored = vec![false; part.model.points().position.len()];
    contact::mark_anchored(&part.anchors, 0.0, &mut anchored);
    anchored.iter().map(|a| !a).collect()
}

/// The stiffness K of the free particles (the anchored ones are masked out).
pub(super) struct Operator<'a> {
    pub(super) part: &'a mut Part,
    pub(super) free: Vec<bool>,
    pub(super) applied: usize,
}

impl Operator<'_> {
    /// K v by central differences of the world's accelerations (see the module doc).
    pub(super) fn apply(&mut self, v: &[[f64; 3]]) -> Field {
        let scale = v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            return vec![[0.0; 3]; v.len()];
        }
        let eps = 1e-6 * H / scale;
        let mut acceleration = [Vec::new(), Vec::new()];
        for (side, sign) in [1.0, -1.0].into_iter().enumerate() {
            let p = self.part.model.points_mut();
            for ((y, x), v) in p.position.iter_mut().zip(p.reference).zip(v) {
                *y = [0, 1, 2].map(|a| x[a] + sign * eps * v[a]);
            }
            acceleration[side] = self.part.accelerations_at(0.0, [0.0; 3]).to_vec();
        }
        self.applied += 1;
        let mass = self.part.model.points().mass;
        (0..v.len())
            .map(|i| {
                if !self.free[i] {
                    return [0.0; 3];
                }
                let (plus, minus) = (acceleration[0][i], acceleration[1][i]);
                [0, 1, 2].map(|a| -mass[i] * (plus[a] - minus[a]) / (2.0 * eps))
            })
            .collect()
    }

    /// Solves K x = b by conjugate gradients from `guess`, to ‖r‖ < `tol` ‖b‖,
    /// preconditioned by the particle volumes.
    pub(super) fn solve(&mut self, b: &[[f64; 3]], guess: Field, tol: f64) -> Field {
        let vol: Vec<f64> = self.part.model.points().mass.to_vec();
        let precondition = |r: &[[f64; 3]]| -> Field {
            r.iter().zip(&vol).map(|(r, v)| r.map(|x| x / v)).collect()
        };
        let mut x = guess;
        let kx = self.apply(&x);
        let mut r: Field = b
            .iter()
            .zip(&kx)
            .map(|(b, k)| [0, 1, 2].map(|a| b[a] - k[a]))
            .collect();
        let target = tol * dot(b, b).sqrt();
        let mut z = precondition(&r);
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        for _ in 0..200_000 {
            if dot(&r, &r).sqrt() < target {
                break;
            }
            let kp = self.apply(&p);
            let alpha = rz / dot(&p, &kp);
            for i in 0..x.len() {
                for a in 0..3 {
                    x[i][a] += alpha * p[i][a];
                    r[i][a] -= alpha * kp[i][a];
                }
            }
            z = precondition(&r);
            let rz_new = dot(&r, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..x.len() {
                for a in 0..3 {
                    p[i][a] = z[i][a] + beta * p[i][a];
                }
            }
        }
        x
    }
}

/// The first bending frequency (Hz) of the beam with both ends free (`clamp` = 0): no
/// clamp at all. Inverse iteration as in [`measure`], each iterate kept M-orthogonal to
/// the six rigid motions (K's kernel), from u_y = (x − L/2)².
pub(super) fn free_free(beam: Beam, tol: f64) -> f64 {
    let mut p = run::prepare(&beam.scene(0.0)).expect("prepares");
    let part = part(&mut p);
    let points = part.model.points();
    let n = points.position.len();
    let x = points.reference.to_vec();
    let mass = points.mass.to_vec();
    let total: f64 = mass.iter().sum();
    let centre = [0, 1, 2].map(|a| (0..n).map(|i| mass[i] * x[i][a]).sum::<f64>() / total);
    let mdot = |a: &[[f64; 3]], b: &[[f64; 3]]| -> f64 {
        (0..n)
            .map(|i| mass[i] * (a[i][0] * b[i][0] + a[i][1] * b[i][1] + a[i][2] * b[i][2]))
            .sum()
    };
    let mut rigid: Vec<Field> = Vec::new();
    for a in 0..3 {
        rigid.push(
            (0..n)
                .map(|_| [0, 1, 2].map(|c| f64::from(u8::from(c == a))))
                .collect(),
        );
        rigid.push(
            (0..n)
                .map(|i| {
                    let r = [0, 1, 2].map(|c| x[i][c] - centre[c]);
                    let e = [0, 1, 2].map(|c| f64::from(u8::from(c == a)));
                    [
                        e[1] * r[2] - e[2] * r[1],
                        e[2] * r[0] - e[0] * r[2],
                        e[0] * r[1] - e[1] * r[0],
                    ]
                })
                .collect(),
        );
    }
    for k in 0..rigid.len() {
        for j in 0..k {
            let c = mdot(&rigid[k], &rigid[j]);
            let rj = rigid[j].clone();
            for (v, w) in rigid[k].iter_mut().zip(&rj) {
                for a in 0..3 {
                    v[a] -= c * w[a];
                }
            }
        }
        let norm = mdot(&rigid[k], &rigid[k]).sqrt();
        for v in rigid[k].iter_mut() {
            for a in v.iter_mut() {
                *a /= norm;
            }
        }
    }
    let project = |u: &mut Field| {
        for r in &rigid {
            let c = mdot(u, r);
            for (v, w) in u.iter_mut().zip(r) {
                for a in 0..3 {
                    v[a] -= c * w[a];
                }
            }
        }
    };
    let half = 0.5 * beam.length();
    let mut u: Field = x
        .iter()
        .map(|p| [0.0, (p[0] - half).powi(2), 0.0])
        .collect();
    project(&mut u);
    let mut op = Operator {
        part,
        free: vec![true; n],
        applied: 0,
    };
    let mut omega2 = 0.0;
    for _ in 0..4 {
        let mu: Field = u.iter().zip(&mass).map(|(v, m)| v.map(|x| x * m)).collect();
        let guess = if omega2 > 0.0 {
            u.iter().map(|v| v.map(|x| x / omega2)).collect()
        } else {
            vec![[0.0; 3]; n]
        };
        let mut next = op.solve(&mu, guess, tol);
        project(&mut next);
        omega2 = mdot(&next, &u) / mdot(&next, &next);
        u = next;
    }
    omega2.sqrt() / (2.0 * std::f64::consts::PI)
}
