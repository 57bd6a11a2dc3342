//! Membranes from meshes: a flat mesh sheet against the lattice's stiffness and
//! Poisson ratio, a curved open mesh placed on its surface at the spacing.

use std::path::PathBuf;

use perifrac_math::dist;

use super::tests::{model, scene, stress, stress_depth, stress_in};

/// Writes `obj` to a fresh temporary directory (kept while the guard lives).
fn obj_file(name: &str, obj: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join(name);
    std::fs::write(&path, obj).expect("write the mesh");
    (dir, path)
}

/// The rectangle of [`stress`] as a mesh: two triangles in the y = 0 plane.
fn rectangle_obj() -> String {
    let (a, b) = (0.8, stress_depth() / 2.0);
    format!(
        "v {} 0 {}\nv {a} 0 {}\nv {a} 0 {b}\nv {} 0 {b}\nf 1 3 2\nf 1 4 3\n",
        -a, -b, -b, -a
    )
}

const MESH_BODY: &str = "[body.membrane]\nthickness = 0.001\n";

/// Han's bond-based law on a flat rectangle given as a two-triangle mesh, remeshed to
/// the spacing, against the built-in triangular lattice of the same rectangle. The
/// remeshed particles are irregular (edges in [4/5, 4/3] h), so the sum over a cut's
/// bonds is a rougher quadrature of Han's continuum integral than the lattice's, which
/// is within 3% of it (`biaxial_stretch_…`); the stress may differ from the
/// lattice's by that much again (5%), and ν, a ratio of two such sums over the same
/// particles, stays within 3% of the bond-based 1/3.
#[test]
fn a_flat_mesh_sheet_has_the_stiffness_and_poisson_ratio_of_the_lattice() {
    let (_dir, path) = obj_file("rectangle.obj", &rectangle_obj());
    let shape = format!("{{ type = \"mesh\", path = \"{}\" }}", path.display());
    let eps = 1e-6;
    let (lattice_xx, _, _) = stress([eps, 0.0]);
    let (sxx, szz, m) = stress_in(&shape, 0.3, MESH_BODY, [eps, 0.0]);
    let nu = szz / sxx;
    println!(
        "mesh sheet: {} particles, σ_xx = {sxx:.4e} Pa (lattice {lattice_xx:.4e}), ν = {nu:.4}",
        m.len()
    );
    assert!(
        (sxx / lattice_xx - 1.0).abs() < 0.05,
        "σ_xx = {sxx:e} Pa where the lattice gives {lattice_xx:e}"
    );
    assert!((nu - 1.0 / 3.0).abs() < 0.01, "ν = {nu}");
    let (biaxial_xx, biaxial_zz, _) = stress_in(&shape, 0.3, MESH_BODY, [eps, eps]);
    let (lattice_b, _, _) = stress([eps, eps]);
    assert!(
        (biaxial_xx / lattice_b - 1.0).abs() < 0.05 && (biaxial_zz / lattice_b - 1.0).abs() < 0.05,
        "biaxial σ = {biaxial_xx:e}, {biaxial_zz:e} Pa where the lattice gives {lattice_b:e}"
    );
}

/// An OBJ hemisphere cap of radius `r` (pole +y), `rings` × `segments`, wound outward.
fn cap_obj(r: f64, rings: usize, segments: usize) -> String {
    let mut obj = format!("v 0 {r} 0\n");
    for i in 1..=rings {
        let polar = std::f64::consts::FRAC_PI_2 * i as f64 / rings as f64;
        for j in 0..segments {
            let azimuth = std::f64::consts::TAU * j as f64 / segments as f64;
            obj += &format!(
                "v {} {} {}\n",
                r * polar.sin() * azimuth.cos(),
                r * polar.cos(),
                r * polar.sin() * azimuth.sin()
            );
        }
    }
    let at = |i: usize, j: usize| 2 + (i - 1) * segments + j % segments;
    for j in 0..segments {
        obj += &format!("f 1 {} {}\n", at(1, j + 1), at(1, j));
    }
    for i in 1..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    obj
}

/// A hemisphere cap given as a coarse mesh (8 rings of 32 facets, facets 3–6
/// spacings wide) becomes a sheet whose particles lie on the mesh (they are
/// projected onto it: to round-off) at the requested spacing: mean edge of the
/// sheet's triangles within 3% of h, every edge in [0.7, 1.5) h (Botsch and
/// Kobbelt's [4/5, 4/3] band about a target L rescaled to ≈ 1.09 h, give or take the
/// last relaxation), so every triangle edge is a bond (R = 1.5 h); its particle
/// areas sum to the area of its own triangles, which chord the cap's facets (within
/// 1% of the input's area).
#[test]
fn a_curved_open_mesh_becomes_a_sheet_on_the_mesh_at_the_spacing() {
    let h = 0.02;
    let (_dir, path) = obj_file("cap.obj", &cap_obj(0.25, 8, 32));
    let shape = format!("{{ type = \"mesh\", path = \"{}\" }}", path.display());
    let s = scene(&shape, "", MESH_BODY);
    let m = model(&s);
    let input =
        crate::geometry::mesh::TriMesh::load_surface(&path, &Default::default()).expect("the cap");
    let bvh = crate::geometry::mesh::Bvh::new(
        (0..input.triangles.len())
            .map(|t| input.corners(t))
            .collect(),
    );
    let off = (0..m.len())
        .map(|i| {
            bvh.closest(m.reference[i])
                .expect("a triangle")
                .distance_squared
                .sqrt()
        })
        .fold(0.0, f64::max);
    assert!(off < 1e-9, "a particle {off} m off the mesh");
    let triangles = m.sheet_triangles();
    assert_eq!(triangles, m.mesh_triangles);
    assert!(
        triangles.iter().all(|&t| m.triangle_intact(t)),
        "every edge a bond"
    );
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let lengths: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| dist(m.reference[a as usize], m.reference[b as usize]))
        .collect();
    let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
    let (shortest, longest) = lengths
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| {
            (lo.min(l), hi.max(l))
        });
    println!(
        "cap: {} particles, {} triangles, edges {:.3}–{:.3} h, mean {:.3} h",
        m.len(),
        triangles.len(),
        shortest / h,
        longest / h,
        mean / h
    );
    assert!((mean / h - 1.0).abs() < 0.03, "mean edge {mean} m");
    assert!(
        shortest > 0.7 * h && longest < 1.5 * h,
        "edges {shortest}–{longest} m"
    );
    let area: f64 = m.area.iter().sum();
    let own: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| m.reference[v as usize]);
            0.5 * perifrac_math::norm(perifrac_math::cross(
                perifrac_math::sub(b, a),
                perifrac_math::sub(c, a),
            ))
        })
        .sum();
    assert!(
        (area / own - 1.0).abs() < 1e-9,
        "areas {area} vs triangles {own}"
    );
    assert!(
        (area / input.area() - 1.0).abs() < 0.01,
        "area {area} vs the mesh's {}",
        input.area()
    );
}
