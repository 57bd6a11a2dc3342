//! The checks of membrane bodies and their sources (Han et al.).

use super::*;

/// The diffused quantity's initial value and the sources and sinks of membrane body
/// `i`: finite values, one effect per source (a rate or a held value), a time window
/// that opens, a region that is a valid shape, spots that exist.
fn sources(scene: &Scene, i: &str, spec: &MembraneSpec) -> Check {
    if !spec.quantity.is_finite() {
        return Err(issue(
            &["body", i, "membrane", "quantity"],
            format!("the initial quantity must be finite, got {}", spec.quantity),
        ));
    }
    for (k, source) in spec.sources.iter().enumerate() {
        let k = k.to_string();
        let p = |key: &'static str| ["body", i, "membrane", "source", k.as_str(), key];
        match (source.rate, source.value) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(issue(
                    &["body", i, "membrane", "source", &k],
                    "give a source exactly one of rate (θ per second added; negative is a \
                     sink) and value (θ held there)",
                ));
            }
            (Some(x), None) | (None, Some(x)) if !x.is_finite() => {
                let key = if source.rate.is_some() {
                    "rate"
                } else {
                    "value"
                };
                return Err(issue(&p(key), format!("must be finite, got {x}")));
            }
            _ => {}
        }
        if !(source.start.is_finite() && source.start >= 0.0) {
            return Err(issue(
                &p("start"),
                format!("the start time must be ≥ 0 s, got {}", source.start),
            ));
        }
        if source.until.is_nan() || source.until <= source.start {
            return Err(issue(
                &p("until"),
                format!(
                    "the source stops before it starts (start = {} s, until = {} s): \
                     give until > start, or leave it out for a source that never stops",
                    source.start, source.until
                ),
            ));
        }
        if let Some(region) = &source.region {
            shape(scene, &p("region"), region)?;
        }
        if let Some(scatter) = &source.scatter {
            if scatter.count == 0 {
                return Err(issue(
                    &["body", i, "membrane", "source", &k, "scatter", "count"],
                    "a scattered source needs at least one spot",
                ));
            }
            positive(
                &["body", i, "membrane", "source", &k, "scatter", "radius"],
                scatter.radius,
                "the spot radius (m)",
            )?;
        }
    }
    Ok(())
}

/// Membranes (Han et al. 2021) run a whole scene; their shape is a sheet (a box or
/// slab, a cylinder, or a mesh with its thickness), their materials use neither plasticity, Chen's fracture,
/// anisotropy nor Laplacian damping; membrane keys belong to membranes only.
pub(super) fn membrane(scene: &Scene) -> Check {
    let first = scene
        .bodies
        .iter()
        .position(|b| b.model == ModelKind::Membrane);
    for (i, b) in scene.bodies.iter().enumerate() {
        let i = i.to_string();
        let is_membrane = b.model == ModelKind::Membrane;
        if b.lattice.is_some() && matches!(b.model, ModelKind::Membrane | ModelKind::Mpm) {
            return Err(issue(
                &["body", &i, "lattice"],
                "`lattice` chooses how the body is tet-meshed, and membranes and MPM bodies are not tet-meshed: remove it",
            ));
        }
        if let Some(first) = first.filter(|_| !is_membrane) {
            return Err(issue(
                &["body", &i, "model"],
                format!(
                    "body {first} is a membrane and this one is not: a scene runs one solver, \
                     so give every body model = \"membrane\" or none"
                ),
            ));
        }
        if !is_membrane {
            if b.membrane.is_some() {
                return Err(issue(
                    &["body", &i, "membrane"],
                    "[body.membrane] is for model = \"membrane\" only",
                ));
            }
            if scene.materials[&b.material].membrane.is_some() {
                return Err(issue(
                    &["materials", &b.material, "membrane"],
                    format!(
                        "body {i} is not a membrane: [materials.{}.membrane] is for model = \"membrane\" only",
                        b.material
                    ),
                ));
            }
            continue;
        }
        let thickness = b.membrane.as_ref().and_then(|m| m.thickness);
        match (&b.shape, thickness) {
            (ShapeSpec::Box { .. } | ShapeSpec::Slab { .. } | ShapeSpec::Cylinder { .. }, None) => {
            }
            (ShapeSpec::Mesh { .. }, Some(t)) if t.is_finite() && t > 0.0 => {}
            (ShapeSpec::Mesh { .. }, Some(t)) => {
                return Err(issue(
                    &["body", &i, "membrane", "thickness"],
                    format!("the sheet thickness must be a positive length in m, got {t}"),
                ));
            }
            (ShapeSpec::Mesh { .. }, None) => {
                return Err(issue(
                    &["body", &i, "membrane", "thickness"],
                    "a membrane given by a mesh needs its sheet thickness: add \
                     [body.membrane] thickness = … (m)",
                ));
            }
            (
                ShapeSpec::Box { .. } | ShapeSpec::Slab { .. } | ShapeSpec::Cylinder { .. },
                Some(_),
            ) => {
                return Err(issue(
                    &["body", &i, "membrane", "thickness"],
                    "a box, slab or cylinder membrane takes its thickness from its shape (the \
                     smallest side, the height): remove thickness, which is for mesh sheets",
                ));
            }
            _ => {
                return Err(issue(
                    &["body", &i, "shape"],
                    "a membrane is a rectangle (type = \"box\" or \"slab\": the smallest side is the \
                     thickness), a disc (type = \"cylinder\": the height is the thickness) or a \
                     triangle mesh (type = \"mesh\", open or closed, with [body.membrane] thickness)",
                ));
            }
        }
        if let Some(spec) = &b.membrane
            && !(spec.cutoff.is_finite() && (1.0..=4.0).contains(&spec.cutoff))
        {
            return Err(issue(
                &["body", &i, "membrane", "cutoff"],
                format!(
                    "the cutoff R must be in [1, 4] particle spacings (below 1 no particle has a \
                     neighbour, above 4 the bonds grow as R²), got {}",
                    spec.cutoff
                ),
            ));
        }
        if let Some(spec) = &b.membrane {
            sources(scene, &i, spec)?;
        }
        let m = &scene.materials[&b.material];
        let state = b
            .membrane
            .as_ref()
            .is_some_and(|s| s.membrane_model == MembraneFormulation::State);
        let law = m.membrane.as_ref().map(|s| s.law).unwrap_or_default();
        if state && law != MembraneLaw::Linear {
            return Err(issue(
                &["materials", &b.material, "membrane", "law"],
                format!(
                    "body {i} uses membrane_model = \"state\", which is linear elastic: remove \
                     law (the rubber and elastoplastic laws are bond laws, membrane_model = \"bond\")"
                ),
            ));
        }
        let unsupported = [
            ("yield_psi0", m.yield_psi0.is_some()),
            ("yield_stretch", m.yield_stretch.is_some()),
            ("critical_stretch", m.critical_stretch.is_some()),
            ("critical_compression", m.critical_compression.is_some()),
            ("alpha", m.alpha != 0.0),
            ("anisotropy", m.anisotropy.is_some()),
            ("laplacian_damping", m.laplacian_damping != 0.0),
        ];
        if let Some((key, _)) = unsupported.iter().find(|(_, set)| *set) {
            return Err(issue(
                &["materials", &b.material, key],
                format!(
                    "body {i} is a membrane, whose fracture is set by [materials.{}.membrane] \
                     fracture_energy and which has no plasticity, anisotropy or Laplacian damping: \
                     remove {key}",
                    b.material
                ),
            ));
        }
        if let Some(spec) = &m.membrane {
            let p = |key: &'static str| ["materials", b.material.as_str(), "membrane", key];
            if let Some(g) = spec.fracture_energy {
                positive(&p("fracture_energy"), g, "the fracture energy G_f (J/m²)")?;
            }
            positive(
                &p("diffusion_capacity"),
                spec.diffusion_capacity,
                "the diffusive capacity C (J/(kg·unit))",
            )?;
            if !(spec.diffusion_conductivity.is_finite() && spec.diffusion_conductivity >= 0.0) {
                return Err(issue(
                    &p("diffusion_conductivity"),
                    format!(
                        "the diffusion coefficient k must be ≥ 0 W/(m·unit), got {}",
                        spec.diffusion_conductivity
                    ),
                ));
            }
            if !(spec.expansion.is_finite() && spec.expansion.abs() < 1e3) {
                return Err(issue(
                    &p("expansion"),
                    format!(
                        "the expansion coefficient α must be finite, |α| < 1000 per unit, got {}",
                        spec.expansion
                    ),
                ));
            }
            if !(spec.rubber_coefficient.is_finite() && spec.rubber_coefficient <= 0.0) {
                return Err(issue(
                    &p("rubber_coefficient"),
                    format!(
                        "c*/c of Eq. 19 must be ≤ 0, got {}",
                        spec.rubber_coefficient
                    ),
                ));
            }
            if !(spec.rubber_exponent.is_finite() && spec.rubber_exponent > 1.0) {
                return Err(issue(
                    &p("rubber_exponent"),
                    format!("n of Eq. 19 must be > 1, got {}", spec.rubber_exponent),
                ));
            }
            if !(spec.elastic_limit.is_finite()
                && spec.elastic_limit > 0.0
                && spec.elastic_limit < 1.0)
            {
                return Err(issue(
                    &p("elastic_limit"),
                    format!(
                        "η₀ of Eq. 20 must be in (0, 1) (a strain), got {}",
                        spec.elastic_limit
                    ),
                ));
            }
            positive(&p("softening"), spec.softening, "β of Eq. 20")?;
        }
    }
    Ok(())
}
