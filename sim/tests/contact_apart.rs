//! Bodies that interleaved (issue 31, item 7; `docs/contact.md`, "Keeping bodies
//! apart"): two rubbery spheres (E = 1 MPa, λ = 25 mm) meeting at 4 m/s brought
//! particles of the two bodies to 0.4 mm of each other, their fronts overlapping by
//! 0.7λ, because contact was only a penalty spring that surfaces meeting fast push
//! through. These tests run `assets/scenes/contact-spheres.toml`, smaller spheres for
//! speed, at its 4 m/s and at a fifth of the P-wave speed, and measure the closest
//! two particles of the two bodies come, in particle spacings, every step.

use std::path::Path;

use perifrac_sim::run::{self, Prepared};
use perifrac_sim::scene::Scene;

mod common;
use common::{model, momentum};

/// The shipped scene's material: E = 1 MPa, ν = 0.45, ρ = 1100 kg/m³.
const DENSITY: f64 = 1100.0;

/// P-wave speed c_p = √(E(1 − ν)/((1 + ν)(1 − 2ν))/ρ) of the scene's material.
fn wave_speed() -> f64 {
    let (e, nu) = (1.0e6, 0.45);
    (e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) / DENSITY).sqrt()
}

/// The contact-spheres scene with spheres of `radius` (surfaces 10 mm apart) closing
/// at `closing` m/s, for `duration` s.
fn spheres(radius: f64, closing: f64, duration: f64) -> Prepared {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/contact-spheres.toml");
    let text = std::fs::read_to_string(&path).expect("the scene");
    let c = radius + 0.005;
    let v = 0.5 * closing;
    let mut text = text.replace("duration = 0.04 ", &format!("duration = {duration} "));
    for (from, to) in [
        (
            "center = [-0.105, 0.0, 0.0], radius = 0.1 }",
            format!("center = [-{c}, 0.0, 0.0], radius = {radius} }}"),
        ),
        (
            "center = [0.105, 0.0, 0.0], radius = 0.1 }",
            format!("center = [{c}, 0.0, 0.0], radius = {radius} }}"),
        ),
        (
            "velocity = [2.0, 0.0, 0.0]",
            format!("velocity = [{v}, 0.0, 0.0]"),
        ),
        (
            "velocity = [-2.0, 0.0, 0.0]",
            format!("velocity = [-{v}, 0.0, 0.0]"),
        ),
    ] {
        assert!(text.contains(from), "the scene changed: no {from:?}");
        text = text.replace(from, &to);
    }
    let scene = Scene::parse(&text, &path, path.parent().expect("dir")).expect("scene");
    run::prepare(&scene).expect("prepares")
}

/// What one collision showed.
#[derive(Debug)]
struct Collision {
    /// The smallest r_ij/l̄ over pairs of particles of the two bodies and every step,
    /// l̄ = V̄^{1/3} the particle spacing, V̄ the particles' mean volume.
    closest: f64,
    /// The deepest the fronts overlapped: max x of the left sphere's particles less
    /// min x of the right's, in λ (negative: they never crossed).
    front: f64,
    /// The largest |Σ m v| over the steps, relative to one sphere's momentum.
    drift: f64,
    /// Speed of separation over speed of approach (centres of mass).
    rebound: f64,
}

/// Runs the prepared spheres to the end, measuring every step.
fn collide(mut p: Prepared, closing: f64, duration: f64) -> Collision {
    let lambda = 0.025;
    let points = model(&p).points();
    let n = points.mass.len();
    let body = model(&p).point_bodies().to_vec();
    let spacing = (points.mass.iter().sum::<f64>() / DENSITY / n as f64).cbrt();
    let one: f64 = (0..n)
        .filter(|&i| body[i] == 0)
        .map(|i| points.mass[i])
        .sum();
    let scale = one * 0.5 * closing;
    let steps = (duration / p.world.dt).round() as usize;
    let (mut closest, mut front, mut drift) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for _ in 0..steps {
        p.world.step().expect("steps");
        let y = model(&p).points().position;
        // Only particles within 4 spacings of the other sphere's front can be closest.
        let right_front = (0..n)
            .filter(|&i| body[i] == 1)
            .map(|i| y[i][0])
            .fold(f64::INFINITY, f64::min);
        let left_front = (0..n)
            .filter(|&i| body[i] == 0)
            .map(|i| y[i][0])
            .fold(f64::NEG_INFINITY, f64::max);
        front = front.max((left_front - right_front) / lambda);
        let band = 4.0 * lambda;
        let left: Vec<usize> = (0..n)
            .filter(|&i| body[i] == 0 && y[i][0] > right_front - band)
            .collect();
        let right: Vec<usize> = (0..n)
            .filter(|&i| body[i] == 1 && y[i][0] < left_front + band)
            .collect();
        for &i in &left {
            for &j in &right {
                let d = [0, 1, 2].map(|a| y[i][a] - y[j][a]);
                let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                closest = closest.min(r / spacing);
            }
        }
        let m = momentum(&p);
        drift = drift.max(m.iter().map(|x| x.abs()).fold(0.0, f64::max) / scale);
    }
    let points = model(&p).points();
    let centre_velocity = |b: u32| {
        let (mut mv, mut m) = (0.0, 0.0);
        for i in (0..n).filter(|&i| body[i] == b) {
            mv += points.mass[i] * points.velocity[i][0];
            m += points.mass[i];
        }
        mv / m
    };
    Collision {
        closest,
        front,
        drift,
        rebound: (centre_velocity(1) - centre_velocity(0)) / closing,
    }
}

/// At the scene's 4 m/s (smaller spheres): no two particles of the two bodies come
/// closer than half a spacing, momentum is kept, and they bounce apart.
#[test]
fn rubbery_spheres_at_4_m_s_stay_half_a_spacing_apart() {
    let (radius, closing, duration) = (0.06, 4.0, 0.022);
    let c = collide(spheres(radius, closing, duration), closing, duration);
    eprintln!("4 m/s ({:.3} c_p): {c:?}", closing / wave_speed());
    assert!(
        c.closest >= 0.5,
        "particles came to {:.3} spacings",
        c.closest
    );
    assert!(c.drift < 1e-9, "momentum drift {:e}", c.drift);
    assert!(c.front < 0.0, "the fronts crossed by {:.2}λ", c.front);
    assert!(c.rebound > 0.2, "they part: rebound ratio {}", c.rebound);
}

/// At a closing speed of a fifth of the P-wave speed (11.7 m/s) as well.
#[test]
fn rubbery_spheres_at_a_fifth_of_the_wave_speed_stay_half_a_spacing_apart() {
    let (radius, duration) = (0.06, 0.018);
    let closing = 0.2 * wave_speed();
    let c = collide(spheres(radius, closing, duration), closing, duration);
    eprintln!("{closing:.1} m/s (0.2 c_p): {c:?}");
    assert!(
        c.closest >= 0.5,
        "particles came to {:.3} spacings",
        c.closest
    );
    assert!(c.drift < 1e-9, "momentum drift {:e}", c.drift);
    assert!(c.front < 0.0, "the fronts crossed by {:.2}λ", c.front);
    assert!(c.rebound > 0.0, "they part: rebound ratio {}", c.rebound);
}

/// While the spheres are kept apart (the impulses at work), one and two threads give
/// the same bytes.
#[test]
fn keeping_apart_gives_the_same_bytes_with_one_and_two_threads() {
    let closing = 0.2 * wave_speed();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let mut p = spheres(0.06, closing, 0.01);
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
            (bytes, p.world.contact.as_ref().map(|c| c.apart.steps))
        })
    };
    let (one, kept) = run(1);
    let (two, _) = run(2);
    assert!(kept.is_some_and(|k| k > 0), "the impulses acted: {kept:?}");
    assert!(one == two, "the bytes differ between 1 and 2 threads");
}
