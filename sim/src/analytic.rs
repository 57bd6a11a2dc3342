//! Analytic figures of the validation scenes (issue 6): the first bending frequency of
//! a cantilever (Euler–Bernoulli) and the lateral contraction of a stretched beam
//! (Poisson ratio), measured from recorded runs.

use crate::accuracy::{Trajectory, record};
use crate::error::{Result, SimError};
use crate::material::Material;
use crate::scene::{Scene, ShapeSpec};

/// β₁L of the first bending mode of a clamped–free beam: the smallest root of
/// cos βL cosh βL = −1.
pub const CANTILEVER_BETA1_L: f64 = 1.875_104_068_711_961;

/// β₂L of the second bending mode of a clamped–free beam.
pub const CANTILEVER_BETA2_L: f64 = 4.694_091_132_974_175;

/// First bending frequency in Hz of a uniform Euler–Bernoulli cantilever of length
/// `length`, rectangular cross-section of `depth` in the bending direction, Young's
/// modulus `e` and density `rho`: f₁ = (β₁L)²/(2π) √(E I / (ρ A L⁴)), I/A = depth²/12.
pub fn euler_bernoulli_first_frequency(e: f64, rho: f64, depth: f64, length: f64) -> f64 {
    CANTILEVER_BETA1_L.powi(2) / (2.0 * std::f64::consts::PI)
        * (e * depth * depth / 12.0 / (rho * length.powi(4))).sqrt()
}

/// Mean displacement along `axis`, frame by frame, of the particles whose rest
/// position along `along` is within `tolerance` of the largest (the free end).
pub fn tip_displacement(
    trajectory: &Trajectory,
    along: usize,
    axis: usize,
    tolerance: f64,
) -> Vec<(f64, f64)> {
    let far = trajectory
        .rest
        .iter()
        .map(|p| p[along])
        .fold(f64::NEG_INFINITY, f64::max);
    let tip: Vec<usize> = (0..trajectory.rest.len())
        .filter(|&i| trajectory.rest[i][along] >= far - tolerance)
        .collect();
    trajectory
        .times
        .iter()
        .zip(&trajectory.frames)
        .map(|(&t, x)| {
            let u: f64 = tip
                .iter()
                .map(|&i| x[i][axis] - trajectory.rest[i][axis])
                .sum();
            (t, u / tip.len().max(1) as f64)
        })
        .collect()
}

/// Mean period of an oscillation about `centre` from the samples `(t, value)` taken at
/// `t > after`: the times of the crossings of `centre` (linearly interpolated between
/// samples) are half a period apart, so the period is 2 (t_last − t_first)/(n − 1).
/// `None` with fewer than three crossings (less than a full period).
pub fn period_from_crossings(samples: &[(f64, f64)], centre: f64, after: f64) -> Option<f64> {
    let crossings: Vec<f64> = samples
        .windows(2)
        .filter(|w| w[0].0 > after)
        .filter_map(|w| {
            let (a, b) = (w[0].1 - centre, w[1].1 - centre);
            ((a < 0.0) != (b < 0.0)).then(|| w[0].0 + (w[1].0 - w[0].0) * a / (a - b))
        })
        .collect();
    (crossings.len() >= 3).then(|| {
        2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
    })
}

/// Poisson ratio measured in `frame` of a beam stretched along `along`:
/// ν = −ε_lateral / ε_axial over the particles of the middle fifth of the beam
/// (away from the anchors), each strain the least-squares slope of the displacement
/// against the rest coordinate (ε_lateral the mean of the two lateral directions).
pub fn lateral_contraction(trajectory: &Trajectory, frame: usize, along: usize) -> f64 {
    let rest = &trajectory.rest;
    let x = &trajectory.frames[frame];
    let (lo, hi) = rest
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.min(p[along]), a.1.max(p[along]))
        });
    let mid = 0.5 * (lo + hi);
    let middle: Vec<usize> = (0..rest.len())
        .filter(|&i| (rest[i][along] - mid).abs() <= 0.1 * (hi - lo))
        .collect();
    let slope = |k: usize| {
        let n = middle.len() as f64;
        let c = middle.iter().map(|&i| rest[i][k]).sum::<f64>() / n;
        let uc = middle.iter().map(|&i| x[i][k] - rest[i][k]).sum::<f64>() / n;
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for &i in &middle {
            let dx = rest[i][k] - c;
            sxy += dx * (x[i][k] - rest[i][k] - uc);
            sxx += dx * dx;
        }
        sxy / sxx
    };
    let lateral: Vec<f64> = (0..3).filter(|&k| k != along).map(slope).collect();
    -0.5 * (lateral[0] + lateral[1]) / slope(along)
}

/// The first bending frequency of a released cantilever: measured and analytic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frequency {
    /// From the tip's crossings of its rest position after the release (Hz); `None`
    /// if the run shows less than a period.
    pub measured: Option<f64>,
    /// Euler–Bernoulli f₁ (Hz).
    pub euler_bernoulli: f64,
    /// Wall-clock seconds of the run.
    pub wall: f64,
}

/// Runs a cantilever-release scene (`assets/scenes/cantilever-release.toml`: the first
/// body a box along x clamped at its left end, bent along y by an anchor released at
/// its `until`; gravity only moves the centre of the oscillation) with its own model
/// and measures the first bending frequency from the tip's vertical motion after the
/// last release.
pub fn first_bending_frequency(scene: &Scene) -> Result<Frequency> {
    let invalid = |message: &str| {
        SimError::Refused(format!(
            "scene '{}': body 0: {message} (see assets/scenes/cantilever-release.toml)",
            scene.scene.name
        ))
    };
    let body = scene
        .bodies
        .first()
        .ok_or_else(|| invalid("a cantilever scene needs one body"))?;
    let ShapeSpec::Box { size, .. } = body.shape else {
        return Err(invalid("the cantilever must be a `box` along x"));
    };
    let material = Material::from_spec(
        scene
            .materials
            .get(&body.material)
            .ok_or_else(|| invalid("the body's material is not defined"))?,
    );
    let release = body
        .anchors
        .iter()
        .map(|a| a.until)
        .filter(|t| t.is_finite())
        .fold(0.0, f64::max);
    let euler_bernoulli = euler_bernoulli_first_frequency(
        material.youngs_modulus(),
        material.density,
        size[1],
        size[0],
    );
    let run = record(scene, scene.frame_count())?;
    let tip: Vec<(f64, f64)> = tip_displacement(&run.particles, 0, 1, 0.6 * body.resolution)
        .into_iter()
        .filter(|s| s.0 > release)
        .collect();
    // A centred moving average over the second mode's Euler–Bernoulli period
    // (β₂L = 4.6941) removes that mode without shifting the first one's phase.
    let window = ((CANTILEVER_BETA1_L / CANTILEVER_BETA2_L).powi(2) / euler_bernoulli
        * scene.scene.fps)
        .round() as usize
        / 2;
    let smooth: Vec<(f64, f64)> = (window..tip.len().saturating_sub(window))
        .map(|i| {
            let w = &tip[i - window..=i + window];
            (
                tip[i].0,
                w.iter().map(|s| s.1).sum::<f64>() / w.len() as f64,
            )
        })
        .collect();
    // The tip oscillates about the midpoint of its extremes.
    let (lo, hi) = smooth
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, s| {
            (a.0.min(s.1), a.1.max(s.1))
        });
    Ok(Frequency {
        measured: period_from_crossings(&smooth, 0.5 * (lo + hi), release).map(|p| 1.0 / p),
        euler_bernoulli,
        wall: run.wall,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_period_of_a_sampled_sine_is_recovered() {
        let f = 7.0;
        let samples: Vec<(f64, f64)> = (0..400)
            .map(|i| {
                let t = i as f64 / 300.0;
                (t, 0.3 + (2.0 * std::f64::consts::PI * f * t + 0.4).sin())
            })
            .collect();
        let period = period_from_crossings(&samples, 0.3, 0.1).expect("crossings");
        assert!((period * f - 1.0).abs() < 1e-3, "{period}");
    }

    #[test]
    fn a_uniaxially_stretched_block_gives_its_poisson_ratio() {
        let rest: Vec<[f64; 3]> = (0..1000)
            .map(|i| [(i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64])
            .collect();
        let strained = rest
            .iter()
            .map(|p| [1.01 * p[0], 0.997 * p[1] + 0.1, 0.997 * p[2]])
            .collect();
        let trajectory = Trajectory {
            rest,
            times: vec![0.0],
            frames: vec![strained],
        };
        assert!((lateral_contraction(&trajectory, 0, 0) - 0.3).abs() < 1e-9);
    }
}
