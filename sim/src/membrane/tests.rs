//! Membrane checks: the micro-spring stress and Poisson ratio of the bond-based law,
//! diffusion against the analytic 1D solution and its conservation, the stability of
//! velocity Verlet at the stable step, and fracture of a notched strip at η_c.

use std::path::Path;

use perifrac_math::dist;

use super::*;
use crate::geometry::discretize::discretize;
use crate::run::prepare;

/// Han Table 1, "Crack path" column: E = 2×10⁴ Pa, ν = 0.3, ρ = 5000 kg/m³, C = 1,
/// k = 0.01, G_f = 11.3, Δx = 0.02 m; `shape` and extra keys filled in.
pub(super) fn scene(shape: &str, membrane: &str, extra: &str) -> Scene {
    scene_with(shape, "", membrane, extra)
}

/// [`scene`] with extra material keys.
fn scene_with(shape: &str, material: &str, membrane: &str, extra: &str) -> Scene {
    let text = format!(
        "[scene]\nname = \"m\"\nduration = 0.1\nfps = 10\ngravity = [0, 0, 0]\n\
         [materials.film]\ndensity = 5000\nyoungs_modulus = 2e4\npoisson_ratio = 0.3\n{material}\n\
         [materials.film.membrane]\n{membrane}\n\
         [[body]]\nmaterial = \"film\"\nmodel = \"membrane\"\nresolution = 0.02\nshape = {shape}\n{extra}\n\
         [output]\npreview = false\n"
    );
    Scene::parse(&text, Path::new("membrane.toml"), Path::new(".")).expect("scene")
}

pub(super) fn model(scene: &Scene) -> MembraneModel {
    let disc = discretize(scene).expect("sheet");
    MembraneModel::from_scene(scene, &disc).expect("model")
}

/// Σ V_i f_i over the particles with `side(x_i) < 0`: the force the rest of the sheet
/// pulls them with, through the bonds that cross the cut.
fn traction(m: &MembraneModel, side: impl Fn([f64; 3]) -> f64) -> [f64; 3] {
    let mut t = [0.0; 3];
    for i in 0..m.len() {
        if side(m.reference[i]) < 0.0 {
            for (t, f) in t.iter_mut().zip(m.force[i]) {
                *t += m.volume[i] * f;
            }
        }
    }
    t
}

/// A rectangle 1.6 m along x by 70 rows along z: the in-plane stress under a uniform
/// strain (ε_x, ε_z), measured as the traction across the cuts x = 0 and z = 0 over
/// the cut's length and the thickness.
pub(super) fn stress(strain: [f64; 2]) -> (f64, f64, MembraneModel) {
    stress_of(0.3, "", strain)
}

/// The depth (along z) of the rectangle of [`stress`]: 70 rows of the lattice.
pub(super) fn stress_depth() -> f64 {
    70.0 * 0.02 * 3f64.sqrt() / 2.0
}

/// [`stress`] for Poisson ratio `nu` and the extra body keys `body` (the formulation).
fn stress_of(nu: f64, body: &str, strain: [f64; 2]) -> (f64, f64, MembraneModel) {
    let depth = stress_depth();
    stress_in(
        &format!("{{ type = \"slab\", center = [0, 0, 0], size = [1.6, 0.001, {depth}] }}"),
        nu,
        body,
        strain,
    )
}

/// [`stress_of`] on the sheet `shape` (1.6 m × [`stress_depth`] in the y = 0 plane,
/// 1 mm thick).
pub(super) fn stress_in(
    shape: &str,
    nu: f64,
    body: &str,
    strain: [f64; 2],
) -> (f64, f64, MembraneModel) {
    let depth = stress_depth();
    let mut s = scene(shape, "", body);
    s.materials.get_mut("film").expect("film").poisson_ratio = Some(nu);
    let mut m = model(&s);
    for i in 0..m.len() {
        let x = m.reference[i];
        m.position[i] = [x[0] * (1.0 + strain[0]), x[1], x[2] * (1.0 + strain[1])];
    }
    m.internal_forces();
    let t = 0.001;
    let sxx = traction(&m, |x| x[0] - 1e-9)[0] / (depth * t);
    let szz = traction(&m, |x| x[2] - 1e-9)[2] / (1.6 * t);
    (sxx, szz, m)
}

#[test]
fn biaxial_stretch_gives_the_micro_spring_stress_and_poisson_one_third() {
    let eps = 1e-6;
    let (sxx, szz, m) = stress([eps, eps]);
    // The virial of the micro-spring law at an interior particle:
    // σ = ½ Σ_j c η W_ij V_j |ξ| ξ̂ ⊗ ξ̂ (small strain, η = ε on every bond).
    let i = (0..m.len())
        .min_by(|&a, &b| {
            let r = |p: [f64; 3]| p[0] * p[0] + p[2] * p[2];
            r(m.reference[a]).total_cmp(&r(m.reference[b]))
        })
        .expect("particles");
    let c = m.bodies[0].micromodulus;
    let mut predicted = [0.0; 2];
    for k in m.bonds.range(i) {
        let j = (m.bonds.neighbours[k] & INDEX) as usize;
        let xi = m.rest_length[k];
        let d = [
            m.reference[j][0] - m.reference[i][0],
            m.reference[j][2] - m.reference[i][2],
        ];
        for a in 0..2 {
            predicted[a] += 0.5 * c * eps * m.weight[k] * m.volume[j] * d[a] * d[a] / xi;
        }
    }
    // The free edges along the cut carry less (about 1/(3 rows)), so 1.5%.
    for (measured, predicted) in [(sxx, predicted[0]), (szz, predicted[1])] {
        assert!(
            (measured / predicted - 1.0).abs() < 0.015,
            "σ = {measured:e} Pa where the micro-spring law gives {predicted:e} Pa"
        );
    }
    // Han's Appendix A closed form (continuum integral over the disc of radius R):
    // σ = π c h R³ ε / 24; the R = 1.5 h lattice is within 3% of it.
    let r = m.bodies[0].cutoff;
    let continuum = std::f64::consts::PI * c * 0.001 * r.powi(3) * eps / 24.0;
    assert!((predicted[0] / continuum - 1.0).abs() < 0.03);
    // Uniaxial strain: σ_zz/σ_xx = C12/C11 = ν (plane stress), 1/3 for central forces
    // on the isotropic triangular lattice.
    let (sxx, szz, _) = stress([eps, 0.0]);
    let nu = szz / sxx;
    assert!((nu - 1.0 / 3.0).abs() < 0.01, "ν = {nu}");
}

const STATE: &str = "[body.membrane]\nmembrane_model = \"state\"\n";

#[test]
fn the_state_based_option_takes_the_poisson_ratio_and_youngs_modulus() {
    let eps = 1e-6;
    for nu in [0.2, 0.45] {
        // The plane-stress stiffness C from two uniaxial strains; then the uniaxial
        // stress response: ν = C21/C22, E = C11 − C12 C21/C22.
        let (c11, c21, _) = stress_of(nu, STATE, [eps, 0.0]);
        let (c12, c22, _) = stress_of(nu, STATE, [0.0, eps]);
        let measured_nu = c21 / c22;
        let e = (c11 - c12 * c21 / c22) / eps;
        println!("requested ν = {nu}: ν = {measured_nu:.4}, E = {e:.1} Pa");
        assert!(
            (measured_nu / nu - 1.0).abs() < 0.05,
            "ν = {measured_nu} where {nu} was asked"
        );
        assert!(
            (e / 2e4 - 1.0).abs() < 0.05,
            "E = {e} Pa where 2e4 was asked"
        );
    }
}

/// θ(x, t) on [0, L] with θ(0) = 1, θ(L) = 0 and θ = 0 at t = 0:
/// 1 − x/L − Σ_n 2/(nπ) sin(nπx/L) exp(−D n²π² t/L²).
fn analytic(x: f64, t: f64, length: f64, d: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let series: f64 = (1..2000)
        .map(|n| {
            let n = n as f64;
            2.0 / (n * pi)
                * (n * pi * x / length).sin()
                * (-d * n * n * pi * pi * t / (length * length)).exp()
        })
        .sum();
    1.0 - x / length - series
}

#[test]
fn diffusion_on_a_strip_matches_the_analytic_solution() {
    // A strip one particle wide, 61 particles long; k = 0.01, ρC = 5000.
    let s = scene(
        "{ type = \"slab\", center = [0, 0, 0], size = [1.22, 0.001, 0.01] }",
        "diffusion_conductivity = 0.01",
        "",
    );
    let mut m = model(&s);
    let n = m.len();
    assert_eq!(n, 61);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| m.reference[a][0].total_cmp(&m.reference[b][0]));
    let (first, last) = (order[0], order[n - 1]);
    m.quantity[first] = 1.0;
    for (end, value) in [(first, 1.0), (last, 0.0)] {
        m.sources.push(Source {
            particles: vec![end as u32],
            effect: Effect::Value(value),
            start: 0.0,
            until: f64::INFINITY,
        });
    }
    let x0 = m.reference[first][0];
    let length = m.reference[last][0] - x0;
    // Eq. 25 on a chain is the second difference with D = k W / (ρ C): the second
    // moment (1/2A_i) Σ_j W A_j (ξ_x/|ξ|)² of a particle's bonds is W.
    let b = &m.bodies[0];
    let d = b.conductivity * (1.0 - 0.02 / b.cutoff) / (b.density * b.capacity);
    let dt = 0.7 * m.stable_time_step().0;
    let mut t = 0.0;
    for target in [0.05, 0.2] {
        let target = target * length * length / d;
        while t + dt <= target {
            m.diffuse(dt);
            t += dt;
        }
        let (mut err, mut norm) = (0.0, 0.0);
        for i in 0..n {
            let exact = analytic(m.reference[i][0] - x0, t, length, d);
            err += (m.quantity[i] - exact).powi(2);
            norm += exact * exact;
        }
        let l2 = (err / norm).sqrt();
        assert!(l2 < 0.02, "relative L2 error {l2} at t = {t} s");
    }
}

#[test]
fn diffusion_conserves_the_total_quantity_across_a_slit() {
    let s = scene(
        "{ type = \"slab\", center = [0, 0, 0], size = [0.4, 0.001, 0.3] }",
        "diffusion_conductivity = 0.3",
        "[[body.crack]]\npoint = [0, 0, 0]\nnormal = [1, 0, 0]\n\
         region = { type = \"box\", center = [0, 0, 0.1], size = [0.1, 0.1, 0.2] }\n",
    );
    let mut m = model(&s);
    assert!(m.damage.iter().any(|&d| d > 0.0), "the slit cut bonds");
    let mut seed = 12345u64;
    for theta in &mut m.quantity {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *theta = (seed >> 11) as f64 / (1u64 << 53) as f64;
    }
    let before = m.total_quantity();
    let dt = 0.7 * m.stable_time_step().0;
    for _ in 0..500 {
        m.diffuse(dt);
    }
    let after = m.total_quantity();
    assert!(
        ((after - before) / before).abs() < 1e-12,
        "Σ ρCAθ went from {before} to {after}"
    );
    let spread = |q: &[f64]| {
        let mean = q.iter().sum::<f64>() / q.len() as f64;
        q.iter().map(|x| (x - mean).powi(2)).sum::<f64>()
    };
    assert!(
        spread(&m.quantity) < 0.5 * (m.len() as f64 / 12.0),
        "θ evened out"
    );
}

#[test]
fn verlet_at_the_stable_step_keeps_a_wrinkled_sheet_bounded() {
    // Han's Eq. 26 is symplectic Euler, whose positions are Verlet's; both are stable
    // for ωΔt < 2. At dt_safety = 1 (the bound itself) a sheet released from random
    // out-of-plane and in-plane displacements keeps its energy, in both formulations.
    wrinkled_sheet_stays_bounded("");
    wrinkled_sheet_stays_bounded(STATE);
}

fn wrinkled_sheet_stays_bounded(body: &str) {
    let s = {
        let mut s = scene(
            "{ type = \"slab\", center = [0, 0, 0], size = [0.4, 0.001, 0.4] }",
            "",
            body,
        );
        s.scene.dt_safety = 1.0;
        s
    };
    let mut prepared = prepare(&s).expect("prepared");
    let world = &mut prepared.world;
    // Velocities of ±0.5 mm/s in every direction, hashed from the rest position.
    world.set_velocity(
        |x| {
            let mut h =
                (x[0] * 1e4).round() as i64 as u64 ^ ((x[2] * 1e4).round() as i64 as u64) << 20;
            [0, 1, 2].map(|_| {
                h = h
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                1e-3 * ((h >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
            })
        },
        s.scene.duration,
    );
    let energy = |w: &crate::world::World| {
        let m = &w.model::<Membrane>().expect("membrane").model;
        m.kinetic_energy() + m.strain_energy()
    };
    let start = energy(world);
    let mut highest: f64 = 0.0;
    for _ in 0..3000 {
        world.step().expect("no blow-up");
        highest = highest.max(energy(world));
    }
    assert!(
        highest < 1.5 * start,
        "energy grew from {start:e} to {highest:e} J"
    );
}

#[test]
fn a_notched_strip_breaks_at_the_critical_strain_and_not_below() {
    // A strip 1.2 m × 0.35 m with a slit across 40% of its width at x = 0, pulled at
    // both ends slowly (2 mm/s against waves of 0.35 m/s, with light air damping, so
    // that no wave from the start rings up to η_c); the bond strain at the slit tip
    // passes η_c first.
    let s = scene_with(
        "{ type = \"slab\", center = [0, 0, 0], size = [1.2, 0.001, 0.35] }",
        "air_damping = 0.5",
        "fracture_energy = 11.3",
        "[[body.anchor]]\nregion = { type = \"box\", center = [-0.6, 0, 0], size = [0.1, 1, 1] }\nvelocity = [-0.002, 0, 0]\n\
         [[body.anchor]]\nregion = { type = \"box\", center = [0.6, 0, 0], size = [0.1, 1, 1] }\nvelocity = [0.002, 0, 0]\n\
         [[body.crack]]\npoint = [0.001, 0, 0]\nnormal = [1, 0, 0]\n\
         region = { type = \"box\", center = [0, 0, 0.175], size = [0.1, 0.1, 0.28] }\n",
    );
    let mut prepared = prepare(&s).expect("prepared");
    let world = &mut prepared.world;
    let critical = world.model::<Membrane>().expect("membrane").model.bodies[0].critical_strain;
    let max_strain = |m: &MembraneModel| {
        let mut worst: f64 = 0.0;
        for i in 0..m.len() {
            for k in m.bonds.range(i) {
                let nb = m.bonds.neighbours[k];
                if nb & BROKEN == 0 {
                    let j = (nb & INDEX) as usize;
                    let r: f64 = (0..3)
                        .map(|a| (m.position[j][a] - m.position[i][a]).powi(2))
                        .sum();
                    worst = worst.max(r.sqrt() / m.rest_length[k] - 1.0);
                }
            }
        }
        worst
    };
    let mut first_break = None;
    let mut highest_unbroken: f64 = 0.0;
    for step in 0..20_000 {
        let before = max_strain(&world.model::<Membrane>().expect("membrane").model);
        let broke = world.step().expect("step");
        if broke > 0 {
            first_break = Some((step, before));
            break;
        }
        highest_unbroken = highest_unbroken.max(before);
    }
    let (_, before) = first_break.expect("the strip broke");
    assert!(
        highest_unbroken >= 0.9 * critical,
        "no bond broke up to {highest_unbroken} (η_c = {critical})"
    );
    assert!(before <= critical && before > 0.9 * critical);
    let m = &world.model::<Membrane>().expect("membrane").model;
    assert!(max_strain(m) <= critical, "every intact bond is within η_c");
    // The first bonds to go are at the slit's tip.
    for i in 0..m.len() {
        for k in m.bonds.range(i) {
            if m.bonds.neighbours[k] & BROKEN != 0 {
                assert!(
                    m.reference[i][0].abs() < 0.05,
                    "a bond broke away from the slit"
                );
            }
        }
    }
}

#[test]
fn a_free_sheet_at_uniform_theta_expands_by_alpha_theta_without_force() {
    let s = scene(
        "{ type = \"slab\", center = [0, 0, 0], size = [0.3, 0.001, 0.2] }",
        "expansion = 0.01\nlaw = \"rubber\"\nrubber_coefficient = -0.2\nrubber_exponent = 3",
        "",
    );
    let mut m = model(&s);
    m.quantity.iter_mut().for_each(|t| *t = 2.0);
    for i in 0..m.len() {
        m.position[i] = m.reference[i].map(|x| x * 1.02);
    }
    m.internal_forces();
    let c = m.bodies[0].micromodulus;
    let worst = m
        .force
        .iter()
        .map(|f| f.iter().map(|x| x.abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-9 * c * m.volume[0],
        "largest force density {worst:e}"
    );
    // Held at its rest size instead, the heated sheet pushes its edges outward.
    m.position = m.reference.clone();
    m.internal_forces();
    let edge = (0..m.len())
        .max_by(|&a, &b| m.reference[a][0].total_cmp(&m.reference[b][0]))
        .expect("particles");
    assert!(
        m.force[edge][0] > 0.0,
        "a constrained heated sheet pushes its edge out"
    );
}

#[test]
fn bad_membrane_keys_name_the_key() {
    let good = "[scene]\nname = \"m\"\n[materials.film]\ndensity = 5000\nyoungs_modulus = 2e4\npoisson_ratio = 0.3\n\
        [materials.film.membrane]\nfracture_energy = 11.3\n\
        [[body]]\nmaterial = \"film\"\nmodel = \"membrane\"\nresolution = 0.02\n\
        shape = { type = \"slab\", center = [0, 0, 0], size = [1, 0.001, 1] }\n";
    let key = |text: &str| match Scene::parse(text, Path::new("bad.toml"), Path::new(".")) {
        Err(perifrac_cache::CacheError::Scene { key, .. }) => key,
        other => panic!("expected a scene error, got {other:?}"),
    };
    assert!(Scene::parse(good, Path::new("good.toml"), Path::new(".")).is_ok());
    let cases = [
        (
            good.replace(
                "type = \"slab\", center = [0, 0, 0], size = [1, 0.001, 1]",
                "type = \"sphere\", center = [0, 0, 0], radius = 1",
            ),
            "body.0.shape",
        ),
        (
            format!("{good}[body.membrane]\ncutoff = 5\n"),
            "body.0.membrane.cutoff",
        ),
        (
            good.replace("fracture_energy = 11.3", "fracture_energy = -1"),
            "materials.film.membrane.fracture_energy",
        ),
        (
            good.replace(
                "fracture_energy = 11.3",
                "law = \"rubber\"\nrubber_exponent = 1",
            ),
            "materials.film.membrane.rubber_exponent",
        ),
        (
            good.replace(
                "poisson_ratio = 0.3\n",
                "poisson_ratio = 0.3\ncritical_stretch = 0.1\n",
            ),
            "materials.film.critical_stretch",
        ),
        (
            format!(
                "{good}[[body]]\nmaterial = \"film\"\nresolution = 0.1\nshape = {{ type = \"box\", center = [0, 2, 0], size = [1, 1, 1] }}\n"
            ),
            "body.1.model",
        ),
        (
            format!("{good}[[body.membrane.source]]\nrate = 1\nvalue = 2\n"),
            "body.0.membrane.source.0",
        ),
        (
            format!("{good}[[body.membrane.source]]\nrate = 1\nstart = 2\nuntil = 1\n"),
            "body.0.membrane.source.0.until",
        ),
        (
            format!(
                "{good}[[body.membrane.source]]\nvalue = 1\nscatter = {{ count = 0, radius = 0.1 }}\n"
            ),
            "body.0.membrane.source.0.scatter.count",
        ),
        (
            format!("{good}[body.membrane]\nquantity = inf\n"),
            "body.0.membrane.quantity",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(key(&text), expected);
    }
}

/// A 0.4 m × 0.3 m sheet without conduction, with the sources of `sources` (TOML).
fn sheet_with_sources(sources: &str) -> Scene {
    scene(
        "{ type = \"slab\", center = [0, 0, 0], size = [0.4, 0.001, 0.3] }",
        "",
        sources,
    )
}

#[test]
fn sources_act_inside_their_region_and_time_window() {
    let s = sheet_with_sources(
        "[body.membrane]\nquantity = 0.5\n\
         [[body.membrane.source]]\nregion = { type = \"sphere\", center = [0.1, 0, 0], radius = 0.05 }\n\
         rate = 2.0\nstart = 0.01\nuntil = 0.03\n\
         [[body.membrane.source]]\nregion = { type = \"sphere\", center = [-0.1, 0, 0], radius = 0.05 }\n\
         value = -1.0\n",
    );
    let mut m = model(&s);
    let dt = 0.001;
    for _ in 0..50 {
        m.diffuse(dt);
    }
    let (mut heated, mut held) = (0, 0);
    for i in 0..m.len() {
        let x = m.reference[i];
        let theta = m.quantity[i];
        let near = |c: f64| ((x[0] - c).powi(2) + x[1] * x[1] + x[2] * x[2]).sqrt() <= 0.05;
        if near(0.1) {
            // Active for the 20 steps that start in [0.01, 0.03) s.
            assert!(
                (theta - (0.5 + 2.0 * 0.02)).abs() < 1e-12,
                "θ = {theta} at {x:?}"
            );
            heated += 1;
        } else if near(-0.1) {
            assert_eq!(theta, -1.0);
            held += 1;
        } else {
            assert_eq!(theta, 0.5, "θ moved outside the sources at {x:?}");
        }
    }
    // A disc of radius 0.05 m on a triangular lattice of 0.02 m: about 22 particles.
    assert!(
        (15..30).contains(&heated),
        "{heated} particles in the first source"
    );
    assert!((15..30).contains(&held), "{held} particles in the second");
}

#[test]
fn a_rate_source_adds_exactly_its_quantity_while_conduction_conserves() {
    let mut s = sheet_with_sources(
        "[[body.membrane.source]]\nregion = { type = \"box\", center = [0.15, 0, 0], size = [0.1, 0.1, 0.3] }\nrate = 3.0\n",
    );
    s.materials.get_mut("film").expect("film").membrane = Some(MembraneMaterialSpec {
        diffusion_conductivity: 0.3,
        ..Default::default()
    });
    let mut m = model(&s);
    let b = &m.bodies[0];
    let per_step: f64 = m.sources[0]
        .particles
        .iter()
        .map(|&i| b.density * b.capacity * m.area[i as usize] * 3.0)
        .sum();
    let dt = 0.7 * m.stable_time_step().0;
    let steps = 400;
    for _ in 0..steps {
        m.diffuse(dt);
    }
    let expected = per_step * dt * steps as f64;
    let total = m.total_quantity();
    assert!(
        ((total - expected) / expected).abs() < 1e-10,
        "Σ ρCAθ = {total}, the source put in {expected}"
    );
    let far = (0..m.len())
        .min_by(|&a, &b| m.reference[a][0].total_cmp(&m.reference[b][0]))
        .expect("particles");
    assert!(
        m.quantity[far] > 0.0,
        "conduction carried θ across the sheet"
    );
}

#[test]
fn scattered_sources_follow_the_scene_seed() {
    let text = "[[body.membrane.source]]\nvalue = 1.0\nscatter = { count = 4, radius = 0.03 }\n";
    let spots = |seed: u64| {
        let mut s = sheet_with_sources(text);
        s.scene.seed = seed;
        model(&s).sources[0].particles.clone()
    };
    let (a, again, other) = (spots(1), spots(1), spots(2));
    assert_eq!(a, again, "the same seed places the same spots");
    assert_ne!(a, other, "another seed places other spots");
    // Four spots of radius 0.03 m (about 9 particles each), possibly overlapping.
    assert!(
        (6..=40).contains(&a.len()),
        "{} particles in 4 spots",
        a.len()
    );
    let m = model(&sheet_with_sources(text));
    let x = |i: u32| m.reference[i as usize];
    // Every particle is within 0.06 m (a spot's diameter) of another one of its spot:
    // the spots are discs, not a scatter of single particles.
    for &i in &a {
        let near = a.iter().filter(|&&j| dist(x(i), x(j)) <= 0.06).count();
        assert!(near >= 4, "particle {i} is nearly alone in its spot");
    }
}
