//! Constitutive tests of the peridynamic model under prescribed (affine) deformations:
//! patch test, rigid rotation, objectivity, Poisson ratio, surface correction,
//! return mapping and anisotropy. Each tolerance is one the physics must meet.

use super::*;
use crate::family;
use crate::geometry::{Cuboid, random_rotation, stuff, stuff_rotated};
use crate::scene::MaterialSpec;
use perifrac_math::mat_vec;

fn material(e: f64, nu: f64) -> MaterialSpec {
    MaterialSpec {
        density: 1000.0,
        bulk_modulus: None,
        shear_modulus: None,
        youngs_modulus: Some(e),
        poisson_ratio: Some(nu),
        yield_psi0: None,
        yield_stretch: None,
        plastic_limit: f64::INFINITY,
        critical_stretch: None,
        critical_compression: None,
        alpha: 0.0,
        anisotropy: None,
        air_damping: 0.0,
        laplacian_damping: 0.0,
        membrane: None,
        mpm: None,
        color: None,
    }
}

/// A box of `size` centred at the origin, meshed at λ, with horizon `horizon`·λ.
fn block(
    size: [f64; 3],
    lambda: f64,
    horizon: f64,
    spec: &MaterialSpec,
    form: DilatationForm,
    correction: bool,
) -> PdModel {
    block_on(size, lambda, None, horizon, spec, form, correction)
}

/// [`block`] on the lattice turned by `rotation` (`None`: aligned with the axes).
fn block_on(
    size: [f64; 3],
    lambda: f64,
    rotation: Option<[[f64; 3]; 3]>,
    horizon: f64,
    spec: &MaterialSpec,
    form: DilatationForm,
    correction: bool,
) -> PdModel {
    let shape = Cuboid {
        center: [0.0; 3],
        half_extents: [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0],
    };
    let mesh = match rotation {
        Some(r) => stuff_rotated(&shape, lambda, r),
        None => stuff(&shape, lambda),
    }
    .expect("box meshes");
    let x: Vec<[f64; 3]> = (0..mesh.tets.len()).map(|t| mesh.barycentre(t)).collect();
    let v: Vec<f64> = (0..mesh.tets.len()).map(|t| mesh.volume(t)).collect();
    let body = vec![0u32; x.len()];
    let delta = horizon * lambda;
    let bonds = family::families_through(&x, &body, &vec![delta; x.len()], &[]).expect("bonds");
    let bodies = vec![BodyModel::new(Material::from_spec(spec), delta)];
    let setup = Setup {
        form,
        surface_correction: correction,
        share: None,
    };
    PdModel::new(x, v, body, bonds, bodies, setup)
}

/// Particles whose whole horizon lies inside the box.
fn interior(m: &PdModel, size: [f64; 3], delta: f64) -> Vec<usize> {
    (0..m.len())
        .filter(|&i| (0..3).all(|a| m.reference.position[i][a].abs() + delta < size[a] / 2.0))
        .collect()
}

fn deform(m: &mut PdModel, f: [[f64; 3]; 3]) {
    for i in 0..m.len() {
        m.particles.position[i] = mat_vec(f, m.reference.position[i]);
    }
}

fn rot_z(angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = angle.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

fn mat_mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// Σ_j |½(A_ij + A_ji)| V_j, the scale of the forces acting on particle i.
fn force_scale(m: &PdModel, i: usize) -> f64 {
    let y = &m.particles.position;
    let a_prime = m.bodies[0].a_prime;
    let c = &m.coef;
    m.bonds
        .range(i)
        .map(|k| {
            let j = (m.bonds.neighbours[k] & INDEX) as usize;
            let e = norm(sub(y[j], y[i])) - m.coef.rest_length[k];
            let half_a = 2.0
                * (a_prime * (m.theta[i] * c.dil[k] as f64 + m.theta[j] * c.dil_rev[k] as f64)
                    + (c.dev[k] + c.dev_rev[k]) as f64 * e);
            half_a.abs() * m.reference.volume[j]
        })
        .sum()
}

#[test]
fn patch_test_dilatation_and_equilibrium() {
    let size = [0.3, 0.3, 0.3];
    let lambda = 0.025;
    let mut m = block(
        size,
        lambda,
        1.45,
        &material(1e6, 0.25),
        DilatationForm::Objective,
        true,
    );
    let eps = 1e-4;
    // A general small strain with shear: F = I + ε G.
    let g = [[1.0, 0.4, -0.3], [0.4, -0.5, 0.2], [-0.3, 0.2, 0.7]];
    let f = [
        [1.0 + eps * g[0][0], eps * g[0][1], eps * g[0][2]],
        [eps * g[1][0], 1.0 + eps * g[1][1], eps * g[1][2]],
        [eps * g[2][0], eps * g[2][1], 1.0 + eps * g[2][2]],
    ];
    let trace = eps * (g[0][0] + g[1][1] + g[2][2]);
    deform(&mut m, f);
    m.internal_forces();
    let theta_error = |m: &PdModel, i: usize, trace: f64| (m.theta[i] - trace).abs() / trace.abs();
    let delta = 1.45 * lambda;
    // Complete families: θ = tr ε and no net force.
    let inner = interior(&m, size, delta);
    assert!(inner.len() > 50, "{} interior particles", inner.len());
    let worst_theta = inner
        .iter()
        .map(|&i| theta_error(&m, i, trace))
        .fold(0.0, f64::max);
    assert!(
        worst_theta < 0.01,
        "θ deviates from tr ε by {worst_theta:.2e} (relative)"
    );
    // Families cut by the surface: the correction keeps θ exact on faces; near edges
    // and corners positive weights cannot be exact for shear (see family.rs), so
    // count how many particles in all are exact.
    let exact = (0..m.len())
        .filter(|&i| theta_error(&m, i, trace) < 0.01)
        .count();
    let exact_fraction = exact as f64 / m.len() as f64;
    assert!(
        exact_fraction > 0.9,
        "θ exact for only {:.1}% of all particles",
        100.0 * exact_fraction
    );
    // Tet barycentres are not centres of symmetry of the BCC lattice (it has 12
    // particle sites per cell), so under a homogeneous deformation each site feels a
    // residual force that an inner relaxation of the sublattices would remove (as in
    // crystals with a multi-site basis); ~3–4% of the bond forces here, with or
    // without the surface correction. Over a region of complete families it sums to
    // zero: that is the equilibrium check. Both need the neighbours' families
    // complete too, so take particles 2δ inside.
    let deep = interior(&m, size, 2.0 * delta);
    let worst = deep
        .iter()
        .map(|&i| norm(m.force[i]) / force_scale(&m, i))
        .fold(0.0, f64::max);
    let mut net = [0.0; 3];
    for &i in &deep {
        for (n, f) in net.iter_mut().zip(m.force[i]) {
            *n += f * m.reference.volume[i];
        }
    }
    let scale: f64 = deep
        .iter()
        .map(|&i| force_scale(&m, i) * m.reference.volume[i])
        .sum();
    let net = norm(net) / scale;
    // Stretches along the axes (and isotropic expansion): exact for every particle.
    let mut worst_axis = 0.0f64;
    for stretch in [
        [eps, 0.0, 0.0],
        [0.0, eps, 0.0],
        [0.0, 0.0, eps],
        [eps, eps, eps],
        [eps, -0.5 * eps, 0.3 * eps],
    ] {
        deform(
            &mut m,
            [
                [1.0 + stretch[0], 0.0, 0.0],
                [0.0, 1.0 + stretch[1], 0.0],
                [0.0, 0.0, 1.0 + stretch[2]],
            ],
        );
        m.internal_forces();
        let tr: f64 = stretch.iter().sum();
        worst_axis = (0..m.len())
            .map(|i| theta_error(&m, i, tr))
            .fold(worst_axis, f64::max);
    }
    assert!(
        worst_axis < 0.01,
        "θ under axis stretches deviates by {worst_axis:.2e}"
    );
    println!(
        "patch test: θ error {worst_theta:.2e} (complete), {worst_axis:.2e} (axis stretches, all), exact for {:.1}% (general F); \
         per-particle residual ≤ {worst:.3e}, net force {net:.2e} of the bond force scale over {} particles",
        100.0 * exact_fraction,
        deep.len()
    );
    assert!(
        worst < 0.06,
        "residual force on complete families: {worst:.3e} of the bond force scale"
    );
    assert!(
        net < 1e-3,
        "net force over complete families: {net:.3e} of the bond force scale"
    );
}

#[test]
fn rigid_rotation_has_no_ghost_forces() {
    for form in [DilatationForm::Objective, DilatationForm::Paper] {
        let mut m = block(
            [0.2, 0.1, 0.1],
            0.025,
            1.45,
            &material(1e6, 0.3),
            form,
            true,
        );
        deform(&mut m, rot_z(std::f64::consts::FRAC_PI_2));
        m.internal_forces();
        let worst = m.force.iter().map(|f| norm(*f)).fold(0.0, f64::max);
        // Force density scale of a 1e-4 strain, for comparison: E ε / λ.
        let scale = 1e6 * 1e-4 / 0.025;
        assert!(
            worst < 1e-9 * scale,
            "{form:?}: ghost force {worst:e} vs {scale:e}"
        );
    }
}

#[test]
fn objectivity_of_a_stretched_rotated_block() {
    let stretch = [[1.001, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let r = rot_z(std::f64::consts::FRAC_PI_2);
    let error = |form: DilatationForm| -> f64 {
        let mut a = block(
            [0.2, 0.1, 0.1],
            0.025,
            1.45,
            &material(1e6, 0.3),
            form,
            true,
        );
        let mut b = a.clone();
        deform(&mut a, stretch);
        a.internal_forces();
        deform(&mut b, mat_mul(r, stretch));
        b.internal_forces();
        let scale = a.force.iter().map(|f| norm(*f)).fold(0.0, f64::max);
        (0..a.len())
            .map(|i| norm(sub(b.force[i], mat_vec(r, a.force[i]))) / scale)
            .fold(0.0, f64::max)
    };
    let objective = error(DilatationForm::Objective);
    let paper = error(DilatationForm::Paper);
    println!("objectivity: objective form {objective:.2e}, paper form {paper:.2e}");
    assert!(objective < 1e-6, "objective form: {objective:e}");
    assert!(
        paper > 1e-2,
        "the paper's ŷ·ξ̂ should break objectivity visibly: {paper:e}"
    );
}

/// Energy of an affine deformation diag(1 + ε, 1 + t, 1 + t).
fn uniaxial_energy(m: &mut PdModel, eps: f64, t: f64) -> f64 {
    deform(
        m,
        [
            [1.0 + eps, 0.0, 0.0],
            [0.0, 1.0 + t, 0.0],
            [0.0, 0.0, 1.0 + t],
        ],
    );
    m.internal_forces();
    m.strain_energy()
}

/// ν from the lateral strain that minimizes the energy of a uniaxially stretched
/// bar with free sides (a parabola through three lateral strains).
fn poisson_of_bar(m: &mut PdModel) -> f64 {
    let eps = 1e-4;
    let h = 2e-5;
    let e: Vec<f64> = [-h, 0.0, h]
        .iter()
        .map(|&t| uniaxial_energy(m, eps, -0.25 * eps + t))
        .collect();
    let t_min = -0.25 * eps - h * (e[2] - e[0]) / (2.0 * (e[2] - 2.0 * e[1] + e[0]));
    -t_min / eps
}

#[test]
fn poisson_ratio_is_recovered() {
    for nu in [0.1, 0.25, 0.4] {
        let mut m = block(
            [0.4, 0.1, 0.1],
            0.02,
            1.45,
            &material(1e6, nu),
            DilatationForm::Objective,
            true,
        );
        let measured = poisson_of_bar(&mut m);
        println!("ν = {nu}: measured {measured:.4}");
        assert!(
            (measured - nu).abs() < 0.05 * nu,
            "ν = {nu}: measured {measured}"
        );
    }
}

/// Young's modulus of a 0.2 m cube at λ = 0.025 (8 particles across, so most families
/// are cut) on the lattice turned by `rotation`, from the energy of a uniaxial stress
/// state (lateral strain −νε): W = ½ E ε² per unit volume.
fn youngs_of_block(rotation: Option<[[f64; 3]; 3]>, horizon: f64, correction: bool) -> f64 {
    let size = [0.2, 0.2, 0.2];
    let nu = 0.25;
    let mut m = block_on(
        size,
        0.025,
        rotation,
        horizon,
        &material(1e6, nu),
        DilatationForm::Objective,
        correction,
    );
    let eps = 1e-4;
    let w = uniaxial_energy(&mut m, eps, -nu * eps);
    let volume: f64 = m.reference.volume.iter().sum();
    2.0 * w / (volume * eps * eps)
}

/// (largest − smallest) / largest.
fn spread(v: &[f64]) -> f64 {
    let (lo, hi) = v
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
    (hi - lo) / hi
}

/// Measured on three lattices: the aligned one and two turned at random (what elastic
/// and breaking bodies get). At δ = λ a family has a handful of bonds and, near the
/// surface, falls back to the scalar corrections, so E there depends on where the
/// lattice meets the surface: 0.962–1.028 × E over ten placements (the aligned cube at
/// sizes 0.200–0.220 m and five turned lattices), while δ = 1.45–3λ stay within
/// 1.005–1.026. A single lattice's spread over δ is then a draw of that placement
/// noise (6.0% on the centred aligned cube, whose E at δ = λ is 0.962; the lattice
/// before centring drew 0.977); the horizon dependence the correction must remove is
/// the spread of the mean over placements, and each single value must still be within
/// 5% of E.
#[test]
fn surface_correction_makes_stiffness_independent_of_horizon() {
    let horizons = [1.0, 1.45, 2.0, 3.0];
    let lattices = [
        None,
        Some(random_rotation(0, 0)),
        Some(random_rotation(1, 0)),
    ];
    let corrected: Vec<Vec<f64>> = lattices
        .iter()
        .map(|&r| {
            horizons
                .iter()
                .map(|&h| youngs_of_block(r, h, true))
                .collect()
        })
        .collect();
    let raw: Vec<f64> = horizons
        .iter()
        .map(|&h| youngs_of_block(None, h, false))
        .collect();
    let mean: Vec<f64> = (0..horizons.len())
        .map(|k| corrected.iter().map(|e| e[k]).sum::<f64>() / lattices.len() as f64)
        .collect();
    println!(
        "E / 1e6 of a cube for δ = {horizons:?} λ: corrected {:.4?} (aligned, turned, turned), \
         mean {:.4?}, uncorrected (aligned) {:.4?}",
        corrected
            .iter()
            .map(|e| e.iter().map(|x| x / 1e6).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
        mean.iter().map(|x| x / 1e6).collect::<Vec<_>>(),
        raw.iter().map(|x| x / 1e6).collect::<Vec<_>>()
    );
    assert!(
        spread(&mean) < 0.05,
        "corrected stiffness varies with δ by {:.1}%",
        100.0 * spread(&mean)
    );
    for e in corrected.iter().flatten() {
        assert!(
            (e / 1e6 - 1.0).abs() < 0.05,
            "corrected E = {e:e}, expected 1e6"
        );
    }
    assert!(
        spread(&raw) > 0.1,
        "without correction δ should matter: {:.1}%",
        100.0 * spread(&raw)
    );
}

#[test]
fn return_mapping_lands_on_yield_surface() {
    let mut spec = material(1e6, 0.3);
    spec.yield_stretch = Some(1e-4);
    let mut m = block(
        [0.2, 0.1, 0.1],
        0.025,
        1.45,
        &spec,
        DilatationForm::Objective,
        true,
    );
    let c = m.bodies[0].constants;
    // Pure shear well past yield.
    let g = 1e-3;
    deform(&mut m, [[1.0, g, 0.0], [g, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    m.internal_forces();
    let ext = &m.plastic.as_ref().expect("plastic state").extension;
    let y = &m.particles.position;
    let critical = (2.0 * c.psi0).sqrt();
    let (mut yielded, mut worst) = (0, 0.0f64);
    for i in 0..m.len() {
        for k in m.bonds.range(i) {
            if ext[k] == 0.0 {
                continue;
            }
            yielded += 1;
            let j = (m.bonds.neighbours[k] & INDEX) as usize;
            let r = m.coef.rest_length[k];
            let e = norm(sub(y[j], y[i])) - r;
            let q = m.coef.dil[k] as f64 * r / c.delta;
            let a_dev = 4.0 * m.coef.dev[k] as f64 * (e - 0.25 * c.delta * q * m.theta[i] - ext[k]);
            worst = worst.max((a_dev.abs() - critical).abs() / critical);
        }
    }
    println!("return mapping: {yielded} bonds yielded, worst |A_dev| error {worst:.2e}");
    assert!(yielded > 100);
    assert!(
        worst < 1e-6,
        "|A_dev| after return mapping is off the yield surface by {worst:e}"
    );
    // The factor printed in Eq. 15, 1/(2b), would leave A_dev at A_c + (1 − 2ω)(A − A_c):
    // off the surface unless ω = ½. Check that our test would see that.
    let omega = c.delta / (0.9 * c.delta);
    assert!((1.0 - 2.0 * omega).abs() > 1e-6);
}

/// Energy of an affine stretch along `axis`.
fn stretch_energy(m: &mut PdModel, axis: usize, eps: f64, only: &[usize]) -> f64 {
    let mut f = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    f[axis][axis] += eps;
    deform(m, f);
    m.internal_forces();
    let y = &m.particles.position;
    let delta = m.bodies[0].constants.delta;
    let c = m.bodies[0].a_prime * delta * family_volume(delta) / 3.0;
    only.iter()
        .map(|&i| {
            let dev: f64 = m
                .bonds
                .range(i)
                .map(|k| {
                    let j = (m.bonds.neighbours[k] & INDEX) as usize;
                    let e = norm(sub(y[j], y[i])) - m.coef.rest_length[k];
                    m.coef.dev[k] as f64 * e * e * m.reference.volume[j]
                })
                .sum();
            c * m.theta[i] * m.theta[i] + dev
        })
        .sum()
}

/// The same energy density for a complete continuum family, by quadrature over the
/// ball of radius δ (Eq. 5–10 with ω = δ/|Gξ|, Eq. 17).
fn quadrature_energy(g: [[f64; 3]; 3], mat: &Material, delta: f64, axis: usize, eps: f64) -> f64 {
    let c = (mat.bulk_modulus - 5.0 / 3.0 * mat.shear_modulus) / 2.0;
    let b = 15.0 * mat.shear_modulus / (2.0 * std::f64::consts::PI * delta.powi(5));
    let (nr, nt, np) = (40, 40, 80);
    let (mut theta, mut dev) = (0.0, 0.0);
    for ir in 0..nr {
        let r = (ir as f64 + 0.5) / nr as f64 * delta;
        for it in 0..nt {
            let ct = -1.0 + 2.0 * (it as f64 + 0.5) / nt as f64;
            let st = (1.0 - ct * ct).sqrt();
            for ip in 0..np {
                let phi = 2.0 * std::f64::consts::PI * (ip as f64 + 0.5) / np as f64;
                let n = [st * phi.cos(), st * phi.sin(), ct];
                let dv = r
                    * r
                    * (delta / nr as f64)
                    * (2.0 / nt as f64)
                    * (2.0 * std::f64::consts::PI / np as f64);
                let omega = delta / norm(mat_vec(g, [r * n[0], r * n[1], r * n[2]]));
                let e = r * eps * n[axis] * n[axis];
                theta += 3.0 / (delta * family_volume(delta)) * omega * e * dv;
                dev += omega * e * e * dv;
            }
        }
    }
    c * theta * theta + b * dev
}

#[test]
fn anisotropy_stiffens_as_eq17_predicts() {
    let mut spec = material(1e6, 0.25);
    let g = [[0.6, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    spec.anisotropy = Some(g);
    let size = [0.3, 0.3, 0.3];
    let lambda = 0.025;
    let mut m = block(size, lambda, 1.45, &spec, DilatationForm::Objective, true);
    let inner = interior(&m, size, 1.45 * lambda);
    let eps = 1e-4;
    let measured = stretch_energy(&mut m, 0, eps, &inner) / stretch_energy(&mut m, 1, eps, &inner);
    let mat = Material::from_spec(&spec);
    let delta = 1.45 * lambda;
    let predicted =
        quadrature_energy(g, &mat, delta, 0, eps) / quadrature_energy(g, &mat, delta, 1, eps);
    println!("anisotropy: x/y stiffness measured {measured:.4}, predicted {predicted:.4}");
    assert!(predicted > 1.2, "G should stiffen x: {predicted}");
    assert!(
        (measured / predicted - 1.0).abs() < 0.05,
        "measured {measured}, predicted {predicted}"
    );
}

/// The bonds of a block broken by one force pass under the uniform strain F = (1 + ε)I,
/// as (broken, rest length) pairs, for a material breaking at s^ω = `stretch` in
/// tension and (optionally) crushing at the strain ε_c = `compression`.
fn broken_under(eps: f64, stretch: f64, compression: Option<f64>) -> (Vec<(bool, f64)>, f64) {
    let spec = MaterialSpec {
        critical_stretch: Some(stretch),
        critical_compression: compression,
        ..material(1e6, 0.25)
    };
    let lambda = 0.02;
    let mut m = block(
        [0.1; 3],
        lambda,
        1.45,
        &spec,
        DilatationForm::Objective,
        true,
    );
    deform(
        &mut m,
        [
            [1.0 + eps, 0.0, 0.0],
            [0.0, 1.0 + eps, 0.0],
            [0.0, 0.0, 1.0 + eps],
        ],
    );
    m.internal_forces();
    let bonds = (0..m.bonds.neighbours.len())
        .map(|k| (m.bonds.neighbours[k] & BROKEN != 0, m.coef.rest_length[k]))
        .collect();
    (bonds, 1.45 * lambda)
}

#[test]
fn a_crushing_material_breaks_every_bond_compressed_past_its_strain_whatever_its_length() {
    // Under F = (1 − ε)I every bond has the strain e/|ξ| = −ε: with ε_c just under ε
    // all crush, short and long alike; just over, none do. (Eq. 19's weighted form,
    // e/δ < −ε_c, would crush only the bonds longer than ε_c δ/ε.)
    let (bonds, delta) = broken_under(-0.01, 1.0, Some(0.0099));
    assert!(bonds.iter().all(|&(b, _)| b), "a bond past ε_c is intact");
    let shortest = bonds.iter().fold(f64::INFINITY, |m, &(_, r)| m.min(r));
    assert!(
        shortest < 0.5 * delta,
        "the block has short bonds: {shortest}"
    );
    assert!(bonds.len() > 2000, "{} bonds", bonds.len());
    let (bonds, _) = broken_under(-0.01, 1.0, Some(0.0101));
    assert!(bonds.iter().all(|&(b, _)| !b), "a bond within ε_c crushed");
    // Chen's tension-only law (no critical_compression) and the same strain in
    // tension under a large s^ω break nothing.
    for (eps, compression) in [(-0.01, None), (0.01, Some(0.0099))] {
        let (bonds, _) = broken_under(eps, 1.0, compression);
        assert!(
            bonds.iter().all(|&(b, _)| !b),
            "ε = {eps}, ε_c = {compression:?}"
        );
    }
}

#[test]
fn a_crushed_bond_pushes_back_in_compression_only_and_yields_at_its_strain() {
    // Under F = (1 + ε)I every bond has the strain ε. Crushed at ε = −0.0101 (ε_c =
    // 0.01), each bond starts from e^c = −0.0001|ξ|; its energy then follows
    // (e − e^c)², at most that of an intact bond at the strain −ε_c, and is nil in
    // tension. (ν = 1/4: no dilatational energy, so an intact block at ε = −0.01 has
    // the same energy as the crushed one at an elastic strain of −0.01.)
    let uniform =
        |eps: f64| [0, 1, 2].map(|a| [0, 1, 2].map(|b| if a == b { 1.0 + eps } else { 0.0 }));
    let energy_at = |m: &mut PdModel, eps: f64| {
        deform(m, uniform(eps));
        m.internal_forces();
        m.strain_energy()
    };
    let spec = |compression| MaterialSpec {
        critical_stretch: Some(1.0),
        critical_compression: compression,
        ..material(1e6, 0.25)
    };
    let build = |s: &MaterialSpec| block([0.1; 3], 0.02, 1.45, s, DilatationForm::Objective, true);
    let w_c = energy_at(&mut build(&spec(None)), -0.01);
    let mut m = build(&spec(Some(0.01)));
    energy_at(&mut m, -0.0101);
    assert!(m.bonds.neighbours.iter().all(|&nb| nb & BROKEN != 0));
    let w = [-0.0101, -0.03, -0.02, -0.025, 0.01].map(|eps| energy_at(&mut m, eps) / w_c);
    println!("crushed block's energy over an intact one's at −ε_c: {w:?}");
    // Loaded to ε_c; yielding further (an elastic law would store 9×); unloaded to 0;
    // reloaded by ε_c/2 (a quarter); in tension, nothing.
    for (got, want) in w.iter().zip([1.0, 1.0, 0.0, 0.25, 0.0]) {
        assert!((got - want).abs() < 1e-6, "{w:?}");
    }
    assert!(m.force.iter().all(|f| *f == [0.0; 3]), "a force in tension");
}
