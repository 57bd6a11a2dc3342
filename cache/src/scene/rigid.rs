//! `[rigid]`: when a fragment leaves its model for the rigid phase, and how rigid
//! pieces collide (the simulator's `rigid` module).

use serde::{Deserialize, Serialize};

/// `[rigid]`: the hand-off of fragments that stopped breaking and vibrating to rigid
/// bodies, and the rigid solver's settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidSpec {
    /// Hand fragments of breaking peridynamic bodies to rigid bodies. Default false:
    /// a piece that goes rigid stops deforming and ringing, which a shot wants and a
    /// scene that measures the physics does not (docs/rigid.md); `perifrac check`
    /// suggests it for shots of 0.1 s or longer.
    #[serde(default)]
    pub enabled: bool,
    /// A fragment goes rigid only while every intact bond is below this fraction of
    /// what breaks it (its critical stretch, or its crushing strain). Default 0.95:
    /// glass pieces ring near their breaking strain for milliseconds after they break
    /// off (docs/rigid.md).
    #[serde(default = "default_margin")]
    pub margin: f64,
    /// ... and while the kinetic energy of its motion relative to its best-fit rigid
    /// motion is under this fraction of its kinetic energy (or that motion's amplitude
    /// is under `rest_amplitude`). Default 0.1.
    #[serde(default = "default_vibration")]
    pub vibration: f64,
    /// Amplitude of the motion relative to the best-fit rigid motion, in particle
    /// spacings, under which a fragment counts as still whatever its own speed: a
    /// piece standing after an impact rings at its own frequency, and what an artist
    /// sees of that ringing is its amplitude, v_rms L/(π c_p) for a piece of size L
    /// and P-wave speed c_p (its fundamental period 2L/c_p), not its speed.
    /// Default 0.05: a twentieth of a spacing (0.8 mm on the demo wall's 16 mm),
    /// below what a render shows, and above the 0.012 spacings at which the demo's
    /// largest glass piece still rang after 9 ms (glass barely damps it).
    #[serde(default = "default_rest_amplitude")]
    pub rest_amplitude: f64,
    /// How long both conditions must hold, in s. Default 2e-4.
    #[serde(default = "default_settle_time")]
    pub settle_time: f64,
    /// Fragments of at most this many particles go rigid, whatever their motion: a
    /// whole body at once, debris broken off a larger body as soon as nothing else
    /// deformable is left (with the last larger piece, so that the step can grow;
    /// until then it moves as particles, which costs less than rigid bodies stepped at
    /// the deformable bodies' step). Default 8.
    #[serde(default = "default_small_fragment")]
    pub small_fragment: usize,
    /// Steps between two looks for fragments to hand over. Default 32.
    #[serde(default = "default_check_every")]
    pub check_every: usize,
    /// The longest time step, in s, once no deformable particle is left (only rigid
    /// pieces move). Default 1/600.
    #[serde(default = "default_step")]
    pub step: f64,
    /// Coulomb friction of rigid pieces with each other, the ground and the colliders.
    /// Default 0.6.
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// Restitution of rigid pieces' impacts. Default 0.1.
    #[serde(default = "default_restitution")]
    pub restitution: f64,
    /// Coefficient of rolling resistance of rigid pieces in contact, a length in m:
    /// the normal force N of a piece's contact acts this far ahead of it, a couple
    /// of at most `rolling_resistance` × N against its spin relative to what it
    /// touches (rolling and spinning about the normal alike). Rapier's contacts have
    /// friction and restitution but no rolling resistance, so without it a chip
    /// spinning on the ground never stops and a piece spun up to hundreds of radians
    /// a second by sliding skips along the ground, turning its spin into bounces.
    /// Default 0.005 (5 mm: the faceted hulls leave the roughness of a shard's
    /// surface below a tet unresolved); 0 turns it off. A piece in flight feels
    /// nothing (docs/rigid.md, "Rolling resistance").
    #[serde(default = "default_rolling_resistance")]
    pub rolling_resistance: f64,
    /// Drag coefficient C_d of the air on rigid pieces in flight: each is slowed by
    /// ½ ρ_air C_d A |v| v, A the mean projected area of a cube of its volume (1.5
    /// V^{2/3}, Cauchy's S/4). Default 1.0, a tumbling irregular fragment's (a cube's
    /// is 0.8–1.05 by orientation); 0 turns the air off. A 16 mm glass grain thrown at
    /// 60 m/s loses half its speed in 0.7 s of flight, which without air it keeps until
    /// it lands and slides (docs/rigid.md, "Air").
    #[serde(default = "default_drag")]
    pub drag: f64,
    /// Density of the air, kg/m³. Default 1.2 (sea level, 20 °C).
    #[serde(default = "default_air_density")]
    pub air_density: f64,
    /// A rigid piece of more than `reenter_points` particles goes back to its model
    /// just before a hit that closes at this multiple of s_c c_p or faster (s_c its
    /// critical stretch, c_p its P-wave speed: a hit at s_c c_p sends a wave of
    /// strain s_c), so the hit breaks what it breaks; 2 catches the hits that break a
    /// glass piece for certain. Default 0: pieces stay rigid. Each piece that goes back
    /// puts the whole world back on its model's step while it rings, and at 2 the demo
    /// shot went from 4 minutes to more than 15 (docs/rigid.md, "Going back").
    #[serde(default = "default_reenter")]
    pub reenter: f64,
    /// Only pieces of more than this many particles go back when hit (a piece a few
    /// particles across has next to no interior to crack), and only hits by pieces of
    /// more than `small_fragment` count (debris breaks nothing). Default 100.
    #[serde(default = "default_reenter_points")]
    pub reenter_points: usize,
}

impl Default for RigidSpec {
    fn default() -> Self {
        RigidSpec {
            enabled: false,
            margin: default_margin(),
            vibration: default_vibration(),
            rest_amplitude: default_rest_amplitude(),
            settle_time: default_settle_time(),
            small_fragment: default_small_fragment(),
            check_every: default_check_every(),
            step: default_step(),
            friction: default_friction(),
            restitution: default_restitution(),
            rolling_resistance: default_rolling_resistance(),
            drag: default_drag(),
            air_density: default_air_density(),
            reenter: default_reenter(),
            reenter_points: default_reenter_points(),
        }
    }
}

fn default_margin() -> f64 {
    0.95
}
fn default_vibration() -> f64 {
    0.1
}
fn default_rest_amplitude() -> f64 {
    0.05
}
fn default_settle_time() -> f64 {
    2e-4
}
fn default_small_fragment() -> usize {
    8
}
fn default_check_every() -> usize {
    32
}
fn default_step() -> f64 {
    1.0 / 600.0
}
fn default_friction() -> f64 {
    0.6
}
fn default_restitution() -> f64 {
    0.1
}
fn default_rolling_resistance() -> f64 {
    0.005
}
fn default_drag() -> f64 {
    1.0
}
fn default_air_density() -> f64 {
    1.2
}
fn default_reenter() -> f64 {
    0.0
}
fn default_reenter_points() -> usize {
    100
}
