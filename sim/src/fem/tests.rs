//! Unit tests of the FEM kernels: rigid motions, ghost forces, the stable step.

use super::*;
use crate::geometry::TetMesh;
use crate::geometry::discretize::Discretization;
use crate::geometry::{Cuboid, stuff};
use crate::material::Material;
use crate::scene::MaterialSpec;

fn material() -> Material {
    Material::from_spec(&MaterialSpec {
        density: 1000.0,
        bulk_modulus: None,
        shear_modulus: None,
        youngs_modulus: Some(1.0e6),
        poisson_ratio: Some(0.3),
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
    })
}

fn block(corotated: bool) -> FemModel {
    let mesh: TetMesh = stuff(
        &Cuboid {
            center: [0.0; 3],
            half_extents: [0.2, 0.05, 0.05],
        },
        0.025,
    )
    .expect("meshes");
    let n = mesh.tets.len();
    let disc = Discretization {
        position: (0..n).map(|t| mesh.barycentre(t)).collect(),
        volume: (0..n).map(|t| mesh.volume(t)).collect(),
        body: vec![0; n],
        tet: (0..n as u32).collect(),
        quality: vec![mesh.quality()],
        conformity: vec![None],
        meshes: vec![mesh],
        sheet_triangles: Vec::new(),
    };
    FemModel::new(&disc, vec![FemBody::new(material(), corotated)]).expect("valid mesh")
}

/// Largest |f| over the vertices relative to the force a 1% strain would give a
/// vertex, μ · 0.01 · λ².
fn relative_force(m: &FemModel) -> f64 {
    let scale = m.bodies[0].mu * 0.01 * 0.025 * 0.025;
    m.force
        .iter()
        .map(|f| dot(*f, *f).sqrt())
        .fold(0.0, f64::max)
        / scale
}

fn rotate_90_about_z(m: &mut FemModel) {
    for (y, x) in m.position.iter_mut().zip(&m.rest) {
        *y = [-x[1], x[0], x[2]];
    }
}

#[test]
fn corotated_fem_has_no_ghost_force_under_a_90_degree_rotation() {
    let mut m = block(true);
    rotate_90_about_z(&mut m);
    m.internal_forces();
    let r = relative_force(&m);
    println!("corotated: |f|max after a 90° turn = {r:.2e} × the force of a 1% strain");
    assert!(r < 1e-8, "ghost force {r}");
    assert!(m.strain_energy().abs() < 1e-12);
}

#[test]
fn linear_fem_has_ghost_forces_under_a_90_degree_rotation() {
    let mut m = block(false);
    rotate_90_about_z(&mut m);
    m.internal_forces();
    let r = relative_force(&m);
    println!("linear: |f|max after a 90° turn = {r:.2e} × the force of a 1% strain");
    // A 90° turn reads as a strain of −1 along x and y: forces of order 100× a 1% strain.
    assert!(r > 10.0, "linear FEM should see a ghost strain, got {r}");
}

#[test]
fn uniform_stretch_gives_uniaxial_stress_free_of_interior_forces() {
    // x ← (1 + e) x: interior vertices are in equilibrium, the net force is zero.
    for corotated in [false, true] {
        let mut m = block(corotated);
        for (y, x) in m.position.iter_mut().zip(&m.rest) {
            *y = [1.001 * x[0], x[1], x[2]];
        }
        m.internal_forces();
        let mut net = [0.0; 3];
        for f in &m.force {
            for k in 0..3 {
                net[k] += f[k];
            }
        }
        let scale = m.bodies[0].mu * 0.001 * 0.025 * 0.025;
        assert!(dot(net, net).sqrt() < 1e-9 * scale * m.len() as f64);
        let interior = m
            .rest
            .iter()
            .zip(&m.force)
            .filter(|(x, _)| x[0].abs() < 0.17 && x[1].abs() < 0.03 && x[2].abs() < 0.03)
            .map(|(_, f)| dot(*f, *f).sqrt())
            .fold(0.0, f64::max);
        assert!(interior < 1e-9 * scale, "interior force {interior}");
    }
}

#[test]
fn stable_step_is_below_the_wave_crossing_time_of_the_smallest_element() {
    let m = block(true);
    let (dt, _) = m.stable_time_step();
    let b = &m.bodies[0];
    let c = ((b.lambda + 2.0 * b.mu) / b.material.density).sqrt();
    let q = TetMesh {
        vertices: m.rest.clone(),
        tets: m.tets.clone(),
    }
    .quality();
    println!(
        "stable dt {dt:.3e} s; min edge / c_p = {:.3e} s",
        q.min_edge / c
    );
    assert!(dt > 0.1 * q.min_edge / c && dt < 2.0 * q.min_edge / c);
}
