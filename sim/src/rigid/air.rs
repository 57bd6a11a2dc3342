//! The air on rigid pieces in flight (docs/rigid.md, "Air").

use super::RigidPhase;

impl RigidPhase {
    /// The air's drag on each awake piece over a step of `dt`: the force ½ ρ_air C_d
    /// A |v| v, A = 1.5 V^{2/3} the mean projected area (Cauchy: a convex body's is a
    /// quarter of its surface; here a cube's of the piece's volume V), given as the
    /// impulse that brings v to the exact solution of
    /// m v̇ = −½ ρ C_d A |v| v over the step, v/(1 + k|v|Δt) with k = ρ C_d A / 2m, so
    /// it never reverses a velocity however long the step. The spin is left alone.
    pub(super) fn drag(&mut self, dt: f64) {
        let s = &self.settings;
        let c = 0.5 * s.air_density * s.drag;
        if c == 0.0 {
            return;
        }
        for piece in &self.pieces {
            let body = &mut self.physics.bodies[piece.body];
            if body.is_sleeping() || !body.is_dynamic() {
                continue;
            }
            let v = *body.linvel();
            let speed = v.norm();
            if speed == 0.0 {
                continue;
            }
            let area = 1.5 * piece.volume.powf(2.0 / 3.0);
            let k = c * area / body.mass();
            let slowed = v / (1.0 + k * speed * dt);
            body.apply_impulse((slowed - v) * body.mass(), false);
        }
    }
}
