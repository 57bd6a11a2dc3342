//! The best-fit rigid motion of a fragment's points: the mass, centre, momenta and
//! inertia a rigid body takes over at the switch (module doc of [`super`]).

use rapier3d_f64::na::{Matrix3, Vector3};

use perifrac_math::rigid_fit;

use super::{array, vector};
use crate::world::Part;

/// What a look at the fragments found of one fragment.
pub(super) struct Fit {
    /// Mass (kg), centre of mass, velocity V = P/M and spin ω = I⁻¹L.
    pub(super) mass: f64,
    pub(super) center: [f64; 3],
    pub(super) velocity: [f64; 3],
    pub(super) spin: [f64; 3],
    pub(super) inertia: Matrix3<f64>,
    /// Kinetic energy of the motion relative to the rigid fit (J).
    pub(super) relative: f64,
    /// Kinetic energy (J).
    pub(super) kinetic: f64,
    /// Twice the largest distance of a point from the centre (m).
    pub(super) size: f64,
    /// The points' mean spacing, V̄^{1/3} (m).
    pub(super) spacing: f64,
}

impl Fit {
    /// The amplitude of the motion relative to the rigid fit, in spacings: its r.m.s.
    /// speed over the angular frequency of the piece's fundamental, π c_p / L (a free
    /// piece of size L rings with period 2L/c_p).
    pub(super) fn amplitude(&self, wave_speed: f64) -> f64 {
        let speed = (2.0 * self.relative / self.mass).sqrt();
        speed * self.size / (std::f64::consts::PI * wave_speed) / self.spacing
    }
}

/// The best-fit rigid motion of `points` (module doc).
pub(super) fn fit(part: &Part, points: &[u32]) -> Fit {
    let p = part.model.points();
    let volume = part.model.contact_points().map(|c| c.volume);
    let mut mass = 0.0;
    let mut moment = [0.0; 3];
    let mut momentum = [0.0; 3];
    let mut kinetic = 0.0;
    let point = |i: u32| {
        let i = i as usize;
        (p.mass[i], p.position[i], p.velocity[i])
    };
    for &i in points {
        let (m, x, v) = point(i);
        mass += m;
        for k in 0..3 {
            moment[k] += m * x[k];
            momentum[k] += m * v[k];
        }
        kinetic += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    let center = moment.map(|s| s / mass);
    let velocity = momentum.map(|s| s / mass);
    let mut angular = Vector3::zeros();
    let mut inertia = Matrix3::zeros();
    let mut reach = 0.0f64;
    let mut spacing = 0.0;
    for &i in points {
        let (m, x, v) = point(i);
        let r = Vector3::new(x[0] - center[0], x[1] - center[1], x[2] - center[2]);
        reach = reach.max(r.norm());
        spacing += volume.map_or(0.0, |v| v[i as usize].cbrt().max(1e-9));
        angular += m * r.cross(&vector(v));
        inertia += m * (Matrix3::identity() * r.norm_squared() - r * r.transpose());
        if points.len() < 4 {
            // A point's own inertia, as a cube of its volume: m l²/6.
            let l2 = volume.map_or(0.0, |v| v[i as usize].cbrt().powi(2));
            inertia += Matrix3::identity() * (m * l2 / 6.0);
        }
    }
    let spin = inertia
        .try_inverse()
        .map_or(Vector3::zeros(), |inv| inv * angular);
    let rigid = 0.5 * mass * (velocity[0].powi(2) + velocity[1].powi(2) + velocity[2].powi(2))
        + 0.5 * spin.dot(&(inertia * spin));
    Fit {
        mass,
        center,
        velocity,
        spin: array(&spin),
        inertia,
        relative: (kinetic - rigid).max(0.0),
        kinetic,
        size: 2.0 * reach,
        spacing: (spacing / points.len() as f64).max(1e-9),
    }
}

/// Where `points` were in the reference configuration and how the piece has turned
/// since: their mass-weighted reference centre X̄ and the rotation R of their best-fit
/// rigid motion X ↦ c + R(X − X̄) ([`rigid_fit`], Kabsch). A reference point X of the
/// piece is at R(X − X̄) in the body frame (identity orientation at the switch). `None`
/// for points without mass.
pub(super) fn reference_pose(part: &Part, points: &[u32]) -> Option<([f64; 3], [[f64; 3]; 3])> {
    let p = part.model.points();
    let fit = rigid_fit(points.iter().map(|&i| {
        let i = i as usize;
        (p.mass[i], p.reference[i], p.position[i])
    }))?;
    Some((fit.rest, fit.rotation))
}
