//! Anchors: particles held at a prescribed rigid motion until their release time, the
//! clamp's ghost layer, and the energy they put in.

use perifrac_math::dot;
use rayon::prelude::*;

use crate::clamp::{Ghosts, Plane};
use crate::error::{Result, SimError};
use crate::geometry::shape::to_sdf;
use crate::model::Points;
use crate::scene::{Clamp, Scene};

use super::{Collider, ColliderShape, face};

/// Particles held at a prescribed rigid motion until a release time, and the ghost
/// layer of a clamp ([`crate::clamp`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Anchor {
    /// The held particles.
    pub particles: Vec<u32>,
    /// The ghosts of a clamp (placed from the free particles each step), or `None`.
    pub clamp: Option<Ghosts>,
    /// Linear velocity.
    pub velocity: [f64; 3],
    /// Angular velocity about `center`.
    pub angular_velocity: [f64; 3],
    /// Centre of rotation at t = 0.
    pub center: [f64; 3],
    /// Release time.
    pub until: f64,
}

impl Anchor {
    /// Position and velocity at time `t` of a particle that was at `x0` at t = 0:
    /// y = c0 + v t + R(ω t)(x0 − c0), ẏ = v + ω × (y − c(t)).
    pub fn motion(&self, x0: [f64; 3], t: f64) -> ([f64; 3], [f64; 3]) {
        let r = rotate(
            self.angular_velocity,
            t,
            [
                x0[0] - self.center[0],
                x0[1] - self.center[1],
                x0[2] - self.center[2],
            ],
        );
        let c = [
            self.center[0] + self.velocity[0] * t,
            self.center[1] + self.velocity[1] * t,
            self.center[2] + self.velocity[2] * t,
        ];
        let w = self.angular_velocity;
        let y = [c[0] + r[0], c[1] + r[1], c[2] + r[2]];
        let v = [
            self.velocity[0] + w[1] * r[2] - w[2] * r[1],
            self.velocity[1] + w[2] * r[0] - w[0] * r[2],
            self.velocity[2] + w[0] * r[1] - w[1] * r[0],
        ];
        (y, v)
    }
}

/// Rotates `v` by the angle |ω|t about ω (Rodrigues).
pub fn rotate(omega: [f64; 3], t: f64, v: [f64; 3]) -> [f64; 3] {
    let angle = dot(omega, omega).sqrt() * t;
    if angle == 0.0 {
        return v;
    }
    let l = dot(omega, omega).sqrt();
    let k = [omega[0] / l, omega[1] / l, omega[2] / l];
    let (s, c) = angle.sin_cos();
    let kxv = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    let kv = dot(k, v);
    [
        v[0] * c + kxv[0] * s + k[0] * kv * (1.0 - c),
        v[1] * c + kxv[1] * s + k[1] * kv * (1.0 - c),
        v[2] * c + kxv[2] * s + k[2] * kv * (1.0 - c),
    ]
}

/// Holds the anchored particles (or mesh vertices) at their prescribed motion at time
/// `t`, then places the clamps' ghosts from the free particles, and marks both in
/// `anchored`; shared by the peridynamic and FEM simulations.
pub fn apply_anchors(
    anchors: &[Anchor],
    t: f64,
    rest: &[[f64; 3]],
    position: &mut [[f64; 3]],
    velocity: &mut [[f64; 3]],
    anchored: &mut [bool],
) {
    mark_anchored(anchors, t, anchored);
    let active = || anchors.iter().filter(move |a| t <= a.until);
    for anchor in active() {
        for &p in &anchor.particles {
            let p = p as usize;
            let (y, v) = anchor.motion(rest[p], t);
            position[p] = y;
            velocity[p] = v;
        }
    }
    for ghosts in active().filter_map(|a| a.clamp.as_ref()) {
        ghosts.place(rest, position, velocity);
    }
}

/// Marks in `anchored` the points the anchors active at `t` hold or place.
pub fn mark_anchored(anchors: &[Anchor], t: f64, anchored: &mut [bool]) {
    anchored.iter_mut().for_each(|a| *a = false);
    for anchor in anchors.iter().filter(|a| t <= a.until) {
        let ghosts = anchor.clamp.iter().flat_map(|g| &g.ghost);
        for &p in anchor.particles.iter().chain(ghosts) {
            anchored[p as usize] = true;
        }
    }
}

/// Carries the internal forces on the ghosts of the clamps active at `t` back to the
/// particles they are made from (see [`Ghosts::carry`]); `acceleration` is the
/// internal force over mass plus `gravity`.
pub fn carry_clamp_forces(
    anchors: &[Anchor],
    t: f64,
    mass: &[f64],
    gravity: [f64; 3],
    acceleration: &mut [[f64; 3]],
) {
    for anchor in anchors.iter().filter(|a| t <= a.until) {
        if let Some(ghosts) = &anchor.clamp {
            ghosts.carry(mass, gravity, acceleration);
        }
    }
}

/// The power the anchors put in, |m a · v| summed over the anchored points (an upper
/// bound on the work of the held points, for the blow-up detector's energy budget).
pub fn anchor_power(
    anchored: &[bool],
    mass: &[f64],
    acceleration: &[[f64; 3]],
    velocity: &[[f64; 3]],
) -> f64 {
    (0..anchored.len())
        .filter(|&i| anchored[i])
        .map(|i| (mass[i] * dot(acceleration[i], velocity[i])).abs())
        .sum()
}

/// The energy a scene can supply over `duration`: the bodies' initial kinetic and
/// strain energy `initial`, free fall, the colliders' kinetic energy, and the bodies
/// (every model's `points`) moved at twice the fastest kinematic collider or anchor.
/// The blow-up detector stops a run whose kinetic energy grows past a multiple of it.
pub fn energy_budget(
    initial: f64,
    points: &[Points<'_>],
    gravity: [f64; 3],
    duration: f64,
    colliders: &[Collider],
    anchors: &[&Anchor],
) -> f64 {
    let norm = |v: [f64; 3]| dot(v, v).sqrt();
    let total_mass: f64 = points.iter().map(|p| p.mass.iter().sum::<f64>()).sum();
    let extent = points
        .iter()
        .flat_map(|p| p.reference)
        .fold(0.0f64, |m, x| m.max(norm(*x)));
    let mut fastest = 0.0f64;
    for c in colliders {
        if let ColliderShape::Mesh(mesh) = &c.shape {
            fastest = fastest.max(mesh.max_speed());
        } else if c.mass.is_none() {
            fastest = fastest.max(norm(c.velocity));
        }
    }
    for a in anchors {
        fastest =
            fastest.max(norm(a.velocity) + norm(a.angular_velocity) * (extent + norm(a.center)));
    }
    initial
        + 0.5 * total_mass * (norm(gravity) * duration).powi(2)
        + colliders.iter().map(Collider::kinetic_energy).sum::<f64>()
        + 0.5 * total_mass * (2.0 * fastest).powi(2)
        + 1e-12
}

/// The mass-weighted centroid of the points `members` (by `weight`).
pub fn centroid(x: &[[f64; 3]], weight: &[f64], members: &[usize]) -> [f64; 3] {
    let mut c = [0.0; 3];
    let mut total = 0.0;
    for &i in members {
        for a in 0..3 {
            c[a] += x[i][a] * weight[i];
        }
        total += weight[i];
    }
    if total > 0.0 { c.map(|s| s / total) } else { c }
}

/// The scene's anchors over the points at `position` (particles, or FEM vertices) of
/// bodies `body`: a point is held when its position is inside the anchor's region (a
/// primitive, a CSG shape or a closed mesh file) and, for a clamp, behind its plane;
/// a default centre of rotation is the held points' centroid weighted by `weight`.
/// A clamp's points within the body's δ behind the plane are its ghosts
/// ([`crate::clamp`]), extrapolated from the body's points in front of the plane that
/// no anchor holds. The clamp is the anchor's `clamp` plane, or by default the face
/// where a fixed box meets the body ([`face_clamps`](super::face_clamps); kept held
/// when that face's ghosts cannot be extrapolated).
pub fn anchors(
    scene: &Scene,
    position: &[[f64; 3]],
    weight: &[f64],
    body: &[u32],
) -> Result<Vec<Anchor>> {
    let mut out = Vec::new();
    let mut held = vec![false; position.len()];
    for (b, spec) in scene.bodies.iter().enumerate() {
        for (k, a) in spec.anchors.iter().enumerate() {
            let region = to_sdf(&a.region, &scene.base_dir).map_err(|message| SimError::Mesh {
                body: spec.name.clone(),
                message: format!("anchor {} region: {message}", k + 1),
            })?;
            let plane = match a.clamp {
                Some(Clamp::Plane(c)) => Some(Plane::new(c.point, c.normal)),
                _ => None,
            };
            let members: Vec<usize> = (0..position.len())
                .into_par_iter()
                .filter(|&i| body[i] == b as u32 && region.distance(position[i]) <= 0.0)
                .filter(|&i| plane.is_none_or(|p| p.distance(position[i]) <= 0.0))
                .collect();
            for &i in &members {
                held[i] = true;
            }
            let center = a
                .center
                .unwrap_or_else(|| centroid(position, weight, &members));
            out.push(Anchor {
                particles: members.iter().map(|&i| i as u32).collect(),
                clamp: None,
                velocity: a.velocity,
                angular_velocity: a.angular_velocity,
                center,
                until: a.until,
            });
        }
    }
    let specs = scene
        .bodies
        .iter()
        .enumerate()
        .flat_map(|(b, spec)| spec.anchors.iter().enumerate().map(move |(k, a)| (b, k, a)));
    for (anchor, (b, k, spec)) in out.iter_mut().zip(specs) {
        let body_spec = &scene.bodies[b];
        // A scene's other models' points: the body is not here.
        if !body.contains(&(b as u32)) {
            continue;
        }
        if let Some(Clamp::Plane(c)) = spec.clamp {
            let plane = Plane::new(c.point, c.normal);
            clamp(anchor, plane, body_spec, b as u32, position, body, &held).map_err(
                |message| SimError::Mesh {
                    body: body_spec.name.clone(),
                    message: format!(
                        "anchor {} clamp: {message}; the plane (body.{b}.anchor.{k}.clamp) must be \
                         the face of the anchor's region, its normal pointing from the region into \
                         the body, and the body must go on for at least 2δ in front of it",
                        k + 1
                    ),
                },
            )?;
        } else if let Some(bounds) = face::candidate(scene, b, spec) {
            let delta = body_spec.delta();
            let face = face::meeting_face(bounds, position, body, b as u32, &held, delta);
            if let (Some(plane), false) = (face, anchor.particles.is_empty()) {
                // A face whose ghosts cannot be extrapolated stays held (not asked for).
                clamp(anchor, plane, body_spec, b as u32, position, body, &held).ok();
            }
        }
    }
    Ok(out)
}

/// Splits the held points of a clamp `anchor` of body `b` into its ghosts (within
/// δ behind `plane`) and the rest, and builds the ghosts' weights from the free points
/// (the body's, in front of the plane, not `held` by any anchor).
fn clamp(
    anchor: &mut Anchor,
    plane: Plane,
    spec: &crate::scene::BodySpec,
    b: u32,
    position: &[[f64; 3]],
    body: &[u32],
    held: &[bool],
) -> std::result::Result<(), String> {
    let delta = spec.delta();
    let (ghost, rest): (Vec<u32>, Vec<u32>) = anchor
        .particles
        .iter()
        .partition(|&&i| plane.distance(position[i as usize]) >= -delta);
    if ghost.is_empty() {
        return Err(if anchor.particles.is_empty() {
            "no particle of the region lies behind the plane".to_string()
        } else {
            format!(
                "none of the region's {} particles behind the plane lies within δ = {delta:.3e} m of it",
                anchor.particles.len()
            )
        });
    }
    // The fits reach 3δ + 1.5λ in front of the plane.
    let reach = 3.0 * delta + 2.0 * spec.resolution;
    let free: Vec<u32> = (0..position.len() as u32)
        .filter(|&i| {
            let d = plane.distance(position[i as usize]);
            body[i as usize] == b && !held[i as usize] && d > 0.0 && d < reach
        })
        .collect();
    anchor.clamp = Some(Ghosts::build(
        position,
        ghost,
        &free,
        plane,
        spec.resolution,
    )?);
    anchor.particles = rest;
    Ok(())
}
