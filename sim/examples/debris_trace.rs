//! Follows one particle of the demo's wall step by step (issue 13, item 5;
//! `docs/lattice.md`, *Physically bounded debris*): the forces on it from its bonds
//! (the peridynamic model) and from particle contact, its velocity, its damage and
//! its gap to the ball, over steps FROM..=TO of the demo at scene seed SEED. Then
//! the fastest wall particle of steps 1..=TO.
//!
//! ```text
//! cargo run --release -p perifrac-sim --example debris_trace -- SEED PARTICLE FROM TO
//! ```
//!
//! Run from the repository's root (it reads `assets/scenes/demo.toml`).

use std::path::Path;
use std::process::ExitCode;

use perifrac_math::{norm, sub};
use perifrac_sim::contact::ColliderShape;
use perifrac_sim::run;
use perifrac_sim::scene::Scene;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let numbers: Vec<Option<u64>> = args.iter().map(|a| a.parse().ok()).collect();
    let [Some(seed), Some(particle), Some(from), Some(to)] = numbers[..] else {
        eprintln!(
            "usage: debris_trace SEED PARTICLE FROM TO (four whole numbers: the demo's scene \
             seed, a wall particle's index, the first and last step to print)"
        );
        return ExitCode::from(2);
    };
    match trace(seed, particle as usize, from, to) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::from(2)
        }
    }
}

fn trace(seed: u64, particle: usize, from: u64, to: u64) -> Result<(), String> {
    let path = Path::new("assets/scenes/demo.toml");
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: {e} (run from the repository's root)", path.display()))?
        .replace("[scene]\n", &format!("[scene]\nseed = {seed}\n"));
    let scene = Scene::parse(&text, path, Path::new("assets/scenes")).map_err(|e| e.to_string())?;
    let mut p = run::prepare(&scene).map_err(|e| e.to_string())?;
    let mass = p.world.parts[0].model.points().mass.to_vec();
    let Some(&m) = mass.get(particle) else {
        return Err(format!(
            "PARTICLE {particle}: the wall has {} particles, give one below that",
            mass.len()
        ));
    };
    let Some((ball, radius)) = p
        .world
        .colliders
        .iter()
        .enumerate()
        .find_map(|(c, col)| match col.shape {
            ColliderShape::Sphere(r) => Some((c, r)),
            _ => None,
        })
    else {
        return Err(format!(
            "{}: the demo has no sphere collider",
            path.display()
        ));
    };
    let mean = mass.iter().sum::<f64>() / mass.len() as f64;
    let rest = p.world.parts[0].model.points().reference[particle];
    println!(
        "dt {:.4e} s; particle {particle}: mass {:.2}× the mean, rest position {:?} mm",
        p.world.dt,
        m / mean,
        rest.map(|x| (x * 1e4).round() / 10.0)
    );
    println!("step | |v| m/s | v m/s | F bonds N | F contact N | damage | gap to the ball mm");
    let (mut top, mut top_at) = (0.0f64, (0, 0));
    let mut acceleration = vec![[0.0; 3]; mass.len()];
    for step in 1..=to {
        p.world.step().map_err(|e| e.to_string())?;
        let model = &p.world.parts[0].model;
        let points = model.points();
        for (i, &v) in points.velocity.iter().enumerate() {
            if norm(v) > top {
                (top, top_at) = (norm(v), (i, step));
            }
        }
        if step < from {
            continue;
        }
        model.accelerations([0.0; 3], &mut acceleration);
        let bonds = acceleration[particle].map(|a| (a * m).round());
        let contact = p
            .world
            .contact
            .as_ref()
            .map_or([0.0; 3], |c| c.force(0)[particle].map(f64::round));
        let v = points.velocity[particle];
        let centre = p.world.colliders[ball].center;
        let gap = norm(sub(points.position[particle], centre)) - radius;
        println!(
            "{step} | {:.1} | {:?} | {bonds:?} | {contact:?} | {:.2} | {:.2}",
            norm(v),
            v.map(|x| (x * 10.0).round() / 10.0),
            model.particles().damage[particle],
            gap * 1e3
        );
    }
    println!(
        "fastest over steps 1..={to}: {top:.1} m/s ({:.2}× the ball), particle {} at step {}",
        top / 50.0,
        top_at.0,
        top_at.1
    );
    Ok(())
}
