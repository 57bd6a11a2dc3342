use std::path::Path;

use perifrac_math::{mul_transpose, norm, rotation_svd};

use super::constitutive::{Elastic, Mat3, determinant, mul, polar_rotation};
use super::*;
use crate::cache::checkpoint::Encoder;
use crate::run::{Prepared, prepare};
use crate::scene::MpmElasticity;
use crate::scene::Scene;
use crate::world::World;

pub(super) fn prepared(text: &str) -> Prepared {
    let scene = Scene::parse(text, Path::new("mpm.toml"), Path::new(".")).expect("scene");
    prepare(&scene).expect("prepares")
}

pub(super) fn mpm(world: &World) -> &Mpm {
    world.model::<Mpm>().expect("an MPM model")
}

pub(super) const OUTPUT: &str = "[output]\ntets = false\nsurface = \"none\"\npreview = false\n";

fn scene(settings: &str, bodies: &str) -> String {
    format!(
        "[scene]\nduration = 1.0\nfps = 1000\n{settings}\n\
         [materials.soft]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.3\n\
         [materials.stiff]\ndensity = 1000\nyoungs_modulus = 1e6\npoisson_ratio = 0.3\n\
         {bodies}{OUTPUT}"
    )
}

#[test]
fn seeding_puts_a_fixed_count_per_cell_and_is_reproducible() {
    let text = scene(
        "gravity = [0, 0, 0]\nseed = 7",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\n\
         shape = { type = \"box\", center = [0.1, 0.1, 0.1], size = [0.1, 0.06, 0.04] }\n",
    );
    let a = prepared(&text);
    let b = prepared(&text);
    let p = &mpm(&a.world).particles;
    // 5 × 3 × 2 cells of 0.02 m, 8 particles each.
    assert_eq!(p.len(), 5 * 3 * 2 * 8);
    assert_eq!(p.position, mpm(&b.world).particles.position);
    let volume: f64 = p.volume.iter().sum();
    assert!((volume - 0.1 * 0.06 * 0.04).abs() < 1e-12);
}

#[test]
fn fixed_corotated_stress_vanishes_under_rotation_and_is_safe_when_inverted() {
    let e = Elastic::from_young(MpmElasticity::FixedCorotated, 1e6, 0.3);
    let r = polar_rotation(&[[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
    let p = e.first_piola(&r);
    assert!(p.iter().flatten().all(|x| x.abs() < 1e-9), "{p:?}");
    // A reflection: one negative singular value, R a rotation.
    let inverted: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -0.5]];
    let s = rotation_svd(&inverted);
    assert!((determinant(&s.u) - 1.0).abs() < 1e-12);
    assert!((determinant(&s.v) - 1.0).abs() < 1e-12);
    assert!((s.sigma.iter().product::<f64>() + 0.5).abs() < 1e-12);
    assert!(
        e.first_piola(&inverted)
            .iter()
            .flatten()
            .all(|x| x.is_finite())
    );
    // Uniaxial stretch: P₁₁ = 2μ(s − 1) + λ(J − 1)J/s with J = s.
    let st = 1.01;
    let f = [[st, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let p = e.first_piola(&f);
    let expected = 2.0 * e.mu * (st - 1.0) + e.lambda * (st - 1.0);
    assert!((p[0][0] - expected).abs() < 1e-6 * expected, "{}", p[0][0]);
}

/// [`polar_rotation`] returns the polar factor of F = RS: R a rotation and S = RᵀF
/// symmetric, positive definite unless F is inverted (then the inversion-safe SVD's
/// UVᵀ, whose S has the one negative eigenvalue). Random rotations times random stretches: near the identity, singular values
/// 0.05–20 (condition numbers up to 400), and inverted. Higham's iteration is the more
/// accurate of the two: S = RᵀF is symmetric to 1e-15 relative where nalgebra's SVD
/// leaves up to 2e-8 when two singular values are close, so the SVD is only a coarse
/// check here (1e-7).
#[test]
fn polar_rotation_is_the_polar_factor() {
    let mut state = 7u64;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let transpose = |r: &Mat3| [0, 1, 2].map(|i| [0, 1, 2].map(|j| r[j][i]));
    let (mut asymmetry, mut orthogonality, mut from_svd) = (0.0f64, 0.0f64, 0.0f64);
    for case in 0..20_000 {
        let mut angle = || 6.3 * uniform();
        let (a, b, c, d, e, f) = (angle(), angle(), angle(), angle(), angle(), angle());
        let u = nalgebra::Rotation3::from_euler_angles(a, b, c).into_inner();
        let v = nalgebra::Rotation3::from_euler_angles(d, e, f).into_inner();
        let inverted = case % 3 == 2;
        let sigma = match case % 3 {
            0 => [0, 1, 2].map(|_| 1.0 + 0.02 * (uniform() - 0.5)),
            1 => [0, 1, 2].map(|_| 0.05 * 400f64.powf(uniform())),
            _ => [1.0 + 0.3 * uniform(), 1.0, -(0.1 + uniform())],
        };
        let m =
            u * nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::from(sigma)) * v.transpose();
        let f: Mat3 = [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[(i, j)]));
        let scale = sigma.iter().fold(0.0f64, |x, s| x.max(s.abs()));
        let r = polar_rotation(&f);
        let rtr = mul(&transpose(&r), &r);
        for (i, row) in rtr.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                let identity = if i == j { 1.0 } else { 0.0 };
                orthogonality = orthogonality.max((x - identity).abs());
            }
        }
        assert!((determinant(&r) - 1.0).abs() < 1e-13, "case {case}: det R");
        let stretch = mul(&transpose(&r), &f);
        if !inverted {
            for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                asymmetry = asymmetry.max((stretch[i][j] - stretch[j][i]).abs() / scale);
            }
        }
        let minors = [
            stretch[0][0],
            stretch[0][0] * stretch[1][1] - stretch[0][1] * stretch[1][0],
            determinant(&stretch),
        ];
        assert_eq!(
            minors.iter().all(|&x| x > 0.0),
            !inverted,
            "case {case}: S = RᵀF positive definite exactly when F is not inverted"
        );
        let svd = rotation_svd(&f);
        let expected = mul_transpose(&svd.u, &svd.v);
        for (row, row_expected) in r.iter().zip(&expected) {
            for (x, y) in row.iter().zip(row_expected) {
                from_svd = from_svd.max((x - y).abs());
            }
        }
    }
    assert!(orthogonality < 1e-14, "RᵀR − I up to {orthogonality:e}");
    assert!(asymmetry < 1e-14, "RᵀF asymmetric by {asymmetry:e} of |F|");
    assert!(
        from_svd < 1e-7,
        "R differs from the SVD's UVᵀ by {from_svd:e}"
    );
}

/// The closed-form Kirchhoff stresses equal P Fᵀ of the first Piola–Kirchhoff ones.
#[test]
fn kirchhoff_stress_is_first_piola_times_f_transpose() {
    let f: Mat3 = [[1.05, 0.02, -0.01], [-0.01, 0.97, 0.03], [0.02, 0.01, 1.02]];
    for energy in [
        MpmElasticity::FixedCorotated,
        MpmElasticity::NeoHookean,
        MpmElasticity::StableNeoHookean,
    ] {
        let e = Elastic::from_young(energy, 1e6, 0.3);
        let expected = mul_transpose(&e.first_piola(&f), &f);
        let tau = e.kirchhoff(&f);
        for (row, row_expected) in tau.iter().zip(&expected) {
            for (x, y) in row.iter().zip(row_expected) {
                assert!(
                    (x - y).abs() < 1e-9 * 1e6,
                    "{energy:?}: {tau:?} vs {expected:?}"
                );
            }
        }
    }
}

#[test]
fn neo_hookean_stress_matches_finite_differences_of_its_energy() {
    let e = Elastic::from_young(MpmElasticity::NeoHookean, 1e6, 0.3);
    let f: Mat3 = [[1.05, 0.02, 0.0], [-0.01, 0.97, 0.03], [0.0, 0.01, 1.02]];
    let p = e.first_piola(&f);
    let h = 1e-6;
    for a in 0..3 {
        for b in 0..3 {
            let (mut up, mut down) = (f, f);
            up[a][b] += h;
            down[a][b] -= h;
            let numeric = (e.energy_density(&up) - e.energy_density(&down)) / (2.0 * h);
            assert!(
                (numeric - p[a][b]).abs() < 1e-3 * (1.0 + p[a][b].abs()),
                "{a}{b}"
            );
        }
    }
    let fc = Elastic::from_young(MpmElasticity::FixedCorotated, 1e6, 0.3);
    let p = fc.first_piola(&f);
    for a in 0..3 {
        for b in 0..3 {
            let (mut up, mut down) = (f, f);
            up[a][b] += h;
            down[a][b] -= h;
            let numeric = (fc.energy_density(&up) - fc.energy_density(&down)) / (2.0 * h);
            assert!(
                (numeric - p[a][b]).abs() < 1e-3 * (1.0 + p[a][b].abs()),
                "{a}{b}"
            );
        }
    }
    let r = polar_rotation(&f);
    let rtr = mul(
        &r,
        &[
            [r[0][0], r[1][0], r[2][0]],
            [r[0][1], r[1][1], r[2][1]],
            [r[0][2], r[1][2], r[2][2]],
        ],
    );
    assert!((rtr[0][0] - 1.0).abs() < 1e-12 && rtr[0][1].abs() < 1e-12);
}

#[test]
fn two_elastic_spheres_colliding_conserve_momentum() {
    let text = scene(
        "gravity = [0, 0, 0]",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [3, 0, 0]\n\
         shape = { type = \"sphere\", center = [-0.06, 0.0, 0.0], radius = 0.05 }\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [-1, 0.2, 0]\n\
         shape = { type = \"sphere\", center = [0.06, 0.01, 0.0], radius = 0.05 }\n",
    );
    let mut p = prepared(&text);
    let before = mpm(&p.world).momentum();
    let steps = (0.03 / p.world.dt) as usize;
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let m = mpm(&p.world);
    let after = m.momentum();
    let error = norm([0, 1, 2].map(|a| after[a] - before[a])) / norm(before);
    eprintln!(
        "{} particles, {steps} steps: momentum {before:?} → {after:?}, relative change {error:.2e}",
        m.particles.len()
    );
    assert!(error < 1e-6);
    // They met: the first sphere slowed down.
    let body0: Vec<usize> = (0..m.particles.len())
        .filter(|&i| m.particles.body[i] == 0)
        .collect();
    let vx: f64 = body0
        .iter()
        .map(|&i| m.particles.velocity[i][0])
        .sum::<f64>()
        / body0.len() as f64;
    assert!(vx < 2.5, "mean x velocity of the first sphere {vx}");
}

#[test]
fn a_free_spinning_body_keeps_its_angular_momentum() {
    let text = scene(
        "gravity = [0, 0, 0]",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"stiff\"\nresolution = 0.02\n\
         angular_velocity = [1, 2, 3]\nvelocity = [0.1, 0, 0]\n\
         shape = { type = \"box\", center = [0.02, 0.03, -0.01], size = [0.1, 0.06, 0.04] }\n",
    );
    let mut p = prepared(&text);
    let before = mpm(&p.world).angular_momentum();
    for _ in 0..1000 {
        p.world.step().expect("steps");
    }
    let after = mpm(&p.world).angular_momentum();
    let error = norm([0, 1, 2].map(|a| after[a] - before[a])) / norm(before);
    eprintln!("1000 steps: angular momentum {before:?} → {after:?}, relative change {error:.2e}");
    assert!(error < 1e-6);
}

#[test]
fn a_block_rests_on_the_ground() {
    let text = scene(
        "",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"stiff\"\nresolution = 0.02\n\
         shape = { type = \"box\", center = [0, 0.03, 0], size = [0.06, 0.06, 0.06] }\n\
         [[collider]]\ntype = \"ground\"\nfriction = 0.5\n",
    );
    let mut p = prepared(&text);
    let centroid = |w: &World| {
        let x = &mpm(w).particles.position;
        [0, 1, 2].map(|a| x.iter().map(|p| p[a]).sum::<f64>() / x.len() as f64)
    };
    // Let it settle under its weight, then hold still for 10⁴ steps.
    for _ in 0..500 {
        p.world.step().expect("no blow-up");
    }
    let start = centroid(&p.world);
    let steps = 10_000;
    for _ in 0..steps {
        p.world.step().expect("no blow-up");
    }
    let end = centroid(&p.world);
    let drift = norm([0, 1, 2].map(|a| end[a] - start[a]));
    let dx = mpm(&p.world).grid.dx;
    eprintln!(
        "{steps} steps of {:.3e} s: centroid drift {drift:.3e} m ({:.3}% of a cell)",
        p.world.dt,
        100.0 * drift / dx
    );
    assert!(drift < 0.01 * dx);
}

#[test]
fn twice_the_stable_step_is_caught_by_the_blowup_detector() {
    let body = "[[body]]\nmodel = \"mpm\"\nmaterial = \"stiff\"\nresolution = 0.02\n\
         shape = { type = \"box\", center = [0, 0.05, 0], size = [0.1, 0.1, 0.1] }\n\
         [[collider]]\ntype = \"ground\"\n";
    let stable = prepared(&scene("", body)).stable_dt.0;
    // One frame a second, so that the step is not shortened to fit a frame.
    let text = scene(&format!("dt = {:e}\nforce_dt = true", 2.0 * stable), body)
        .replace("fps = 1000", "fps = 1");
    let mut p = prepared(&text);
    let caught = (0..20_000).find_map(|_| p.world.step().err());
    assert!(
        matches!(caught, Some(SimError::BlowUp { .. })),
        "{caught:?}"
    );
}

/// The world's checkpoint bytes (its whole state).
pub(super) fn state_bytes(world: &World) -> Vec<u8> {
    let mut out = Encoder::new();
    world.save(&mut out);
    out.finish()
}

/// Runs `run` in a pool of one thread, then in a pool of two, and asserts that both
/// runs give the same bytes.
pub(super) fn same_bytes_on_one_and_two_threads(run: impl Fn() -> Vec<u8> + Sync) {
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(&run)
    };
    assert!(on(1) == on(2), "the thread count changed the state");
}

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let text = scene(
        "",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [0, -2, 0]\n\
         shape = { type = \"sphere\", center = [0, 0.08, 0], radius = 0.06 }\n\
         [[collider]]\ntype = \"ground\"\n",
    );
    same_bytes_on_one_and_two_threads(|| {
        let mut p = prepared(&text);
        for _ in 0..100 {
            p.world.step().expect("steps");
        }
        state_bytes(&p.world)
    });
}

/// The plastic projections (Johnson–Cook with the rate and thermal terms, snow,
/// Drucker–Prager) give the same bytes on one thread and two: three balls, one of
/// each, land on the ground and flow (each body's ε^p grows, so every projection runs).
#[test]
fn plastic_flows_give_the_same_bytes_on_one_and_two_threads() {
    let materials = [
        "type = \"johnson-cook\", yield_stress = 2e3, hardening = 1e4, exponent = 0.5, \
         rate_coefficient = 0.05, melting_temperature = 400, room_temperature = 300, \
         thermal_exponent = 1, specific_heat = 1",
        "type = \"snow\", critical_compression = 0.025, critical_stretch = 0.0075",
        "type = \"drucker-prager\", friction_angle = 30",
    ];
    let mut text = String::from("[scene]\nduration = 1.0\nfps = 1000\n");
    for (k, plasticity) in materials.iter().enumerate() {
        text += &format!(
            "[materials.m{k}]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.3\n\
             [materials.m{k}.mpm]\nplasticity = {{ {plasticity} }}\n\
             [[body]]\nmodel = \"mpm\"\nmaterial = \"m{k}\"\nresolution = 0.02\nvelocity = [0, -3, 0]\n\
             shape = {{ type = \"sphere\", center = [{}, 0.07, 0], radius = 0.06 }}\n",
            0.15 * k as f64
        );
    }
    text += "[[collider]]\ntype = \"ground\"\n";
    text += OUTPUT;
    same_bytes_on_one_and_two_threads(|| {
        let mut p = prepared(&text);
        for _ in 0..100 {
            p.world.step().expect("steps");
        }
        let m = mpm(&p.world);
        for body in 0..3 {
            let flowed = (0..m.particles.len())
                .filter(|&i| m.particles.body[i] as usize == body && m.particles.plastic[i] > 0.0)
                .count();
            assert!(flowed > 0, "no particle of body {body} flowed");
        }
        state_bytes(&p.world)
    });
}

#[test]
fn a_bar_rings_at_its_first_axial_frequency() {
    // A free–free bar with ν = 0 (λ = 0: the 1D wave speed c = √(E/ρ)), first mode
    // u = cos(πx/L), f = c/(2L).
    let (length, e, rho): (f64, f64, f64) = (0.4, 1e6, 1000.0);
    let text = format!(
        "[scene]\nduration = 1.0\nfps = 1000\ngravity = [0, 0, 0]\n\
         [materials.bar]\ndensity = {rho}\nyoungs_modulus = {e}\npoisson_ratio = 0\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"bar\"\nresolution = 0.02\nvelocity = [1e-3, 0, 0]\n\
         shape = {{ type = \"box\", center = [{}, 0, 0], size = [{length}, 0.04, 0.04] }}\n{OUTPUT}",
        length / 2.0
    );
    // The body's initial 1 mm/s sets the blow-up detector's energy budget; the
    // velocities are then replaced by the mode's.
    let mut p = prepared(&text);
    let amplitude = 1e-3;
    {
        let m = p.world.model_mut::<Mpm>().expect("an MPM model");
        let k = std::f64::consts::PI / length;
        for (x, v) in m.particles.position.iter().zip(&mut m.particles.velocity) {
            v[0] = amplitude * (k * x[0]).cos();
        }
    }
    let modal = |w: &World| {
        let m = mpm(w);
        let k = std::f64::consts::PI / length;
        m.particles
            .position
            .iter()
            .zip(&m.particles.velocity)
            .map(|(x, v)| v[0] * (k * x[0]).cos())
            .sum::<f64>()
    };
    let dt = p.world.dt;
    let mut crossings = Vec::new();
    let mut last = modal(&p.world);
    for step in 1..=2000 {
        p.world.step().expect("steps");
        let now = modal(&p.world);
        if last.signum() != now.signum() {
            // Linear interpolation of the zero crossing.
            crossings.push(dt * (step as f64 - 1.0 + last / (last - now)));
        }
        last = now;
        if crossings.len() == 5 {
            break;
        }
    }
    assert_eq!(crossings.len(), 5, "the bar rings");
    let period = (crossings[4] - crossings[0]) / 2.0;
    let analytic = 2.0 * length / (e / rho).sqrt();
    let error = (period - analytic).abs() / analytic;
    eprintln!(
        "period {period:.5e} s, analytic {analytic:.5e} s, error {:.2}%",
        100.0 * error
    );
    assert!(error < 0.05);
}

#[test]
fn a_fast_projectile_carries_its_grid_along() {
    let text = format!(
        "[scene]\nduration = 1.0\nfps = 1000\ngravity = [0, 0, 0]\n\
         [materials.lead]\ndensity = 11000\nyoungs_modulus = 1e8\npoisson_ratio = 0.3\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"lead\"\nresolution = 0.005\nvelocity = [500, 0, 0]\n\
         shape = {{ type = \"sphere\", center = [0, 0, 0], radius = 0.01 }}\n{OUTPUT}"
    );
    let mut p = prepared(&text);
    p.world.step().expect("steps");
    let start = mpm(&p.world).grid.memory_bytes();
    let start_blocks = mpm(&p.world).grid.block_count();
    let steps = (1.0 / (500.0 * p.world.dt)) as usize;
    for _ in 0..steps {
        p.world.step().expect("steps");
    }
    let m = mpm(&p.world);
    let end = m.grid.memory_bytes();
    let travelled =
        m.particles.position.iter().map(|x| x[0]).sum::<f64>() / m.particles.len() as f64;
    eprintln!(
        "{} particles, {steps} steps, {travelled:.3} m: grid {start} B ({start_blocks} blocks) at the start, {end} B ({} blocks) at the end",
        m.particles.len(),
        m.grid.block_count()
    );
    assert!(travelled > 0.99);
    assert!((end as f64) < 2.0 * start as f64 && (start as f64) < 2.0 * end as f64);
}

#[test]
fn pic_flip_transfer_moves_and_conserves_momentum() {
    let text = scene(
        "gravity = [0, 0, 0]",
        "[[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [3, 0, 0]\n\
         shape = { type = \"sphere\", center = [-0.06, 0.0, 0.0], radius = 0.05 }\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"soft\"\nresolution = 0.02\nvelocity = [-1, 0, 0]\n\
         shape = { type = \"sphere\", center = [0.06, 0.0, 0.0], radius = 0.05 }\n\
         [mpm]\ntransfer = \"pic-flip\"\nflip_ratio = 0.9\n",
    );
    let mut p = prepared(&text);
    assert_eq!(
        mpm(&p.world).transfer,
        Transfer::PicFlip { flip_ratio: 0.9 }
    );
    let before = mpm(&p.world).momentum();
    for _ in 0..(0.02 / p.world.dt) as usize {
        p.world.step().expect("steps");
    }
    let after = mpm(&p.world).momentum();
    let error = norm([0, 1, 2].map(|a| after[a] - before[a])) / norm(before);
    assert!(error < 1e-6, "{error:e}");
}
