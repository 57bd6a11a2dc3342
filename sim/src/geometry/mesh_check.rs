//! The checks every tetrahedral mesher's tests run on its output (stuffing and the
//! unstructured mesher).

use std::collections::HashMap;

use perifrac_math::signed_volume;

use super::TetMesh;
use super::sdf::Sdf;

/// Everything measured by [`check`].
pub(crate) struct Report {
    pub(crate) volume: f64,
    pub(crate) min_dihedral: f64,
    pub(crate) max_dihedral: f64,
    pub(crate) mean_edge: f64,
    pub(crate) tets: usize,
    pub(crate) vertices: usize,
    pub(crate) surface_error: f64,
}

/// Asserts that `mesh` is a valid mesh of `sdf`: positive tetrahedra,
/// no unused vertices, every face shared by at most two tetrahedra lying
/// on opposite sides of it, and (if `closed`) a boundary that is a closed
/// oriented manifold surface whose vertices lie within `surface_tol` of
/// the zero set.
pub(crate) fn check(mesh: &TetMesh, sdf: &dyn Sdf, closed: bool, surface_tol: f64) -> Report {
    let mut used = vec![false; mesh.vertices.len()];
    for (t, tet) in mesh.tets.iter().enumerate() {
        assert!(mesh.volume(t) > 0.0, "tet {t} {tet:?} not positive");
        for &v in tet {
            used[v as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u), "unused vertices");

    let mut faces: HashMap<[u32; 3], Vec<u32>> = HashMap::new();
    for tet in &mesh.tets {
        for skip in 0..4 {
            let mut f = [0u32; 3];
            let mut n = 0;
            for (v, &x) in tet.iter().enumerate() {
                if v != skip {
                    f[n] = x;
                    n += 1;
                }
            }
            f.sort_unstable();
            faces.entry(f).or_default().push(tet[skip]);
        }
    }
    let p = |v: u32| mesh.vertices[v as usize];
    for (f, opposite) in &faces {
        assert!(
            opposite.len() <= 2,
            "face {f:?} shared by {}",
            opposite.len()
        );
        if let [u, w] = opposite[..] {
            let su = signed_volume(p(f[0]), p(f[1]), p(f[2]), p(u));
            let sw = signed_volume(p(f[0]), p(f[1]), p(f[2]), p(w));
            assert!(su * sw < 0.0, "tets on face {f:?} overlap");
        }
    }

    let boundary = mesh.boundary_faces();
    let mut surface_error = 0.0f64;
    let expected = faces.values().filter(|o| o.len() == 1).count();
    assert_eq!(boundary.len(), expected);
    if closed {
        let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
        for f in &boundary {
            for e in 0..3 {
                *directed.entry((f[e], f[(e + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &directed {
            assert_eq!(n, 1, "directed boundary edge {a}-{b} used {n} times");
            assert_eq!(
                directed.get(&(b, a)),
                Some(&1),
                "boundary edge {a}-{b} not shared by two faces"
            );
        }
        // The divergence theorem on the boundary gives the total volume.
        let enclosed: f64 = boundary
            .iter()
            .map(|f| signed_volume([0.0; 3], p(f[0]), p(f[1]), p(f[2])))
            .sum();
        let total = mesh.total_volume();
        assert!(
            (enclosed - total).abs() < 1e-9 * total,
            "{enclosed} vs {total}"
        );
        for f in &boundary {
            for &v in f {
                let d = sdf.distance(p(v));
                assert!(
                    d.abs() <= surface_tol,
                    "boundary vertex {v} at distance {d}"
                );
                surface_error = surface_error.max(d.abs());
            }
        }
    }
    let q = mesh.quality();
    Report {
        volume: mesh.total_volume(),
        min_dihedral: q.min_dihedral_deg,
        max_dihedral: q.max_dihedral_deg,
        mean_edge: q.mean_edge,
        tets: q.tets,
        vertices: mesh.vertices.len(),
        surface_error,
    }
}
