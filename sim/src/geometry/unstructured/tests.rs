use std::f64::consts::PI;

use super::*;
use crate::geometry::mesh_check::check;
use crate::geometry::sdf::{Ball, Cuboid, Difference, Sdf};
use crate::geometry::stuffing::stuff;

fn ball() -> Ball {
    Ball {
        center: [0.1, -0.2, 0.3],
        radius: 0.5,
    }
}

/// Cubic anisotropy of a mesh's edge directions n: the mean of n_x⁴ + n_y⁴ + n_z⁴,
/// 3/5 for directions with no preferred axes. A lattice's edges give other values
/// (the BCC lattice's long edges along the axes give 1, its short edges along the
/// cube's diagonals 1/3). Only edges deeper than 2λ in the ball count.
fn cubic_anisotropy(mesh: &TetMesh, lambda: f64) -> f64 {
    let mut sum = 0.0;
    let mut count = 0.0;
    let deep = |p: [f64; 3]| ball().distance(p) < -2.0 * lambda;
    for t in &mesh.tets {
        for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
            let (a, b) = (mesh.vertices[t[i] as usize], mesh.vertices[t[j] as usize]);
            if !deep(a) || !deep(b) {
                continue;
            }
            let d = dist(a, b);
            sum += (0..3).map(|k| ((b[k] - a[k]) / d).powi(4)).sum::<f64>();
            count += 1.0;
        }
    }
    sum / count
}

/// A ball: a valid conforming mesh (every face shared by two tetrahedra on opposite
/// sides, a closed boundary on the sphere), the ball's volume within 0.5%, the mean
/// edge within 5% of the asked length.
#[test]
fn a_ball_gets_a_conforming_mesh_of_its_volume_and_edge_length() {
    let lambda = 0.05;
    let mesh = mesh_unstructured(&ball(), lambda, 3).expect("meshing");
    let r = check(&mesh, &ball(), true, 1e-9);
    let exact = 4.0 / 3.0 * PI * 0.5f64.powi(3);
    let error = r.volume / exact - 1.0;
    println!(
        "ball λ = {lambda}: {} tets, {} vertices, volume error {:+.3}%, dihedral [{:.2}°, \
         {:.2}°], mean edge {:.4}, surface error {:.1e}",
        r.tets,
        r.vertices,
        100.0 * error,
        r.min_dihedral,
        r.max_dihedral,
        r.mean_edge,
        r.surface_error
    );
    assert!(error.abs() < 0.005, "volume error {error}");
    assert!(
        (r.mean_edge / lambda - 1.0).abs() < 0.05,
        "mean edge {}",
        r.mean_edge
    );
}

/// A box with a slot cut out: flat faces, convex and concave creases; valid (a closed
/// manifold boundary: creases passing between vertices pinched it before
/// `cleave::unpinch`, at 1–4 edges a seed; the corner fan it removes leaves a dent, so
/// boundary vertices are within 0.5λ of the surface, not on it) and the volume within
/// 2% (creases are bevelled, as on a turned lattice), for four seeds.
#[test]
fn a_slotted_box_gets_a_conforming_mesh() {
    let shape = Difference(
        Box::new(Cuboid {
            center: [0.0; 3],
            half_extents: [0.5, 0.3, 0.2],
        }),
        Box::new(Cuboid {
            center: [0.0, 0.3, 0.0],
            half_extents: [0.1, 0.15, 0.3],
        }),
    );
    let exact = 1.0 * 0.6 * 0.4 - 0.2 * 0.15 * 0.4;
    for seed in 0..4 {
        let mesh = mesh_unstructured(&shape, 0.05, seed).expect("meshing");
        let r = check(&mesh, &shape, true, 0.5 * 0.05);
        let error = r.volume / exact - 1.0;
        println!(
            "slotted box, seed {seed}: {} tets, volume error {:+.3}%, surface error {:.3}λ",
            r.tets,
            100.0 * error,
            r.surface_error / 0.05
        );
        assert!(error.abs() < 0.02, "volume error {error}");
    }
}

/// The same seed gives the same mesh, bit for bit; another seed another mesh.
#[test]
fn the_seed_decides_the_mesh() {
    let a = mesh_unstructured(&ball(), 0.15, 5).expect("meshing");
    let b = mesh_unstructured(&ball(), 0.15, 5).expect("meshing");
    let c = mesh_unstructured(&ball(), 0.15, 6).expect("meshing");
    assert_eq!(a.tets, b.tets);
    assert!(
        a.vertices
            .iter()
            .zip(&b.vertices)
            .all(|(p, q)| p.map(f64::to_bits) == q.map(f64::to_bits))
    );
    assert!(a.vertices != c.vertices);
}

/// Inside a ball (away from its surface, whose tetrahedra follow the sphere), the
/// edges have no preferred directions: the cubic anisotropy is 3/5 within 0.005,
/// where the stuffing lattice's is off by more than 0.02.
#[test]
fn the_edges_have_no_preferred_directions() {
    let lambda = 0.06;
    let unstructured = cubic_anisotropy(
        &mesh_unstructured(&ball(), lambda, 1).expect("meshing"),
        lambda,
    );
    let lattice = cubic_anisotropy(&stuff(&ball(), lambda).expect("meshing"), lambda);
    println!("cubic anisotropy: unstructured {unstructured:.4}, stuffing {lattice:.4}, none 0.6");
    assert!(
        (unstructured - 0.6).abs() < 0.005,
        "unstructured {unstructured}"
    );
    assert!((lattice - 0.6).abs() > 0.02, "lattice {lattice}");
}

/// Bad input is refused, not meshed.
#[test]
fn bad_edge_lengths_and_thin_shapes_are_errors() {
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            mesh_unstructured(&ball(), bad, 0),
            Err(MeshError::InvalidEdgeLength(_))
        ));
    }
    assert!(matches!(
        mesh_unstructured(&ball(), 1e-6, 0),
        Err(MeshError::LatticeTooLarge { .. })
    ));
}
