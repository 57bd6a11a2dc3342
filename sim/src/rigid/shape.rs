//! The shapes rapier collides: a piece's from its particles, and the scene's colliders
//! mirrored (docs/rigid.md, "Colliders and contact").

use rapier3d_f64::na::{Point3, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::parry::transformation::vhacd::{VHACD, VHACDParameters};
use rapier3d_f64::prelude::*;

use super::{HULL_POINTS, vector};
use crate::contact::{Collider, ColliderShape};

/// A piece's collider from its points' positions `local` in the body frame and their
/// spacings: a cube of half-side `radius` for a single particle (a grain; a ball would
/// roll forever), the convex hull of the points rounded by `radius` up to
/// [`HULL_POINTS`] points (or, where the hull is flat, the union of the particles'
/// cubes), and above that the union of the particles' cubes (concave where the piece
/// is).
pub(super) fn piece(local: &[[f64; 3]], spacing: &[f64], radius: f64) -> ColliderBuilder {
    let cubes = || {
        let shapes = local
            .iter()
            .zip(spacing)
            .map(|(r, &l)| {
                let h = 0.5 * l;
                (
                    Isometry::translation(r[0], r[1], r[2]),
                    SharedShape::cuboid(h, h, h),
                )
            })
            .collect();
        ColliderBuilder::compound(shapes)
    };
    if local.len() == 1 {
        ColliderBuilder::cuboid(radius, radius, radius)
    } else if local.len() <= HULL_POINTS {
        let hull: Vec<Point3<f64>> = local.iter().map(|r| Point3::from(vector(*r))).collect();
        ColliderBuilder::round_convex_hull(&hull, radius).unwrap_or_else(cubes)
    } else {
        cubes()
    }
}

/// A piece's collider from its own surface (docs/rigid.md, "Colliders and contact"):
/// `vertices` in the body frame and their outward triangles (the faces of its
/// particles' tets, [`crate::model::Model::reference_surface`]). The convex hull of the
/// vertices for a piece of up to [`HULL_POINTS`] `points`; above that parry's convex
/// decomposition (V-HACD, its defaults: 64 voxels along the longest side, concavity
/// 0.01), each part the exact hull of the surface's vertices in it. `None` where parry
/// finds no solid (a flat or degenerate surface): the piece then collides as its
/// particles ([`piece`]).
pub(super) fn surface(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    points: usize,
) -> Option<ColliderBuilder> {
    let vertices: Vec<Point3<f64>> = vertices.iter().map(|&v| Point3::from(vector(v))).collect();
    if points <= HULL_POINTS {
        return ColliderBuilder::convex_hull(&vertices);
    }
    let decomposition = VHACD::decompose(&VHACDParameters::default(), &vertices, triangles, true);
    let parts: Vec<(Isometry<f64>, SharedShape)> = decomposition
        .compute_exact_convex_hulls(&vertices, triangles)
        .into_iter()
        .filter_map(|(hull, indices)| SharedShape::convex_mesh(hull, &indices))
        .map(|shape| (Isometry::identity(), shape))
        .collect();
    (!parts.is_empty()).then(|| ColliderBuilder::compound(parts))
}

/// A scene collider's body and shape in rapier: the ground fixed, colliders with a
/// mass dynamic, the others moved at their velocity; a mesh collider as the placed
/// triangle mesh (oriented, its internal edges fixed so that pieces slide over its
/// flat faces without catching), kinematic, put at its pose each step
/// ([`super::RigidPhase::step`]). `None` for a mesh parry refuses (no triangles left
/// once degenerate ones go), which has nothing to collide with.
pub(super) fn mirrored(c: &Collider) -> Option<(RigidBodyBuilder, ColliderBuilder)> {
    Some(match &c.shape {
        ColliderShape::Ground => (
            RigidBodyBuilder::fixed().translation(vector([0.0, c.center[1], 0.0])),
            ColliderBuilder::halfspace(Vector3::y_axis()),
        ),
        ColliderShape::Sphere(r) => (moving(c), ColliderBuilder::ball(*r)),
        ColliderShape::Box(h) => (
            moving(c).enabled_rotations(false, false, false),
            ColliderBuilder::cuboid(h[0], h[1], h[2]),
        ),
        ColliderShape::Mesh(mesh) => {
            let (positions, triangles) = mesh.local_surface();
            let points = positions.iter().map(|&p| Point3::from(vector(p))).collect();
            let flags = TriMeshFlags::ORIENTED | TriMeshFlags::FIX_INTERNAL_EDGES;
            let shape =
                ColliderBuilder::trimesh_with_flags(points, triangles.to_vec(), flags).ok()?;
            // Massless, so that its centre of mass, about which rapier turns a
            // kinematic body, is the pivot the pose turns it about.
            let shape =
                shape.mass_properties(MassProperties::new(Point3::origin(), 0.0, Vector3::zeros()));
            let body = RigidBodyBuilder::kinematic_velocity_based()
                .position(pose(c))
                .linvel(vector(c.velocity))
                .angvel(vector(c.angular_velocity));
            (body, shape)
        }
    })
}

/// A sphere's or box's body: dynamic with a mass, else kinematic at its velocity.
fn moving(c: &Collider) -> RigidBodyBuilder {
    let builder = match c.mass {
        Some(_) => RigidBodyBuilder::dynamic()
            .ccd_enabled(true)
            .gravity_scale(if c.gravity { 1.0 } else { 0.0 }),
        None => RigidBodyBuilder::kinematic_velocity_based(),
    };
    builder
        .translation(vector(c.center))
        .linvel(vector(c.velocity))
}

/// A collider's pose: its centre, and its rotation (the identity but for meshes).
pub(super) fn pose(c: &Collider) -> Isometry<f64> {
    let r = perifrac_math::Rotation3::from_matrix_unchecked(perifrac_math::to_matrix(c.rotation));
    Isometry::from_parts(
        Translation3::from(vector(c.center)),
        UnitQuaternion::from_rotation_matrix(&r),
    )
}
