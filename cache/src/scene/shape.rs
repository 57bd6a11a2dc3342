//! Shapes of bodies, regions and colliders: primitives, CSG and closed triangle meshes,
//! with a mesh's placement (scale, rotation, up axis).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// A shape given by a signed distance function, or a CSG combination of shapes.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeSpec {
    /// Axis-aligned box: centre and full size in m.
    Box {
        /// Centre.
        center: [f64; 3],
        /// Full extents along x, y, z.
        size: [f64; 3],
    },
    /// A thin axis-aligned slab (a box; named for intent). Its thinnest side must be at
    /// least about 1.5 resolutions.
    Slab {
        /// Centre.
        center: [f64; 3],
        /// Full extents along x, y, z.
        size: [f64; 3],
    },
    /// Sphere.
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// Capped cylinder along a coordinate axis.
    Cylinder {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
        /// Full height along `axis`.
        height: f64,
        /// `"x"`, `"y"` or `"z"`. Default `"y"`.
        #[serde(default)]
        axis: Axis,
    },
    /// Union of shapes.
    Union {
        /// The parts.
        parts: Vec<ShapeSpec>,
    },
    /// `base` minus `minus` (notches, holes).
    Difference {
        /// The shape to cut from.
        base: Box<ShapeSpec>,
        /// The shape removed.
        minus: Box<ShapeSpec>,
    },
    /// A closed triangle mesh file, relative to the scene file, placed by
    /// `p ↦ R (scale ⊙ p) + translation`.
    Mesh {
        /// The mesh file (`.obj`, `.ply`, `.gltf`, `.glb`).
        path: PathBuf,
        /// Scale: one factor or one per axis `[x, y, z]`, applied first. Default 1.
        #[serde(default)]
        scale: MeshScale,
        /// Rotation in degrees about x, then y, then z (fixed axes; R = Rz Ry Rx).
        /// Default 0.
        #[serde(default)]
        rotation: [f64; 3],
        /// Translation in m, applied last. Default 0.
        #[serde(default)]
        translation: [f64; 3],
    },
}

impl ShapeSpec {
    /// Makes every mesh path in this shape absolute: `base` joined with it,
    /// canonicalized where the file exists.
    pub(super) fn resolve_mesh_paths(&mut self, base: &Path) {
        match self {
            ShapeSpec::Mesh { path, .. } => {
                let joined = base.join(&*path);
                *path = std::fs::canonicalize(&joined)
                    .or_else(|_| std::path::absolute(&joined))
                    .unwrap_or(joined);
            }
            ShapeSpec::Union { parts } => {
                for part in parts {
                    part.resolve_mesh_paths(base);
                }
            }
            ShapeSpec::Difference { base: b, minus } => {
                b.resolve_mesh_paths(base);
                minus.resolve_mesh_paths(base);
            }
            ShapeSpec::Box { .. }
            | ShapeSpec::Slab { .. }
            | ShapeSpec::Sphere { .. }
            | ShapeSpec::Cylinder { .. } => {}
        }
    }
}

/// The scale of a mesh shape: uniform or per axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum MeshScale {
    /// The same factor on every axis.
    Uniform(f64),
    /// One factor per axis (negative factors mirror).
    PerAxis([f64; 3]),
}

impl Default for MeshScale {
    fn default() -> Self {
        MeshScale::Uniform(1.0)
    }
}

impl MeshScale {
    /// The factor on each axis.
    pub fn factors(self) -> [f64; 3] {
        match self {
            MeshScale::Uniform(s) => [s; 3],
            MeshScale::PerAxis(s) => s,
        }
    }
}

/// A coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// x.
    X,
    /// y.
    #[default]
    Y,
    /// z.
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}
