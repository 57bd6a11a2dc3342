//! The checks of MPM bodies and their materials (Lyu 2021).

use super::*;

/// The material point method runs a whole scene (its bodies share one grid) and has
/// no bonds: no mixing with other models, no initial cracks, no bond parameters.
pub(super) fn mpm(scene: &Scene) -> Check {
    let Some(first) = scene.bodies.iter().position(|b| b.model == ModelKind::Mpm) else {
        if scene.mpm.is_some() {
            return Err(issue(
                &["mpm"],
                "[mpm] sets the grid of model = \"mpm\" bodies and this scene has none: remove it",
            ));
        }
        return Ok(());
    };
    if let Some(settings) = &scene.mpm
        && !(0.0..=1.0).contains(&settings.flip_ratio)
    {
        return Err(issue(
            &["mpm", "flip_ratio"],
            format!(
                "FLIP's share must lie in [0, 1] (0 is PIC), got {}",
                settings.flip_ratio
            ),
        ));
    }
    for (i, b) in scene.bodies.iter().enumerate() {
        let i = i.to_string();
        if b.model != ModelKind::Mpm {
            return Err(issue(
                &["body", &i, "model"],
                format!(
                    "body {first} uses model = \"mpm\" and this one does not: a scene runs one solver, \
                     so give every body model = \"mpm\" or none"
                ),
            ));
        }
        if !b.cracks.is_empty() {
            return Err(issue(
                &["body", &i, "crack"],
                "MPM bodies have no bonds to cut: remove [[body.crack]] or use peridynamics",
            ));
        }
        let m = &scene.materials[&b.material];
        let mut unsupported = bond_keys(m).to_vec();
        unsupported.push(("air_damping", m.air_damping != 0.0));
        if let Some((key, _)) = unsupported.iter().find(|(_, set)| *set) {
            return Err(issue(
                &["materials", &b.material, key],
                format!(
                    "body {i} uses model = \"mpm\", whose materials are set in [materials.{}.mpm]: \
                     remove {key} or use model = \"peridynamics\"",
                    b.material
                ),
            ));
        }
        if let Some(spec) = &m.mpm {
            mpm_material(&b.material, spec)?;
        }
    }
    Ok(())
}

/// The keys of one `[materials.NAME.mpm]`.
fn mpm_material(name: &str, spec: &MpmSpec) -> Check {
    let at = |key: &'static str| ["materials", name, "mpm", key];
    let shock = spec.elasticity == MpmElasticity::Shock;
    match spec.bulk_sound_speed {
        Some(c) => {
            if !shock {
                return Err(issue(
                    &at("bulk_sound_speed"),
                    "the bulk sound speed is read by elasticity = \"shock\" only: remove it or set that elasticity",
                ));
            }
            positive(&at("bulk_sound_speed"), c, "the bulk sound speed c₀ (m/s)")?;
        }
        None if shock => {
            return Err(issue(
                &at("bulk_sound_speed"),
                "elasticity = \"shock\" needs the bulk sound speed c₀ of its Mie–Grüneisen \
                 pressure (Lyu Eq. 7.4): add bulk_sound_speed = <m/s>",
            ));
        }
        None => {}
    }
    if !(spec.shock_slope.is_finite() && spec.shock_slope >= 1.0) {
        return Err(issue(
            &at("shock_slope"),
            format!(
                "the slope S of v_s = c₀ + S v_p must be finite and at least 1 (1.1 in the thesis), got {}",
                spec.shock_slope
            ),
        ));
    }
    positive(
        &at("gruneisen"),
        spec.gruneisen,
        "the Grüneisen parameter γ",
    )?;
    fracture(name, spec)?;
    bonds(name, spec)?;
    let plastic = |key: &'static str| ["materials", name, "mpm", "plasticity", key];
    match spec.plasticity {
        MpmPlasticity::None => {}
        MpmPlasticity::JohnsonCook {
            yield_stress,
            hardening,
            exponent,
            rate_coefficient,
            reference_rate,
            melting_temperature,
            room_temperature,
            thermal_exponent,
            specific_heat,
            taylor_quinney,
        } => {
            let thermal = [
                ("melting_temperature", melting_temperature),
                ("room_temperature", room_temperature),
                ("thermal_exponent", thermal_exponent),
                ("specific_heat", specific_heat),
            ];
            let given: Vec<&str> = thermal
                .iter()
                .filter(|(_, v)| v.is_some())
                .map(|(k, _)| *k)
                .collect();
            if let Some((missing, _)) = thermal.iter().find(|(_, v)| v.is_none())
                && let Some(first) = given.first()
            {
                return Err(issue(
                    &plastic(first),
                    format!(
                        "the thermal Johnson–Cook term needs melting_temperature, room_temperature, \
                         thermal_exponent and specific_heat together: add {missing} or remove {}",
                        given.join(", ")
                    ),
                ));
            }
            if given.is_empty() && taylor_quinney.is_some() {
                return Err(issue(
                    &plastic("taylor_quinney"),
                    "the Taylor–Quinney fraction heats the thermal Johnson–Cook term only: add \
                     melting_temperature, room_temperature, thermal_exponent and specific_heat, \
                     or remove taylor_quinney",
                ));
            }
            if let (Some(melt), Some(room), Some(m), Some(c)) = (
                melting_temperature,
                room_temperature,
                thermal_exponent,
                specific_heat,
            ) {
                positive(
                    &plastic("room_temperature"),
                    room,
                    "the room temperature (K)",
                )?;
                if !(melt.is_finite() && melt > room) {
                    return Err(issue(
                        &plastic("melting_temperature"),
                        format!(
                            "the melting temperature must be finite and above the room temperature \
                             ({room} K), in K, got {melt}"
                        ),
                    ));
                }
                positive(&plastic("thermal_exponent"), m, "the thermal exponent m")?;
                positive(&plastic("specific_heat"), c, "the specific heat (J/(kg K))")?;
                let beta = taylor_quinney.unwrap_or(0.9);
                if !(0.0..=1.0).contains(&beta) {
                    return Err(issue(
                        &plastic("taylor_quinney"),
                        format!(
                            "the Taylor–Quinney fraction of plastic work turned into heat must lie in [0, 1], got {beta}"
                        ),
                    ));
                }
            }
            positive(
                &plastic("yield_stress"),
                yield_stress,
                "the yield stress A (Pa)",
            )?;
            for (key, value, what) in [
                ("hardening", hardening, "the hardening coefficient B (Pa)"),
                ("exponent", exponent, "the hardening exponent n"),
                (
                    "rate_coefficient",
                    rate_coefficient,
                    "the strain-rate coefficient C",
                ),
            ] {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(issue(
                        &plastic(key),
                        format!("{what} must be finite and non-negative, got {value}"),
                    ));
                }
            }
            if exponent > 1.0 {
                return Err(issue(
                    &plastic("exponent"),
                    format!(
                        "the hardening exponent n must lie in [0, 1] (Lyu §7.4.2), got {exponent}"
                    ),
                ));
            }
            positive(
                &plastic("reference_rate"),
                reference_rate,
                "the reference plastic strain rate ε̇₀ (1/s)",
            )?;
        }
        MpmPlasticity::Snow {
            critical_compression,
            critical_stretch,
        } => {
            if !(critical_compression > 0.0 && critical_compression < 1.0) {
                return Err(issue(
                    &plastic("critical_compression"),
                    format!(
                        "θ_c must lie in (0, 1) (singular values are clamped to [1 − θ_c, 1 + θ_s]), got {critical_compression}"
                    ),
                ));
            }
            positive(&plastic("critical_stretch"), critical_stretch, "θ_s")?;
        }
        MpmPlasticity::DruckerPrager { friction_angle } => {
            if !(friction_angle > 0.0 && friction_angle < 90.0) {
                return Err(issue(
                    &plastic("friction_angle"),
                    format!(
                        "the friction angle is in degrees and must lie in (0, 90), got {friction_angle}"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The SPB-MPM keys of one `[materials.NAME.mpm]` (Lyu ch. 6).
fn fracture(name: &str, spec: &MpmSpec) -> Check {
    let at = |key: &'static str| ["materials", name, "mpm", key];
    let Some(g) = spec.energy_release_rate else {
        if spec.erosion_release_rate.is_some() {
            return Err(issue(
                &at("erosion_release_rate"),
                "eigenerosion turns particles peridynamic for SPB-MPM fracture, which \
                 energy_release_rate turns on: add energy_release_rate = <J/m²> or remove \
                 erosion_release_rate",
            ));
        }
        return Ok(());
    };
    positive(
        &at("energy_release_rate"),
        g,
        "the energy release rate G_p of the bonds (J/m²)",
    )?;
    if let Some(erosion) = spec.erosion_release_rate {
        positive(
            &at("erosion_release_rate"),
            erosion,
            "the released energy at which a cell erodes (J/m²)",
        )?;
    }
    Ok(())
}

/// The integral-based MPM's keys of one `[materials.NAME.mpm]` (Lyu ch. 5): its bonds
/// replace the stress of `elasticity`, the plastic flow of `plasticity` and SPB-MPM's
/// fracture, so those keys would be ignored and are refused instead.
fn bonds(name: &str, spec: &MpmSpec) -> Check {
    let Some(bonds) = spec.bonds else {
        return Ok(());
    };
    let at = |key: &'static str| ["materials", name, "mpm", key];
    let replaced = [
        ("elasticity", spec.elasticity != MpmElasticity::default()),
        ("plasticity", spec.plasticity != MpmPlasticity::None),
        ("energy_release_rate", spec.energy_release_rate.is_some()),
    ];
    if let Some((key, _)) = replaced.iter().find(|(_, set)| *set) {
        return Err(issue(
            &at(key),
            format!(
                "[materials.{name}.mpm.bonds] computes the forces from bonds (Lyu ch. 5), which \
                 have their own elasticity, yield and failure: remove {key}, or remove the bonds \
                 table to use {key}"
            ),
        ));
    }
    let keys = |key: &'static str| ["materials", name, "mpm", "bonds", key];
    if let Some(yield_stress) = bonds.yield_stress {
        positive(
            &keys("yield_stress"),
            yield_stress,
            "the bonds' yield stress σ_Y (Pa)",
        )?;
    }
    if let Some(stretch) = bonds.critical_stretch {
        positive(
            &keys("critical_stretch"),
            stretch,
            "the critical elastic stretch of a bond",
        )?;
    }
    if let Some(viscosity) = bonds.viscosity {
        positive(
            &keys("viscosity"),
            viscosity,
            "the bonds' shear viscosity η (Pa·s)",
        )?;
    }
    Ok(())
}
