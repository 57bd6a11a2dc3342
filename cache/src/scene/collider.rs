//! `[[collider]]` (rigid obstacles and projectiles, mesh colliders and their keyframes)
//! and `[contact]` (particle contact between bodies and fragments).

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::{MeshScale, ShapeSpec, default_true};

/// `[[collider]]`: a rigid obstacle or projectile.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ColliderSpec {
    /// An infinite ground plane y = `height`.
    Ground {
        /// Height of the plane. Default 0.
        #[serde(default)]
        height: f64,
        /// Coulomb friction coefficient. Default 0.5.
        #[serde(default = "default_friction")]
        friction: f64,
    },
    /// A rigid sphere: kinematic (moves at `velocity`) or, with a `mass`, dynamic.
    Sphere {
        /// Centre at t = 0.
        center: [f64; 3],
        /// Radius.
        radius: f64,
        /// Velocity at t = 0 in m/s. Default 0.
        #[serde(default)]
        velocity: [f64; 3],
        /// Mass in kg: the sphere is pushed back by what it hits. Default: kinematic.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mass: Option<f64>,
        /// Whether gravity acts on a dynamic collider. Default true.
        #[serde(default = "default_true")]
        gravity: bool,
        /// Coulomb friction coefficient. Default 0.2.
        #[serde(default = "default_collider_friction")]
        friction: f64,
    },
    /// A rigid axis-aligned box: kinematic or, with a `mass`, dynamic.
    Box {
        /// Centre at t = 0.
        center: [f64; 3],
        /// Full size.
        size: [f64; 3],
        /// Velocity at t = 0 in m/s. Default 0.
        #[serde(default)]
        velocity: [f64; 3],
        /// Mass in kg. Default: kinematic.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mass: Option<f64>,
        /// Whether gravity acts on a dynamic collider. Default true.
        #[serde(default = "default_true")]
        gravity: bool,
        /// Coulomb friction coefficient. Default 0.2.
        #[serde(default = "default_collider_friction")]
        friction: f64,
    },
    /// A rigid closed triangle mesh (a table, a floor with steps), static or moved
    /// rigidly by `keyframes` or a per-frame `transforms` file (never both).
    Mesh {
        /// The mesh file (`.obj`, `.ply`, `.gltf`, `.glb`), relative to the scene.
        path: PathBuf,
        /// Scale: one factor or one per axis, applied first. Default 1.
        #[serde(default)]
        scale: MeshScale,
        /// Placement rotation in degrees about x, then y, then z. Default 0.
        #[serde(default)]
        rotation: [f64; 3],
        /// Placement translation in m. Default 0.
        #[serde(default)]
        translation: [f64; 3],
        /// Centre of the keyframes' rotations. Default: the centre of the placed
        /// mesh's bounding box.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pivot: Option<[f64; 3]>,
        /// Poses at increasing times, interpolated (translation linearly, rotation
        /// by slerp) and held before the first and after the last. Default: static.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        keyframes: Vec<KeyframeSpec>,
        /// A text file of poses, one line an output frame from frame 1 (t = 0):
        /// `tx ty tz rx ry rz` (m, degrees, as a keyframe); `#` starts a comment.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        transforms: Option<PathBuf>,
        /// Coulomb friction coefficient. Default 0.5.
        #[serde(default = "default_friction")]
        friction: f64,
    },
}

impl ColliderSpec {
    /// The shape of a mesh collider's file as placed in the scene.
    pub fn mesh_shape(&self) -> Option<ShapeSpec> {
        match self {
            ColliderSpec::Mesh {
                path,
                scale,
                rotation,
                translation,
                ..
            } => Some(ShapeSpec::Mesh {
                path: path.clone(),
                scale: *scale,
                rotation: *rotation,
                translation: *translation,
            }),
            _ => None,
        }
    }
}

/// `[contact]`: contact between particles of different bodies and between unbonded
/// particles of one body (fragments, the faces of an initial crack); see
/// `docs/contact.md`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Turns particle contact on or off. Default: on when the scene has more than one
    /// body, a material with a `critical_stretch` or a `[[body.crack]]`; off otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particles: Option<bool>,
    /// The contact spring as a multiple of the bond micromodulus c = 18κ/(πδ⁴).
    /// Default 15 (Silling & Askari 2005, LAMMPS PERI).
    #[serde(default = "default_contact_stiffness")]
    pub stiffness: f64,
    /// The distance, in particle spacings, below which two particles repel. Default 0.9.
    #[serde(default = "default_contact_distance")]
    pub distance: f64,
    /// Damping ratio ζ of each contact spring along the normal. Default 0.1.
    #[serde(default = "default_contact_damping")]
    pub damping: f64,
    /// Coulomb friction coefficient between particles. Default 0.3.
    #[serde(default = "default_contact_friction")]
    pub friction: f64,
}

impl Default for ContactSpec {
    fn default() -> Self {
        ContactSpec {
            particles: None,
            stiffness: default_contact_stiffness(),
            distance: default_contact_distance(),
            damping: default_contact_damping(),
            friction: default_contact_friction(),
        }
    }
}

fn default_contact_stiffness() -> f64 {
    15.0
}
fn default_contact_distance() -> f64 {
    0.9
}
fn default_contact_damping() -> f64 {
    0.1
}
fn default_contact_friction() -> f64 {
    0.3
}

/// A pose of a mesh collider at a time (`[[collider]] keyframes`): its motion from the
/// placed mesh, x ↦ pivot + R (x − pivot) + translation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeSpec {
    /// Time in s.
    pub time: f64,
    /// Translation in m. Default 0.
    #[serde(default, deserialize_with = "super::exact::array")]
    pub translation: [f64; 3],
    /// Rotation about the pivot in degrees about x, then y, then z (fixed axes; R = Rz
    /// Ry Rx), as for mesh placement. Default 0.
    #[serde(default, deserialize_with = "super::exact::array")]
    pub rotation: [f64; 3],
}

fn default_friction() -> f64 {
    0.5
}
fn default_collider_friction() -> f64 {
    0.2
}
