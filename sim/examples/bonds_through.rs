//! The set-up cost of bonds only through material (issue 13, item 2;
//! `docs/lattice.md`): a scene's particles, then its families found by distance alone
//! and through each non-convex body's material ([`family::families_through`]), the two
//! interleaved, `REPEATS` times each (default 3), with the bond counts.
//!
//! ```text
//! cargo run --release -p perifrac-sim --example bonds_through -- SCENE [REPEATS]
//! ```

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use perifrac_sim::family::{self, Solid};
use perifrac_sim::geometry::discretize::discretize;
use perifrac_sim::geometry::shape::bond_shapes;
use perifrac_sim::scene::Scene;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(path), repeats) = (args.first(), args.get(1)) else {
        eprintln!("usage: bonds_through SCENE [REPEATS]");
        return ExitCode::from(2);
    };
    let Ok(repeats) = repeats.map_or(Ok(3), |r| r.parse::<usize>()) else {
        eprintln!("REPEATS: give a whole number of repeats, such as 3");
        return ExitCode::from(2);
    };
    match measure(Path::new(path), repeats) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{path}: {message}");
            ExitCode::from(2)
        }
    }
}

fn measure(path: &Path, repeats: usize) -> Result<(), String> {
    let scene = Scene::load(path).map_err(|e| e.to_string())?;
    let disc = discretize(&scene).map_err(|e| e.to_string())?;
    let delta: Vec<f64> = disc
        .body
        .iter()
        .map(|&b| scene.bodies[b as usize].delta())
        .collect();
    let shapes = bond_shapes(&scene).map_err(|e| e.to_string())?;
    let solids: Vec<Option<Solid>> = shapes
        .iter()
        .zip(&scene.bodies)
        .map(|(sdf, b)| sdf.as_deref().map(|sdf| Solid::of(sdf, b.resolution)))
        .collect();
    println!(
        "{} particles, {} of {} bodies not convex",
        disc.position.len(),
        solids.iter().filter(|s| s.is_some()).count(),
        solids.len()
    );
    let build = |solids: &[Option<Solid>]| {
        let start = Instant::now();
        let bonds = family::families_through(&disc.position, &disc.body, &delta, solids)
            .map_err(|e| e.to_string())?;
        Ok::<_, String>((start.elapsed().as_secs_f64(), bonds.neighbours.len()))
    };
    for round in 1..=repeats {
        let (distance, all) = build(&[])?;
        let (through, kept) = build(&solids)?;
        println!(
            "round {round}: by distance {distance:.2} s ({all} directed bonds), through \
             material {through:.2} s ({kept}): {:.2}×",
            through / distance
        );
    }
    Ok(())
}
