//! Particle contact (issue 12, `docs/contact.md`): two spheres hitting head-on, three
//! blocks stacked under gravity, a plate shattering on the ground, and the same bytes
//! with one and two threads. Small resolutions; the figures are printed with
//! `--nocapture`.

use std::path::Path;

use perifrac_sim::run::{self, Prepared};
use perifrac_sim::scene::Scene;

mod common;
use common::{model, momentum};

fn prepare(text: &str) -> Prepared {
    let scene = Scene::parse(text, Path::new("contact-test.toml"), Path::new(".")).expect("scene");
    run::prepare(&scene).expect("prepares")
}

/// Particle spacing l = V^{1/3} of a body: the mean over its particles of (m/ρ)^{1/3}.
fn spacing(p: &Prepared, density: f64, body: u32) -> f64 {
    let m = model(p);
    let (mass, bodies) = (m.points().mass, m.point_bodies());
    let of: Vec<f64> = (0..mass.len())
        .filter(|&i| bodies[i] == body)
        .map(|i| (mass[i] / density).cbrt())
        .collect();
    of.iter().sum::<f64>() / of.len() as f64
}

/// The smallest r − d over pairs of a particle of body `a` and one of body `b`: their
/// distance less their contact distance d = 0.9 (l_i + l_j)/2 (negative: overlap).
fn closest(p: &Prepared, a: u32, b: u32, density: f64) -> f64 {
    let m = model(p);
    let (points, body) = (m.points(), m.point_bodies());
    let y = points.position;
    let l = |i: usize| (points.mass[i] / density).cbrt();
    let mut best = f64::INFINITY;
    for i in (0..y.len()).filter(|&i| body[i] == a) {
        for j in (0..y.len()).filter(|&j| body[j] == b) {
            let d = [0, 1, 2].map(|k| y[i][k] - y[j][k]);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            best = best.min(r - 0.9 * 0.5 * (l(i) + l(j)));
        }
    }
    best
}

/// The mean velocity of body `b`.
fn body_velocity(p: &Prepared, b: u32) -> [f64; 3] {
    let m = model(p);
    let (points, body) = (m.points(), m.point_bodies());
    let members: Vec<usize> = (0..body.len()).filter(|&i| body[i] == b).collect();
    let mass: f64 = members.iter().map(|&i| points.mass[i]).sum();
    [0, 1, 2].map(|a| {
        members
            .iter()
            .map(|&i| points.mass[i] * points.velocity[i][a])
            .sum::<f64>()
            / mass
    })
}

const SPHERES: &str = r#"
[scene]
duration = 0.0003
fps = 10000.0
gravity = [0.0, 0.0, 0.0]

[materials.steel]
density = 7850.0
youngs_modulus = 2.0e11
poisson_ratio = 0.3

[[body]]
material = "steel"
shape = { type = "sphere", center = [-0.0205, 0.0, 0.0], radius = 0.02 }
resolution = 0.007
velocity = [5.0, 0.0, 0.0]

[[body]]
material = "steel"
shape = { type = "sphere", center = [0.0205, 0.0, 0.0], radius = 0.02 }
resolution = 0.007
velocity = [-5.0, 0.0, 0.0]
"#;

/// Two elastic spheres closing at 10 m/s (each at 5 m/s): momentum is conserved to
/// 1e-9 of one sphere's, no particle comes closer to one of the other sphere than the
/// contact distance less 10% of the spacing, and they bounce apart.
#[test]
fn two_spheres_head_on_conserve_momentum_and_do_not_interpenetrate() {
    let mut p = prepare(SPHERES);
    let l = spacing(&p, 7850.0, 0);
    let start = momentum(&p);
    let total_mass: f64 = model(&p).points().mass.iter().sum();
    let scale = 0.5 * total_mass * 5.0;
    let contact = p.world.contact.as_ref().expect("two bodies: contact is on");
    eprintln!(
        "two spheres: stable step of the model {:.3e} s, of contact {:.3e} s",
        model(&p).stable_time_step().0,
        contact.stable_time_step().0
    );
    let closing = body_velocity(&p, 0)[0] - body_velocity(&p, 1)[0];
    let steps = (0.0003 / p.world.dt) as usize;
    let mut deepest = 0.0f64;
    let mut drift = 0.0f64;
    for step in 0..steps {
        p.world.step().expect("steps");
        let now = momentum(&p);
        drift = drift.max(
            (0..3)
                .map(|a| (now[a] - start[a]).abs())
                .fold(0.0, f64::max)
                / scale,
        );
        if step % 4 == 0 {
            deepest = deepest.max(-closest(&p, 0, 1, 7850.0));
        }
    }
    let parting = body_velocity(&p, 1)[0] - body_velocity(&p, 0)[0];
    let rebound = parting / closing;
    eprintln!(
        "two spheres: {} particles, spacing {l:.2e} m, {steps} steps; momentum drift {drift:.2e} of one sphere's; \
         deepest overlap {:.3} spacings below the contact distance; rebound speed ratio {rebound:.3}",
        model(&p).points().mass.len(),
        deepest / l
    );
    assert!(drift < 1e-9, "momentum drift {drift:e}");
    assert!(deepest < 0.1 * l, "overlap {} spacings", deepest / l);
    assert!(
        rebound > 0.2 && rebound <= 1.0,
        "they bounce apart, no faster than they came: rebound ratio {rebound}"
    );
    let contact = p.world.contact.as_ref().expect("contact");
    assert!(
        contact.builds < steps as u64 / 2,
        "the Verlet list is reused: {} builds",
        contact.builds
    );
}

/// Without `[contact]` the two spheres pass through each other: the test above can fail.
#[test]
fn without_contact_the_spheres_pass_through_each_other() {
    let text = format!("{SPHERES}\n[contact]\nparticles = false\n");
    let mut p = prepare(&text);
    assert!(p.world.contact.is_none());
    let steps = (0.0003 / p.world.dt) as usize;
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let overlap = -closest(&p, 0, 1, 7850.0);
    assert!(
        overlap > 0.5 * spacing(&p, 7850.0, 0),
        "they overlap by {overlap} m"
    );
}

const BLOCKS: &str = r#"
[scene]
duration = 1.0
fps = 10.0

[materials.soft]
density = 1000.0
youngs_modulus = 2.0e6
poisson_ratio = 0.3
air_damping = 2.0

[[body]]
material = "soft"
shape = { type = "box", center = [0.0, 0.05, 0.0], size = [0.1, 0.1, 0.1] }
resolution = 0.04

[[body]]
material = "soft"
shape = { type = "box", center = [0.0, 0.15, 0.0], size = [0.1, 0.1, 0.1] }
resolution = 0.04

[[body]]
material = "soft"
shape = { type = "box", center = [0.0, 0.25, 0.0], size = [0.1, 0.1, 0.1] }
resolution = 0.04

[[collider]]
type = "ground"

[contact]
damping = 0.7
"#;

/// The lowest and highest particle heights of body `b`.
fn extent_y(p: &Prepared, b: u32) -> (f64, f64) {
    let m = model(p);
    let (y, body) = (m.points().position, m.point_bodies());
    (0..y.len())
        .filter(|&i| body[i] == b)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), i| {
            (lo.min(y[i][1]), hi.max(y[i][1]))
        })
}

/// The potential energy of the contact springs between particles of different bodies
/// of one material (bulk modulus `kappa`, horizon `delta`, `density`), with the
/// default `[contact]` stiffness s = 15 and distance ϱ = 0.9: Σ ½ k_ij (d_ij − r)² over
/// the pairs closer than d_ij = ϱ (l_i + l_j)/2, k_ij = s · 18κ/(πδ⁵) V_i V_j (the
/// spring of `docs/contact.md`, whose force k_ij (d_ij − r) is −∂/∂r of this).
fn contact_energy(p: &Prepared, kappa: f64, delta: f64, density: f64) -> f64 {
    let m = model(p);
    let (points, body) = (m.points(), m.point_bodies());
    let y = points.position;
    let volume = |i: usize| points.mass[i] / density;
    let modulus = 15.0 * 18.0 * kappa / (std::f64::consts::PI * delta.powi(5));
    let mut total = 0.0;
    for i in 0..y.len() {
        for j in (i + 1)..y.len() {
            if body[i] == body[j] {
                continue;
            }
            let d = [0, 1, 2].map(|k| y[i][k] - y[j][k]);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let reach = 0.9 * 0.5 * (volume(i).cbrt() + volume(j).cbrt());
            if r < reach {
                total += 0.5 * modulus * volume(i) * volume(j) * (reach - r).powi(2);
            }
        }
    }
    total
}

/// Kinetic + strain + gravitational energy of the blocks, and the potential energy of
/// the contact springs between them (E = 2 MPa, ν = 0.3: κ = E/(3(1 − 2ν)); δ =
/// 1.45 λ).
fn energy(p: &Prepared) -> (f64, f64) {
    let m = model(p);
    let points = m.points();
    let potential: f64 = points
        .mass
        .iter()
        .zip(points.position)
        .map(|(m, y)| m * 9.81 * y[1])
        .sum();
    let springs = contact_energy(p, 2.0e6 / (3.0 * (1.0 - 2.0 * 0.3)), 1.45 * 0.04, 1000.0);
    (m.kinetic_energy() + m.strain_energy() + potential, springs)
}

/// Three blocks stacked on the ground for 1 s under gravity: after they settle (0.2 s:
/// as placed, face to face, their surface particles are closer than the contact
/// distance), the closest pair between neighbouring blocks stays within 10% of the
/// spacing of the contact distance (neither sinking in nor floating), and the energy
/// never grows. The energy includes the contact springs': placed face to face, the
/// blocks' surface particles overlap their contact distance, and those springs hold
/// energy that they give to the blocks when released (1.3e-2 J on the centred lattice,
/// which the blocks' energy alone counted as a gain of 7.7e-3 J).
#[test]
fn three_stacked_blocks_rest_on_each_other() {
    let mut p = prepare(BLOCKS);
    let l = spacing(&p, 1000.0, 0);
    let gaps = |p: &Prepared| [closest(p, 0, 1, 1000.0), closest(p, 1, 2, 1000.0)];
    let start = gaps(&p);
    let (e0, springs0) = energy(&p);
    let weight_scale = model(&p).points().mass.iter().sum::<f64>() * 9.81 * l;
    let steps = (1.0 / p.world.dt) as usize;
    let settled = (0.2 / p.world.dt) as usize;
    let (mut worst, mut gained, mut bodies_only) = (0.0f64, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for step in 1..=steps {
        p.world.step().expect("steps");
        if step % 20 == 0 || step == steps {
            if step >= settled {
                for g in gaps(&p) {
                    worst = worst.max(g.abs());
                }
            }
            let (e, springs) = energy(&p);
            gained = gained.max(e + springs - e0 - springs0);
            bodies_only = bodies_only.max(e - e0);
        }
    }
    eprintln!(
        "stacked blocks: spacing {l:.3e} m, {steps} steps; closest pairs as placed {:.3}, {:.3} spacings from the contact distance; \
         after 0.2 s at most {:.3} spacings from it; contact springs as placed {springs0:.2e} J; energy gain at most \
         {gained:.2e} J with them, {bodies_only:.2e} J without (M g l = {weight_scale:.2e} J)",
        start[0] / l,
        start[1] / l,
        worst / l
    );
    assert!(
        worst < 0.1 * l,
        "a gap is {} spacings from the contact distance",
        worst / l
    );
    assert!(gained < 0.01 * weight_scale, "energy grew by {gained:e} J");
}

const PLATE: &str = r#"
[scene]
duration = 0.02
fps = 500.0

[materials.glass]
density = 2500.0
youngs_modulus = 5.0e8
poisson_ratio = 0.22
critical_stretch = 0.004

[[body]]
material = "glass"
shape = { type = "box", center = [0.0, 0.012, 0.0], size = [0.16, 0.02, 0.16] }
resolution = 0.01
velocity = [0.0, -8.0, 0.0]
angular_velocity = [0.0, 0.0, 20.0]

[[collider]]
type = "ground"
"#;

/// Pairs of particles from different fragments closer than half the spacing.
fn close_fragment_pairs(p: &Prepared, l: f64) -> (usize, usize) {
    let columns = p.world.particles();
    let y = model(p).points().position;
    let fragments = columns
        .fragment
        .iter()
        .copied()
        .collect::<std::collections::BTreeSet<_>>()
        .len();
    let mut count = 0;
    for i in 0..y.len() {
        for j in i + 1..y.len() {
            if columns.fragment[i] == columns.fragment[j] {
                continue;
            }
            let d = [0, 1, 2].map(|k| y[i][k] - y[j][k]);
            if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < 0.25 * l * l {
                count += 1;
            }
        }
    }
    (count, fragments)
}

/// A plate thrown edge-first onto the ground shatters; 12 ms on, pairs from
/// different fragments closer than half the spacing are under 1% of the particles
/// with contact, and are reported without it.
#[test]
fn shattered_plate_fragments_do_not_overlap() {
    let mut figures = Vec::new();
    for contact in [false, true] {
        let text = format!("{PLATE}\n[contact]\nparticles = {contact}\n");
        let mut p = prepare(&text);
        let l = spacing(&p, 2500.0, 0);
        let steps = (0.012 / p.world.dt) as usize;
        for _ in 0..steps {
            p.world.step().expect("steps");
        }
        let n = model(&p).points().mass.len();
        let (close, fragments) = close_fragment_pairs(&p, l);
        eprintln!(
            "shattered plate, contact {contact}: {n} particles, {fragments} fragments, \
             {close} pairs from different fragments closer than half the spacing ({:.2}% of the particles)",
            100.0 * close as f64 / n as f64
        );
        figures.push((close, n, fragments));
    }
    let (close, n, fragments) = figures[1];
    let (before, ..) = figures[0];
    assert!(fragments > 3, "the plate shatters: {fragments} fragments");
    assert!(
        (close as f64) < 0.01 * n as f64,
        "{close} close pairs from different fragments of {n} particles"
    );
    assert!(
        close < before,
        "contact separates fragments: {close} close pairs with it, {before} without"
    );
}

/// The spheres' run with one and with two threads gives the same bytes.
#[test]
fn contact_gives_the_same_bytes_with_one_and_two_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let mut p = prepare(SPHERES);
            for _ in 0..60 {
                p.world.step().expect("steps");
            }
            let points = model(&p).points();
            let mut bytes = Vec::new();
            for (y, v) in points.position.iter().zip(points.velocity) {
                for a in 0..3 {
                    bytes.extend(y[a].to_le_bytes());
                    bytes.extend(v[a].to_le_bytes());
                }
            }
            (bytes, p.world.contact.as_ref().map(|c| c.builds))
        })
    };
    let (one, builds) = run(1);
    let (two, _) = run(2);
    assert!(builds.is_some_and(|b| b > 0));
    assert!(one == two, "the bytes differ between 1 and 2 threads");
}

fn scenes_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes")
}

const VASE_ON_TABLE: &str = r#"
[scene]
duration = 0.2
fps = 50.0

[materials.soft]
density = 1000.0
bulk_modulus = 2.5e5
shear_modulus = 1.2e5
air_damping = 20.0

[[body]]
material = "soft"
shape = { type = "mesh", path = "../meshes/vase.obj", scale = 0.5, translation = [0.0, 0.303, 0.0] }
resolution = 0.008
velocity = [0.0, -0.3, 0.0]

[[collider]]
type = "mesh"
path = "../meshes/table.obj"
"#;

/// The vase (half size) dropped on the table mesh (top face at y = 0.30 m) comes to
/// rest on it: no particle is ever below the top by more than 10% of the spacing, and
/// at the end it sits there, slow.
#[test]
fn vase_dropped_on_a_mesh_table_rests_on_it() {
    let scene = Scene::parse(
        VASE_ON_TABLE,
        Path::new("vase-on-table.toml"),
        &scenes_dir(),
    )
    .expect("scene");
    let mut p = run::prepare(&scene).expect("prepares");
    let l = spacing(&p, 1000.0, 0);
    let top = 0.30;
    let steps = (0.2 / p.world.dt) as usize;
    let mut lowest = f64::INFINITY;
    for step in 1..=steps {
        p.world.step().expect("steps");
        if step % 5 == 0 || step == steps {
            lowest = lowest.min(extent_y(&p, 0).0);
        }
    }
    let v = body_velocity(&p, 0);
    let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    eprintln!(
        "vase on a mesh table: spacing {l:.2e} m, {steps} steps; lowest particle {:.3} spacings below the top; \
         final velocity {v:.3?} m/s, lowest particle at the end {:.4} m",
        (top - lowest) / l,
        extent_y(&p, 0).0
    );
    assert!(
        top - lowest < 0.1 * l,
        "a particle sank {} spacings into the table",
        (top - lowest) / l
    );
    assert!(
        extent_y(&p, 0).0 < top + 0.5 * l,
        "it rests on the table, not above it"
    );
    assert!(
        speed < 0.1,
        "it comes to rest: {speed} m/s (from 0.3 m/s and a fall)"
    );
}

/// A keyframed mesh collider is where its keyframes put it, between them by linear
/// interpolation and slerp, and drags what it touches along.
#[test]
fn keyframed_mesh_collider_moves_and_carries() {
    let text = r#"
[scene]
duration = 0.1
fps = 50.0
gravity = [0.0, 0.0, 0.0]

[materials.soft]
density = 1000.0
bulk_modulus = 2.5e5
shear_modulus = 1.2e5

[[body]]
material = "soft"
shape = { type = "box", center = [0.0, 0.32, 0.0], size = [0.08, 0.04, 0.08] }
resolution = 0.02

[[collider]]
type = "mesh"
path = "../meshes/table.obj"
friction = 1.0
keyframes = [
  { time = 0.0 },
  { time = 0.1, translation = [0.0, 0.05, 0.0], rotation = [0.0, 90.0, 0.0] },
]
"#;
    let scene = Scene::parse(text, Path::new("moving-table.toml"), &scenes_dir()).expect("scene");
    let mut colliders = perifrac_sim::contact::colliders(&scene).expect("colliders");
    let table = &mut colliders[0];
    let pivot = table.center;
    table.set_time(0.05);
    assert!(
        (table.center[1] - pivot[1] - 0.025).abs() < 1e-12,
        "half way up"
    );
    let q = table.orientation();
    let half_angle = (45.0f64.to_radians() / 2.0).sin();
    assert!(
        (q[1] - half_angle).abs() < 1e-9,
        "45° about y half way: {q:?}"
    );
    table.set_time(1.0);
    assert!(
        (table.center[1] - pivot[1] - 0.05).abs() < 1e-12,
        "held after the last keyframe"
    );
    let mut p = run::prepare(&scene).expect("prepares");
    let start = extent_y(&p, 0).0;
    let steps = (0.1 / p.world.dt) as usize;
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let rise = extent_y(&p, 0).0 - start;
    assert!(rise > 0.03, "the rising table lifts the block: {rise} m");
}

/// A mesh collider's transforms file with a bad line is refused with the file and line.
#[test]
fn bad_transforms_file_names_the_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let table = scenes_dir().join("../meshes/table.obj");
    std::fs::copy(&table, dir.path().join("table.obj")).expect("copy");
    std::fs::write(
        dir.path().join("poses.txt"),
        "0 0 0 0 0 0\n0 0.01 0 zero 0 0\n",
    )
    .expect("write");
    let text = r#"
[scene]
[materials.m]
density = 1000.0
bulk_modulus = 2.5e5
shear_modulus = 1.2e5
[[body]]
material = "m"
shape = { type = "box", center = [0.0, 0.4, 0.0], size = [0.1, 0.1, 0.1] }
resolution = 0.05
[[collider]]
type = "mesh"
path = "table.obj"
transforms = "poses.txt"
"#;
    let scene = Scene::parse(text, &dir.path().join("s.toml"), dir.path()).expect("scene");
    let err = perifrac_sim::contact::colliders(&scene)
        .expect_err("refused")
        .to_string();
    assert!(err.contains("poses.txt:2"), "{err}");
}

/// Measurement, not a check (`cargo test -p perifrac-sim --test contact -- --ignored
/// --nocapture demo_contact_share`): the demo's glass wall hit by the rigid sphere and
/// by the peridynamic steel ball, the first 1,000 steps (the impact and the first
/// fragments); particle contact's share of the step time, broken bonds and the ball's
/// speed.
#[test]
#[ignore = "a measurement of the demo's contact share, minutes long: run it on purpose"]
fn demo_contact_share() {
    for name in ["demo.toml", "demo-deformable-ball.toml"] {
        let scene = Scene::load(&scenes_dir().join(name)).expect("scene");
        let mut p = run::prepare(&scene).expect("prepares");
        p.world.reset_times();
        let start = std::time::Instant::now();
        let mut broken = 0;
        for _ in 0..1000 {
            broken += p.world.step().expect("steps");
        }
        let wall = start.elapsed().as_secs_f64();
        let contact = p.world.contact.as_ref().map_or(0.0, |c| c.time);
        let builds = p.world.contact.as_ref().map_or(0, |c| c.builds);
        let ball = if p.world.colliders.len() > 1 {
            p.world.colliders[1].velocity[2]
        } else {
            body_velocity(&p, 1)[2]
        };
        eprintln!(
            "{name}: dt {:.3e} s, 1000 steps in {wall:.1} s; particle contact {contact:.1} s = {:.1}% of the step time \
             ({builds} list builds); {broken} bonds broken; ball at {ball:.1} m/s at t = {:.2} ms",
            p.world.dt,
            100.0 * contact / wall,
            p.world.time * 1e3
        );
    }
}

/// Bad `[contact]` keys are refused with the key and the allowed range.
#[test]
fn bad_contact_keys_are_refused() {
    let bad = |extra: &str| {
        let text = format!("{SPHERES}\n[contact]\n{extra}\n");
        Scene::parse(&text, Path::new("s.toml"), Path::new("."))
            .expect_err("refused")
            .to_string()
    };
    let e = bad("distance = 2.0");
    assert!(
        e.contains("contact.distance") && e.contains("(0, 1.5]"),
        "{e}"
    );
    let e = bad("damping = -0.1");
    assert!(e.contains("contact.damping"), "{e}");
    let e = bad("friction = -1.0");
    assert!(e.contains("contact.friction"), "{e}");
    let e = bad("particle = true");
    assert!(e.contains("particle"), "{e}");
}

/// Two particles of one body touch within at most their reference distance, whatever
/// `[contact] distance` says: a bar cut in two by a slot half a λ wide (no bond crosses
/// it, `docs/lattice.md`) stays at rest with `distance = 1.2`. Reaching past the
/// reference distance would push the slot's faces apart at t = 0 (as it would
/// fragments whose bonds broke in tension).
#[test]
fn a_contact_distance_over_one_pushes_no_unbonded_pair_apart_at_rest() {
    let text = format!(
        "{}\n[contact]\nparticles = true\ndistance = 1.2\n",
        include_str!("scenes/slotted-bar.toml")
    );
    let mut p = prepare(&text);
    for _ in 0..50 {
        p.world.step().expect("steps");
    }
    let fastest = model(&p)
        .points()
        .velocity
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max);
    eprintln!("slotted bar, distance 1.2: fastest particle after 50 steps {fastest:.3e} m/s");
    assert!(
        fastest < 1e-9,
        "the slot's faces pushed apart: {fastest:.3e} m/s"
    );
}
