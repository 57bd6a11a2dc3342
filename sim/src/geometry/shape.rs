//! Scene shapes as signed distance functions: primitives, CSG, and mesh files (exact
//! signed distance to the closed surface, [`MeshSdf`]).

use std::path::Path;

use super::mesh::{MeshSdf, Placement, TriMesh};
use super::sdf::{Ball, Cuboid, Cylinder, Difference, Sdf, Union};
use crate::error::SimError;
use crate::scene::{Scene, ShapeSpec};

/// How a mesh file of a shape is placed in the scene.
pub fn placement(shape: &ShapeSpec) -> Option<Placement> {
    match shape {
        ShapeSpec::Mesh {
            scale,
            rotation,
            translation,
            ..
        } => Some(Placement {
            scale: scale.factors(),
            rotation_deg: *rotation,
            translation: *translation,
        }),
        _ => None,
    }
}

/// The signed distance function of a shape; mesh files (relative to `base_dir`) are
/// read and must be closed. The error says what is wrong with the file.
pub fn to_sdf(shape: &ShapeSpec, base_dir: &Path) -> Result<Box<dyn Sdf>, String> {
    Ok(match shape {
        ShapeSpec::Box { center, size } | ShapeSpec::Slab { center, size } => Box::new(Cuboid {
            center: *center,
            half_extents: [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0],
        }),
        ShapeSpec::Sphere { center, radius } => Box::new(Ball {
            center: *center,
            radius: *radius,
        }),
        ShapeSpec::Cylinder {
            center,
            radius,
            height,
            axis,
        } => Box::new(Cylinder {
            center: *center,
            axis: axis.index(),
            radius: *radius,
            half_height: height / 2.0,
        }),
        ShapeSpec::Union { parts } => Box::new(Union(
            parts
                .iter()
                .map(|p| to_sdf(p, base_dir))
                .collect::<Result<Vec<_>, _>>()?,
        )),
        ShapeSpec::Difference { base, minus } => Box::new(Difference(
            to_sdf(base, base_dir)?,
            to_sdf(minus, base_dir)?,
        )),
        ShapeSpec::Mesh { path, .. } => {
            let placement = placement(shape).unwrap_or_default();
            let surface =
                TriMesh::load(&base_dir.join(path), &placement).map_err(|e| e.to_string())?;
            Box::new(MeshSdf::new(&surface))
        }
    })
}

/// Whether the shape is certainly convex (a box, slab, sphere or cylinder), so that
/// every segment between two of its points stays inside it and bonds need no test
/// against the material ([`crate::family::Solid`]). Unions, differences and mesh
/// files count as not convex.
pub fn is_convex(shape: &ShapeSpec) -> bool {
    matches!(
        shape,
        ShapeSpec::Box { .. }
            | ShapeSpec::Slab { .. }
            | ShapeSpec::Sphere { .. }
            | ShapeSpec::Cylinder { .. }
    )
}

/// The signed distance of each body of `scene` that is not convex, whose bonds must
/// stay inside it ([`crate::family::Solid`], issue 13), and `None` for a convex one;
/// the error names the body.
///
/// # Errors
/// [`SimError::Mesh`] if a body's mesh file cannot be read.
pub fn bond_shapes(scene: &Scene) -> Result<Vec<Option<Box<dyn Sdf>>>, SimError> {
    scene
        .bodies
        .iter()
        .map(|b| {
            (!is_convex(&b.shape))
                .then(|| to_sdf(&b.shape, &scene.base_dir))
                .transpose()
                .map_err(|message| SimError::Mesh {
                    body: b.name.clone(),
                    message,
                })
        })
        .collect()
}
