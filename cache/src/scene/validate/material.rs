//! The checks of a `[materials.NAME]` table (Chen Table 1's constants, fracture,
//! plasticity, damping), and the keys only a bonded model reads.

use super::*;

/// The checks of material `name`: positive density and moduli (or E and ν), yield,
/// fracture and damping keys in range.
pub(super) fn material(name: &str, m: &MaterialSpec) -> Check {
    let p = |key: &'static str| ["materials", name, key];
    positive(&p("density"), m.density, "density (kg/m³)")?;
    match (
        m.bulk_modulus,
        m.shear_modulus,
        m.youngs_modulus,
        m.poisson_ratio,
    ) {
        (Some(k), Some(mu), None, None) => {
            positive(&p("bulk_modulus"), k, "the bulk modulus (Pa)")?;
            positive(&p("shear_modulus"), mu, "the shear modulus (Pa)")?;
            let nu = (3.0 * k - 2.0 * mu) / (2.0 * (3.0 * k + mu));
            if nu <= -1.0 || nu >= 0.5 {
                return Err(issue(
                    &p("shear_modulus"),
                    format!("κ and μ give a Poisson ratio of {nu}, outside (−1, 0.5)"),
                ));
            }
        }
        (None, None, Some(e), Some(nu)) => {
            positive(&p("youngs_modulus"), e, "Young's modulus (Pa)")?;
            if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
                return Err(issue(
                    &p("poisson_ratio"),
                    format!(
                        "the Poisson ratio must be in (−1, 0.5) (0.5 is incompressible, which an explicit solver cannot step), got {nu}"
                    ),
                ));
            }
        }
        _ => {
            return Err(issue(
                &["materials", name],
                "give either bulk_modulus and shear_modulus, or youngs_modulus and poisson_ratio",
            ));
        }
    }
    match (m.yield_psi0, m.yield_stretch) {
        (Some(_), Some(_)) => {
            return Err(issue(
                &p("yield_stretch"),
                "give yield_psi0 or yield_stretch, not both",
            ));
        }
        (Some(v), None) => positive(&p("yield_psi0"), v, "Ψ0")?,
        (None, Some(v)) => positive(&p("yield_stretch"), v, "the yield stretch")?,
        (None, None) => {}
    }
    if m.plastic_limit.is_nan() || m.plastic_limit < 0.0 {
        return Err(issue(
            &p("plastic_limit"),
            format!("γ/|ξ| must be ≥ 0 (or inf), got {}", m.plastic_limit),
        ));
    }
    if let Some(s) = m.critical_stretch {
        positive(&p("critical_stretch"), s, "the critical stretch")?;
    }
    if let Some(s) = m.critical_compression {
        positive(&p("critical_compression"), s, "the critical compression")?;
        if s >= 1.0 {
            return Err(issue(
                &p("critical_compression"),
                format!(
                    "{s} is a compressive strain of 100% or more, which no bond reaches: \
                     give a strain below 1 (about 0.01 for glass) or remove the key"
                ),
            ));
        }
        if m.critical_stretch.is_none() {
            return Err(issue(
                &p("critical_compression"),
                "a material that crushes must also break in tension: set critical_stretch \
                 (typically 1/10 to 1/20 of critical_compression for a brittle solid)"
                    .to_string(),
            ));
        }
    }
    if !(m.alpha.is_finite() && m.alpha >= 0.0) {
        return Err(issue(
            &p("alpha"),
            format!("α must be ≥ 0, got {}", m.alpha),
        ));
    }
    if let Some(g) = m.anisotropy {
        let det = g[0][0] * (g[1][1] * g[2][2] - g[1][2] * g[2][1])
            - g[0][1] * (g[1][0] * g[2][2] - g[1][2] * g[2][0])
            + g[0][2] * (g[1][0] * g[2][1] - g[1][1] * g[2][0]);
        if !(det.is_finite() && det.abs() > 1e-12) {
            return Err(issue(
                &p("anisotropy"),
                "the anisotropy matrix G must be finite and invertible",
            ));
        }
    }
    if let Some(c) = &m.color {
        c.srgb().map_err(|message| issue(&p("color"), message))?;
    }
    for (key, v) in [
        ("air_damping", m.air_damping),
        ("laplacian_damping", m.laplacian_damping),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(issue(
                &p(key),
                format!("a damping rate (1/s) must be ≥ 0, got {v}"),
            ));
        }
    }
    Ok(())
}

/// The material keys only a bonded (peridynamic) model reads, each with whether the
/// material sets it: the FEM and MPM refuse a set one by name.
pub(super) fn bond_keys(m: &MaterialSpec) -> [(&'static str, bool); 6] {
    [
        ("yield_psi0", m.yield_psi0.is_some()),
        ("yield_stretch", m.yield_stretch.is_some()),
        ("critical_stretch", m.critical_stretch.is_some()),
        ("critical_compression", m.critical_compression.is_some()),
        ("anisotropy", m.anisotropy.is_some()),
        ("laplacian_damping", m.laplacian_damping != 0.0),
    ]
}
