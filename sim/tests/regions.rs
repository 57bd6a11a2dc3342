//! Anchor and crack regions given by mesh files: they are read through the mesh's
//! signed distance and hold (or cut) exactly what lies inside the mesh. Before the
//! restructure a mesh-shaped region passed validation and was then skipped.

use perifrac_sim::pd::Peridynamics;
use perifrac_sim::run;
use perifrac_sim::scene::Scene;

/// An axis-aligned box [lo, hi] as a closed, outward-oriented OBJ.
fn box_obj(lo: [f64; 3], hi: [f64; 3]) -> String {
    let mut text = String::new();
    for k in 0..8 {
        let p = [0, 1, 2].map(|a| if k >> a & 1 == 1 { hi[a] } else { lo[a] });
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    // Corner k has bit a set when it is on the hi side of axis a (OBJ is 1-based).
    for f in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        text += &format!(
            "f {} {} {}\nf {} {} {}\n",
            f[0], f[1], f[2], f[0], f[2], f[3]
        );
    }
    text
}

fn inside(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> bool {
    (0..3).all(|a| p[a] > lo[a] && p[a] < hi[a])
}

#[test]
fn a_mesh_shaped_anchor_holds_exactly_the_particles_inside_the_mesh() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Off the lattice's planes, so no particle sits on the region's faces.
    let (lo, hi) = ([-0.1013, -0.0517, -0.0611], [-0.0437, 0.0383, 0.0529]);
    std::fs::write(dir.path().join("grip.obj"), box_obj(lo, hi)).expect("mesh written");
    let text = "[scene]\nduration = 0.01\n[materials.m]\ndensity = 1000\nyoungs_modulus = 1e6\n\
        poisson_ratio = 0.25\n[[body]]\nmaterial = \"m\"\nresolution = 0.02\n\
        shape = { type = \"box\", center = [0, 0, 0], size = [0.2, 0.06, 0.06] }\n\
        [[body.anchor]]\nregion = { type = \"mesh\", path = \"grip.obj\" }\n\
        [[body.crack]]\npoint = [0.0313, 0, 0]\nnormal = [1, 0, 0]\n\
        region = { type = \"mesh\", path = \"grip.obj\", translation = [0.1, 0, 0] }\n";
    let scene = Scene::parse(text, &dir.path().join("s.toml"), dir.path()).expect("scene");
    let p = run::prepare(&scene).expect("prepares");
    let part = &p.world.parts[0];
    let x = part.model.points().reference;
    let held: Vec<u32> = part.anchors[0].particles.clone();
    let expected: Vec<u32> = (0..x.len() as u32)
        .filter(|&i| inside(x[i as usize], lo, hi))
        .collect();
    assert!(!expected.is_empty());
    assert_eq!(
        held, expected,
        "the anchor holds the particles inside the mesh"
    );

    // A crack cuts the bonds that cross its plane x = 0.0313 with their midpoint inside
    // its region, the same box moved along x: moved by 0.2 (x ∈ (0.0987, 0.1563)) the
    // region misses the plane and cuts nothing; moved by 0.1 it holds the plane.
    let cut = |translation: f64| {
        let text = text.replace(
            "translation = [0.1, 0, 0]",
            &format!("translation = [{translation}, 0, 0]"),
        );
        let scene = Scene::parse(&text, &dir.path().join("s.toml"), dir.path()).expect("scene");
        let p = run::prepare(&scene).expect("prepares");
        let m = &p.world.model::<Peridynamics>().expect("peridynamic").model;
        m.particles.damage.iter().filter(|&&d| d > 0.0).count()
    };
    assert_eq!(cut(0.2), 0, "a crack region off the plane cuts nothing");
    assert!(cut(0.1) > 0, "a crack region on the plane cuts bonds");
}

#[test]
fn a_mesh_region_that_is_not_closed_names_the_body_and_the_region() {
    let dir = tempfile::tempdir().expect("temp dir");
    let open: String = box_obj([0.0; 3], [0.1; 3])
        .lines()
        .take(8 + 10)
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path().join("open.obj"), open).expect("mesh written");
    let text = "[scene]\nduration = 0.01\n[materials.m]\ndensity = 1000\nyoungs_modulus = 1e6\n\
        poisson_ratio = 0.25\n[[body]]\nname = \"bar\"\nmaterial = \"m\"\nresolution = 0.02\n\
        shape = { type = \"box\", center = [0, 0, 0], size = [0.2, 0.06, 0.06] }\n\
        [[body.anchor]]\nregion = { type = \"mesh\", path = \"open.obj\" }\n";
    let scene = Scene::parse(text, &dir.path().join("s.toml"), dir.path()).expect("scene");
    let err = run::prepare(&scene).expect_err("an open mesh cannot bound a region");
    let message = err.to_string();
    assert!(
        message.contains("bar")
            && message.contains("anchor 1 region")
            && message.contains("open.obj"),
        "{message}"
    );
}
