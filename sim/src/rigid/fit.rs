//! The best-fit rigid motion of a fragment's points: the mass, centre, momenta and
//! inertia a rigid body takes over at the switch (module doc of [`super`]).

use rapier3d_f64::na::{Matrix3, Point3, Vector3};
use rapier3d_f64::prelude::MassProperties;

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

/// The inertia tensor about the origin of the solid that the closed, outward-wound
/// surface `vertices`/`triangles` bounds, at the uniform density that gives it
/// `mass` (parry's polyhedral mass properties, moved to the origin by the parallel
/// axis theorem). `None` for a surface that bounds no volume.
pub(super) fn solid_inertia(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    mass: f64,
) -> Option<Matrix3<f64>> {
    let points: Vec<Point3<f64>> = vertices.iter().map(|&v| Point3::from(vector(v))).collect();
    let unit = MassProperties::from_trimesh(1.0, &points, triangles);
    let volume = unit.mass();
    if !(volume.is_finite() && volume > 0.0) {
        return None;
    }
    let scale = mass / volume;
    let d = unit.local_com.coords;
    let about_centre = unit.reconstruct_inertia_matrix() * scale;
    Some(about_centre + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * mass)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed, outward-wound surface of the tet (0,0,0), (a,0,0), (0,b,0), (0,0,c).
    fn tet(a: f64, b: f64, c: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let vertices = vec![[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
        let triangles = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        (vertices, triangles)
    }

    #[test]
    fn a_sliver_turns_as_its_solid_not_as_a_cube_of_its_volume() {
        // A flat tet 4 cm × 4 cm × 0.1 mm (the meshes' slivers): its points' inertia
        // as a cube of its volume (m l²/6, l = V^{1/3}) is a hundredth of its own.
        let (a, b, c) = (0.04, 0.04, 1e-4);
        let (vertices, triangles) = tet(a, b, c);
        let mass = 2200.0 * a * b * c / 6.0;
        let inertia = solid_inertia(&vertices, &triangles, mass).expect("a solid");
        // About the origin (a vertex): I_xx = m (b² + c²)/10 for this tet.
        let expected = mass * (b * b + c * c) / 10.0;
        assert!(
            (inertia[(0, 0)] / expected - 1.0).abs() < 1e-9,
            "{} against {expected}",
            inertia[(0, 0)]
        );
        let cube = mass * (a * b * c / 6.0f64).powf(2.0 / 3.0) / 6.0;
        println!(
            "I_xx {:.3e}, as a cube of its volume {cube:.3e}",
            inertia[(0, 0)]
        );
        assert!(inertia[(0, 0)] > 50.0 * cube);
        // A surface that bounds nothing has no inertia.
        assert!(solid_inertia(&vertices[..3], &triangles[..1], mass).is_none());
    }
}
