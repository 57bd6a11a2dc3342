//! The angle a crack leaves a notch at, read from the bonds that broke (issue 33,
//! item 7): the Kalthoff–Winkler plate (`assets/scenes/kalthoff-winkler.toml`, after
//! Silling 2003) and `perifrac bench accuracy`'s crack-angle table.
//!
//! A crack is where bonds broke. For a notch whose tip is at `tip` in the plane z = 0
//! and whose crack runs into x > tip.x on the side `side · y > side · tip.y`, the
//! reference midpoints of the bonds that broke during the run (not those cut at
//! set-up) between 2δ and `reach` from the tip give the angle: their median polar
//! angle about the tip, from +x toward the side (the damaged band is widest near the
//! tip, where a least-squares line leans on it), the medians of three equal shells of
//! that range, and the principal axis of their second moments about the tip.

use crate::error::{Result, SimError};
use crate::family::{BROKEN, INDEX};
use crate::run;
use crate::scene::{CrackSpec, LatticeOrientation, Scene, ShapeSpec};
use crate::world::World;

/// The notches of `assets/scenes/kalthoff-winkler.toml`: tips at (50 mm, ±25 mm), each
/// crack running away from the centreline.
pub const KALTHOFF_WINKLER_NOTCHES: [Notch; 2] = [
    Notch {
        tip: [0.05, 0.025],
        side: 1.0,
    },
    Notch {
        tip: [0.05, -0.025],
        side: -1.0,
    },
];

/// How far from a Kalthoff–Winkler notch tip its crack is read (m).
pub const KALTHOFF_WINKLER_REACH: f64 = 0.045;

/// How a variant of the Kalthoff–Winkler plate cuts its notches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NotchCut {
    /// As the experiment: 1.5 mm slots cut out of the plate (the scene as shipped).
    Slots,
    /// Zero-width pre-cuts: the plate a plain box, the bonds across each notch's
    /// plane cut at set-up (`[[body.crack]]`).
    ZeroWidth,
}

/// The Kalthoff–Winkler scene `base` (`assets/scenes/kalthoff-winkler.toml`) at
/// spacing `lambda`, its critical stretch scaled as Silling & Askari 2005's
/// s₀ = √(5G/(9κδ)) ∝ δ^{-1/2}, with `cut` notches on `lattice`.
pub fn kalthoff_winkler_variant(
    base: &Scene,
    lambda: f64,
    cut: NotchCut,
    lattice: LatticeOrientation,
) -> Result<Scene> {
    let refuse = |what: &str| {
        SimError::Refused(format!(
            "scene '{}': {what}: not the Kalthoff–Winkler plate of \
             assets/scenes/kalthoff-winkler.toml",
            base.scene.name
        ))
    };
    let mut scene = base.clone();
    let body = scene.bodies.first_mut().ok_or_else(|| refuse("no body"))?;
    let scale = (body.resolution / lambda).sqrt();
    body.resolution = lambda;
    body.lattice = Some(lattice);
    if cut == NotchCut::ZeroWidth {
        let ShapeSpec::Difference { base: plate, .. } = &body.shape else {
            return Err(refuse(
                "the plate is not a `difference` (a box minus its notches)",
            ));
        };
        body.shape = (**plate).clone();
        for notch in KALTHOFF_WINKLER_NOTCHES {
            let y = notch.tip[1];
            body.cracks.push(CrackSpec {
                point: [0.0, y, 0.0],
                normal: [0.0, 1.0, 0.0],
                region: ShapeSpec::Box {
                    center: [0.5 * notch.tip[0], y, 0.0],
                    size: [notch.tip[0], 0.01, 0.02],
                },
            });
        }
    }
    let material = body.material.clone();
    let stretch = scene
        .materials
        .get_mut(&material)
        .and_then(|m| m.critical_stretch.as_mut())
        .ok_or_else(|| refuse("the plate's material has no critical_stretch"))?;
    *stretch *= scale;
    Ok(scene)
}

/// A notch whose crack is read: its tip (x, y) and the side (+1 or −1 in y) the crack
/// runs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Notch {
    /// The notch's tip in the plate's plane (m).
    pub tip: [f64; 2],
    /// +1: the crack runs toward larger y; −1: toward smaller.
    pub side: f64,
}

/// The reference midpoints (x, y) of the bonds of the first body that broke during a
/// run, and that body's horizon δ.
#[derive(Debug, Clone)]
pub struct Broken {
    /// Midpoints of the bonds that broke during the run (m).
    pub midpoints: Vec<[f64; 2]>,
    /// The body's horizon δ (m).
    pub delta: f64,
    /// The body's particles.
    pub points: usize,
}

/// A crack's angle from its notch, in degrees from +x toward the notch's side.
#[derive(Debug, Clone, PartialEq)]
pub struct CrackAngle {
    /// The median polar angle of the broken bonds 2δ to the reach from the tip.
    pub median: f64,
    /// The medians of three equal shells from the tip to the reach (NaN where a shell
    /// holds no broken bond); the first starts at 2δ.
    pub shells: [f64; 3],
    /// The principal axis of the broken bonds' second moments about the tip.
    pub axis: f64,
    /// How many broken bonds the angle is read from.
    pub bonds: usize,
}

/// Runs `scene` to its end (the first body peridynamic) and returns the bonds that
/// broke during the run. `each_step(world, step)` is called after every step (for
/// diagnostics such as where contact acted).
pub fn broken_during_run(
    scene: &Scene,
    mut each_step: impl FnMut(&World, usize),
) -> Result<Broken> {
    let delta = scene
        .bodies
        .first()
        .ok_or_else(|| {
            SimError::Refused(format!(
                "scene '{}': no body to read cracks from (add a [[body]])",
                scene.scene.name
            ))
        })?
        .delta();
    let mut p = run::prepare(scene)?;
    let steps = p.steps_per_frame * scene.frame_count();
    let broken_at_setup = broken_flags(&p.world);
    for step in 0..steps {
        p.world.step()?;
        each_step(&p.world, step);
    }
    let model = p.world.parts[0].model.as_ref();
    let x = model.points().reference;
    let mut midpoints = Vec::new();
    if let Some(bonds) = model.contact_points().and_then(|c| c.bonds) {
        for (i, xi) in x.iter().enumerate() {
            for k in bonds.range(i) {
                let n = bonds.neighbours[k];
                if n & BROKEN == 0 || broken_at_setup[k] {
                    continue;
                }
                let xj = x[(n & INDEX) as usize];
                midpoints.push([0.5 * (xi[0] + xj[0]), 0.5 * (xi[1] + xj[1])]);
            }
        }
    }
    Ok(Broken {
        midpoints,
        delta,
        points: x.len(),
    })
}

/// Which bonds of the first body are broken now (empty if it has none).
fn broken_flags(world: &World) -> Vec<bool> {
    let model = world.parts[0].model.as_ref();
    model
        .contact_points()
        .and_then(|c| c.bonds)
        .map(|b| b.neighbours.iter().map(|&n| n & BROKEN != 0).collect())
        .unwrap_or_default()
}

/// The angle of the crack from `notch`, read from the broken bonds 2δ to `reach` from
/// its tip (module docs).
pub fn crack_angle(broken: &Broken, notch: Notch, reach: f64) -> CrackAngle {
    let polar: Vec<(f64, f64)> = broken
        .midpoints
        .iter()
        .filter_map(|m| {
            let (dx, dy) = (m[0] - notch.tip[0], notch.side * (m[1] - notch.tip[1]));
            let r = dx.hypot(dy);
            (dx >= -broken.delta && dy >= 0.0 && r >= 2.0 * broken.delta && r <= reach)
                .then(|| (r, dy.atan2(dx).to_degrees()))
        })
        .collect();
    let median = |lo: f64, hi: f64| {
        let mut a: Vec<f64> = polar
            .iter()
            .filter(|p| p.0 >= lo && p.0 < hi)
            .map(|p| p.1)
            .collect();
        a.sort_by(f64::total_cmp);
        a.get(a.len() / 2).copied().unwrap_or(f64::NAN)
    };
    let (sxx, sxy, syy) = polar.iter().fold((0.0, 0.0, 0.0), |(a, b, c), &(r, t)| {
        let (dx, dy) = (r * t.to_radians().cos(), r * t.to_radians().sin());
        (a + dx * dx, b + dx * dy, c + dy * dy)
    });
    let third = reach / 3.0;
    CrackAngle {
        median: median(0.0, f64::INFINITY),
        shells: [
            median(0.0, third),
            median(third, 2.0 * third),
            median(2.0 * third, f64::INFINITY),
        ],
        axis: (0.5 * (2.0 * sxy).atan2(sxx - syy)).to_degrees(),
        bonds: polar.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bonds broken along a line at 70° from a tip, and a few scattered on the other
    /// side and behind it, read back at 70°.
    #[test]
    fn a_straight_crack_reads_at_its_angle() {
        let tip = [0.05, 0.025];
        let angle = 70f64.to_radians();
        let mut midpoints: Vec<[f64; 2]> = (0..100)
            .map(|k| {
                let r = 0.001 * f64::from(k) * 0.5;
                [tip[0] + r * angle.cos(), tip[1] + r * angle.sin()]
            })
            .collect();
        // The other side of the notch's line and behind the tip: not this crack.
        midpoints.push([0.07, 0.02]);
        midpoints.push([0.03, 0.04]);
        let broken = Broken {
            midpoints,
            delta: 0.0019,
            points: 0,
        };
        let a = crack_angle(&broken, Notch { tip, side: 1.0 }, 0.0452);
        assert!((a.median - 70.0).abs() < 1e-9, "{a:?}");
        assert!((a.axis - 70.0).abs() < 1e-9, "{a:?}");
        assert!(a.shells.iter().all(|s| (s - 70.0).abs() < 1e-9), "{a:?}");
        // 2δ = 3.8 mm to 45.2 mm: r = 4.0, 4.5, … 45.0 mm.
        assert_eq!(a.bonds, 83);
        // Read from the lower side, mirrored: nothing there.
        let below = crack_angle(&broken, Notch { tip, side: -1.0 }, 0.0452);
        assert_eq!(below.bonds, 1);
    }
}
