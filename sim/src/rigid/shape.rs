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
/// particles' tets, [`crate::model::Model::reference_surface`]), and its particles'
/// positions `points` in that frame. The convex hull of the vertices for a piece of up
/// to [`HULL_POINTS`] points; above that parry's convex decomposition (V-HACD, its
/// defaults: 64 voxels along the longest side, concavity 0.01), each part the exact
/// hull of the surface's vertices in it. Each part's hull takes in the particles it
/// should hold ([`cover`]): the exact hulls hold every surface vertex but not always
/// the inside, so a piece could rest with particles, and the tets around them,
/// centimetres into the ground. `None` where parry finds no solid (a flat or
/// degenerate surface): the piece then collides as its particles ([`piece`]).
pub(super) fn surface(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    points: &[[f64; 3]],
) -> Option<ColliderBuilder> {
    let vertices: Vec<Point3<f64>> = vertices.iter().map(|&v| Point3::from(vector(v))).collect();
    let points: Vec<Point3<f64>> = points.iter().map(|&p| Point3::from(vector(p))).collect();
    if points.len() <= HULL_POINTS {
        let all: Vec<Point3<f64>> = vertices.iter().chain(&points).copied().collect();
        return ColliderBuilder::convex_hull(&all);
    }
    let decomposition = VHACD::decompose(&VHACDParameters::default(), &vertices, triangles, true);
    let hulls: Vec<Vec<Point3<f64>>> = decomposition
        .compute_exact_convex_hulls(&vertices, triangles)
        .into_iter()
        .map(|(hull, _)| hull)
        .collect();
    let parts: Vec<(Isometry<f64>, SharedShape)> = cover(hulls, &points)
        .into_iter()
        .map(|shape| (Isometry::identity(), shape))
        .collect();
    (!parts.is_empty()).then(|| ColliderBuilder::compound(parts))
}

/// The convex parts `hulls` (their points) as shapes, each grown to take in the
/// particles of `points` that no part holds: a particle outside every part joins the
/// part nearest it, whose hull is then taken again (the others are kept as they are).
/// V-HACD's exact hulls are the hulls of the surface vertices in each part's voxels,
/// so a part whose voxels reach into the piece but whose vertices lie on one face is a
/// thin shell over that face; on the demo shot the largest pieces had up to 563
/// particles outside every part, one 3.9 cm out. Degenerate (flat) parts are left
/// out.
fn cover(mut hulls: Vec<Vec<Point3<f64>>>, points: &[Point3<f64>]) -> Vec<SharedShape> {
    let mut shapes: Vec<Option<SharedShape>> = hulls
        .iter()
        .map(|hull| SharedShape::convex_hull(hull))
        .collect();
    let mut grown = vec![false; hulls.len()];
    for p in points {
        let distances = shapes.iter().map(|shape| {
            shape
                .as_ref()
                .map_or(f64::INFINITY, |s| s.distance_to_local_point(p, true))
        });
        let (nearest, distance) =
            distances.enumerate().fold(
                (0, f64::INFINITY),
                |best, (k, d)| if d < best.1 { (k, d) } else { best },
            );
        if distance > 0.0 && distance.is_finite() {
            hulls[nearest].push(*p);
            grown[nearest] = true;
        }
    }
    for ((shape, hull), grown) in shapes.iter_mut().zip(&hulls).zip(grown) {
        if grown {
            *shape = SharedShape::convex_hull(hull);
        }
    }
    shapes.into_iter().flatten().collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    type Points = Vec<[f64; 3]>;

    /// The closed surface of an L-shaped slab, 40 cm × 30 cm × 6 cm less a 16 × 14 cm
    /// corner, as the faces of 2 cm cells (outward), and its cells' centres in three
    /// layers: a concave piece that V-HACD splits.
    fn l_slab() -> (Points, Vec<[u32; 3]>, Points) {
        let (nx, nz, h, t) = (20i64, 15i64, 0.02, 0.06);
        let filled =
            |i: i64, k: i64| (0..nx).contains(&i) && (0..nz).contains(&k) && !(i >= 12 && k >= 8);
        let (mut vertices, mut triangles, mut points) = (Vec::new(), Vec::new(), Vec::new());
        let mut quad = |corners: [[f64; 3]; 4]| {
            let base = vertices.len() as u32;
            vertices.extend(corners);
            triangles.push([base, base + 1, base + 2]);
            triangles.push([base, base + 2, base + 3]);
        };
        for i in 0..nx {
            for k in 0..nz {
                if !filled(i, k) {
                    continue;
                }
                let (x0, x1) = (i as f64 * h, (i + 1) as f64 * h);
                let (z0, z1) = (k as f64 * h, (k + 1) as f64 * h);
                quad([[x0, 0.0, z0], [x1, 0.0, z0], [x1, 0.0, z1], [x0, 0.0, z1]]);
                quad([[x0, t, z0], [x0, t, z1], [x1, t, z1], [x1, t, z0]]);
                if !filled(i - 1, k) {
                    quad([[x0, 0.0, z0], [x0, 0.0, z1], [x0, t, z1], [x0, t, z0]]);
                }
                if !filled(i + 1, k) {
                    quad([[x1, 0.0, z0], [x1, t, z0], [x1, t, z1], [x1, 0.0, z1]]);
                }
                if !filled(i, k - 1) {
                    quad([[x0, 0.0, z0], [x0, t, z0], [x1, t, z0], [x1, 0.0, z0]]);
                }
                if !filled(i, k + 1) {
                    quad([[x0, 0.0, z1], [x1, 0.0, z1], [x1, t, z1], [x0, t, z1]]);
                }
                for y in [0.01, 0.03, 0.05] {
                    points.push([x0 + 0.5 * h, y, z0 + 0.5 * h]);
                }
            }
        }
        (vertices, triangles, points)
    }

    /// The largest distance of `points` outside `collider` (0 when all are inside).
    fn outside(collider: &ColliderBuilder, points: &[[f64; 3]]) -> f64 {
        points
            .iter()
            .map(|&p| {
                collider
                    .shape
                    .distance_to_local_point(&Point3::from(vector(p)), true)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_piece_collider_holds_every_particle_of_the_piece() {
        let (vertices, triangles, mut points) = l_slab();
        assert!(points.len() > HULL_POINTS);
        // A particle 2 cm above the top face: a piece whose particles stand off its
        // reference surface as it was turned (it rang, or a crushed zone set).
        points.push([0.05, 0.08, 0.05]);
        let collider = surface(&vertices, &triangles, &points).expect("a solid");
        let parts = collider
            .shape
            .as_compound()
            .expect("V-HACD parts")
            .shapes()
            .len();
        assert!(parts > 1, "{parts} parts");
        assert!(
            outside(&collider, &points) < 1e-9,
            "{}",
            outside(&collider, &points)
        );
        // Every surface vertex is held as before, and the parts grew only where a
        // particle was outside: nothing reaches 1 mm beyond the slab's bounds but the
        // particle above it.
        assert!(outside(&collider, &vertices) < 1e-9);
        let aabb = collider.shape.compute_local_aabb();
        assert!(aabb.mins.y > -1e-3 && aabb.maxs.y < 0.08 + 1e-9, "{aabb:?}");
        assert!(
            aabb.maxs.x < 0.4 + 1e-3 && aabb.maxs.z < 0.3 + 1e-3,
            "{aabb:?}"
        );
    }
}
