//! The rigid phase (`sim/src/rigid`, docs/rigid.md): a fragment's momenta and kinetic
//! energy across the switch, pieces that land and come to rest, a rigid piece that
//! breaks a deformable wall, pieces on a mesh collider, and the same bytes with 1 and
//! 2 threads and after a resume in the rigid phase. Small resolutions; figures with `--nocapture`.

mod common;

use std::path::Path;

use perifrac_sim::rigid::RigidPhase;
use perifrac_sim::run::{self, Prepared, RunOptions, StopRequest};
use perifrac_sim::scene::Scene;

fn scene(text: &str) -> Scene {
    Scene::parse(text, Path::new("rigid-test.toml"), Path::new(".")).expect("scene")
}

const GLASS: &str = "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 3.3e10\n\
                     shear_modulus = 2.0e10\ncritical_stretch = 0.0005\n";

/// (Σ m v, Σ m x × v, Σ ½ m |v|²) over the first part's points.
fn momenta(p: &Prepared) -> ([f64; 3], [f64; 3], f64) {
    let points = p.world.parts[0].model.points();
    let (mut linear, mut angular, mut kinetic) = ([0.0; 3], [0.0; 3], 0.0);
    for ((m, x), v) in points.mass.iter().zip(points.position).zip(points.velocity) {
        for a in 0..3 {
            linear[a] += m * v[a];
        }
        angular[0] += m * (x[1] * v[2] - x[2] * v[1]);
        angular[1] += m * (x[2] * v[0] - x[0] * v[2]);
        angular[2] += m * (x[0] * v[1] - x[1] * v[0]);
        kinetic += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    (linear, angular, kinetic)
}

fn relative(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    d / (0..3).map(|k| a[k] * a[k]).sum::<f64>().sqrt()
}

/// A tumbling glass block handed over as one piece.
fn tumbling_block() -> Prepared {
    let text = format!(
        "[scene]\ngravity = [0, 0, 0]\n{GLASS}[[body]]\nmaterial = \"glass\"\nresolution = 0.02\n\
         shape = {{ type = \"box\", center = [0.3, 0.2, -0.1], size = [0.12, 0.06, 0.08] }}\n\
         velocity = [1.0, -2.0, 3.0]\nangular_velocity = [5.0, -3.0, 2.0]\n\
         [rigid]\nenabled = true\nsmall_fragment = 100000\n"
    );
    run::prepare(&scene(&text)).expect("prepares")
}

#[test]
fn a_rigidly_moving_fragment_keeps_its_momenta_and_energy_across_the_switch() {
    let mut p = tumbling_block();
    let (linear, angular, kinetic) = momenta(&p);
    let settings = p
        .world
        .rigid_settings
        .clone()
        .expect("a breaking body has a rigid phase");
    let mut rigid = RigidPhase::new(settings, &p.world.colliders, Default::default());
    assert_eq!(rigid.look(&mut p.world.parts, 0.0), 1, "one piece");
    let (l2, a2, k2) = momenta(&p);
    let errors = [
        relative(linear, l2),
        relative(angular, a2),
        (kinetic - k2).abs() / kinetic,
    ];
    println!("relative change of P, L, E across the switch: {errors:?}");
    assert!(errors.iter().all(|&e| e < 1e-9), "{errors:?}");
}

#[test]
fn a_vibrating_fragment_keeps_its_momenta_and_loses_only_its_vibration() {
    let mut p = tumbling_block();
    // A vibration on top of the rigid motion: a breathing mode about the centroid.
    {
        let points = p.world.parts[0].model.points_mut();
        for (v, x) in points.velocity.iter_mut().zip(points.reference.iter()) {
            let r = [x[0] - 0.3, x[1] - 0.2, x[2] + 0.1];
            for k in 0..3 {
                v[k] += 4.0 * r[k];
            }
        }
    }
    let (linear, angular, kinetic) = momenta(&p);
    let settings = p.world.rigid_settings.clone().expect("rigid phase");
    let mut rigid = RigidPhase::new(settings, &p.world.colliders, Default::default());
    assert_eq!(rigid.look(&mut p.world.parts, 0.0), 1);
    let (l2, a2, k2) = momenta(&p);
    println!(
        "P {:.2e}, L {:.2e}, E {kinetic:.4} J -> {k2:.4} J",
        relative(linear, l2),
        relative(angular, a2)
    );
    assert!(relative(linear, l2) < 1e-9 && relative(angular, a2) < 1e-9);
    // The breathing mode's energy goes: what is left is below, and more than the
    // translation's.
    assert!(k2 < kinetic * 0.999 && k2 > 0.5 * 2200.0 * 0.12 * 0.06 * 0.08 * 14.0 * 0.9);
}

#[test]
fn the_air_slows_a_flying_piece_as_quadratic_drag_does() {
    // A glass block thrown at 200 m/s without gravity: m v̇ = −½ ρ_air C_d A |v| v
    // halves its speed after t = 1/(k v₀), k = ρ_air C_d A / 2m, A = 1.5 V^{2/3} (the
    // defaults: ρ_air 1.2 kg/m³, C_d 1), here V the block's own volume.
    let text = format!(
        "[scene]\ngravity = [0, 0, 0]\n{GLASS}[[body]]\nmaterial = \"glass\"\nresolution = 0.02\n\
         shape = {{ type = \"box\", center = [0.3, 0.2, -0.1], size = [0.12, 0.06, 0.08] }}\n\
         velocity = [120.0, 0.0, 160.0]\nangular_velocity = [5.0, -3.0, 2.0]\n\
         [rigid]\nenabled = true\nsmall_fragment = 100000\n"
    );
    let mut p = run::prepare(&scene(&text)).expect("prepares");
    let settings = p.world.rigid_settings.clone().expect("rigid phase");
    let mut rigid = RigidPhase::new(settings, &p.world.colliders, Default::default());
    assert_eq!(rigid.look(&mut p.world.parts, 0.0), 1, "one piece");
    let (v0, volume) = (200.0, 0.12 * 0.06 * 0.08f64);
    let k = 1.2 * 1.0 * 1.5 * volume.powf(2.0 / 3.0) / (2.0 * 2200.0 * volume);
    let dt = 1.0 / 600.0;
    let steps = (1.0 / (k * v0) / dt).round() as usize;
    for _ in 0..steps {
        rigid.step(dt, [0.0; 3], &mut p.world.parts, &mut p.world.colliders);
    }
    let (linear, _, _) = momenta(&p);
    let mass: f64 = p.world.parts[0].model.points().mass.iter().sum();
    let speed = (0..3)
        .map(|a| (linear[a] / mass).powi(2))
        .sum::<f64>()
        .sqrt();
    let expected = v0 / (1.0 + k * v0 * steps as f64 * dt);
    println!(
        "after {:.3} s: {speed:.2} m/s, quadratic drag {expected:.2} m/s",
        steps as f64 * dt
    );
    assert!(
        (speed / expected - 1.0).abs() < 0.03,
        "{speed} m/s, expected {expected}"
    );
}

/// A slab of glass (two particles thick) dropped on its corner for `duration` s:
/// a few grains break off, the pieces go rigid and land (`rigid_rest.rs` drops a
/// weaker plate that shatters).
fn plate_drop(duration: f64) -> Scene {
    scene(&format!(
        "[scene]\nduration = {duration}\nfps = 10\n{GLASS}critical_compression = 0.01\n\
         [[body]]\nname = \"plate\"\nmaterial = \"glass\"\nresolution = 0.02\n\
         shape = {{ type = \"box\", center = [0.0, 0.03, 0.0], size = [0.12, 0.04, 0.12] }}\n\
         velocity = [0.0, -6.0, 0.0]\nangular_velocity = [4.0, 0.0, 3.0]\n\
         [[collider]]\ntype = \"ground\"\n[rigid]\nenabled = true\n\
         [output]\npreview = false\nusd = false\ncheckpoint_every = 2\n"
    ))
}

/// Runs `s` again stopped once each of `stops` steps are taken (at the next stop
/// point), in turn, each stop resumed (one run that goes through every stop, rather
/// than a run to the end for each: a resume that lost state differs from the frames
/// after it whichever stop came first): the particle frames of `whole`, the
/// uninterrupted run.
fn stopped_and_resumed(s: &Scene, whole: &Path, stops: &[u64]) {
    let stopped = tempfile::tempdir().expect("temp dir");
    let mut last = 0;
    for (k, &after) in stops.iter().enumerate() {
        let stop = RunOptions {
            stop: StopRequest::after_steps(after),
            resume: k > 0,
            ..RunOptions::default()
        };
        let e = run::run(s, stopped.path(), &stop, &mut |_| {}).expect_err("stops");
        assert!(e.to_string().contains("stop after"), "{e}");
        // Each stop after the last: resumed, the run went on to the next one.
        let perifrac_sim::SimError::Interrupted { step, .. } = e else {
            panic!("expected an interruption, got {e}");
        };
        assert!(
            step >= after && step > last,
            "{e} (the stop before at step {last})"
        );
        last = step;
    }
    let resume = RunOptions {
        resume: true,
        ..RunOptions::default()
    };
    let m = run::run(s, stopped.path(), &resume, &mut |_| {}).expect("resumes");
    assert_eq!(m.status.to_string(), "complete");
    for f in 1..=m.frames() {
        let name = format!("particles/{f:04}.ply");
        let a = std::fs::read(whole.join(&name)).expect("frame");
        let b = std::fs::read(stopped.path().join(&name)).expect("frame");
        assert!(a == b, "{name} differs after stops after {stops:?} steps");
    }
}

#[test]
fn the_rigid_phase_threads_stops_and_resumes_to_the_same_bytes() {
    // Stopped in the rigid phase after frame 2 of 3 (0.2 s in), and again part way
    // through frame 3, once only rigid pieces move.
    let s = plate_drop(0.3);
    let [whole, ..] = common::threads_and_resume(&s, 2);
    let m = perifrac_sim::cache::manifest::Manifest::read(&whole.path().join("manifest.json"))
        .expect("manifest");
    stopped_and_resumed(&s, whole.path(), &[m.steps - 29]);
}

#[test]
fn a_stop_while_pieces_rest_among_particles_resumes_to_the_same_bytes() {
    // A jelly cube shattered on the ground: its grains go rigid and rest on the ground
    // beside pieces still deformable. Rapier's broad phase keeps optimiser counters it
    // does not save; stopped anywhere, the resumed run optimised its tree otherwise and
    // differed from frame 3 on (until stops waited for the stop points).
    let s = scene(
        "[scene]\nduration = 0.05\nfps = 80\n[materials.jelly]\ndensity = 1000.0\n\
         youngs_modulus = 1.0e5\npoisson_ratio = 0.3\ncritical_stretch = 0.05\n\
         [[body]]\nmaterial = \"jelly\"\nresolution = 0.008\nvelocity = [0, -6, 0]\n\
         shape = { type = \"box\", center = [0, 0.03, 0], size = [0.05, 0.05, 0.05] }\n\
         [[collider]]\ntype = \"ground\"\n[rigid]\nenabled = true\n\
         [output]\npreview = false\nusd = false\n",
    );
    let whole = tempfile::tempdir().expect("temp dir");
    let m = run::run(&s, whole.path(), &RunOptions::default(), &mut |_| {}).expect("runs");
    let frame = m.steps / 4;
    stopped_and_resumed(&s, whole.path(), &[frame + 1, 2 * frame + 40]);
}

#[test]
fn a_rigid_piece_striking_a_deformable_wall_breaks_bonds_in_it() {
    // A glass pellet (small, `small_fragment` above its particle count: rigid at the
    // first look, 150 µs before it arrives) shot at 40 m/s into a brittle plate: the
    // rigid pellet cracks the plate.
    let text = format!(
        "[scene]\nduration = 0.0005\nfps = 10000\ngravity = [0, 0, 0]\n{GLASS}\
         [materials.brittle]\ndensity = 1200.0\nyoungs_modulus = 3.0e9\n\
         poisson_ratio = 0.3\ncritical_stretch = 0.002\n\
         [[body]]\nname = \"pellet\"\nmaterial = \"glass\"\nresolution = 0.01\n\
         lattice = \"aligned\"\nvelocity = [0, 0, 40]\n\
         shape = {{ type = \"box\", center = [0, 0, -0.016], size = [0.02, 0.02, 0.02] }}\n\
         [[body]]\nname = \"plate\"\nmaterial = \"brittle\"\nresolution = 0.01\n\
         shape = {{ type = \"box\", center = [0, 0, 0.01], size = [0.08, 0.08, 0.02] }}\n\
         [rigid]\nenabled = true\ncheck_every = 4\nsmall_fragment = 500\n\
         [output]\npreview = false\nusd = false\n"
    );
    let mut p = run::prepare(&scene(&text)).expect("prepares");
    let pellet = p.world.parts[0]
        .model
        .point_bodies()
        .iter()
        .filter(|&&b| b == 0)
        .count();
    let (mut rigid_at_impact, mut broken) = (None, 0);
    while p.world.time < 0.0005 {
        p.world.step().expect("steps");
        broken = p.world.parts[0].model.broken_bonds();
        if broken > 0 && rigid_at_impact.is_none() {
            rigid_at_impact = Some(p.world.rigid.as_ref().map_or(0, |r| r.frozen_points()));
            println!("first broken bond at {:e} s", p.world.time);
        }
    }
    println!("{rigid_at_impact:?} rigid points at the first broken bond; {broken} broken");
    assert!(pellet < 500, "{pellet} particles in the pellet");
    assert_eq!(
        rigid_at_impact,
        Some(pellet),
        "the rigid pellet breaks the first bond"
    );
    assert!(
        broken > 20,
        "the rigid pellet cracks the plate: {broken} bonds"
    );
}

/// A glass cube cut in two by a pre-cut plane and dropped corner first on the ground
/// at `speed` m/s from 5 mm: its halves go rigid in the air and land. `rigid`:
/// "" (all peridynamics) or the `[rigid]` table's keys.
#[test]
fn rigid_pieces_land_on_a_mesh_collider_instead_of_falling_through_it() {
    // The cut cube set down on a slab that is a mesh collider (its top at y = 0.1 m),
    // the ground 0.1 m below: the halves go rigid before they land, so rapier, not
    // particle contact, must hold them up. Each half collides as its own surface (the
    // faces of its tets), so the surface an artist renders rests on the slab: its
    // lowest vertex within 1.5 mm of the top (as unions of the particles' cubes the
    // halves floated 3.6 mm above it).
    let dir = tempfile::tempdir().expect("temp dir");
    // Static, or sliding 5 cm along x and turning 10° about y over the first 0.3 s,
    // as the halves land and topple: they ride on it. The halves are born side by
    // side, their surfaces' convex parts overlapping across the cut; colliding as
    // those parts they wedged against each other, toppled together and were carried
    // 1.7 cm (docs/rigid.md, "Pieces born side by side").
    let mut shifts = Vec::new();
    for keyframes in [
        "",
        "keyframes = [{ time = 0.0 }, { time = 0.3, translation = [0.05, 0.0, 0.0], \
         rotation = [0.0, 10.0, 0.0] }]\n",
    ] {
        let text = cut_cube_on_slab(
            dir.path(),
            0.5,
            "[rigid]\nenabled = true\n",
            keyframes,
            0.105,
        )
        .replace("duration = 0.006\nfps = 500", "duration = 2.5\nfps = 10")
        .replace("usd = false\n", "usd = false\ntets = true\n");
        let s = Scene::parse(&text, &dir.path().join("drop.toml"), dir.path()).expect("scene");
        let out = dir.path().join(if keyframes.is_empty() {
            "still"
        } else {
            "moving"
        });
        let manifest = run::run(&s, &out, &RunOptions::default(), &mut |_| {}).expect("runs");
        let frame = |k: usize| {
            perifrac_sim::cache::ply::ParticleFrame::read(
                &out.join(format!("particles/{k:04}.ply")),
            )
            .expect("reads")
        };
        let last = manifest.frames();
        let (first, end) = (frame(1), frame(last));
        let (lowest, fastest) = common::lowest_and_fastest(&end);
        let tets =
            perifrac_sim::cache::vtu::TetFrame::read(&out.join(format!("tets/{last:04}.vtu")))
                .expect("reads the tets");
        let surface = tets.points.iter().map(|x| x[1]).fold(f64::MAX, f64::min);
        let mean_x = |f: &perifrac_sim::cache::ply::ParticleFrame| {
            f.position.iter().map(|x| f64::from(x[0])).sum::<f64>() / f.position.len() as f64
        };
        println!(
            "{} steps; lowest particle {lowest:.4} m, lowest surface vertex {surface:.4} m \
             (slab top 0.1 m); fastest {fastest:.2e} m/s",
            manifest.steps
        );
        assert!(
            manifest.steps < 20_000,
            "{} steps: the halves never went rigid",
            manifest.steps
        );
        assert!(
            (surface - 0.1).abs() < 1.5e-3,
            "the surface rests on the slab: lowest vertex {surface} m"
        );
        assert!(
            lowest > 0.1 - 0.25 * 0.025,
            "through the slab: lowest {lowest} m"
        );
        assert!(fastest < 0.05, "at rest: {fastest} m/s");
        shifts.push(mean_x(&end) - mean_x(&first));
        if !keyframes.is_empty() {
            // Stopped while the pieces ride the moving slab (its pose and velocity
            // are set again each step), resumed to the same bytes.
            stopped_and_resumed(&s, &out, &[500]);
        }
    }
    // Carried along by the slab: 5 cm further than on the still one (the 10° turn
    // moves them a few millimetres too).
    let carried = shifts[1] - shifts[0];
    println!("carried {carried:.4} m by a slab moving 0.05 m");
    assert!(
        (carried - 0.05).abs() < 0.01,
        "carried {carried} m by a slab moving 0.05 m"
    );
}

/// [`cut_cube_drop`]'s cube `lift` higher, over a slab that is a mesh collider (its
/// top at y = 0.1 m, the ground 0.1 m below), moved by `keyframes` (a TOML line, or
/// empty); the slab written into `dir`.
fn cut_cube_on_slab(dir: &Path, speed: f64, rigid: &str, keyframes: &str, lift: f64) -> String {
    let slab = "v -0.2 0 -0.2\nv 0.2 0 -0.2\nv 0.2 0.1 -0.2\nv -0.2 0.1 -0.2\n\
                v -0.2 0 0.2\nv 0.2 0 0.2\nv 0.2 0.1 0.2\nv -0.2 0.1 0.2\n\
                f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\n\
                f 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n";
    std::fs::write(dir.join("slab.obj"), slab).expect("writes the slab");
    let mut text = cut_cube_text(dir, speed, rigid)
        .replace(
            "translation = [0, 0.0799, 0]",
            &format!("translation = [0, {}, 0]", 0.0799 + lift),
        )
        .replace(
            "point = [0, 0.08, 0]",
            &format!("point = [0, {}, 0]", 0.08 + lift),
        )
        .replace(
            "center = [0, 0.08, 0]",
            &format!("center = [0, {}, 0]", 0.08 + lift),
        );
    text.push_str(&format!(
        "[[collider]]\ntype = \"mesh\"\npath = \"slab.obj\"\nfriction = 0.6\n{keyframes}"
    ));
    text
}

#[test]
fn a_rigid_piece_hit_hard_on_a_mesh_collider_goes_back_too() {
    // The corner drop at 3 m/s onto the slab mesh instead of the ground: going back
    // breaks about what peridynamics breaks, staying rigid nothing.
    let dir = tempfile::tempdir().expect("temp dir");
    let broken = |rigid: &str, name: &str| {
        let text = cut_cube_on_slab(dir.path(), 3.0, rigid, "", 0.1);
        let s = Scene::parse(&text, &dir.path().join("drop.toml"), dir.path()).expect("scene");
        let m = run::run(
            &s,
            &dir.path().join(name),
            &RunOptions::default(),
            &mut |_| {},
        )
        .expect("runs");
        m.broken_bonds
    };
    let pd = broken("", "pd");
    let went_back = broken("[rigid]\nenabled = true\nreenter = 1\n", "back");
    let stayed = broken("[rigid]\nenabled = true\n", "stay");
    println!(
        "on the slab mesh at 3 m/s: {pd} bonds broken in peridynamics, {went_back} going \
         back, {stayed} staying rigid"
    );
    assert!(
        pd > 100,
        "the corner drop breaks bonds in peridynamics: {pd}"
    );
    assert_eq!(stayed, 0, "a rigid piece breaks nothing");
    assert!(
        went_back as f64 > 0.5 * pd as f64 && (went_back as f64) < 2.0 * pd as f64,
        "going back on a mesh breaks about what peridynamics breaks: {went_back} against {pd}"
    );
}

fn cut_cube_drop(dir: &Path, speed: f64, rigid: &str) -> Scene {
    let text = cut_cube_text(dir, speed, rigid);
    Scene::parse(&text, &dir.join("drop.toml"), dir).expect("scene")
}

/// The text of [`cut_cube_drop`]'s scene (the cube written into `dir`).
fn cut_cube_text(dir: &Path, speed: f64, rigid: &str) -> String {
    let cube = "v -0.05 -0.05 -0.025\nv 0.05 -0.05 -0.025\nv 0.05 0.05 -0.025\n\
                v -0.05 0.05 -0.025\nv -0.05 -0.05 0.025\nv 0.05 -0.05 0.025\n\
                v 0.05 0.05 0.025\nv -0.05 0.05 0.025\nf 1 4 3\nf 1 3 2\nf 5 6 7\n\
                f 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\n\
                f 2 3 7\nf 2 7 6\n";
    std::fs::write(dir.join("cube.obj"), cube).expect("writes the cube");
    format!(
        "[scene]\nduration = 0.006\nfps = 500\n{GLASS}critical_compression = 0.01\n\
         [[body]]\nmaterial = \"glass\"\nresolution = 0.025\nvelocity = [0, -{speed}, 0]\n\
         shape = {{ type = \"mesh\", path = \"cube.obj\", rotation = [30, 0, 40], \
         translation = [0, 0.0799, 0] }}\n\
         [[body.crack]]\npoint = [0, 0.08, 0]\nnormal = [1, 0, 0]\n\
         region = {{ type = \"box\", center = [0, 0.08, 0], size = [0.3, 0.3, 0.3] }}\n\
         [[collider]]\ntype = \"ground\"\n\
         [contact]\ndamping = 0.5\nfriction = 0.6\ndistance = 1.0\n{rigid}\
         [output]\npreview = false\nusd = false\n"
    )
}

#[test]
fn a_rigid_piece_hit_hard_goes_back_and_breaks_as_peridynamics_does() {
    // What decides whether a rigid piece goes back to peridynamics when it is hit:
    // the same drop all in peridynamics. At 3 m/s (1.15 s_c c_p) the corner that
    // lands breaks bonds; a piece that stays rigid (the default, `reenter = 0`) breaks
    // none, one that goes back (`reenter = 1`) about as many. At 6 m/s (2.3 s_c c_p)
    // `reenter = 2` goes back. At 0.5 m/s nothing breaks and nothing goes back: the
    // run is the one that stays rigid, byte for byte. A run stopped after going back
    // resumes to the same bytes.
    let dir = tempfile::tempdir().expect("temp dir");
    let run = |speed: f64, rigid: &str| {
        let label: String = rigid.chars().filter(char::is_ascii_alphanumeric).collect();
        let out = dir.path().join(format!("{speed}-{label}"));
        let s = cut_cube_drop(dir.path(), speed, rigid);
        let m = run::run(&s, &out, &RunOptions::default(), &mut |_| {}).expect("runs");
        (m.broken_bonds, m.steps, out)
    };
    let stay = "[rigid]\nenabled = true\n";
    let back = "[rigid]\nenabled = true\nreenter = 1\n";
    let hard = "[rigid]\nenabled = true\nreenter = 2\n";
    let (pd, _, _) = run(3.0, "");
    let (went_back, back_steps, back_out) = run(3.0, back);
    let (stayed, stay_steps, _) = run(3.0, stay);
    println!(
        "3 m/s: {pd} bonds broken in peridynamics, {went_back} going back \
         ({back_steps} steps), {stayed} staying rigid ({stay_steps} steps)"
    );
    assert!(
        pd > 100,
        "the corner drop breaks bonds in peridynamics: {pd}"
    );
    assert_eq!(stayed, 0, "a rigid piece breaks nothing");
    assert!(
        went_back as f64 > 0.5 * pd as f64 && (went_back as f64) < 2.0 * pd as f64,
        "going back breaks about what peridynamics breaks: {went_back} against {pd}"
    );
    // Stopped while the piece that went back breaks, and resumed: the same bytes.
    let s = cut_cube_drop(dir.path(), 3.0, back);
    stopped_and_resumed(&s, &back_out, &[back_steps / 20, back_steps / 2]);
    let (broke, hard_steps, _) = run(6.0, hard);
    println!("6 m/s, reenter = 2: {broke} bonds broken ({hard_steps} steps)");
    assert!(broke > 100, "a hit at 2.3 s_c c_p goes back at 2: {broke}");
    let (gentle, gentle_steps, a) = run(0.5, hard);
    let (_, _, b) = run(0.5, stay);
    println!("0.5 m/s: {gentle} bonds broken, {gentle_steps} steps");
    assert_eq!(gentle, 0);
    for f in 1..=3 {
        let name = format!("particles/{f:04}.ply");
        let (x, y) = (std::fs::read(a.join(&name)), std::fs::read(b.join(&name)));
        assert!(
            x.expect("frame") == y.expect("frame"),
            "{name}: a gentle landing goes back"
        );
    }
}

/// The fastest particle (m/s) of the first part.
fn fastest_point(p: &Prepared) -> f64 {
    p.world.parts[0]
        .model
        .points()
        .velocity
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max)
}

#[test]
fn a_rolling_glass_ball_comes_to_rest_with_rolling_resistance() {
    // Rapier's contacts have friction and restitution but no rolling resistance: a
    // rounded piece rolling on the ground rolled on for seconds (the demo shot's
    // rounded chips before the pieces collided as their surfaces, its pieces spun up
    // by sliding that then skipped along the ground). A glass ball (r = 4 cm, 721
    // particles, its surface's convex parts) rolled at 3 m/s comes to rest within 2 s
    // with the default `rolling_resistance` (5 mm), and still rolls after 3 s without.
    let text = |rolling: &str| {
        format!(
            "[scene]\nduration = 3.0\nfps = 10\n{GLASS}[[body]]\nmaterial = \"glass\"\n\
             resolution = 0.016\nshape = {{ type = \"sphere\", center = [0, 0.05, 0], radius = 0.04 }}\n\
             velocity = [0, 0, 3]\nangular_velocity = [120, 0, 0]\n\
             [[collider]]\ntype = \"ground\"\n[rigid]\nenabled = true\nsmall_fragment = 1000\n\
             {rolling}[output]\npreview = false\nusd = false\n"
        )
    };
    let speed_at = |rolling: &str, seconds: f64| {
        let mut p = run::prepare(&scene(&text(rolling))).expect("prepares");
        let settings = p.world.rigid_settings.clone().expect("rigid phase");
        let mut rigid = RigidPhase::new(settings, &p.world.colliders, Default::default());
        assert_eq!(rigid.look(&mut p.world.parts, 0.0), 1, "one piece");
        let dt = 1.0 / 600.0;
        for _ in 0..(seconds / dt).round() as usize {
            rigid.step(
                dt,
                [0.0, -9.81, 0.0],
                &mut p.world.parts,
                &mut p.world.colliders,
            );
        }
        fastest_point(&p)
    };
    let with = speed_at("", 2.0);
    let without = speed_at("rolling_resistance = 0\n", 3.0);
    println!(
        "fastest particle: {with:.4} m/s after 2 s; without rolling resistance {without:.3} m/s after 3 s"
    );
    assert!(with < 0.05, "at rest within 2 s: {with} m/s");
    assert!(without > 0.5, "rolls on without it: {without} m/s");
}
