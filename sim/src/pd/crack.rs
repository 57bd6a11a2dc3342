//! Initial cracks (`[[body.crack]]`) in a peridynamic body: bonds that cross the crack
//! plane inside the crack's region ([`Cracks`]) are cut before the run starts.

use super::PdModel;
use crate::error::Result;
use crate::family::Cracks;
use crate::scene::Scene;

/// Cuts every bond of the scene's initial cracks (see [`Cracks::cuts`]).
pub fn cut_initial_cracks(model: &mut PdModel, scene: &Scene) -> Result<()> {
    let cracks = Cracks::of_scene(scene)?;
    if cracks.is_empty() {
        return Ok(());
    }
    let body = model.reference.body.clone();
    let x = model.reference.position.clone();
    model.cut_bonds(|i, j| cracks.cuts(body[i], x[i], x[j]));
    Ok(())
}
