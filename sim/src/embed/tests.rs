//! Topology and interpolation tests of the embedded mesh (Chen §5.2): a plane cut
//! splits a block into two closed surfaces, a vertex with k groups yields k − 1
//! copies, nothing splits while no bond breaks, and vertices follow affine motions
//! exactly.

use std::collections::HashMap;

use perifrac_math::{det3, mat_mul, norm};

use super::gradient::inverse;
use super::placement::Rigid;
use super::*;
use crate::family;
use crate::geometry::{Cuboid, TetMesh, stuff};

/// A box of `size` centred at the origin, meshed at λ, horizon 1.45λ.
fn block(size: [f64; 3], lambda: f64) -> (Discretization, Bonds) {
    let mesh = stuff(
        &Cuboid {
            center: [0.0; 3],
            half_extents: size.map(|s| s / 2.0),
        },
        lambda,
    )
    .expect("box meshes");
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
    let delta = vec![1.45 * lambda; n];
    let (bonds, _) =
        family::build(&disc.position, &disc.volume, &disc.body, &delta, false).expect("bonds");
    (disc, bonds)
}

fn names() -> Vec<String> {
    vec!["block".into()]
}

/// Breaks every bond i→j with `cut(i, j)` (both directions when it is symmetric).
fn cut(bonds: &mut Bonds, cut: impl Fn(usize, usize) -> bool) {
    for i in 0..bonds.offsets.len() - 1 {
        for k in bonds.range(i) {
            let j = (bonds.neighbours[k] & INDEX) as usize;
            if cut(i, j) {
                bonds.neighbours[k] |= BROKEN;
            }
        }
    }
}

/// Connected components of a triangle set (through shared vertices).
fn components(faces: &[[u32; 3]]) -> Vec<Vec<[u32; 3]>> {
    let n = faces.iter().flatten().max().map_or(0, |&v| v as usize + 1);
    let mut sets = UnionFind::new(n);
    for f in faces {
        sets.union(f[0] as usize, f[1] as usize);
        sets.union(f[0] as usize, f[2] as usize);
    }
    let mut out: HashMap<usize, Vec<[u32; 3]>> = HashMap::new();
    for f in faces {
        out.entry(sets.find(f[0] as usize)).or_default().push(*f);
    }
    let mut v: Vec<_> = out.into_values().collect();
    v.sort_by_key(|c| c.len());
    v
}

/// Every edge of `faces` is used by exactly two faces, once in each direction.
fn assert_closed_manifold(faces: &[[u32; 3]]) {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for f in faces {
        for e in 0..3 {
            *directed.entry((f[e], f[(e + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "edge {a}→{b} used {n} times in one direction");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "edge {a}–{b} has no opposite half-edge: the surface is open there"
        );
    }
}

/// Volume enclosed by outward-wound triangles (divergence theorem).
fn enclosed_volume(faces: &[[u32; 3]], x: &[[f64; 3]]) -> f64 {
    faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| x[v as usize]);
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

#[test]
fn nothing_splits_while_no_bond_breaks() {
    let (disc, bonds) = block([0.1, 0.1, 0.1], 0.02);
    let mut mesh = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    let vertices = mesh.vertex_count();
    let tets = mesh.tets.clone();
    for _ in 0..3 {
        assert_eq!(mesh.update(&bonds), SplitStats::default());
    }
    assert_eq!(mesh.vertex_count(), vertices);
    assert_eq!(mesh.tets, tets);
    let boundary = mesh.boundary();
    assert!(boundary.iter().all(|b| !b.2), "no crack faces");
    let faces: Vec<[u32; 3]> = boundary.iter().map(|b| b.0).collect();
    assert_eq!(components(&faces).len(), 1);
    assert_closed_manifold(&faces);
    let volume = enclosed_volume(&faces, &mesh.reference);
    assert!((volume - disc.meshes[0].total_volume()).abs() < 1e-12);
}

#[test]
fn a_plane_cut_splits_the_block_into_two_closed_surfaces() {
    let lambda = 0.02;
    let (disc, mut bonds) = block([0.12, 0.1, 0.08], lambda);
    let mut mesh = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    let x = disc.position.clone();
    let side = |p: [f64; 3]| p[1] - 0.003;
    cut(&mut bonds, |i, j| side(x[i]) * side(x[j]) < 0.0);
    let stats = mesh.update(&bonds);
    println!("plane cut: {stats:?}");
    assert!(stats.new_crack_faces > 0 && stats.split > 0);
    // Every crack face opened: all its vertices were split in this one pass.
    assert_eq!(mesh.active_crack_faces(), 0);
    assert_eq!(mesh.retired, stats.new_crack_faces);
    assert_eq!(stats.retired, stats.new_crack_faces);
    let boundary = mesh.boundary();
    let faces: Vec<[u32; 3]> = boundary.iter().map(|b| b.0).collect();
    let parts = components(&faces);
    assert_eq!(parts.len(), 2, "two fragments");
    for part in &parts {
        assert_closed_manifold(part);
    }
    // Each fragment's surface encloses the volume of its tets, and the crack
    // faces come in pairs.
    let below: f64 = (0..x.len())
        .filter(|&p| side(x[p]) < 0.0)
        .map(|p| disc.volume[p])
        .sum();
    let total = disc.meshes[0].total_volume();
    let mut volumes: Vec<f64> = parts
        .iter()
        .map(|p| enclosed_volume(p, &mesh.reference))
        .collect();
    volumes.sort_by(f64::total_cmp);
    let mut expected = [below, total - below];
    expected.sort_by(f64::total_cmp);
    for (v, e) in volumes.iter().zip(expected) {
        assert!((v - e).abs() < 1e-12 * total.max(1.0), "{v} vs {e}");
    }
    let crack = boundary.iter().filter(|b| b.2).count();
    assert_eq!(crack, 2 * stats.new_crack_faces);
    // Copies: every new vertex descends from an original one, and splitting again
    // changes nothing.
    assert!(
        mesh.parent[mesh.original_vertices()..]
            .iter()
            .all(|&p| p != NO_PARENT)
    );
    assert_eq!(mesh.update(&bonds), SplitStats::default());
}

#[test]
fn a_vertex_with_k_groups_yields_k_minus_one_copies() {
    let (disc, mut bonds) = block([0.1, 0.1, 0.1], 0.02);
    let mut mesh = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    // The interior vertex nearest the centre; crack every face around it.
    let v = (0..mesh.vertex_count())
        .min_by(|&a, &b| {
            let n = |p: [f64; 3]| p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
            n(mesh.reference[a]).total_cmp(&n(mesh.reference[b]))
        })
        .unwrap() as u32;
    let star: Vec<usize> = (0..mesh.tets.len())
        .filter(|&p| mesh.tets[p].contains(&v))
        .collect();
    let k = star.len();
    assert!(k >= 4, "an interior vertex has at least 4 tets, got {k}");
    cut(&mut bonds, |i, j| star.contains(&i) && star.contains(&j));
    let stats = mesh.update(&bonds);
    let copies = (0..mesh.vertex_count() as u32)
        .filter(|&w| w != v && mesh.root(w) == v)
        .count();
    assert_eq!(copies, k - 1, "{k} groups, {stats:?}");
    // Each tet of the star now has its own copy.
    let mut ids: Vec<u32> = star
        .iter()
        .map(|&p| *mesh.tets[p].iter().find(|&&w| mesh.root(w) == v).unwrap())
        .collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), k);
}

#[test]
fn splits_over_several_updates_match_one_update() {
    // The topology depends on the crack set only: cutting in two halves, split
    // after each, gives the same boundary (up to copy numbering) as one update.
    let (disc, mut bonds) = block([0.1, 0.1, 0.1], 0.02);
    let x = disc.position.clone();
    let on_plane = |i: usize, j: usize| (x[i][1] - 0.003) * (x[j][1] - 0.003) < 0.0;
    let mut once = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    let mut twice = once.clone();
    let mut half = bonds.clone();
    cut(&mut half, |i, j| on_plane(i, j) && x[i][0] + x[j][0] < 0.0);
    twice.update(&half);
    cut(&mut bonds, on_plane);
    twice.update(&bonds);
    once.update(&bonds);
    assert_eq!(once.vertex_count(), twice.vertex_count());
    let canon = |m: &EmbeddedMesh| {
        let mut f: Vec<(u32, [u32; 3])> = m
            .boundary()
            .iter()
            .map(|b| {
                let mut r = b.0.map(|v| m.root(v));
                r.sort_unstable();
                (b.1, r)
            })
            .collect();
        f.sort_unstable();
        f
    };
    assert_eq!(canon(&once), canon(&twice));
}

#[test]
fn affine_motion_is_exact() {
    let (disc, mut bonds) = block([0.1, 0.08, 0.06], 0.02);
    let mut mesh = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    let x = disc.position.clone();
    // The cut plane y = 0.003 lies between barycentres: the lattice is centred on the
    // block, so y = 0 is a lattice plane and holds barycentres, which a plane through
    // them would leave bonded to both sides (neither side's motion is then exact).
    let plane = 0.003;
    let nearest = x
        .iter()
        .map(|p| (p[1] - plane).abs())
        .fold(f64::MAX, f64::min);
    assert!(
        nearest > 1e-4,
        "a particle lies on the cut plane: {nearest:e}"
    );
    cut(&mut bonds, |i, j| {
        (x[i][1] - plane) * (x[j][1] - plane) < 0.0
    });
    mesh.update(&bonds);
    let mass: Vec<f64> = disc.volume.iter().map(|v| 1000.0 * v).collect();
    // Upper part: a rotation by 1 rad about z with a stretch; lower part: a shift.
    let (c, s) = (1.0f64.cos(), 1.0f64.sin());
    let upper = [[1.1 * c, -s, 0.0], [1.1 * s, c, 0.0], [0.0, 0.0, 0.9]];
    let motion = |p: [f64; 3], up: bool| -> [f64; 3] {
        if up {
            [0, 1, 2].map(|a| (0..3).map(|b| upper[a][b] * p[b]).sum::<f64>() + 0.5)
        } else {
            [p[0] + 0.01, p[1] - 0.2, p[2]]
        }
    };
    let y: Vec<[f64; 3]> = x.iter().map(|&p| motion(p, p[1] > plane)).collect();
    let gradient = deformation_gradients(&bonds, &x, &y, &disc.volume, None);
    let positions = mesh.positions(&x, &y, &mass, &gradient);
    let mut worst = 0.0f64;
    for (v, p) in positions.iter().enumerate() {
        // A copy belongs to the side of its tets.
        let t = mesh
            .tets
            .iter()
            .position(|t| t.contains(&(v as u32)))
            .unwrap();
        let expected = motion(mesh.reference[v], x[t][1] > plane);
        worst = worst.max(
            (0..3)
                .map(|a| (p[a] - expected[a]).abs())
                .fold(0.0, f64::max),
        );
    }
    // The same weights on displacements alone (Eq. 20–22 integrated exactly).
    let identity = vec![[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; x.len()];
    let plain = mesh.positions(&x, &y, &mass, &identity);
    let mut plain_worst = 0.0f64;
    for (v, p) in plain.iter().enumerate() {
        let t = mesh
            .tets
            .iter()
            .position(|t| t.contains(&(v as u32)))
            .unwrap();
        let expected = motion(mesh.reference[v], x[t][1] > plane);
        plain_worst = plain_worst.max(
            (0..3)
                .map(|a| (p[a] - expected[a]).abs())
                .fold(0.0, f64::max),
        );
    }
    println!(
        "affine motion, λ = 0.02 m: max vertex error {worst:.2e} m (first-order), \
         {plain_worst:.2e} m (displacement average, Eq. 20–22)"
    );
    assert!(worst < 1e-12, "{worst}");
    assert!(
        plain_worst > 1e-3,
        "the plain average is not exact: {plain_worst}"
    );
}

#[test]
fn a_face_without_a_bond_is_reported() {
    let mesh = TetMesh {
        vertices: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
        ],
        tets: vec![[0, 1, 2, 3], [1, 2, 4, 3]],
    };
    let n = 2;
    let disc = Discretization {
        position: (0..n).map(|t| mesh.barycentre(t)).collect(),
        volume: (0..n).map(|t| mesh.volume(t)).collect(),
        body: vec![0; n],
        tet: vec![0, 1],
        quality: vec![mesh.quality()],
        conformity: vec![None],
        meshes: vec![mesh],
        sheet_triangles: Vec::new(),
    };
    let (bonds, _) =
        family::build(&disc.position, &disc.volume, &disc.body, &[0.1, 0.1], false).unwrap();
    let err = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap_err();
    assert!(
        err.to_string()
            .contains("body 'block': tets 0 and 1 share a face"),
        "{err}"
    );
}

/// Breaks every bond of particle `q` (both directions) except those to `keep`.
fn detach(bonds: &mut Bonds, q: usize, keep: &[usize]) {
    cut(bonds, |i, j| {
        (i == q && !keep.contains(&j)) || (j == q && !keep.contains(&i))
    });
}

/// The smallest tet volume over its rest volume, and the longest tet edge, of
/// `positions`.
fn worst_tet(mesh: &EmbeddedMesh, positions: &[[f64; 3]]) -> (f64, f64) {
    let mut smallest = f64::INFINITY;
    let mut longest = 0.0f64;
    for (p, t) in mesh.tets.iter().enumerate() {
        let [a, b, c, d] = t.map(|v| positions[v as usize]);
        smallest = smallest.min(signed_volume(a, b, c, d) / mesh.rest_volume(p));
        for i in 0..4 {
            for j in i + 1..4 {
                let (x, y) = (positions[t[i] as usize], positions[t[j] as usize]);
                longest = longest.max(norm(sub(x, y)));
            }
        }
    }
    (smallest, longest)
}

/// The particle nearest the block's centre.
fn central(x: &[[f64; 3]]) -> usize {
    (0..x.len())
        .min_by(|&a, &b| norm(x[a]).total_cmp(&norm(x[b])))
        .unwrap()
}

/// x reflected through the plane through a, b, c.
fn reflect(x: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> [f64; 3] {
    let n = cross(sub(b, a), sub(c, a));
    let n = n.map(|v| v / norm(n));
    let h = dot(sub(x, a), n);
    [0, 1, 2].map(|k| x[k] - 2.0 * h * n[k])
}

#[test]
fn a_nearly_detached_particle_does_not_invert_or_stretch_its_tet() {
    // Regression (issue 13): in the demo, particles left with 3–4 of ~120 bonds had
    // correspondence gradients with det F = −6.1 or +5.0, and their tets came out
    // inside out or 5λ long. Here the central particle keeps three bonds and sits
    // at its mirror image through its three neighbours: the bonds keep their
    // lengths, F fitted to them is a reflection.
    let lambda = 0.02;
    let (disc, mut bonds) = block([0.1, 0.1, 0.1], lambda);
    let x = disc.position.clone();
    let q = central(&x);
    let adjacent: Vec<usize> = EmbeddedMesh::build(&disc, &bonds, &names())
        .unwrap()
        .adjacent[q]
        .iter()
        .map(|&r| r as usize)
        .collect();
    let mut near: Vec<usize> = bonds
        .range(q)
        .map(|k| (bonds.neighbours[k] & INDEX) as usize)
        .filter(|j| !adjacent.contains(j))
        .collect();
    near.sort_by(|&a, &b| norm(sub(x[a], x[q])).total_cmp(&norm(sub(x[b], x[q]))));
    // Of the eight nearest, the three whose bonds span the most volume.
    let spread =
        |[a, b, c]: [usize; 3]| det3(&[sub(x[a], x[q]), sub(x[b], x[q]), sub(x[c], x[q])]).abs();
    let mut keep = [near[0], near[1], near[2]];
    for a in 0..8 {
        for b in a + 1..8 {
            for c in b + 1..8 {
                if spread([near[a], near[b], near[c]]) > spread(keep) {
                    keep = [near[a], near[b], near[c]];
                }
            }
        }
    }
    detach(&mut bonds, q, &keep);
    let mut mesh = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    mesh.update(&bonds);
    let mut y = x.clone();
    y[q] = reflect(x[q], keep.map(|j| x[j]));
    for j in keep {
        let (rest, now) = (norm(sub(x[j], x[q])), norm(sub(x[j], y[q])));
        assert!(
            (rest - now).abs() < 1e-12 * rest,
            "the bonds keep their lengths"
        );
    }
    // The correspondence F of the kept bonds is a reflection: its tet, placed by
    // it, would be inside out.
    let (mut k, mut m) = ([[0.0; 3]; 3], [[0.0; 3]; 3]);
    for j in keep {
        let (xi, eta) = (sub(x[j], x[q]), sub(y[j], y[q]));
        for r in 0..3 {
            for c in 0..3 {
                k[r][c] += xi[r] * xi[c];
                m[r][c] += eta[r] * xi[c];
            }
        }
    }
    let fitted = mat_mul(&m, &inverse(k).expect("three bonds span 3-D"));
    assert!(det3(&fitted) < 0.0, "det F = {}", det3(&fitted));
    let mass: Vec<f64> = disc.volume.iter().map(|v| 2200.0 * v).collect();
    let gradient = deformation_gradients(&bonds, &x, &y, &disc.volume, None);
    assert!(
        (det3(&gradient[q]) - 1.0).abs() < 1e-9,
        "a rotation replaces F"
    );
    let positions = mesh.positions(&x, &y, &mass, &gradient);
    let (smallest, longest) = worst_tet(&mesh, &positions);
    println!(
        "detached particle: smallest tet {smallest:.3} of its rest volume, longest edge {:.2}λ",
        longest / lambda
    );
    assert!(smallest >= MIN_VOLUME_FRACTION * (1.0 - 1e-9), "{smallest}");
    assert!(longest < 3.0 * lambda, "{}λ", longest / lambda);
}

#[test]
fn a_tet_hanging_by_one_face_and_pushed_through_it_is_mended() {
    // A tet whose particle keeps only the bond across one face (a compressed bond
    // does not break), and has been pushed through that face: its three face vertices follow the block, its own vertex
    // its particle, on the wrong side. The untangling puts it right.
    let lambda = 0.02;
    let (disc, mut bonds) = block([0.1, 0.1, 0.1], lambda);
    let x = disc.position.clone();
    let q = central(&x);
    let built = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    let f = 0;
    let r = built.adjacent[q][f] as usize;
    let face = TET_FACES[f].map(|i| built.reference[built.tets[q][i] as usize]);
    detach(&mut bonds, q, &[r]);
    let mut mesh = built;
    mesh.update(&bonds);
    // The particle goes through the face to 1.5 times its tet's height beyond it.
    let mut y = x.clone();
    let mirror = reflect(x[q], face);
    y[q] = [0, 1, 2].map(|a| x[q][a] + 3.0 * (mirror[a] - x[q][a]));
    let mass: Vec<f64> = disc.volume.iter().map(|v| 2200.0 * v).collect();
    let gradient = deformation_gradients(&bonds, &x, &y, &disc.volume, None);
    // Eq. 20–21's average alone leaves the tet inside out.
    let mut plain = vec![[0.0; 3]; mesh.vertex_count()];
    let mut weight = vec![0.0; mesh.vertex_count()];
    for (p, t) in mesh.tets.iter().enumerate() {
        for &v in t {
            let d = sub(mesh.reference[v as usize], x[p]);
            let pred = [0, 1, 2].map(|a| y[p][a] + dot(gradient[p][a], d));
            for a in 0..3 {
                plain[v as usize][a] += mass[p] * pred[a];
            }
            weight[v as usize] += mass[p];
        }
    }
    for (p, w) in plain.iter_mut().zip(&weight) {
        *p = p.map(|c| c / w);
    }
    let [a, b, c, d] = mesh.tets[q].map(|v| plain[v as usize]);
    assert!(
        signed_volume(a, b, c, d) < 0.0,
        "the plain average inverts tet {q}"
    );
    let positions = mesh.positions(&x, &y, &mass, &gradient);
    let (smallest, longest) = worst_tet(&mesh, &positions);
    println!(
        "hanging tet: smallest tet {smallest:.3} of its rest volume, longest edge {:.2}λ",
        longest / lambda
    );
    assert!(smallest >= MIN_VOLUME_FRACTION * (1.0 - 1e-9), "{smallest}");
    assert!(longest < 3.0 * lambda, "{}λ", longest / lambda);
}

/// The central tet of an unbroken 0.1 m block at λ = 0.02 (one fragment of far more
/// than SMALL_FRAGMENT tets, no vertex in its tet alone) turned inside out by its
/// vertex `corner` pushed towards its mirror image in the opposite face by `factor`
/// (1: onto it), with predictions that agree on the wrong place (so the rounds and the
/// rigid placement cannot mend it), then untangled: the smallest volume over rest
/// volume and the longest edge (in λ) of all tets.
fn untangle_pushed(corner: usize, factor: f64) -> (f64, f64) {
    let lambda = 0.02;
    let (disc, bonds) = block([0.1, 0.1, 0.1], lambda);
    let mesh = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    assert!(mesh.tets.len() > SMALL_FRAGMENT);
    let q = central(&disc.position);
    let t = mesh.tets[q];
    let mut points = mesh.reference.clone();
    let face = TET_FACES[corner].map(|i| points[t[i] as usize]);
    let v = t[corner] as usize;
    assert!(
        t.iter()
            .all(|&w| mesh.tets.iter().filter(|s| s.contains(&w)).count() > 1)
    );
    let mirror = reflect(points[v], face);
    points[v] = [0, 1, 2].map(|a| points[v][a] + factor * (mirror[a] - points[v][a]));
    let [a, b, c, d] = t.map(|w| points[w as usize]);
    assert!(signed_volume(a, b, c, d) < 0.0, "tet {q} is not inverted");
    let wrong = points.clone();
    let predict = |_: usize, w: usize| wrong[w];
    let mut incident: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
    for (p, s) in mesh.tets.iter().enumerate() {
        for &w in s {
            incident[w as usize].push(p as u32);
        }
    }
    let star = |w: usize| incident[w].as_slice();
    let mass: Vec<f64> = disc.volume.iter().map(|v| 2200.0 * v).collect();
    let rigid = Rigid {
        reference: &disc.position,
        position: &disc.position,
        mass: &mass,
    };
    mesh.untangle(&mut points, &predict, &star, &rigid);
    let (smallest, longest) = worst_tet(&mesh, &points);
    (smallest, longest / lambda)
}

#[test]
fn a_tet_without_a_vertex_of_its_own_in_a_large_fragment_is_lifted() {
    // To 0.3 of its height beyond the face: step 3 lifts a vertex whose other tets
    // stay above the bound (the code before it left −0.30).
    let (smallest, longest) = untangle_pushed(0, 0.65);
    assert!(smallest >= MIN_VOLUME_FRACTION * (1.0 - 1e-9), "{smallest}");
    assert!(longest < 3.0, "{longest}λ");
}

#[test]
fn a_tet_no_vertex_can_lift_within_the_bound_is_still_turned_right_side_out() {
    // To 0.6 of its height beyond the face: every lift to the bound takes another
    // tet below it, and step 3 alone left the tet at −1.6 of its rest volume; the
    // last resort lifts it, its neighbours flat but not inverted.
    let (smallest, longest) = untangle_pushed(0, 1.3);
    println!("smallest volume {smallest:.4} of the rest volume, longest edge {longest:.2}λ");
    assert!(smallest >= FLOOR_FRACTION * (1.0 - 1e-9), "{smallest}");
    assert!(longest < 3.0, "{longest}λ");
}

/// The volume a closed, outward-wound triangle surface encloses (divergence theorem),
/// and whether it is closed: every directed edge's reverse used exactly once.
fn enclosed(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> (f64, bool) {
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    let mut volume = 0.0;
    for t in triangles {
        let [a, b, c] = t.map(|v| vertices[v as usize]);
        volume += dot(a, cross(b, c)) / 6.0;
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    let closed = edges
        .iter()
        .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1));
    (volume, closed)
}

#[test]
fn a_piece_surface_is_closed_and_holds_its_tets_volume() {
    // The rigid phase's colliders: the whole block's surface encloses its tets, each
    // half of it (split at x = 0, its bonds intact or not) a closed surface around
    // its own tets' volume, whatever split the crack made of the vertices.
    let lambda = 0.02;
    let (disc, mut bonds) = block([0.1, 0.06, 0.08], lambda);
    let x = disc.position.clone();
    cut(&mut bonds, |i, j| (x[i][0] < 0.0) != (x[j][0] < 0.0));
    let mut mesh = EmbeddedMesh::build(&disc, &bonds, &names()).unwrap();
    mesh.update(&bonds);
    assert!(
        mesh.vertex_count() > mesh.original_vertices(),
        "the cut split vertices"
    );
    let all: Vec<u32> = (0..x.len() as u32).collect();
    let whole = mesh.piece_surface(&all);
    let (volume, closed) = enclosed(&whole.vertices, &whole.triangles);
    assert!(
        whole.reach > 0.3 * lambda && whole.reach < 1.5 * lambda,
        "a surface vertex {} λ from its particle",
        whole.reach / lambda
    );
    assert!(closed, "the block's surface is closed");
    let tets: f64 = disc.volume.iter().sum();
    assert!(
        (volume - tets).abs() < 1e-12,
        "the block's surface encloses {volume} m³, its tets {tets} m³"
    );
    for side in [true, false] {
        let half: Vec<u32> = all
            .iter()
            .copied()
            .filter(|&i| (x[i as usize][0] < 0.0) == side)
            .collect();
        let surface = mesh.piece_surface(&half);
        let (volume, closed) = enclosed(&surface.vertices, &surface.triangles);
        let tets: f64 = half.iter().map(|&i| disc.volume[i as usize]).sum();
        assert!(closed, "a half's surface is closed");
        assert!(
            (volume - tets).abs() < 1e-12 * tets.max(1.0) + 1e-15,
            "a half's surface encloses {volume} m³, its tets {tets} m³"
        );
        assert!(surface.vertices.len() < mesh.original_vertices());
    }
}
