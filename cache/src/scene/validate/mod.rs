//! Range checks on a parsed scene: each problem is reported with its dotted key.

mod material;
mod membrane;
mod mpm;
mod world;

use self::material::{bond_keys, material};
use self::world::{collider, contact, rigid, schedule};
use super::{
    BodySpec, Clamp, ClampSpec, MaterialSpec, MembraneFormulation, MembraneLaw, MembraneSpec,
    ModelKind, MpmElasticity, MpmPlasticity, MpmSpec, Scene, ShapeSpec, SurfaceMethod, VdbSpec,
};

/// One problem: where (dotted path) and what, with the fix.
pub(super) struct Issue {
    pub path: Vec<String>,
    pub message: String,
}

type Check = Result<(), Issue>;

fn issue(path: &[&str], message: impl Into<String>) -> Issue {
    Issue {
        path: path.iter().map(|s| s.to_string()).collect(),
        message: message.into(),
    }
}

fn positive(path: &[&str], value: f64, what: &str) -> Check {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(issue(
            path,
            format!("{what} must be a positive finite number, got {value}"),
        ))
    }
}

fn finite3(path: &[&str], v: [f64; 3]) -> Check {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(issue(
            path,
            format!("every component must be finite, got {v:?}"),
        ))
    }
}

pub(super) fn validate(scene: &Scene) -> Check {
    let s = &scene.scene;
    positive(
        &["scene", "duration"],
        s.duration,
        "the duration in seconds",
    )?;
    positive(&["scene", "fps"], s.fps, "frames per second")?;
    let frames = s.duration * s.fps;
    if frames.is_nan() || frames > MAX_FRAMES {
        return Err(issue(
            &["scene", "duration"],
            format!(
                "duration × fps = {frames:e} frames; a cache holds at most {MAX_FRAMES:e} \
                 (a file a frame): shorten the duration or lower fps"
            ),
        ));
    }
    finite3(&["scene", "gravity"], s.gravity)?;
    if let Some(dt) = s.dt {
        positive(&["scene", "dt"], dt, "the time step in seconds")?;
    }
    if !(s.dt_safety > 0.0 && s.dt_safety <= 1.0) {
        return Err(issue(
            &["scene", "dt_safety"],
            format!("must be in (0, 1], got {}", s.dt_safety),
        ));
    }
    positive(
        &["scene", "blowup_energy_growth"],
        s.blowup_energy_growth,
        "the energy growth factor",
    )?;
    for (name, m) in &scene.materials {
        material(name, m)?;
    }
    if scene.bodies.is_empty() {
        return Err(issue(
            &["body"],
            "the scene has no [[body]]: add at least one",
        ));
    }
    for (i, b) in scene.bodies.iter().enumerate() {
        body(scene, &i.to_string(), b)?;
    }
    mpm::mpm(scene)?;
    fem(scene)?;
    membrane::membrane(scene)?;
    for (i, c) in scene.colliders.iter().enumerate() {
        collider(scene, &i.to_string(), c)?;
    }
    contact(scene)?;
    rigid(scene)?;
    schedule(scene)?;
    vdb(&scene.output.vdb)?;
    positive(
        &["output", "playback_fps"],
        scene.output.playback_fps,
        "the playback rate in frames per second",
    )?;
    if scene.output.tets == Some(false) && scene.output.surface == SurfaceMethod::Embedded {
        return Err(issue(
            &["output", "tets"],
            "surface = \"embedded\" reads the split tet meshes: set tets = true or leave it out",
        ));
    }
    let membranes = scene.bodies.iter().any(|b| b.model == ModelKind::Membrane);
    if scene.output.surface == SurfaceMethod::Sheet && !membranes {
        return Err(issue(
            &["output", "surface"],
            "surface = \"sheet\" meshes membranes (model = \"membrane\"): use \"embedded\" \
             or \"vdb\" for solids",
        ));
    }
    Ok(())
}

/// The most frames a scene may write (duration × fps): each is at least one file,
/// and the frame number is part of every file name and counter.
pub const MAX_FRAMES: f64 = 1e7;

/// Radius of a sphere with the volume of a cube of side 1: (3/(4π))^(1/3), a
/// particle's volume-equivalent sphere radius in particle spacings. The `vdb`
/// method's sphere radius is `radius_scale` times this.
pub const SPHERE_RADIUS_PER_SPACING: f64 = 0.620_350_490_899_400_1;

/// The smallest sphere radius, in voxels, that OpenVDB's `ParticlesToLevelSet`
/// rasterizes (smaller particles are dropped).
const MIN_RASTER_RADIUS_VOXELS: f64 = 1.5;

fn vdb(v: &VdbSpec) -> Check {
    let p = |key: &'static str| ["output", "vdb", key];
    positive(
        &p("voxel_size"),
        v.voxel_size,
        "the voxel size (in particle spacings)",
    )?;
    positive(&p("radius_scale"), v.radius_scale, "the radius scale")?;
    let radius_voxels = v.radius_scale * SPHERE_RADIUS_PER_SPACING / v.voxel_size;
    if radius_voxels < MIN_RASTER_RADIUS_VOXELS {
        return Err(issue(
            &p("voxel_size"),
            format!(
                "particle spheres would be {radius_voxels:.2} voxels in radius and OpenVDB drops those under {MIN_RASTER_RADIUS_VOXELS}: use voxel_size ≤ {:.3} (or a larger radius_scale)",
                v.radius_scale * SPHERE_RADIUS_PER_SPACING / MIN_RASTER_RADIUS_VOXELS
            ),
        ));
    }
    if v.iterations > 1000 {
        return Err(issue(
            &p("iterations"),
            format!("at most 1000 filter passes, got {}", v.iterations),
        ));
    }
    if !(v.offset.is_finite() && v.offset.abs() <= 10.0) {
        return Err(issue(
            &p("offset"),
            format!(
                "the offset must be within ±10 particle spacings, got {}",
                v.offset
            ),
        ));
    }
    if !(0.0..=1.0).contains(&v.adaptivity) {
        return Err(issue(
            &p("adaptivity"),
            format!("adaptivity must be in [0, 1], got {}", v.adaptivity),
        ));
    }
    if v.min_fragment_particles == 0 {
        return Err(issue(
            &p("min_fragment_particles"),
            "must be at least 1 (1 surfaces every fragment)",
        ));
    }
    Ok(())
}

fn body(scene: &Scene, i: &str, b: &BodySpec) -> Check {
    let p = |key: &'static str| ["body", i, key];
    if !scene.materials.contains_key(&b.material) {
        let known: Vec<&str> = scene.materials.keys().map(String::as_str).collect();
        return Err(issue(
            &p("material"),
            format!("no material named '{}'; defined: {known:?}", b.material),
        ));
    }
    positive(&p("resolution"), b.resolution, "the resolution λ (m)")?;
    if !(b.horizon.is_finite() && b.horizon >= 1.0) {
        return Err(issue(
            &p("horizon"),
            format!(
                "the horizon δ/λ must be at least 1.0 (a smaller family has too few bonds to hold the body together), got {}",
                b.horizon
            ),
        ));
    }
    finite3(&p("velocity"), b.velocity)?;
    finite3(&p("angular_velocity"), b.angular_velocity)?;
    shape(scene, &["body", i, "shape"], &b.shape)?;
    for (k, a) in b.anchors.iter().enumerate() {
        let k = k.to_string();
        shape(scene, &["body", i, "anchor", &k, "region"], &a.region)?;
        finite3(&["body", i, "anchor", &k, "velocity"], a.velocity)?;
        finite3(
            &["body", i, "anchor", &k, "angular_velocity"],
            a.angular_velocity,
        )?;
        if let Some(center) = a.center {
            finite3(&["body", i, "anchor", &k, "center"], center)?;
        }
        if a.until.is_nan() || a.until < 0.0 {
            return Err(issue(
                &["body", i, "anchor", &k, "until"],
                format!(
                    "the release time must be ≥ 0 s (or inf: never released), got {}",
                    a.until
                ),
            ));
        }
        if let Some(Clamp::Plane(clamp)) = &a.clamp {
            clamp_spec(b, i, &k, a.velocity, a.angular_velocity, clamp)?;
        }
    }
    for (k, c) in b.cracks.iter().enumerate() {
        let k = k.to_string();
        let n = c.normal;
        if !(n.iter().all(|x| x.is_finite()) && n.iter().map(|x| x * x).sum::<f64>() > 0.0) {
            return Err(issue(
                &["body", i, "crack", &k, "normal"],
                "the crack normal must be a finite non-zero vector",
            ));
        }
        finite3(&["body", i, "crack", &k, "point"], c.point)?;
        shape(scene, &["body", i, "crack", &k, "region"], &c.region)?;
    }
    Ok(())
}

/// A clamp of anchor `k` of body `i`: a finite point, a finite non-zero normal, a
/// fixed anchor, a peridynamic body. (Whether the normal points into the body is
/// checked at set-up, against the particles.)
fn clamp_spec(
    b: &BodySpec,
    i: &str,
    k: &str,
    velocity: [f64; 3],
    angular_velocity: [f64; 3],
    clamp: &ClampSpec,
) -> Check {
    let p = |key: &'static str| ["body", i, "anchor", k, "clamp", key];
    finite3(&p("point"), clamp.point)?;
    let n = clamp.normal;
    if !(n.iter().all(|x| x.is_finite()) && n.iter().map(|x| x * x).sum::<f64>() > 0.0) {
        return Err(issue(
            &p("normal"),
            format!(
                "the clamp's normal must be a finite non-zero vector pointing from the clamp \
                 into the free body, got {n:?}"
            ),
        ));
    }
    for (key, v) in [
        ("velocity", velocity),
        ("angular_velocity", angular_velocity),
    ] {
        if v != [0.0; 3] {
            return Err(issue(
                &["body", i, "anchor", k, key],
                format!(
                    "a clamp is fixed, got {key} = {v:?}: remove {key}, or remove clamp for a \
                     held region that moves"
                ),
            ));
        }
    }
    if b.model != ModelKind::Peridynamics {
        return Err(issue(
            &["body", i, "anchor", k, "clamp"],
            "a clamp is a ghost layer over the peridynamic horizon, for model = \"peridynamics\" \
             only: remove clamp (the held region's face is then the clamp)",
        ));
    }
    Ok(())
}

/// The FEM reference solvers are elastic and run a whole scene: no mixing with
/// peridynamic bodies, no plasticity, fracture, anisotropy, initial cracks or
/// Laplacian damping (which is defined over bonds).
fn fem(scene: &Scene) -> Check {
    let Some(first) = scene.bodies.iter().position(|b| b.model.is_fem()) else {
        return Ok(());
    };
    for (i, b) in scene.bodies.iter().enumerate() {
        let i = i.to_string();
        if !b.model.is_fem() {
            return Err(issue(
                &["body", &i, "model"],
                format!(
                    "body {first} uses a FEM model and this one peridynamics: a scene runs one solver, \
                     so give every body model = \"fem-linear\" or \"fem-corotated\", or none"
                ),
            ));
        }
        if !b.cracks.is_empty() {
            return Err(issue(
                &["body", &i, "crack"],
                "the FEM reference solvers cannot start cracked: remove [[body.crack]] or use peridynamics",
            ));
        }
        let m = &scene.materials[&b.material];
        let unsupported = bond_keys(m);
        if let Some((key, _)) = unsupported.iter().find(|(_, set)| *set) {
            return Err(issue(
                &["materials", &b.material, key],
                format!(
                    "body {i} uses a FEM reference solver, which is elastic with air damping only: \
                     remove {key} or use model = \"peridynamics\""
                ),
            ));
        }
    }
    Ok(())
}

fn shape(scene: &Scene, path: &[&str], s: &ShapeSpec) -> Check {
    let with = |key: &'static str| -> Vec<&str> {
        let mut v = path.to_vec();
        v.push(key);
        v
    };
    match s {
        ShapeSpec::Box { center, size } | ShapeSpec::Slab { center, size } => {
            finite3(&with("center"), *center)?;
            if !size.iter().all(|x| x.is_finite() && *x > 0.0) {
                return Err(issue(
                    &with("size"),
                    format!("every side must be positive, got {size:?}"),
                ));
            }
        }
        ShapeSpec::Sphere { center, radius } => {
            finite3(&with("center"), *center)?;
            positive(&with("radius"), *radius, "the radius")?;
        }
        ShapeSpec::Cylinder {
            center,
            radius,
            height,
            ..
        } => {
            finite3(&with("center"), *center)?;
            positive(&with("radius"), *radius, "the radius")?;
            positive(&with("height"), *height, "the height")?;
        }
        ShapeSpec::Union { parts } => {
            if parts.is_empty() {
                return Err(issue(&with("parts"), "a union needs at least one part"));
            }
            for (k, part) in parts.iter().enumerate() {
                let k = k.to_string();
                let mut p = with("parts");
                p.push(&k);
                shape(scene, &p, part)?;
            }
        }
        ShapeSpec::Difference { base, minus } => {
            shape(scene, &with("base"), base)?;
            shape(scene, &with("minus"), minus)?;
        }
        ShapeSpec::Mesh {
            path: file,
            scale,
            rotation,
            translation,
        } => {
            let factors = scale.factors();
            if !factors.iter().all(|s| s.is_finite() && *s != 0.0) {
                return Err(issue(
                    &with("scale"),
                    format!("every scale factor must be finite and non-zero, got {factors:?}"),
                ));
            }
            finite3(&with("rotation"), *rotation)?;
            finite3(&with("translation"), *translation)?;
            let full = scene.base_dir.join(file);
            if !scene.cached && !full.is_file() {
                return Err(issue(
                    &with("path"),
                    format!(
                        "mesh file {} does not exist (paths are relative to the scene file)",
                        full.display()
                    ),
                ));
            }
        }
    }
    Ok(())
}
