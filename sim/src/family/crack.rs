//! The scene's initial cracks (`[[body.crack]]`), for any model with bonds: which
//! bonds a crack plane cuts before the first step.

use perifrac_math::{add, dot, scale, sub};

use crate::error::{Result, SimError};
use crate::geometry::sdf::Sdf;
use crate::geometry::shape::to_sdf;
use crate::scene::Scene;

/// One crack: its body, a point on its plane, its normal and its region.
struct Crack {
    body: u32,
    point: [f64; 3],
    normal: [f64; 3],
    region: Box<dyn Sdf>,
}

/// The initial cracks of a scene, for any model with bonds: [`Cracks::cuts`] says
/// whether a bond of body b from x_i to x_j is cut.
pub struct Cracks {
    cracks: Vec<Crack>,
}

impl std::fmt::Debug for Cracks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Cracks({})", self.cracks.len())
    }
}

impl Cracks {
    /// Reads the crack regions of every body (a primitive, CSG shape or closed mesh
    /// file); an unreadable region names its body and crack.
    pub fn of_scene(scene: &Scene) -> Result<Cracks> {
        let mut cracks = Vec::new();
        for (b, spec) in scene.bodies.iter().enumerate() {
            for (k, crack) in spec.cracks.iter().enumerate() {
                let region =
                    to_sdf(&crack.region, &scene.base_dir).map_err(|message| SimError::Mesh {
                        body: spec.name.clone(),
                        message: format!("crack {} region: {message}", k + 1),
                    })?;
                cracks.push(Crack {
                    body: b as u32,
                    point: crack.point,
                    normal: crack.normal,
                    region,
                });
            }
        }
        Ok(Cracks { cracks })
    }

    /// Whether the scene has no initial crack.
    pub fn is_empty(&self) -> bool {
        self.cracks.is_empty()
    }

    /// Whether the bond of body `body` from `xi` to `xj` is cut: i and j lie on
    /// opposite sides of a crack plane of that body and the bond's midpoint is inside
    /// the crack's region.
    pub fn cuts(&self, body: u32, xi: [f64; 3], xj: [f64; 3]) -> bool {
        self.cracks.iter().any(|c| {
            let side = |x: [f64; 3]| dot(sub(x, c.point), c.normal);
            let mid = scale(add(xi, xj), 0.5);
            c.body == body && side(xi) * side(xj) < 0.0 && c.region.distance(mid) <= 0.0
        })
    }
}
