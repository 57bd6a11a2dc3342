//! Physically bounded debris (issue 13, item 5; `docs/lattice.md`): the demo's glass
//! wall hit by its 50 m/s steel ball, at a coarser λ so that it runs in the suite. A
//! rigid ball drives the glass in front of it at its own speed and a free back face
//! at most doubles that (1-D elastic waves), so no particle should leave faster than
//! 2× the ball. With Chen's tension-only law the crushed zone under the ball stores
//! its compression and gives it back as speed, past 2×; the demo's crushing glass
//! (`critical_compression`) and inelastic fragment contact keep it under.

use std::path::Path;

use perifrac_sim::run;
use perifrac_sim::scene::Scene;

/// The fastest particle of the demo scene (as shipped but for λ = 0.024 m and what
/// `edit` does to its text) at the scene's frame times (what its cache holds), in
/// units of the ball's speed.
fn fastest(edit: impl Fn(String) -> String) -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/demo.toml");
    let text = std::fs::read_to_string(&path).expect("the demo scene");
    let text = edit(text.replace("resolution = 0.016 ", "resolution = 0.024 "));
    let scene = Scene::parse(&text, &path, Path::new(".")).expect("scene");
    let mut p = run::prepare(&scene).expect("prepares");
    let frames = (scene.scene.duration * scene.scene.fps).round() as usize;
    let mut top: f64 = 0.0;
    for _ in 0..frames {
        for _ in 0..p.steps_per_frame {
            p.world.step().expect("steps");
        }
        let points = p.world.parts[0].model.points();
        for v in points.velocity {
            top = top.max((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
        }
    }
    top / 50.0
}

#[test]
fn no_wall_particle_leaves_faster_than_twice_the_ball() {
    let shipped = fastest(|t| t);
    let tension_only = fastest(|t| {
        t.lines()
            .filter(|l| !l.starts_with("critical_compression") && !l.starts_with("damping"))
            .collect::<Vec<_>>()
            .join("\n")
    });
    eprintln!(
        "demo at λ = 0.024 m: fastest particle {shipped:.2}× the ball, \
         {tension_only:.2}× with Chen's tension-only glass and the default contact damping"
    );
    assert!(shipped < 2.0, "debris at {shipped:.2}× the ball's speed");
    assert!(
        tension_only > 2.0,
        "the unbounded case must show the excess: {tension_only:.2}×"
    );
}
