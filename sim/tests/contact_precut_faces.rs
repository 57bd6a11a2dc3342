//! Issue 33 item 7: particle contact bent the Kalthoff–Winkler cracks because the
//! faces of its notches, sheared past each other, pushed on each other: diagonal pairs
//! across a cut come closer than their contact distance when one face slides along
//! the other, and their springs carried shear across the cut even without friction
//! (`docs/contact.md`). The faces of a pre-existing cut now touch only once they have
//! come apart. A block cut through by a zero-width pre-cut (`[[body.crack]]`), its
//! upper half slid along the cut: the contact impulse on it is zero (3.99e-3 N s
//! before).

use std::path::Path;

mod common;

use perifrac_sim::run;
use perifrac_sim::scene::Scene;

/// A 60 × 40 × 20 mm block (λ = 5 mm, E = 1 MPa, ν = 0.25, ρ = 1000 kg/m³) cut
/// through at y = 0, its lower half held, and `upper` the motion of the upper half.
fn block(upper: &str) -> String {
    format!(
        "[scene]\nduration = 0.1\nfps = 100\n\
         [materials.m]\ndensity = 1000\nyoungs_modulus = 1e6\npoisson_ratio = 0.25\n\
         critical_stretch = 0.5\n\
         [[body]]\nmaterial = \"m\"\nresolution = 0.005\nlattice = \"aligned\"\n\
         shape = {{ type = \"box\", center = [0, 0, 0], size = [0.06, 0.04, 0.02] }}\n\
         [[body.crack]]\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\n\
         region = {{ type = \"box\", center = [0, 0, 0], size = [1, 0.01, 1] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0, -0.5, 0], size = [1, 1, 1] }}\n\
         clamp = false\n\
         {upper}\n\
         [contact]\nparticles = true\nfriction = 0.0\n"
    )
}

/// Steps `text` to its end; returns Σ |F| Δt of the contact forces on the upper half
/// (N s) and the lowest an upper-half particle went below its rest height, in
/// particle spacings V̄^{1/3}.
fn run_block(text: &str) -> (f64, f64) {
    let scene = Scene::parse(text, Path::new("block.toml"), Path::new(".")).expect("scene");
    let mut p = run::prepare(&scene).expect("prepares");
    let steps = p.steps_per_frame * (scene.scene.duration * scene.scene.fps).round() as usize;
    let upper: Vec<usize> = {
        let x = p.world.parts[0].model.points().reference;
        (0..x.len()).filter(|&i| x[i][1] > 0.0).collect()
    };
    let points = p.world.parts[0].model.points();
    let volume: f64 = points.mass.iter().sum::<f64>() / 1000.0 / points.mass.len() as f64;
    let spacing = volume.cbrt();
    let (mut impulse, mut sink) = (0.0, 0.0f64);
    for _ in 0..steps {
        p.world.step().expect("steps");
        let force = p.world.contact.as_ref().expect("contact").force(0);
        let points = p.world.parts[0].model.points();
        for &i in &upper {
            let f = force[i];
            impulse += (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt() * p.world.dt;
            sink = sink.max(points.reference[i][1] - points.position[i][1]);
        }
    }
    (impulse, sink / spacing)
}

#[test]
fn a_precut_slid_along_itself_carries_no_contact_force() {
    // The upper half moved rigidly along the cut by 6 mm (more than two spacings).
    let text = block(
        "[[body.anchor]]\nregion = { type = \"box\", center = [0, 0.5, 0], size = [1, 1, 1] }\n\
         velocity = [0.06, 0, 0]\nclamp = false\n",
    )
    .replace("[scene]\n", "[scene]\ngravity = [0, 0, 0]\n");
    let (impulse, _) = run_block(&text);
    eprintln!(
        "pre-cut slid 6 mm along itself: contact impulse on the upper half {impulse:.3e} N s"
    );
    assert!(
        impulse == 0.0,
        "the faces pushed on each other: {impulse:e} N s"
    );
}

/// Which faces have come apart is state: the block sheared along its cut by an anchor
/// on its top layer only (the particles along the cut free), with 1 and 2 threads and
/// stopped and resumed, gives the same bytes.
#[test]
fn closed_faces_thread_and_resume_to_the_same_bytes() {
    let text = block(
        "[[body.anchor]]\nregion = { type = \"box\", center = [0, 0.517, 0], size = [1, 1, 1] }\n\
         velocity = [0.06, 0, 0]\nclamp = false\n",
    )
    .replace("[scene]\n", "[scene]\ngravity = [0, 0, 0]\n");
    let scene = Scene::parse(&text, Path::new("block.toml"), Path::new(".")).expect("scene");
    common::threads_and_resume(&scene, 5);
}
