//! The best-fit rigid motion of a fragment's points: the mass, centre, momenta and
//! inertia a rigid body takes over at the switch (module doc of [`super`]).

use rapier3d_f64::na::{Matrix3, Vector3};

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
}

/// The best-fit rigid motion of `points` (module doc).
pub(super) fn fit(part: &Part, points: &[u32]) -> Fit {
    let p = part.model.points();
    let volume = part.model.contact_points().map(|c| c.volume);
    let mut mass = 0.0;
    let mut moment = [0.0; 3];
    let mut momentum = [0.0; 3];
    let mut kinetic = 0.0;
    for &i in points {
        let (m, x, v) = (
            p.mass[i as usize],
            p.position[i as usize],
            p.velocity[i as usize],
        );
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
    for &i in points {
        let (m, x, v) = (
            p.mass[i as usize],
            p.position[i as usize],
            p.velocity[i as usize],
        );
        let r = Vector3::new(x[0] - center[0], x[1] - center[1], x[2] - center[2]);
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
    }
}
