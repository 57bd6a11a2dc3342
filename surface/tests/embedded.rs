//! The `embedded` method on a block cut by pre-broken bonds across a tilted plane:
//! the cut follows tet faces (zig-zag, Chen §7, Fig. 18); after smoothing it must lie
//! within 0.25λ of the plane with an area within 5% of the plane's section, each
//! fragment keeping its volume and every tet its orientation.

use perifrac_sim::cache::vtu::TetFrame;
use perifrac_sim::embed::{EmbeddedMesh, NO_PARENT};
use perifrac_sim::family::{self, BROKEN, INDEX};
use perifrac_sim::geometry::discretize::Discretization;
use perifrac_sim::geometry::unstructured::mesh_unstructured;
use perifrac_sim::geometry::{Cuboid, TetMesh, stuff};
use perifrac_surface::embedded::surface;

const LAMBDA: f64 = 0.02;
const SIZE: [f64; 3] = [0.2, 0.12, 0.16];

/// A cut plane n·x = c (unit n).
type Plane = ([f64; 3], f64);

/// A plane across the block, normal `n` (normalized here), offset `c`.
fn plane(n: [f64; 3], c: f64) -> Plane {
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    (n.map(|x| x / l), c)
}

/// The horizontal cut of the figures, and a tilted one.
const LEVEL: ([f64; 3], f64) = ([0.0, 1.0, 0.0], 0.0025);
const TILTED: ([f64; 3], f64) = ([0.25, 1.0, -0.15], 0.004);

const BLOCK: Cuboid = Cuboid {
    center: [0.0; 3],
    half_extents: [SIZE[0] / 2.0, SIZE[1] / 2.0, SIZE[2] / 2.0],
};

fn cut_block(cut: Plane) -> TetFrame {
    cut_mesh(stuff(&BLOCK, LAMBDA).expect("box meshes"), cut)
}

/// `mesh` cut by pre-broken bonds across `cut`, as a frame of the split tet mesh.
fn cut_mesh(mesh: TetMesh, cut: Plane) -> TetFrame {
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
    let (mut bonds, _) = family::build(
        &disc.position,
        &disc.volume,
        &disc.body,
        &vec![1.45 * LAMBDA; n],
        false,
    )
    .unwrap();
    let mut embedded = EmbeddedMesh::build(&disc, &bonds, &["block".into()]).unwrap();
    let (normal, c) = cut;
    let side = |p: [f64; 3]| normal[0] * p[0] + normal[1] * p[1] + normal[2] * p[2] - c;
    for i in 0..n {
        for k in bonds.range(i) {
            let j = (bonds.neighbours[k] & INDEX) as usize;
            if side(disc.position[i]) * side(disc.position[j]) < 0.0 {
                bonds.neighbours[k] |= BROKEN;
            }
        }
    }
    embedded.update(&bonds);
    TetFrame {
        points: embedded.reference.clone(),
        tets: embedded.tets.clone(),
        particle: (0..n as u32).collect(),
        damage: vec![0.0; n],
        parent: embedded
            .parent
            .iter()
            .map(|&p| if p == NO_PARENT { -1 } else { p as i32 })
            .collect(),
    }
}

/// Max distance from the plane (in λ) and area over the plane's section, of the
/// crack faces of the fragment below the plane.
fn measure(frame: &TetFrame, cut: Plane, passes: usize) -> (f64, f64, f64) {
    let s = surface(frame, passes);
    let (normal, c) = cut;
    let dist = |p: [f64; 3]| normal[0] * p[0] + normal[1] * p[1] + normal[2] * p[2] - c;
    let below = |t: u32| {
        let tet = frame.tets[t as usize];
        let centre = [0, 1, 2].map(|a| {
            tet.iter()
                .map(|&v| frame.points[v as usize][a])
                .sum::<f64>()
                / 4.0
        });
        dist(centre) < 0.0
    };
    let mut max = 0.0f64;
    let mut area = 0.0;
    for ((f, &crack), &owner) in s.triangles.iter().zip(&s.crack).zip(&s.owner) {
        if !crack || !below(owner) {
            continue;
        }
        let [a, b, c] = f.map(|v| s.points[v as usize]);
        for p in [a, b, c] {
            max = max.max(dist(p).abs());
        }
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let x = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        area += 0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    }
    // The plane meets only the four side faces of the box: its section is the
    // box's x–z section over |n_y|.
    let section = SIZE[0] * SIZE[2] / normal[1].abs();
    (max / LAMBDA, area / section, s.stats.volume_error)
}

/// After 20 passes no tet is inverted and every original triangle that lay in a face
/// of the box still does (the block's flat faces stay flat; smoothing slides rim
/// vertices within them).
fn assert_smoothed_mesh_is_sound(frame: &TetFrame) {
    let s = surface(frame, 20);
    for t in &frame.tets {
        let [a, b, c, d] = t.map(|v| s.points[v as usize]);
        let e = |p: [f64; 3]| [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
        let (u, v, w) = (e(b), e(c), e(d));
        let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]);
        assert!(det > 0.0);
    }
    let on_face = |p: [f64; 3], a: usize| (p[a].abs() - SIZE[a] / 2.0).abs() < 1e-12;
    let mut on_a_face = 0;
    for (f, _) in s.triangles.iter().zip(&s.crack).filter(|(_, c)| !**c) {
        for a in 0..3 {
            if f.iter().all(|&v| on_face(frame.points[v as usize], a)) {
                on_a_face += 1;
                for &v in f {
                    let (before, after) = (frame.points[v as usize], s.points[v as usize]);
                    assert!(
                        (after[a] - before[a]).abs() < 1e-12,
                        "a vertex of a triangle in the face x[{a}] = {} left it: {before:?} → \
                         {after:?}",
                        before[a]
                    );
                }
            }
        }
    }
    assert!(on_a_face > 0);
}

#[test]
fn smoothing_flattens_a_zig_zag_planar_cut() {
    let cut = plane(LEVEL.0, LEVEL.1);
    let frame = cut_block(cut);
    let (d0, a0, _) = measure(&frame, cut, 0);
    let (d1, a1, volume_error) = measure(&frame, cut, 20);
    println!(
        "horizontal cut y = {} m, λ = {LAMBDA} m, {} tets: max distance from the plane \
         {d0:.3}λ → {d1:.3}λ, area / plane area {a0:.3} → {a1:.3}, fragment volume change \
         {volume_error:.1e}",
        LEVEL.1,
        frame.tets.len()
    );
    assert!(a0 > 1.05, "the unsmoothed cut zig-zags");
    assert!(d1 <= 0.25, "max distance {d1}λ");
    assert!((a1 - 1.0).abs() <= 0.05, "area ratio {a1}");
    assert!(volume_error < 1e-3, "volume change {volume_error}");
    assert_smoothed_mesh_is_sound(&frame);
    let [r0, r1] = surface(&frame, 20).stats.roughness.map(|h| h / LAMBDA);
    println!("zig-zag (median height over the ring's plane) {r0:.3}λ → {r1:.3}λ");
    assert!(r0 > 0.2 && r1 < 0.02, "zig-zag {r0}λ → {r1}λ");
}

#[test]
fn smoothing_a_tilted_cut() {
    // The rim of a tilted cut zig-zags on the block's faces and crosses the block's
    // vertical edges, which the stuffing bevels: rim vertices slide within the faces
    // and along the bevels (figures printed).
    let cut = plane(TILTED.0, TILTED.1);
    let frame = cut_block(cut);
    let (d0, a0, _) = measure(&frame, cut, 0);
    let (d1, a1, volume_error) = measure(&frame, cut, 20);
    println!(
        "tilted cut n = {:?}: max distance from the plane {d0:.3}λ → {d1:.3}λ, area / plane \
         area {a0:.3} → {a1:.3}, fragment volume change {volume_error:.1e}",
        TILTED.0
    );
    assert!(a0 > 1.05, "the unsmoothed cut zig-zags");
    assert!(d1 <= 0.25, "max distance {d1}λ");
    assert!((a1 - 1.0).abs() <= 0.05, "area ratio {a1}");
    assert!(volume_error < 1e-3, "volume change {volume_error}");
    assert_smoothed_mesh_is_sound(&frame);
}

#[test]
fn the_boundary_of_the_cut_block_is_two_closed_surfaces_with_flags() {
    let frame = cut_block(plane(TILTED.0, TILTED.1));
    let s = surface(&frame, 0);
    let crack = s.crack.iter().filter(|&&c| c).count();
    assert!(
        crack > 0 && crack % 2 == 0,
        "crack faces come in pairs: {crack}"
    );
    let fragments = s.fragment.iter().max().map_or(0, |&f| f + 1);
    assert_eq!(fragments, 2);
    // Every edge shared by exactly two triangles.
    let mut edges: Vec<(u32, u32)> = s
        .triangles
        .iter()
        .flat_map(|f| (0..3).map(move |e| (f[e], f[(e + 1) % 3])))
        .collect();
    edges.sort_unstable();
    for w in edges.windows(2) {
        assert_ne!(w[0], w[1], "a directed edge used twice");
    }
    for &(a, b) in &edges {
        assert!(edges.binary_search(&(b, a)).is_ok(), "edge {a}–{b} is open");
    }
}

/// The block's faces meet at right angles, and the unstructured mesh keeps its edges
/// (the stuffing lattice bevels them): a vertex on an edge between two faces gets a
/// copy per face, each with that face's normal, so a preview shades the edges sharp.
/// Averaged across the crease, such a vertex's normal would point at 45°.
#[test]
fn the_render_mesh_keeps_each_block_face_its_normal_up_to_its_edges() {
    let mesh = mesh_unstructured(&BLOCK, LAMBDA, 1).expect("box meshes");
    let frame = cut_mesh(mesh, plane(TILTED.0, TILTED.1));
    let s = surface(&frame, 4);
    let mesh = s.render_mesh(&frame.damage);
    // The axis (0–5, sign included) of an original triangle lying in a face of the
    // block; none for the triangles of the corners the stuffing bevels.
    let face_axis = |f: [u32; 3]| {
        let [a, b, c] = f.map(|w| s.points[w as usize]);
        let (e1, e2) = (
            [0, 1, 2].map(|k| b[k] - a[k]),
            [0, 1, 2].map(|k| c[k] - a[k]),
        );
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let l = n.iter().map(|x| x * x).sum::<f64>().sqrt();
        (0..3).find_map(|k| (n[k].abs() > 0.9999 * l).then_some(2 * k + usize::from(n[k] < 0.0)))
    };
    // Split-mesh vertices whose original faces all lie in the block's faces, with the
    // faces they touch.
    let mut faces_at = vec![Some(Vec::new()); s.points.len()];
    for (f, _) in s.triangles.iter().zip(&s.crack).filter(|(_, c)| !**c) {
        let axis = face_axis(*f);
        for &v in f {
            faces_at[v as usize] = match (faces_at[v as usize].take(), axis) {
                (Some(mut list), Some(a)) => {
                    if !list.contains(&a) {
                        list.push(a);
                    }
                    Some(list)
                }
                _ => None,
            };
        }
    }
    let mut on_edges = 0;
    for (i, &v) in mesh.vertex.iter().enumerate() {
        let Some(faces) = &faces_at[v as usize] else {
            continue;
        };
        if faces.len() < 2 || !mesh.mesh.surface_indices.contains(&(i as u32)) {
            continue;
        }
        on_edges += 1;
        let n = mesh.mesh.normals[i];
        let along = n.iter().fold(0.0f32, |m, c| m.max(c.abs()));
        assert!(
            along > 0.9999,
            "a vertex on the block's edge at {:?} has the normal {n:?}",
            s.points[v as usize]
        );
    }
    println!("{on_edges} render vertices on the block's edges, each with its face's normal");
    assert!(on_edges > 100, "{on_edges} vertices on edges");
}
