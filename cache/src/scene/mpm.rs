//! `[materials.NAME.mpm]` and `[mpm]`: the material point method's keys (Lyu 2021).

use serde::{Deserialize, Serialize};

/// `[materials.NAME.mpm]`: how a material behaves in the material point method
/// (Lyu 2021 ch. 3 and 7).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpmSpec {
    /// Elastic energy: `"fixed-corotated"` (Eq. 3.5), `"neo-hookean"` (Eq. 3.8),
    /// `"stable-neo-hookean"` (Eq. 7.1–7.2) or `"shock"` (stable Neo-Hookean shear with
    /// the Mie–Grüneisen pressure, Eq. 7.3–7.4). Default `"fixed-corotated"`.
    #[serde(default)]
    pub elasticity: MpmElasticity,
    /// Bulk sound speed c₀ of the Mie–Grüneisen pressure (m/s, Eq. 7.4); required
    /// with `elasticity = "shock"`, refused otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bulk_sound_speed: Option<f64>,
    /// Slope S of the shock–particle velocity relation v_s = c₀ + S v_p (Eq. 7.4).
    /// Default 1.1 (the thesis' value).
    #[serde(default = "default_shock_slope")]
    pub shock_slope: f64,
    /// Grüneisen parameter γ (Eq. 7.4). Default 1.6 (the thesis' value).
    #[serde(default = "default_gruneisen")]
    pub gruneisen: f64,
    /// Plastic flow (`[materials.NAME.mpm.plasticity]`, with a `type`). Default none.
    #[serde(default)]
    pub plasticity: MpmPlasticity,
    /// Critical energy release rate G_p of the peridynamic bonds (J/m², Lyu Eq.
    /// 6.12): given, the material fractures by SPB-MPM (Lyu ch. 6), its particles
    /// turning peridynamic where the grid's released energy erodes a cell. Default
    /// none (the material never fractures).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy_release_rate: Option<f64>,
    /// The released energy G_i at which eigenerosion turns a cell's particles
    /// peridynamic (J/m², Lyu Eq. 6.10). Default: `energy_release_rate` (the thesis:
    /// "theoretically the same"); lower makes the peridynamic region grow ahead of
    /// the crack.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub erosion_release_rate: Option<f64>,
    /// `[materials.NAME.mpm.bonds]`: the integral-based MPM (Lyu ch. 5), internal
    /// forces from peridynamic bonds between the material points instead of the
    /// stress divergence. Default none (the stress of `elasticity`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bonds: Option<MpmBonds>,
}

/// `[materials.NAME.mpm.bonds]`: the integral-based MPM's bonds (Lyu ch. 5). Their
/// energy (Eq. 5.5) takes λ and μ from the material's Young's modulus and Poisson
/// ratio.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpmBonds {
    /// The bonds' yield stress σ_Y (Pa): a bond flows where its deviatoric stress
    /// (2μ + λ)(e_dev − e_p) passes ±σ_Y (Eq. 5.10 with ψ_p = σ_Y²/2), about the
    /// uniaxial yield stress. Default none (elastic bonds).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_stress: Option<f64>,
    /// The critical elastic stretch l_threshold (Eq. 5.21) at which a bond breaks,
    /// raised by the share of broken bonds in its grid cell. Default none (bonds
    /// never break).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub critical_stretch: Option<f64>,
    /// The bonds' shear viscosity η (Pa·s): a viscoelastic (Maxwell) material whose
    /// bonds' stress beyond `yield_stress` (beyond 0 without one) relaxes with the
    /// time τ = η/G, G = (λ + 2μ)/3, while a volume term keeps its volume: honey, or
    /// with a yield stress whipped cream (Lyu §5.3.3, Fig. 5.10–5.11). Default none
    /// (no viscous flow).
    pub viscosity: Option<f64>,
}

impl Default for MpmSpec {
    fn default() -> MpmSpec {
        MpmSpec {
            elasticity: MpmElasticity::default(),
            bulk_sound_speed: None,
            shock_slope: default_shock_slope(),
            gruneisen: default_gruneisen(),
            plasticity: MpmPlasticity::default(),
            energy_release_rate: None,
            erosion_release_rate: None,
            bonds: None,
        }
    }
}

fn default_shock_slope() -> f64 {
    1.1
}
fn default_gruneisen() -> f64 {
    1.6
}
fn default_reference_rate() -> f64 {
    1.0
}

/// The elastic energy density ψ(F) of an MPM material.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MpmElasticity {
    /// Fixed corotated, ψ = μ‖F − R‖² + λ/2 (J − 1)² (Lyu Eq. 3.5): defined when
    /// inverted.
    #[default]
    FixedCorotated,
    /// Neo-Hookean, ψ = μ/2 (tr FᵀF − 3) − μ log J + λ/2 (log J)² (Lyu Eq. 3.8).
    NeoHookean,
    /// Stable Neo-Hookean (Smith et al. 2018; Lyu Eq. 7.1), ψ = μ/2 (I_C − 3) +
    /// λ/2 (J − α)² − μ/2 log(I_C + 1): defined when inverted.
    StableNeoHookean,
    /// The shock-wave model (Lyu §7.2.2): the deviatoric Cauchy stress of the stable
    /// Neo-Hookean energy and the Mie–Grüneisen pressure (Eq. 7.4) of J and the
    /// internal energy (Eq. 7.3).
    Shock,
}

/// `[materials.NAME.mpm.plasticity]`: the plastic flow of an MPM material.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MpmPlasticity {
    /// Purely elastic.
    #[default]
    None,
    /// J2 flow with Johnson–Cook hardening by radial return (Lyu Eq. 7.5–7.8, App.
    /// B): σ_y = (A + B (ε^p)ⁿ)(1 + C ln(ε̇^p/ε̇₀)), times the thermal factor
    /// (1 − T*^m), T* = (T − T_room)/(T_melt − T_room) of Johnson & Cook (1983) when
    /// the four temperature keys are given (all or none), with the particle heated by
    /// ΔT = β σ_y Δε^p/(ρ c).
    JohnsonCook {
        /// Yield stress A (Pa).
        yield_stress: f64,
        /// Strain hardening coefficient B (Pa). Default 0.
        #[serde(default)]
        hardening: f64,
        /// Strain hardening exponent n (0: perfectly plastic). Default 0.
        #[serde(default)]
        exponent: f64,
        /// Strain-rate hardening coefficient C. Default 0.
        #[serde(default)]
        rate_coefficient: f64,
        /// Reference equivalent plastic strain rate ε̇₀ (1/s). Default 1 (the thesis').
        #[serde(default = "default_reference_rate")]
        reference_rate: f64,
        /// Melting temperature T_melt (K), where σ_y reaches 0. With
        /// `room_temperature`, `thermal_exponent` and `specific_heat`, it turns on the
        /// thermal term; without them the thesis' form (no temperature) is used.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        melting_temperature: Option<f64>,
        /// Room temperature T_room (K): the particles' initial temperature, below which
        /// the thermal factor is 1.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        room_temperature: Option<f64>,
        /// Thermal softening exponent m of (1 − T*^m).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        thermal_exponent: Option<f64>,
        /// Specific heat c (J/(kg K)) of the adiabatic heating.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        specific_heat: Option<f64>,
        /// Taylor–Quinney fraction β of the plastic work turned into heat, in [0, 1].
        /// Default 0.9 (with the thermal keys only).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        taylor_quinney: Option<f64>,
    },
    /// Snow (Stomakhin et al. 2013; Lyu §3.3.3): the singular values of the elastic
    /// deformation gradient clamped to [1 − θ_c, 1 + θ_s].
    Snow {
        /// Critical compression θ_c, in (0, 1).
        critical_compression: f64,
        /// Critical stretch θ_s, positive.
        critical_stretch: f64,
    },
    /// Drucker–Prager (Klár et al. 2016) on the Hencky strain of the elastic
    /// deformation gradient: sand-like, no cohesion.
    DruckerPrager {
        /// Friction angle φ in degrees, in (0, 90).
        friction_angle: f64,
    },
}

/// `[mpm]`: settings of the MPM grid shared by every MPM body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpmSettings {
    /// Particle–grid velocity transfer: `"apic"` (affine, conserves angular momentum)
    /// or `"pic-flip"` (a blend of PIC and FLIP by `flip_ratio`). Default `"apic"`.
    #[serde(default)]
    pub transfer: MpmTransfer,
    /// FLIP's share α of the `"pic-flip"` blend, in [0, 1] (0: PIC). Default 0.95.
    #[serde(default = "default_flip_ratio")]
    pub flip_ratio: f64,
}

impl Default for MpmSettings {
    fn default() -> MpmSettings {
        MpmSettings {
            transfer: MpmTransfer::default(),
            flip_ratio: default_flip_ratio(),
        }
    }
}

fn default_flip_ratio() -> f64 {
    0.95
}

/// How velocities move between MPM particles and the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MpmTransfer {
    /// APIC (Jiang et al. 2015), the MLS-MPM default.
    #[default]
    Apic,
    /// PIC/FLIP blend: v_p ← α (v_p + Σ w_ip Δv_i) + (1 − α) Σ w_ip v_i.
    PicFlip,
}
