//! Criterion benchmarks of the hot kernels: one force evaluation (dilatation, return
//! mapping, forces, fracture) of a wall of Chen Table 1 with each material, and the
//! neighbour search. Fixed scenes, so runs compare across commits.

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use perifrac_sim::family;
use perifrac_sim::geometry::discretize::discretize;
use perifrac_sim::pd::Peridynamics;
use perifrac_sim::run;
use perifrac_sim::scene::Scene;

fn wall(material: &str) -> Scene {
    let text = format!(
        "[scene]\nname = \"bench\"\n[materials.m]\n{material}\n[[body]]\nmaterial = \"m\"\nresolution = 0.02\n\
         shape = {{ type = \"box\", center = [0, 0.25, 0], size = [0.5, 0.5, 0.1] }}\n"
    );
    Scene::parse(&text, Path::new("bench.toml"), Path::new(".")).expect("bench scene")
}

fn kernels(c: &mut Criterion) {
    let materials = [
        (
            "elastic",
            "density = 1200\nbulk_modulus = 1e7\nshear_modulus = 6e6",
        ),
        (
            "plastic",
            "density = 1200\nbulk_modulus = 1e7\nshear_modulus = 6e6\nyield_stretch = 1e-3\nplastic_limit = 0.2",
        ),
        (
            "glass",
            "density = 2200\nbulk_modulus = 3.3e10\nshear_modulus = 2e10\ncritical_stretch = 0.0005",
        ),
    ];
    let mut group = c.benchmark_group("internal_forces");
    group.sample_size(20);
    for (name, material) in materials {
        let mut prepared = run::prepare(&wall(material)).expect("prepares");
        let model = &mut prepared
            .world
            .model_mut::<Peridynamics>()
            .expect("peridynamic")
            .model;
        // A small affine stretch so plasticity and fracture have work to check.
        for i in 0..model.len() {
            model.particles.position[i][0] = 1.0005 * model.reference.position[i][0];
        }
        group.bench_function(name, |b| b.iter(|| model.internal_forces()));
    }
    group.finish();
    let scene = wall(materials[0].1);
    let disc = discretize(&scene).expect("meshes");
    let delta = vec![1.45 * 0.02; disc.position.len()];
    c.bench_function("family_build", |b| {
        b.iter(|| {
            family::build(&disc.position, &disc.volume, &disc.body, &delta, true).expect("bonds")
        })
    });
}

criterion_group!(benches, kernels);
criterion_main!(benches);
