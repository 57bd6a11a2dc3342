//! Initial cracks (`[[body.crack]]`): bonds of a body that cross the crack plane inside
//! the crack's region are cut before the run starts.

use perifrac_math::{add, dot, scale, sub};

use super::PdModel;
use crate::error::{Result, SimError};
use crate::geometry::shape::to_sdf;
use crate::scene::Scene;

/// Cuts every bond of the scene's initial cracks: a bond i→j of body b is cut when i
/// and j lie on opposite sides of the crack plane and the bond's midpoint is inside
/// the crack's region (a primitive, CSG shape or closed mesh file).
pub fn cut_initial_cracks(model: &mut PdModel, scene: &Scene) -> Result<()> {
    for (b, spec) in scene.bodies.iter().enumerate() {
        for (k, crack) in spec.cracks.iter().enumerate() {
            let region =
                to_sdf(&crack.region, &scene.base_dir).map_err(|message| SimError::Mesh {
                    body: spec.name.clone(),
                    message: format!("crack {} region: {message}", k + 1),
                })?;
            let (p, n) = (crack.point, crack.normal);
            let side = |x: [f64; 3]| dot(sub(x, p), n);
            let body = model.reference.body.clone();
            let x = model.reference.position.clone();
            model.cut_bonds(|i, j| {
                let (xi, xj) = (x[i], x[j]);
                let mid = scale(add(xi, xj), 0.5);
                body[i] == b as u32 && side(xi) * side(xj) < 0.0 && region.distance(mid) <= 0.0
            });
        }
    }
    Ok(())
}
