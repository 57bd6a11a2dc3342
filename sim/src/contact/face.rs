//! The clamp by default (issue 33, item 6): a fixed box held over the end of a
//! peridynamic body is clamped at the face where it meets the body ([`crate::clamp`])
//! instead of holding a slab whose free neighbours are bonded to a rigid wall, which is
//! 9.5% too soft at 6 particles across (docs/lattice.md, "The clamp by default").
//!
//! The face is found from the particles at set-up: a face of the box meets the body
//! where free particles of the body (in no anchor's region) lie within δ in front of
//! it, over the face (their other two coordinates within the box's), i.e. where bonds
//! cross it from free particles into the region. Exactly one such face makes the clamp;
//! none (a region holding the whole body, or clear of it) or two and more (a region
//! inside the body, over an edge or a corner, or over part of a cross-section) keep the
//! whole region held.

use crate::clamp::Plane;
use crate::scene::{AnchorSpec, ModelKind, Scene, ShapeSpec};

use super::Anchor;

/// The bounds (lo, hi) of the region of anchor `spec` of body `b` when the clamp by
/// default may apply to it: no `clamp` key, fixed (zero `velocity` and
/// `angular_velocity`), a peridynamic body whose material does not break (a clamp's
/// extrapolation weights are fixed at set-up, for a field that is continuous in front
/// of the plane), and a `box` or `slab` region.
pub(super) fn candidate(
    scene: &Scene,
    b: usize,
    spec: &AnchorSpec,
) -> Option<([f64; 3], [f64; 3])> {
    let body = &scene.bodies[b];
    let breaks = scene
        .materials
        .get(&body.material)
        .is_none_or(|m| m.critical_stretch.is_some());
    let fixed = spec.velocity == [0.0; 3] && spec.angular_velocity == [0.0; 3];
    if spec.clamp.is_some() || !fixed || breaks || body.model != ModelKind::Peridynamics {
        return None;
    }
    match spec.region {
        ShapeSpec::Box { center, size } | ShapeSpec::Slab { center, size } => Some((
            [0, 1, 2].map(|a| center[a] - 0.5 * size[a]),
            [0, 1, 2].map(|a| center[a] + 0.5 * size[a]),
        )),
        _ => None,
    }
}

/// The face of the box `[lo, hi]` where it meets body `b` (module doc): the plane of
/// the one face with free points of the body (`body[i] == b`, not `held`) within
/// `delta` in front of it, through the face's centre, its normal out of the box; `None`
/// unless exactly one face has them.
pub(super) fn meeting_face(
    (lo, hi): ([f64; 3], [f64; 3]),
    position: &[[f64; 3]],
    body: &[u32],
    b: u32,
    held: &[bool],
    delta: f64,
) -> Option<Plane> {
    // met[2a] is the face x_a = lo_a, met[2a + 1] the face x_a = hi_a.
    let mut met = [false; 6];
    for (i, x) in position.iter().enumerate() {
        if body[i] != b || held[i] {
            continue;
        }
        for a in 0..3 {
            let over = (0..3).all(|c| c == a || (lo[c]..=hi[c]).contains(&x[c]));
            if over && x[a] < lo[a] && lo[a] - x[a] <= delta {
                met[2 * a] = true;
            } else if over && x[a] > hi[a] && x[a] - hi[a] <= delta {
                met[2 * a + 1] = true;
            }
        }
    }
    let mut faces = (0..6).filter(|&f| met[f]);
    let (face, None) = (faces.next()?, faces.next()) else {
        return None;
    };
    let (a, sign) = (face / 2, if face % 2 == 0 { -1.0 } else { 1.0 });
    let mut point = [0, 1, 2].map(|c| 0.5 * (lo[c] + hi[c]));
    point[a] = if sign > 0.0 { hi[a] } else { lo[a] };
    let mut normal = [0.0; 3];
    normal[a] = sign;
    Some(Plane::new(point, normal))
}

/// The anchors of `anchors` (one per anchor of `scene`, in scene order, as
/// [`super::anchors`] returns them) that the clamp by default made clamps: (body index,
/// anchor index within the body, the clamp's plane).
pub fn face_clamps(scene: &Scene, anchors: &[Anchor]) -> Vec<(usize, usize, Plane)> {
    let specs = scene
        .bodies
        .iter()
        .enumerate()
        .flat_map(|(b, body)| body.anchors.iter().enumerate().map(move |(k, a)| (b, k, a)));
    anchors
        .iter()
        .zip(specs)
        .filter(|(_, (_, _, spec))| spec.clamp.is_none())
        .filter_map(|(anchor, (b, k, _))| anchor.clamp.as_ref().map(|g| (b, k, g.plane)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bar x ∈ [−0.3, 1], y, z ∈ [−0.1, 0.1], points every 0.05.
    fn bar() -> Vec<[f64; 3]> {
        let mut x = Vec::new();
        for i in 0..26 {
            for j in 0..4 {
                for k in 0..4 {
                    let at = |n: i32| -0.075 + 0.05 * f64::from(n);
                    x.push([-0.275 + 0.05 * f64::from(i), at(j), at(k)]);
                }
            }
        }
        x
    }

    fn face(lo: [f64; 3], hi: [f64; 3]) -> Option<Plane> {
        let x = bar();
        let held: Vec<bool> = x
            .iter()
            .map(|p| (0..3).all(|a| (lo[a]..=hi[a]).contains(&p[a])))
            .collect();
        meeting_face((lo, hi), &x, &vec![0; x.len()], 0, &held, 0.0725)
    }

    #[test]
    fn a_box_over_the_end_is_clamped_at_its_inner_face() {
        let plane = face([-0.5, -0.2, -0.2], [0.0, 0.2, 0.2]).expect("one face");
        assert_eq!(plane.normal, [1.0, 0.0, 0.0]);
        assert_eq!(plane.distance([0.0, 0.3, -0.7]), 0.0);
        // The other end, the face at x = 0.9 facing −x.
        let plane = face([0.9, -0.2, -0.2], [1.5, 0.2, 0.2]).expect("one face");
        assert_eq!((plane.normal, plane.point[0]), ([-1.0, 0.0, 0.0], 0.9));
    }

    #[test]
    fn regions_that_meet_the_body_in_more_or_fewer_faces_are_held() {
        // Inside the body: two faces along x (and y, z are its surface).
        assert_eq!(face([0.2, -0.2, -0.2], [0.4, 0.2, 0.2]), None);
        // Over the end but half the section: the face y = 0 meets the body too.
        assert_eq!(face([-0.5, -0.2, -0.2], [0.0, 0.0, 0.2]), None);
        // The whole body, and none of it.
        assert_eq!(face([-1.0, -1.0, -1.0], [2.0, 1.0, 1.0]), None);
        assert_eq!(face([-1.0, -1.0, -1.0], [-0.5, 1.0, 1.0]), None);
    }
}
