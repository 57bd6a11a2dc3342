use std::collections::HashMap;
use std::f64::consts::PI;

use perifrac_math::{signed_volume, sub};

use super::super::{Ball, Cuboid, Cylinder, Difference, Union};
use super::stencil::{Node, stencil};
use super::*;
use crate::geometry::mesh_check::{Report, check};

/// Small deterministic generator for test data.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Meshes `sdf`, checks it with [`check`] and the dihedral bounds, and
/// returns the report after asserting no tetrahedron was dropped.
fn mesh_and_check(name: &str, sdf: &dyn Sdf, lambda: f64, exact_volume: f64) -> Report {
    let (mesh, dropped) = stuff_counted(sdf, lambda).expect("meshing failed");
    assert_eq!(dropped, 0, "{name}: dropped degenerate tets");
    let r = check(&mesh, sdf, true, 1e-6);
    let err = r.volume / exact_volume - 1.0;
    println!(
        "{name:>10} λ={lambda}: {} tets, {} vertices, volume error {:+.3}%, \
         dihedral [{:.2}°, {:.2}°], mean edge {:.4}, surface error {:.1e}",
        r.tets,
        r.vertices,
        100.0 * err,
        r.min_dihedral,
        r.max_dihedral,
        r.mean_edge,
        r.surface_error
    );
    assert!(
        r.min_dihedral >= 8.0,
        "{name}: min dihedral {}",
        r.min_dihedral
    );
    assert!(
        r.max_dihedral <= 165.0,
        "{name}: max dihedral {}",
        r.max_dihedral
    );
    r
}

fn volume_error(r: &Report, exact: f64) -> f64 {
    (r.volume / exact - 1.0).abs()
}

fn unit_cube() -> Cuboid {
    Cuboid {
        center: [0.5; 3],
        half_extents: [0.5; 3],
    }
}

#[test]
fn cube_meshes_with_good_quality() {
    let cube = unit_cube();
    let coarse = mesh_and_check("cube", &cube, 0.1, 1.0);
    assert!(volume_error(&coarse, 1.0) < 0.01);
    let fine = mesh_and_check("cube", &cube, 0.05, 1.0);
    assert!(volume_error(&fine, 1.0) < 0.005);
    assert!(
        (fine.mean_edge / 0.05 - 1.0).abs() < 0.15,
        "mean edge {}",
        fine.mean_edge
    );
}

#[test]
fn ball_meshes_with_good_quality() {
    let r = 0.5;
    let ball = Ball {
        center: [0.1, -0.2, 0.3],
        radius: r,
    };
    let exact = 4.0 / 3.0 * PI * r * r * r;
    let report = mesh_and_check("ball", &ball, 0.05, exact);
    assert!(volume_error(&report, exact) < 0.02);
}

#[test]
fn cylinder_union_and_difference_have_right_volumes() {
    let cyl = Cylinder {
        center: [0.0, 0.0, 0.0],
        axis: 2,
        radius: 0.3,
        half_height: 0.5,
    };
    let exact = PI * 0.3 * 0.3 * 1.0;
    let r = mesh_and_check("cylinder", &cyl, 0.05, exact);
    assert!(volume_error(&r, exact) < 0.02);

    // A box with a ball bulging out of its +x face (the ball crosses no
    // other face): one box plus a half ball.
    let union = Union(vec![
        Box::new(Cuboid {
            center: [0.0; 3],
            half_extents: [0.5; 3],
        }),
        Box::new(Ball {
            center: [0.5, 0.0, 0.0],
            radius: 0.3,
        }),
    ]);
    let exact = 1.0 + 2.0 / 3.0 * PI * 0.3f64.powi(3);
    let r = mesh_and_check("union", &union, 0.05, exact);
    assert!(volume_error(&r, exact) < 0.02);

    // A 1 × 0.5 × 0.5 bar with a 0.1-wide, 0.125-deep slot through it.
    let bar = Cuboid {
        center: [0.0; 3],
        half_extents: [0.5, 0.25, 0.25],
    };
    let notch = Cuboid {
        center: [0.0, 0.25, 0.0],
        half_extents: [0.05, 0.125, 0.3],
    };
    let difference = Difference(Box::new(bar), Box::new(notch));
    let exact = 0.25 - 0.1 * 0.125 * 0.5;
    let r = mesh_and_check("difference", &difference, 0.025, exact);
    assert!(volume_error(&r, exact) < 0.02);
}

#[test]
fn thin_slab_is_resolved() {
    let slab = Cuboid {
        center: [0.0; 3],
        half_extents: [0.5, 0.01, 0.25],
    };
    let r = mesh_and_check("slab", &slab, 0.0125, 0.01);
    assert!(r.tets > 0);
    assert!(volume_error(&r, 0.01) < 0.03);
}

#[test]
fn bad_input_gives_errors() {
    let ball = Ball {
        center: [0.0; 3],
        radius: 0.5,
    };
    assert_eq!(stuff(&ball, 0.0), Err(MeshError::InvalidEdgeLength(0.0)));
    assert_eq!(stuff(&ball, -1.0), Err(MeshError::InvalidEdgeLength(-1.0)));
    assert!(matches!(
        stuff(&ball, f64::NAN),
        Err(MeshError::InvalidEdgeLength(x)) if x.is_nan()
    ));
    assert!(matches!(
        stuff(&ball, f64::INFINITY),
        Err(MeshError::InvalidEdgeLength(_))
    ));
    assert!(matches!(
        stuff(&ball, f64::MAX),
        Err(MeshError::InvalidEdgeLength(_))
    ));
    assert!(matches!(
        stuff(&ball, 1e300),
        Err(MeshError::EmptyMesh { suggested_edge_length, .. }) if suggested_edge_length == 0.25
    ));

    let speck = Ball {
        center: [0.3, 0.2, 0.1],
        radius: 1e-4,
    };
    match stuff(&speck, 0.1) {
        Err(MeshError::EmptyMesh {
            edge_length,
            suggested_edge_length,
        }) => {
            assert_eq!(edge_length, 0.1);
            assert!(suggested_edge_length > 0.0 && suggested_edge_length <= 1e-4);
        }
        other => panic!("expected EmptyMesh, got {other:?}"),
    }

    match stuff(&unit_cube(), 1e-300) {
        Err(MeshError::LatticeTooLarge {
            points,
            suggested_edge_length,
            ..
        }) => {
            assert_eq!(points, u64::MAX);
            assert!(suggested_edge_length.is_finite());
            assert!(Lattice::covering([0.0; 3], [1.0; 3], suggested_edge_length).is_ok());
        }
        other => panic!("expected LatticeTooLarge, got {other:?}"),
    }
    match stuff(&unit_cube(), 1e-4) {
        Err(MeshError::LatticeTooLarge {
            points,
            suggested_edge_length,
            ..
        }) => {
            assert!(points > MAX_LATTICE_POINTS);
            assert!(suggested_edge_length > 1e-4);
            let lattice = Lattice::covering([0.0; 3], [1.0; 3], suggested_edge_length);
            assert!(lattice.is_ok(), "suggestion still too fine");
        }
        other => panic!("expected LatticeTooLarge, got {other:?}"),
    }

    let bad_axis = Cylinder {
        center: [0.0; 3],
        axis: 7,
        radius: 1.0,
        half_height: 1.0,
    };
    assert!(matches!(
        stuff(&bad_axis, 0.1),
        Err(MeshError::InvalidBounds { .. })
    ));
    assert!(matches!(
        stuff(&Union(Vec::new()), 0.1),
        Err(MeshError::InvalidBounds { .. })
    ));
    let inverted = Cuboid {
        center: [0.0; 3],
        half_extents: [0.5, -0.5, 0.5],
    };
    assert!(matches!(
        stuff(&inverted, 0.1),
        Err(MeshError::InvalidBounds { .. })
    ));

    struct Broken;
    impl Sdf for Broken {
        fn distance(&self, p: [f64; 3]) -> f64 {
            if p[0] > 0.2 {
                f64::NAN
            } else {
                p[0].abs() - 0.5
            }
        }
        fn bounds(&self) -> ([f64; 3], [f64; 3]) {
            ([-0.5; 3], [0.5; 3])
        }
    }
    assert!(matches!(
        stuff(&Broken, 0.1),
        Err(MeshError::NonFiniteDistance { .. })
    ));
}

#[test]
fn meshing_is_deterministic() {
    let shape = Difference(
        Box::new(Ball {
            center: [0.0; 3],
            radius: 0.5,
        }),
        Box::new(Cylinder {
            center: [0.0; 3],
            axis: 1,
            radius: 0.15,
            half_height: 1.0,
        }),
    );
    let a = stuff(&shape, 0.06).expect("mesh");
    let b = stuff(&shape, 0.06).expect("mesh");
    assert!(!a.tets.is_empty());
    assert_eq!(a, b);
}

/// Volume-weighted centroid and products of inertia (I_xy, I_yz, I_zx) about it of
/// the tets of `mesh`.
fn centroid_and_products(mesh: &TetMesh) -> ([f64; 3], [f64; 3]) {
    let mut m = 0.0;
    let mut c = [0.0; 3];
    for t in 0..mesh.tets.len() {
        let (v, x) = (mesh.volume(t), mesh.barycentre(t));
        m += v;
        (0..3).for_each(|k| c[k] += v * x[k]);
    }
    c = c.map(|x| x / m);
    let mut p = [0.0; 3];
    for t in 0..mesh.tets.len() {
        let (v, x) = (mesh.volume(t), mesh.barycentre(t));
        let d = sub(x, c);
        (0..3).for_each(|k| p[k] += v * d[k] * d[(k + 1) % 3]);
    }
    (c, p)
}

/// Issue 13: the lattice sat 0.08λ off the axis of a centred box, so a cantilever
/// loaded straight down bent sideways (7.4% of its deflection at 4 particles across).
#[test]
fn a_centred_box_gets_a_symmetric_mesh() {
    let shape = Cuboid {
        center: [0.3, -0.2, 0.1],
        half_extents: [0.5, 0.1, 0.1],
    };
    for lambda in [0.05, 0.0333, 0.025] {
        let mesh = stuff(&shape, lambda).expect("mesh");
        let (c, p) = centroid_and_products(&mesh);
        let inertia = 0.2 * 0.2 * 0.2 * 0.2 * 1.0 / 12.0;
        let unmatched = [1, 2].map(|k| mirror_mismatch(&mesh, k, shape.center[k]));
        println!(
            "λ {lambda}: centroid {c:?}, products {p:?} (of {inertia:e}), tets without a mirror image {unmatched:?}"
        );
        for k in 0..3 {
            assert!((c[k] - shape.center[k]).abs() < 1e-9, "centroid {c:?}");
            assert!(p[k].abs() < 1e-9 * inertia, "products of inertia {p:?}");
        }
        assert_eq!(unmatched, [0; 2], "tets without a mirror image in y and z");
    }
}

/// Tets whose barycentre has no mirror image in the plane `x[axis] = at` (to 1e-7 m).
fn mirror_mismatch(mesh: &TetMesh, axis: usize, at: f64) -> usize {
    let key = |x: [f64; 3]| x.map(|v| (v * 1e7).round() as i64);
    let set: std::collections::HashSet<[i64; 3]> = (0..mesh.tets.len())
        .map(|t| key(mesh.barycentre(t)))
        .collect();
    (0..mesh.tets.len())
        .filter(|&t| {
            let mut x = mesh.barycentre(t);
            x[axis] = 2.0 * at - x[axis];
            !set.contains(&key(x))
        })
        .count()
}

/// A sphere wrinkled at the lattice scale (up to one spacing high): many
/// cut configurations, warps and stencil cases per mesh.
struct Wrinkled {
    ball: Ball,
    waves: Vec<([f64; 3], f64)>,
    amplitude: f64,
}

impl Wrinkled {
    fn new(rng: &mut Lcg, h: f64) -> Self {
        let ball = Ball {
            center: [rng.next(), rng.next(), rng.next()],
            radius: 0.2 + 0.2 * rng.next(),
        };
        let waves = (0..6)
            .map(|_| {
                let dir = [0, 1, 2].map(|_| rng.next() - 0.5);
                let len = dir.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
                let k = (0.3 + 0.7 * rng.next()) * PI / h;
                (dir.map(|x| x * k / len), 2.0 * PI * rng.next())
            })
            .collect();
        Self {
            ball,
            waves,
            amplitude: (0.25 + 0.75 * rng.next()) * h,
        }
    }
}

impl Sdf for Wrinkled {
    fn distance(&self, p: [f64; 3]) -> f64 {
        let wave: f64 = self
            .waves
            .iter()
            .map(|(k, phase)| (k[0] * p[0] + k[1] * p[1] + k[2] * p[2] + phase).sin())
            .sum();
        self.ball.distance(p) + self.amplitude * wave / self.waves.len() as f64
    }
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let (lo, hi) = self.ball.bounds();
        (
            lo.map(|x| x - self.amplitude),
            hi.map(|x| x + self.amplitude),
        )
    }
}

#[test]
fn random_shapes_keep_dihedral_bounds() {
    let mut rng = Lcg(7);
    let (mut lo, mut hi) = (180.0f64, 0.0f64);
    let mut tets = 0;
    for trial in 0..24 {
        let lambda = 0.03 + 0.03 * rng.next();
        let h = lambda / MEAN_EDGE_PER_SPACING;
        let (mesh, dropped) = if trial % 2 == 0 {
            let shape = Wrinkled::new(&mut rng, h);
            let m = stuff_counted(&shape, lambda).expect("mesh");
            check(&m.0, &shape, false, 0.0);
            m
        } else {
            let shape = Ball {
                center: [rng.next(), rng.next(), rng.next()],
                radius: 0.1 + 0.3 * rng.next(),
            };
            let m = stuff_counted(&shape, lambda).expect("mesh");
            check(&m.0, &shape, true, 1e-9);
            m
        };
        assert_eq!(dropped, 0);
        let q = mesh.quality();
        lo = lo.min(q.min_dihedral_deg);
        hi = hi.max(q.max_dihedral_deg);
        tets += q.tets;
    }
    println!("random shapes: {tets} tets, dihedral angles in [{lo:.2}°, {hi:.2}°]");
    assert!(lo >= 8.0, "min dihedral {lo}");
    assert!(hi <= 165.0, "max dihedral {hi}");
}

fn unit_lattice(n: usize) -> Lattice {
    let corners = (n + 1).pow(3);
    Lattice {
        origin: [0.0; 3],
        h: 1.0,
        cells: [n; 3],
        corners,
        total: corners + n.pow(3),
    }
}

#[test]
fn lattice_tets_are_congruent_and_positive_or_negative() {
    let lattice = unit_lattice(3);
    let mut count = 0;
    lattice
        .for_each_tet(|ids, coords| -> Result<(), ()> {
            for (id, c) in ids.iter().zip(coords) {
                assert_eq!(lattice.coords(*id), *c);
            }
            let p = coords.map(|c| lattice.position(c));
            assert!((signed_volume(p[0], p[1], p[2], p[3]).abs() - 1.0 / 12.0).abs() < 1e-12);
            assert!((dist(p[0], p[1]) - 1.0).abs() < 1e-12);
            assert!((dist(p[2], p[3]) - 1.0).abs() < 1e-12);
            count += 1;
            Ok(())
        })
        .expect("visit");
    // 3 directions × (n - 1) · n² centre edges, 4 tets each.
    assert_eq!(count, 3 * 2 * 9 * 4);
}

/// Barycentric containment test (strict, with a tiny tolerance).
fn contains(t: &[[f64; 3]; 4], x: [f64; 3]) -> bool {
    let v = signed_volume(t[0], t[1], t[2], t[3]);
    (0..4).all(|i| {
        let mut u = *t;
        u[i] = x;
        signed_volume(u[0], u[1], u[2], u[3]) / v > 1e-12
    })
}

#[test]
fn stencils_tile_the_inside_of_every_lattice_tet() {
    // Every orientation and parity of BCC tet, every sign pattern, random
    // cut positions from a linear field: the stencil tets must be
    // non-degenerate and cover {field < 0} exactly once.
    let lattice = unit_lattice(3);
    let mut rng = Lcg(99);
    lattice
        .for_each_tet(|_, coords| -> Result<(), ()> {
            let p = coords.map(|c| lattice.position(c));
            for code in 0..81 {
                let signs = [1, 3, 9, 27].map(|d| ((code / d) % 3) as i8 - 1);
                let values = signs.map(|s| f64::from(s) * (0.2 + 0.8 * rng.next()));
                let at = |n: Node| match n {
                    Node::Vertex(l) => p[l],
                    Node::Cut(a, b) => lerp(p[a], p[b], values[a] / (values[a] - values[b])),
                };
                let stencil = stencil(signs, coords);
                let tets: Vec<[[f64; 3]; 4]> = stencil.tets().iter().map(|t| t.map(at)).collect();
                for t in &tets {
                    assert!(signed_volume(t[0], t[1], t[2], t[3]).abs() > 1e-6);
                }
                for _ in 0..60 {
                    let w = [0, 1, 2, 3].map(|_| -rng.next().max(1e-300).ln());
                    let sum: f64 = w.iter().sum();
                    let w = w.map(|x| x / sum);
                    let x = [0, 1, 2].map(|k| (0..4).map(|i| w[i] * p[i][k]).sum());
                    let phi: f64 = (0..4).map(|i| w[i] * values[i]).sum();
                    if phi.abs() < 1e-9 {
                        continue;
                    }
                    let hits = tets.iter().filter(|t| contains(t, x)).count();
                    assert_eq!(
                        hits,
                        usize::from(phi < 0.0),
                        "signs {signs:?} coords {coords:?}"
                    );
                }
            }
            Ok(())
        })
        .expect("visit");
}

#[test]
fn neighbouring_stencils_agree_on_shared_faces() {
    // Random signs on a small lattice: every output face is shared by at
    // most two tets, and faces used once lie on the surface (cut points
    // and zero vertices only).
    let n = 4;
    let lattice = unit_lattice(n);
    let mut rng = Lcg(2024);
    for _ in 0..400 {
        let signs: Vec<i8> = (0..lattice.total)
            .map(|id| {
                let c = lattice.coords(id);
                // The outer layer of both grids stays outside, as padding does.
                if c.iter().any(|&x| x <= 1 || x >= 2 * n as i64 - 1) {
                    1
                } else {
                    (rng.next() * 3.0) as i8 - 1
                }
            })
            .collect();
        const CUT: u64 = 1 << 62;
        let mut faces: HashMap<[u64; 3], usize> = HashMap::new();
        lattice
            .for_each_tet(|ids, coords| -> Result<(), ()> {
                let s = ids.map(|id| signs[id]);
                for t in stencil(s, coords).tets() {
                    let keys = t.map(|node| match node {
                        Node::Vertex(l) => ids[l] as u64,
                        Node::Cut(a, b) => {
                            let (a, b) = (ids[a].min(ids[b]), ids[a].max(ids[b]));
                            CUT | ((a as u64) << 20) | b as u64
                        }
                    });
                    for skip in 0..4 {
                        let mut f = [0u64; 3];
                        let mut m = 0;
                        for (v, &k) in keys.iter().enumerate() {
                            if v != skip {
                                f[m] = k;
                                m += 1;
                            }
                        }
                        f.sort_unstable();
                        *faces.entry(f).or_default() += 1;
                    }
                }
                Ok(())
            })
            .expect("visit");
        for (f, &count) in &faces {
            assert!(count <= 2, "face {f:?} used {count} times");
            if count == 1 {
                for &k in f {
                    assert!(
                        k & CUT != 0 || signs[k as usize] == 0,
                        "non-surface boundary face {f:?}"
                    );
                }
            }
        }
    }
}
