//! Reference solvers for validation and benchmarks (Chen et al. 2018 §6, Figs.
//! 10–13): explicit FEM with linear tetrahedra on the very tet meshes the peridynamic
//! particles come from, linear and corotated linear.
//!
//! Per tet e with rest edge matrix D_m = [X₁−X₀, X₂−X₀, X₃−X₀], B = D_m⁻¹ and rest
//! volume V, the deformation gradient is F = D_s B (D_s the current edge matrix).
//! The stress is the linear one of Hooke's law with Lamé λ = κ − 2μ/3 and μ,
//!
//! ```text
//! linear:     ε = ½(F + Fᵀ) − I,            P = 2μ ε + λ tr(ε) I
//! corotated:  F = R S,  ε = ½(RᵀF + FᵀR) − I,  P = R (2μ ε + λ tr(ε) I)
//! ```
//!
//! (corotated: the linear stress in the tet's rotated frame, Müller & Gross 2004;
//! R by [`rotation::extract`]). The nodal forces are the columns of
//! H = −V P Bᵀ on vertices 1–3 and f₀ = −(f₁ + f₂ + f₃) (Sifakis & Barbič 2012,
//! Eq. 4.6). Masses are lumped: ρV/4 to each vertex of every tet. Each vertex sums the
//! forces of its tets in a fixed order (gather), so results do not depend on the
//! thread count.
//!
//! Output particles are the tet barycentres, ordered as the peridynamic particles of
//! the same scene, so the two caches can be compared particle by particle.

pub mod rotation;
mod solver;

pub use solver::Fem;

use perifrac_math::{det_sum, det3, dot, inverse3, mat_mul, sub};
use rayon::prelude::*;

use crate::error::{Result, SimError};
use crate::geometry::discretize::Discretization;
use crate::material::Material;

/// A 3×3 matrix, rows first.
pub type M3 = [[f64; 3]; 3];

/// A body's material as the FEM uses it.
#[derive(Debug, Clone)]
pub struct FemBody {
    /// The material (density, moduli, air damping).
    pub material: Material,
    /// Lamé's first parameter λ = κ − 2μ/3 (Pa).
    pub lambda: f64,
    /// Shear modulus μ (Pa).
    pub mu: f64,
    /// Corotated (true) or linear (false) strain.
    pub corotated: bool,
}

impl FemBody {
    /// The FEM constants of `material`.
    pub fn new(material: Material, corotated: bool) -> FemBody {
        let mu = material.shear_modulus;
        let lambda = material.bulk_modulus - 2.0 * mu / 3.0;
        FemBody {
            material,
            lambda,
            mu,
            corotated,
        }
    }

    /// The linear stress 2μ ε + λ tr(ε) I.
    fn hooke(&self, eps: &M3) -> M3 {
        let tr = eps[0][0] + eps[1][1] + eps[2][2];
        let mut s = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] = 2.0 * self.mu * eps[i][j];
            }
            s[i][i] += self.lambda * tr;
        }
        s
    }

    /// Strain energy density μ ε:ε + ½ λ tr(ε)².
    fn energy_density(&self, eps: &M3) -> f64 {
        let tr = eps[0][0] + eps[1][1] + eps[2][2];
        let dd: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| eps[i][j] * eps[i][j])
            .sum();
        self.mu * dd + 0.5 * self.lambda * tr * tr
    }
}

/// The FEM model: vertices, tets, their rest shapes and the force kernel.
#[derive(Debug, Clone)]
pub struct FemModel {
    /// Rest positions X of the vertices (all bodies' meshes, one after another).
    pub rest: Vec<[f64; 3]>,
    /// Current vertex positions x.
    pub position: Vec<[f64; 3]>,
    /// Vertex velocities.
    pub velocity: Vec<[f64; 3]>,
    /// Lumped vertex masses (kg).
    pub mass: Vec<f64>,
    /// Body of each vertex.
    pub vertex_body: Vec<u32>,
    /// Tets as four global vertex indices.
    pub tets: Vec<[u32; 4]>,
    /// B = D_m⁻¹ per tet.
    inverse_rest: Vec<M3>,
    /// Rest volume V per tet.
    pub volume: Vec<f64>,
    /// Body of each tet.
    pub tet_body: Vec<u32>,
    /// Per-body constants.
    pub bodies: Vec<FemBody>,
    /// Rotation of each tet at the last force evaluation (corotated; warm start).
    pub rotation: Vec<rotation::Quaternion>,
    /// Tets around each vertex, CSR offsets.
    incidence_offsets: Vec<usize>,
    /// (tet, corner) around each vertex, in increasing tet order.
    incidence: Vec<(u32, u8)>,
    /// Global tet of each output particle (the peridynamic particle order).
    pub particle_tet: Vec<u32>,
    /// Output particle of each tet.
    tet_particle: Vec<u32>,
    /// Nodal forces per tet (scratch).
    tet_force: Vec<[[f64; 3]; 4]>,
    /// Internal force on each vertex (N, scratch).
    pub force: Vec<[f64; 3]>,
}

impl FemModel {
    /// Builds the model on the meshes of `disc`; `bodies[b]` holds body b's constants.
    /// Fails on a degenerate tet (zero or negative volume).
    pub fn new(disc: &Discretization, bodies: Vec<FemBody>) -> Result<FemModel> {
        let mut rest = Vec::new();
        let mut vertex_body = Vec::new();
        let mut tets = Vec::new();
        let mut tet_body = Vec::new();
        let mut tet_offset = Vec::new();
        for (b, mesh) in disc.meshes.iter().enumerate() {
            let base = rest.len() as u32;
            tet_offset.push(tets.len());
            rest.extend_from_slice(&mesh.vertices);
            vertex_body.extend(std::iter::repeat_n(b as u32, mesh.vertices.len()));
            tets.extend(mesh.tets.iter().map(|t| t.map(|v| v + base)));
            tet_body.extend(std::iter::repeat_n(b as u32, mesh.tets.len()));
        }
        let mut inverse_rest = Vec::with_capacity(tets.len());
        let mut volume = Vec::with_capacity(tets.len());
        for (e, t) in tets.iter().enumerate() {
            let dm = edge_matrix(&rest, t);
            let det = det3(&dm);
            if !(det > 0.0 && det.is_finite()) {
                return Err(SimError::Mesh {
                    body: format!("{}", tet_body[e]),
                    message: format!(
                        "tet {e} has volume {:e}: the FEM needs positively oriented tets",
                        det / 6.0
                    ),
                });
            }
            inverse_rest.push(inverse3(&dm, det));
            volume.push(det / 6.0);
        }
        let n = rest.len();
        let mut mass = vec![0.0; n];
        let mut count = vec![0usize; n];
        for (e, t) in tets.iter().enumerate() {
            let rho = bodies[tet_body[e] as usize].material.density;
            for &v in t {
                mass[v as usize] += 0.25 * rho * volume[e];
                count[v as usize] += 1;
            }
        }
        let mut incidence_offsets = vec![0usize; n + 1];
        for v in 0..n {
            incidence_offsets[v + 1] = incidence_offsets[v] + count[v];
        }
        let mut fill = incidence_offsets.clone();
        let mut incidence = vec![(0u32, 0u8); incidence_offsets[n]];
        for (e, t) in tets.iter().enumerate() {
            for (c, &v) in t.iter().enumerate() {
                incidence[fill[v as usize]] = (e as u32, c as u8);
                fill[v as usize] += 1;
            }
        }
        let particle_tet: Vec<u32> = disc
            .body
            .iter()
            .zip(&disc.tet)
            .map(|(&b, &t)| (tet_offset[b as usize] + t as usize) as u32)
            .collect();
        let mut tet_particle = vec![0u32; tets.len()];
        for (p, &e) in particle_tet.iter().enumerate() {
            tet_particle[e as usize] = p as u32;
        }
        let m = tets.len();
        Ok(FemModel {
            position: rest.clone(),
            velocity: vec![[0.0; 3]; n],
            rest,
            mass,
            vertex_body,
            tets,
            inverse_rest,
            volume,
            tet_body,
            bodies,
            rotation: vec![rotation::IDENTITY; m],
            incidence_offsets,
            incidence,
            particle_tet,
            tet_particle,
            tet_force: vec![[[0.0; 3]; 4]; m],
            force: vec![[0.0; 3]; n],
        })
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.rest.len()
    }

    /// Whether there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.rest.is_empty()
    }

    /// The output particle (tet barycentre, in cache order) of the first tet around
    /// vertex `v`: where a vertex is reported in messages.
    pub fn particle_of_vertex(&self, v: usize) -> usize {
        let (e, _) = self.incidence[self.incidence_offsets[v]];
        self.tet_particle[e as usize] as usize
    }

    /// The strain ε (in the rotated frame for corotated bodies) and the rotation R of
    /// tet e at the current positions; `q` is the warm start of R and is updated.
    fn strain(&self, e: usize, q: &mut rotation::Quaternion) -> (M3, Option<M3>) {
        let corotated = self.bodies[self.tet_body[e] as usize].corotated;
        strain(
            &self.position,
            &self.rest,
            &self.tets[e],
            &self.inverse_rest[e],
            corotated.then_some(q),
        )
    }

    /// Fills `force` with the internal nodal forces at the current positions
    /// (per tet, then gathered per vertex).
    pub fn internal_forces(&mut self) {
        let FemModel {
            position,
            rest,
            tets,
            inverse_rest,
            volume,
            tet_body,
            bodies,
            rotation,
            tet_force,
            incidence_offsets,
            incidence,
            force,
            ..
        } = self;
        tet_force
            .par_iter_mut()
            .zip(rotation.par_iter_mut())
            .enumerate()
            .with_min_len(512)
            .for_each(|(e, (f, q))| {
                let body = &bodies[tet_body[e] as usize];
                let b = &inverse_rest[e];
                let (eps, r) = strain(position, rest, &tets[e], b, body.corotated.then_some(q));
                let stress = body.hooke(&eps);
                let p = match r {
                    Some(r) => mat_mul(&r, &stress),
                    None => stress,
                };
                // H = −V P Bᵀ: column a is the force on vertex a + 1.
                let v = volume[e];
                *f = [[0.0; 3]; 4];
                for a in 0..3 {
                    for k in 0..3 {
                        let h = -v * (p[k][0] * b[a][0] + p[k][1] * b[a][1] + p[k][2] * b[a][2]);
                        f[a + 1][k] = h;
                        f[0][k] -= h;
                    }
                }
            });
        let tet_force = &*tet_force;
        force
            .par_iter_mut()
            .enumerate()
            .with_min_len(512)
            .for_each(|(v, f)| {
                let mut s = [0.0; 3];
                for &(e, c) in &incidence[incidence_offsets[v]..incidence_offsets[v + 1]] {
                    let g = tet_force[e as usize][c as usize];
                    for k in 0..3 {
                        s[k] += g[k];
                    }
                }
                *f = s;
            });
    }

    /// Total strain energy Σ_e V_e Ψ(ε_e) at the current positions (corotated: with
    /// the rotations of the last force evaluation as the starting guess).
    pub fn strain_energy(&self) -> f64 {
        det_sum(self.tets.len(), |e| {
            let mut q = self.rotation[e];
            let (eps, _) = self.strain(e, &mut q);
            self.volume[e] * self.bodies[self.tet_body[e] as usize].energy_density(&eps)
        })
    }

    /// Kinetic energy ½ Σ m v².
    pub fn kinetic_energy(&self) -> f64 {
        det_sum(self.len(), |i| {
            0.5 * self.mass[i] * dot(self.velocity[i], self.velocity[i])
        })
    }

    /// Positions of the output particles: tet barycentres of the current vertex
    /// positions, in cache order.
    pub fn particle_positions(&self) -> Vec<[f64; 3]> {
        self.particle_average(&self.position)
    }

    /// Velocities of the output particles (mean of their tets' vertex velocities).
    pub fn particle_velocities(&self) -> Vec<[f64; 3]> {
        self.particle_average(&self.velocity)
    }

    fn particle_average(&self, field: &[[f64; 3]]) -> Vec<[f64; 3]> {
        self.particle_tet
            .par_iter()
            .map(|&e| {
                let t = self.tets[e as usize];
                let mut s = [0.0; 3];
                for &v in &t {
                    for k in 0..3 {
                        s[k] += 0.25 * field[v as usize][k];
                    }
                }
                s
            })
            .collect()
    }

    /// The stable time step of central differences, 2/√λ_max, with λ_max of M⁻¹K
    /// bounded by the largest element eigenvalue of M_e⁻¹K_e (Irons & Treharne 1971,
    /// with M_e = ρV/4 per vertex, the element's share of the lumped mass; K_e the
    /// linear stiffness at rest, which is the corotated one's too). Each element's
    /// eigenvalue is found by power iteration on its 12 degrees of freedom. Returns
    /// the time step and the output particle of the limiting tet.
    pub fn stable_time_step(&self) -> (f64, usize) {
        let rates: Vec<f64> = (0..self.tets.len())
            .into_par_iter()
            .map(|e| self.element_eigenvalue(e))
            .collect();
        let (worst, lambda) =
            rates
                .iter()
                .copied()
                .enumerate()
                .fold(
                    (0, 0.0f64),
                    |(bi, bl), (i, l)| if l > bl { (i, l) } else { (bi, bl) },
                );
        let particle = self.tet_particle.get(worst).map_or(0, |&p| p as usize);
        if lambda <= 0.0 {
            return (f64::INFINITY, particle);
        }
        (2.0 / lambda.sqrt(), particle)
    }

    /// λ_max(M_e⁻¹ K_e) of tet e by power iteration (the matrix is symmetric: M_e is a
    /// multiple of the identity; its rigid modes have eigenvalue 0).
    fn element_eigenvalue(&self, e: usize) -> f64 {
        let body = &self.bodies[self.tet_body[e] as usize];
        let b = &self.inverse_rest[e];
        let v = self.volume[e];
        let inv_mass = 4.0 / (body.material.density * v);
        let apply = |u: &[[f64; 3]; 4]| -> [[f64; 3]; 4] {
            let mut du = [[0.0; 3]; 3];
            for a in 0..3 {
                for k in 0..3 {
                    du[k][a] = u[a + 1][k] - u[0][k];
                }
            }
            let stress = body.hooke(&sym(&mat_mul(&du, b)));
            let mut f = [[0.0; 3]; 4];
            for a in 0..3 {
                for k in 0..3 {
                    let h = inv_mass * v * (0..3).map(|j| stress[k][j] * b[a][j]).sum::<f64>();
                    f[a + 1][k] = h;
                    f[0][k] -= h;
                }
            }
            f
        };
        // A start with a component along every deformation mode.
        let mut u = [[0.0; 3]; 4];
        for (a, row) in u.iter_mut().enumerate() {
            for (k, x) in row.iter_mut().enumerate() {
                *x = (((a * 3 + k) * 7) % 11) as f64 - 5.0 + 0.1 * (a * k) as f64;
            }
        }
        let mut lambda = 0.0;
        for _ in 0..60 {
            let w = apply(&u);
            let uu: f64 = u.iter().map(|r| dot(*r, *r)).sum();
            let uw: f64 = u.iter().zip(&w).map(|(a, b)| dot(*a, *b)).sum();
            lambda = uw / uu;
            let ww: f64 = w.iter().map(|r| dot(*r, *r)).sum::<f64>().sqrt();
            if ww == 0.0 {
                return 0.0;
            }
            u = w.map(|r| r.map(|x| x / ww));
        }
        lambda
    }
}

/// The strain of a tet with corners `t` and B = `b`: ½(∇u + ∇uᵀ) (linear), or with a
/// rotation warm start `q`, ½(RᵀF + FᵀR) − I and R (corotated).
fn strain(
    position: &[[f64; 3]],
    rest: &[[f64; 3]],
    t: &[u32; 4],
    b: &M3,
    q: Option<&mut rotation::Quaternion>,
) -> (M3, Option<M3>) {
    // ∇u = (D_s − D_m) B, from displacements so that small strains keep their digits.
    let mut du = [[0.0; 3]; 3];
    let u0 = sub(position[t[0] as usize], rest[t[0] as usize]);
    for a in 0..3 {
        let v = t[a + 1] as usize;
        let ua = sub(position[v], rest[v]);
        for k in 0..3 {
            du[k][a] = ua[k] - u0[k];
        }
    }
    let grad = mat_mul(&du, b);
    let Some(q) = q else {
        return (sym(&grad), None);
    };
    let mut f = grad;
    for (k, row) in f.iter_mut().enumerate() {
        row[k] += 1.0;
    }
    let r = rotation::extract(&f, q);
    // RᵀF − I = Rᵀ∇u + (Rᵀ − I): both parts stay accurate for small strains.
    let mut g = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            g[i][j] = r[0][i] * grad[0][j] + r[1][i] * grad[1][j] + r[2][i] * grad[2][j] + r[j][i];
        }
        g[i][i] -= 1.0;
    }
    (sym(&g), Some(r))
}

fn edge_matrix(x: &[[f64; 3]], t: &[u32; 4]) -> M3 {
    let x0 = x[t[0] as usize];
    let mut d = [[0.0; 3]; 3];
    for a in 0..3 {
        let xa = x[t[a + 1] as usize];
        for k in 0..3 {
            d[k][a] = xa[k] - x0[k];
        }
    }
    d
}

fn sym(a: &M3) -> M3 {
    let mut s = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            s[i][j] = 0.5 * (a[i][j] + a[j][i]);
        }
    }
    s
}

fn col(m: &M3, j: usize) -> [f64; 3] {
    [m[0][j], m[1][j], m[2][j]]
}

#[cfg(test)]
mod tests;
