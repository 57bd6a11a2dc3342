//! Checks of what the scene's bodies share: the colliders, particle contact, the rigid
//! phase and the frame schedule.

use super::{Check, finite3, issue, positive, shape};
use crate::scene::{ColliderSpec, ModelKind, Scene};

pub(super) fn schedule(scene: &Scene) -> Check {
    let mut start = 0.0;
    for (k, s) in scene.output.schedule.iter().enumerate() {
        let i = k.to_string();
        if !(s.until.is_finite() && s.until > start && s.until < scene.scene.duration) {
            return Err(issue(
                &["output", "schedule", i.as_str(), "until"],
                format!(
                    "a segment ends after the one before it ({start} s) and before the scene's \
                     duration ({} s), got {}",
                    scene.scene.duration, s.until
                ),
            ));
        }
        positive(
            &["output", "schedule", i.as_str(), "fps"],
            s.fps,
            "a segment's frames a second",
        )?;
        start = s.until;
    }
    Ok(())
}

pub(super) fn rigid(scene: &Scene) -> Check {
    let r = &scene.rigid;
    let p = |key: &'static str| ["rigid", key];
    let fraction = |key: &'static str, v: f64, what: &str| {
        if v.is_finite() && v > 0.0 && v < 1.0 {
            Ok(())
        } else {
            Err(issue(&p(key), format!("{what} must be in (0, 1), got {v}")))
        }
    };
    fraction(
        "margin",
        r.margin,
        "the margin (a fraction of the stretch that breaks a bond)",
    )?;
    fraction(
        "vibration",
        r.vibration,
        "the vibration (a fraction of the fragment's kinetic energy)",
    )?;
    positive(
        &p("rest_amplitude"),
        r.rest_amplitude,
        "the rest amplitude in particle spacings",
    )?;
    positive(&p("settle_time"), r.settle_time, "the settle time in s")?;
    positive(&p("step"), r.step, "the rigid phase's longest step in s")?;
    if r.check_every == 0 {
        return Err(issue(
            &p("check_every"),
            "check_every counts steps between two looks for settled fragments: at least 1",
        ));
    }
    if !(r.friction.is_finite() && r.friction >= 0.0) {
        return Err(issue(
            &p("friction"),
            format!("friction must be ≥ 0, got {}", r.friction),
        ));
    }
    if !(r.restitution.is_finite() && (0.0..=1.0).contains(&r.restitution)) {
        return Err(issue(
            &p("restitution"),
            format!("restitution must be in [0, 1], got {}", r.restitution),
        ));
    }
    if !(r.rolling_resistance.is_finite() && r.rolling_resistance >= 0.0) {
        return Err(issue(
            &p("rolling_resistance"),
            format!(
                "rolling_resistance is the coefficient of rolling resistance of rigid \
                 pieces in contact, a length in m (a couple of at most it times the normal \
                 force against their spin): ≥ 0 (0.005 by default, 0 for none), got {}",
                r.rolling_resistance
            ),
        ));
    }
    if !(r.drag.is_finite() && r.drag >= 0.0) {
        return Err(issue(
            &p("drag"),
            format!(
                "drag is the air's drag coefficient C_d on rigid pieces: ≥ 0 (about 1 for \
                 a tumbling fragment, 0 without air), got {}",
                r.drag
            ),
        ));
    }
    if !(r.air_density.is_finite() && r.air_density >= 0.0) {
        return Err(issue(
            &p("air_density"),
            format!(
                "air_density is in kg/m³: ≥ 0 (1.2 at sea level), got {}",
                r.air_density
            ),
        ));
    }
    if !(r.reenter.is_finite() && r.reenter >= 0.0) {
        return Err(issue(
            &p("reenter"),
            format!(
                "reenter is a multiple of s_c c_p, the closing speed of a hit that strains \
                 a piece to its critical stretch: ≥ 0 (0: pieces stay rigid), got {}",
                r.reenter
            ),
        ));
    }
    Ok(())
}

pub(super) fn contact(scene: &Scene) -> Check {
    let c = &scene.contact;
    let p = |key: &'static str| ["contact", key];
    positive(
        &p("stiffness"),
        c.stiffness,
        "the contact stiffness (a multiple of the bond micromodulus)",
    )?;
    if !(c.distance.is_finite() && c.distance > 0.0 && c.distance <= 1.5) {
        return Err(issue(
            &p("distance"),
            format!(
                "the contact distance must be in (0, 1.5] particle spacings (0.9 is usual), got {}",
                c.distance
            ),
        ));
    }
    if !(c.damping.is_finite() && (0.0..=1.0).contains(&c.damping)) {
        return Err(issue(
            &p("damping"),
            format!(
                "the damping ratio must be in [0, 1] (1 is critical), got {}",
                c.damping
            ),
        ));
    }
    if !(c.friction.is_finite() && c.friction >= 0.0) {
        return Err(issue(
            &p("friction"),
            format!("friction must be ≥ 0, got {}", c.friction),
        ));
    }
    if scene.particle_contact() {
        if let Some(b) = scene
            .bodies
            .iter()
            .position(|b| matches!(b.model, ModelKind::Membrane | ModelKind::Mpm))
        {
            if c.particles == Some(true) {
                return Err(issue(
                    &p("particles"),
                    format!(
                        "body {} is a {} and its particles take no part in particle contact (MPM collides through its grid; membranes have no volume): set particles = false",
                        scene.bodies[b].name,
                        if scene.bodies[b].model == ModelKind::Mpm {
                            "MPM body"
                        } else {
                            "membrane"
                        }
                    ),
                ));
            }
        }
    }
    Ok(())
}

pub(super) fn collider(scene: &Scene, i: &str, c: &ColliderSpec) -> Check {
    let p = |key: &'static str| ["collider", i, key];
    let friction = match c {
        ColliderSpec::Ground { height, friction } => {
            if !height.is_finite() {
                return Err(issue(&p("height"), "the ground height must be finite"));
            }
            *friction
        }
        ColliderSpec::Sphere {
            center,
            radius,
            velocity,
            mass,
            friction,
            ..
        } => {
            finite3(&p("center"), *center)?;
            finite3(&p("velocity"), *velocity)?;
            positive(&p("radius"), *radius, "the radius")?;
            if let Some(m) = mass {
                positive(&p("mass"), *m, "the mass (kg)")?;
            }
            *friction
        }
        ColliderSpec::Box {
            center,
            size,
            velocity,
            mass,
            friction,
            ..
        } => {
            finite3(&p("center"), *center)?;
            finite3(&p("velocity"), *velocity)?;
            if !size.iter().all(|x| x.is_finite() && *x > 0.0) {
                return Err(issue(
                    &p("size"),
                    format!("every side must be positive, got {size:?}"),
                ));
            }
            if let Some(m) = mass {
                positive(&p("mass"), *m, "the mass (kg)")?;
            }
            *friction
        }
        ColliderSpec::Mesh {
            pivot,
            keyframes,
            transforms,
            friction,
            ..
        } => {
            if let Some(shape_spec) = c.mesh_shape() {
                shape(scene, &["collider", i], &shape_spec)?;
            }
            if let Some(pivot) = pivot {
                finite3(&p("pivot"), *pivot)?;
            }
            if transforms.is_some() && !keyframes.is_empty() {
                return Err(issue(
                    &p("transforms"),
                    "a mesh collider moves by keyframes or by a transforms file, not both: remove one",
                ));
            }
            if let Some(file) = transforms {
                let full = scene.base_dir.join(file);
                if !scene.cached && !full.is_file() {
                    return Err(issue(
                        &p("transforms"),
                        format!(
                            "transforms file {} does not exist (paths are relative to the scene file)",
                            full.display()
                        ),
                    ));
                }
            }
            let mut last = f64::NEG_INFINITY;
            for (k, key) in keyframes.iter().enumerate() {
                if !(key.time.is_finite() && key.time >= 0.0 && key.time > last) {
                    return Err(issue(
                        &p("keyframes"),
                        format!(
                            "keyframe {k}: times must be finite, ≥ 0 s and increasing, got {} after {last}",
                            key.time
                        ),
                    ));
                }
                last = key.time;
                finite3(&p("keyframes"), key.translation)?;
                finite3(&p("keyframes"), key.rotation)?;
            }
            *friction
        }
    };
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(issue(
            &p("friction"),
            format!("friction must be ≥ 0, got {friction}"),
        ));
    }
    Ok(())
}
