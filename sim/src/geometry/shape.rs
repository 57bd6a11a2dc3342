//! Scene shapes as signed distance functions.

use super::sdf::{Ball, Cuboid, Cylinder, Difference, Sdf, Union};
use crate::scene::ShapeSpec;

/// The signed distance function of a primitive or CSG shape; `None` for a mesh file
/// (meshes are read by the mesh loader, not here).
pub fn to_sdf(shape: &ShapeSpec) -> Option<Box<dyn Sdf>> {
    Some(match shape {
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
        ShapeSpec::Union { parts } => {
            Box::new(Union(parts.iter().map(to_sdf).collect::<Option<Vec<_>>>()?))
        }
        ShapeSpec::Difference { base, minus } => {
            Box::new(Difference(to_sdf(base)?, to_sdf(minus)?))
        }
        ShapeSpec::Mesh { .. } => return None,
    })
}
