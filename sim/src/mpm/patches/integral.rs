//! The integral-based MPM (Lyu 2021 ch. 5): every material point of a body carries
//! peridynamic bonds from the start, and the grid's internal forces come from the
//! bond force states, f_i = Σ_p w_ip V_p Σ_q (T_p⟨q⟩ − T_q⟨p⟩) V_q (Eq. 5.2–5.3, 5.7),
//! instead of the stress divergence. The forces reach the grid as SPB-MPM's do (Δt
//! f_p / m_p on v_p before P2G, which P2G spreads by w_ip: Eq. 5.2); the families,
//! their storage, the fragments and the checkpoint are the patches'.
//!
//! **Energy** (Eq. 5.5): ψ_p = c_p Σ_q G_p(n_q) ω_q V_q [μ (ē_q − e^p_q)² + λ/2 (e_q − e^p_q)²]
//! with e = |Y|/|X| − 1 a bond's extension, ē = |F X|/|X| − 1 that of its average
//! deformed bond Ȳ = F X (F of Eq. 4.4 over the intact bonds), e^p its plastic
//! extension (Eq. 5.9), ω = δ/|X| as SPB-MPM's, and c_p = 5 / Σ_q ω_q V_q over a
//! full reference family. The thesis leaves the weights' scale open (its λ, μ of Table 5.1
//! are artistic: a "μ of 500" bar); with c_p a uniform uniaxial strain ε stores
//! (λ + 2μ) ε²/2 (the isotropic mean of n_x⁴ is 1/5), the P-wave modulus of the
//! material, so the MPM's time step and wave speed hold. In any uniform strain ē = e,
//! so the bonds act as a bond-based model: λ_eff = μ_eff = (λ + 2μ)/3, exact for
//! Poisson's ratio 1/4 (`perifrac check` says so for other ratios). Σ ω V is that of
//! the body's fullest family; a family cut by a surface falls short along each axis a
//! by s_a = (Σ_full ω V / 5) / Σ ω V n_a⁴, and each of its bonds' weights is raised
//! by G(n) = (Σ_a n_a²/s_a²)^(−1/2) (the surface correction factors of Madenci and
//! Oterkus, Peridynamic Theory and Its Applications, 2014): the bar of the tests, all within δ of a side but its core,
//! was 17% too stiff without it, 5.5% with it.
//!
//! **Force state** (Eq. 5.6). The thesis differentiates μ(|Ȳ|/|X| − 1)² by Ȳ as if
//! it were the bond's own, T = 2μω/|X|² (|Ȳ| − |X|) dir Ȳ: a force along F X, not
//! along the bond, whose torques about p do not cancel when the deformation is not
//! smooth (measured in the tests: 1.5·10⁻³ of Σ|T||Y| on a family scattered by 1 mm,
//! against 2·10⁻¹⁷ here), so a body would spin itself up. Here ψ_p is differentiated through F
//! (∂F/∂Y_q = ω_q V_q (·) ⊗ K⁻¹X_q):
//!
//! T_p⟨q⟩ = ω_q [P_μ K⁻¹ X_q + c_p G_p(n_q) λ (e_q − e^p_q)/|X_q| dir Y_q],
//! P_μ = c_p Σ_k 2μ G_p(n_k) ω_k V_k (ē_k − e^p_k) dir(F X_k) ⊗ X_k/|X_k|,
//!
//! which is Eq. 5.6 where the deformation is uniform and keeps angular momentum
//! always (P_μ Fᵀ is symmetric). The λ term, a spring along each bond, also holds the
//! correspondence term's zero-energy modes. A family whose intact bonds no longer span
//! space (K's smallest eigenvalue below [`super::MIN_SHAPE`] of its whole family's
//! mean) keeps its springs only.
//!
//! **Plasticity** (Eq. 5.9–5.11): ϑ = 3 Σ ω |X|² e V / Σ ω |X|² V over the intact
//! bonds (Eq. 5.16 with the reference lengths, so that a uniform dilatation ε gives ϑ
//! = 3ε), e_dev = e − ϑ/3, and a bond flows where E_dev = (2μ + λ)(e_dev − e^p)
//! passes ±σ_Y: e^p += (E_dev ∓ σ_Y)/(2μ + λ), which puts E_dev back on the yield
//! surface f = E_dev²/2 − ψ_p = 0 with ψ_p = σ_Y²/2. Two changes from the print:
//! Eq. 5.10's factor ω/|X| is left out of E_dev (it would tie the yield to the
//! discretization), and Eq. 5.11's |X|/λ is replaced by the step that lands on the
//! surface, 1/(2μ + λ) (with |X|/λ a bond overshoots or stops short of it). σ_Y is
//! then about the uniaxial yield stress: a bar of Poisson's ratio 1/4 under σ has
//! E_dev = σ on its bonds along the load.
//!
//! **Viscoelasticity** (§5.3.3). Eq. 5.12–5.20 linearize about the last step's
//! configuration, taken as equilibrated: each step's force is the modulus state times
//! the bond displacement over that step, M·U. That relaxes every bond fully each
//! step, a viscosity of the order of the bonds' modulus times Δt, which the grid and
//! the step set instead of the material. Here the reference configuration still
//! follows the deformed one, at the material's own pace: a bond's natural length
//! |X| exp(e^p) flows toward its current length with the relaxation time τ = η/G, η
//! the `viscosity` and G = (λ + 2μ)/3 the bonds' shear modulus (above), as a Maxwell
//! element. In the bond's logarithmic extension ε = ln(|Y|/|X|), the elastic part s =
//! ε − e^p follows ds/dt = ε̇ − (s ∓ s_Y)/τ while |s| passes s_Y = σ_Y/(2μ + λ) (0
//! without a yield stress); it is integrated exactly over the last step with ε̇ =
//! Y·(v_q − v_p)/|Y|² held constant,
//!
//! s ← ±s_Y + e^(−Δt/τ) (s − Δt ε̇ ∓ s_Y) + ε̇ τ (1 − e^(−Δt/τ)),
//!
//! clamped between the yield surface and the unrelaxed s where σ_Y > 0. The result
//! does not depend on the step: a strain held still relaxes as e^(−t/τ), and where τ
//! ≪ Δt the stress left, G τ ε̇ = ηε̇, is a Newtonian fluid's (relaxing the whole s
//! each step, it would be inviscid). A steady pull carries 3ηε̇ (Trouton; tested). The
//! springs flow toward their own length, the μ term toward F X's, each with its own
//! e^p, so that every flow only lowers its term's energy; the springs and the μ term
//! take the elastic extension as |Y|/|X| − exp(e^p), whose stiffness stays that of
//! the reference length, so the MPM's step holds as the bonds flow.
//!
//! The bonds relax whole, volume included, so a viscous body keeps its volume by a
//! term of its own, Eq. 5.15's λϑ²/2 taken on the material point's own F, the one the
//! grid advects (F ← (I + Δt C) F, as for every MPM particle): ψ_vol = K (ln J)²/2, K
//! = λ + 2μ/3, whose Kirchhoff stress K ln J I goes to the grid in the stress stage as
//! a material point's does ([`super::Patches::volume_modulus`]; none where that F has
//! inverted). The MPM's step counts K in the wave speed. Where the bonds have not
//! relaxed (t ≪ τ) the body is K stiffer in bulk than the elastic one. Three other
//! choices were tried and taken out. With ψ_vol on the F of the intact bonds (Eq. 4.4,
//! P += K ln J F⁻ᵀ), a family that the flow has stirred no longer measures the
//! particles' spacing: a cream pie thrown at a wall at 4 m/s dilated to a median J of
//! 1.73 (the grid's; 3.45 at the 90th percentile) with no stress to pull it back
//! (1.00 and 1.06 on the grid's J). With the bonds' ϑ of Eq. 5.16 as the volume, a
//! ball of honey flattened to a single layer of particles on landing (a family
//! flattened to a sheet has ϑ = 0 at J = 0). With only the deviatoric part ε − ln(J)/3
//! relaxing, the flow depends on J and can raise the energy: the ball spread across
//! the ground at up to 17 m/s and blew up, with the step quartered too. η alone makes a Maxwell fluid (honey, Fig.
//! 5.10); with σ_Y the flow beyond the yield stress is viscous (Duvaut–Lions), as
//! whipped cream (Fig. 5.11).
//!
//! **Failure** (Eq. 5.21): a bond breaks when l = (e − e^p)/(1 + p_inactive) passes
//! l_threshold, p_inactive the share of broken bonds among the bonds of the particles
//! in the grid cell of the bond's particle; a pair breaks when either end's l passes,
//! so both directions go together. Then **the crack cut** (§5.4): the particles that
//! broke a bond this step are grouped by their grid cell; each group's centre point
//! and the current direction of its most stretched broken bond make a fracture plane,
//! and every intact bond that crosses the plane inside that cell is cut too.
//!
//! **Two-time integration** (§5.4) is not used: particles with a broken bond that
//! move off the grid by their own forces, at the MPM's step, are unstable in an
//! impact (docs/mpm.md, "Integral-based MPM"); every particle moves with the grid.
//!
//! **Anchors.** Every particle of a body is bonded, those its anchors hold too: their
//! bonds pull on their free neighbours, but the bond force on an anchored particle is
//! its anchor's reaction and stays off the grid (its δu_p is zero in Eq. 5.1, so it
//! has no term in Eq. 5.2; [`Patches::apply`]). On the grid it went to the free nodes
//! next to the clamp and a notched bar broke at its clamp's edge, not at its notch.

use perifrac_math::{dot, mat_mul, mat_vec, norm, scale, sub};

use super::reference::{Bond, Member, NO_MIRROR, Shape};
use super::{Measure, Patches, State};
use crate::error::Result;
use crate::family::{BROKEN, INDEX};
use crate::mpm::MpmParticles;
use crate::mpm::constitutive;

/// The isotropic mean of n_x⁴ over directions, 1/5: c_p Σ ω V = 1/that.
const UNIAXIAL_WEIGHT: f64 = 5.0;

/// An integral-based body's bonds (`[materials.NAME.mpm.bonds]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegralBonds {
    /// Lamé's λ (Pa).
    pub lambda: f64,
    /// Lamé's μ (Pa).
    pub mu: f64,
    /// The bonds' yield stress σ_Y (Pa), or `None` for elastic bonds.
    pub yield_stress: Option<f64>,
    /// l_threshold of Eq. 5.21, or `None`: the bonds never break.
    pub critical_stretch: Option<f64>,
    /// The shear viscosity η (Pa·s) of viscoelastic bonds, or `None`.
    pub viscosity: Option<f64>,
}

impl IntegralBonds {
    /// How many plastic extensions each bond keeps ([`flows_per_bond`]).
    pub(super) fn flows_per_bond(&self) -> usize {
        flows_per_bond(self.viscosity, self.yield_stress)
    }

    /// How the bonds take e^p off: multiplicatively where they are viscous.
    pub(super) fn strain(&self) -> Strain {
        if self.viscosity.is_some() {
            Strain::Multiplicative
        } else {
            Strain::Additive
        }
    }

    /// The bonds' [`Law`] in a body whose fullest family has Σ ω V = `full_weight`,
    /// for a step `dt`.
    pub(super) fn law(&self, full_weight: f64, dt: f64) -> Law {
        // The bonds' shear modulus, (λ + 2μ)/3 (the module documentation).
        let shear = (self.lambda + 2.0 * self.mu) / 3.0;
        let flow = match (self.viscosity, self.yield_stress) {
            (Some(eta), _) => {
                let tau = eta / shear;
                Flow::Maxwell {
                    decay: (-dt / tau).exp(),
                    tau,
                    dt,
                }
            }
            (None, Some(_)) => Flow::Return,
            (None, None) => Flow::Elastic,
        };
        Law {
            bonds: *self,
            c: UNIAXIAL_WEIGHT / full_weight,
            flow,
        }
    }
}

/// How many plastic extensions a bond of a body with these bonds' `viscosity` and
/// `yield_stress` keeps: none for elastic bonds, e^p for plastic ones, and for
/// viscous ones the springs' and the μ term's apart (the module documentation).
pub fn flows_per_bond(viscosity: Option<f64>, yield_stress: Option<f64>) -> usize {
    match (viscosity, yield_stress) {
        (Some(_), _) => 2,
        (None, Some(_)) => 1,
        (None, None) => 0,
    }
}

/// How a body's bonds act this step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Law {
    pub(super) bonds: IntegralBonds,
    /// c_p = 5 / Σ ω V of the body's fullest family.
    pub(super) c: f64,
    pub(super) flow: Flow,
}

/// How a bond's extension flows into its e^p.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Flow {
    /// Elastic bonds: no flow.
    Elastic,
    /// Plastic bonds: the stress beyond ±σ_Y returns to the yield surface.
    Return,
    /// Viscous bonds: the stress (beyond ±σ_Y, if any) relaxes with the time τ, its
    /// step's `decay` exp(−Δt/τ), for a step `dt` (the module documentation).
    Maxwell { decay: f64, tau: f64, dt: f64 },
}

/// How a body's bonds take their plastic extension e^p off a bond's (the module
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Strain {
    /// e − e^p with e = |Y|/|X| − 1: elastic and plastic bonds (and SPB-MPM's
    /// members, whose springs are zero).
    Additive,
    /// |Y|/|X| − exp(e^p): e^p a logarithmic flow, the natural length |X| exp(e^p),
    /// and the stiffness that of |X| (viscous bonds, which flow far).
    Multiplicative,
}

impl Strain {
    /// A bond's elastic extension: `length` long in the reference, `current` long
    /// now, with plastic extension `plastic`. Its derivative by |Y| is 1/|X| either
    /// way.
    pub(super) fn elastic(self, current: f64, length: f64, plastic: f64) -> f64 {
        match self {
            Strain::Additive => current / length - 1.0 - plastic,
            Strain::Multiplicative => current / length - plastic.exp(),
        }
    }
}

/// The member's state at the step's start, after its bonds' plastic flow: P_μ K⁻¹ in
/// `force` and c_p λ in `spring` (the module documentation), with its K's `shape`.
/// `extensions` are its bonds' e^p (empty for elastic bonds), updated here.
pub(super) fn state(
    member: Member<'_>,
    shape: Shape,
    extensions: &mut [f64],
    p: &MpmParticles,
    law: &Law,
    delta: f64,
) -> State {
    let Member { i, family, table } = member;
    let bonds = &law.bonds;
    let (x0, x, v, volume) = (&p.reference, &p.position, &p.velocity, &p.volume);
    let mut moment = [[0.0; 3]; 3];
    // Σ ω (v_q − v_p) ⊗ X V, for viscous bonds' rates.
    let mut rate_moment = [[0.0; 3]; 3];
    let viscous = bonds.viscosity.is_some();
    let (mut dilatation, mut weights) = (0.0, 0.0);
    let plastic_dilatation = bonds.viscosity.is_none() && bonds.yield_stress.is_some();
    for (&nb, bond) in family.iter().zip(table) {
        if nb & BROKEN != 0 {
            continue;
        }
        let q = (nb & INDEX) as usize;
        let length = bond.length;
        let w = delta / length * volume[q];
        let xi = sub(x0[q], x0[i]);
        let y = sub(x[q], x[i]);
        for a in 0..3 {
            for b in 0..3 {
                moment[a][b] += w * y[a] * xi[b];
            }
        }
        if viscous {
            let dv = sub(v[q], v[i]);
            for a in 0..3 {
                for b in 0..3 {
                    rate_moment[a][b] += w * dv[a] * xi[b];
                }
            }
        }
        if plastic_dilatation {
            dilatation += w * length * length * (norm(y) / length - 1.0);
            weights += w * length * length;
        }
    }
    let c = law.c;
    let spring = c * bonds.lambda;
    // F over the intact bonds (Eq. 4.4), where they span space and keep its sign.
    let measured = match shape {
        Shape::Spanning(shape_inverse) => {
            let f = mat_mul(&moment, &shape_inverse);
            (constitutive::determinant(&f) > 0.0).then_some((f, shape_inverse))
        }
        Shape::Stale | Shape::Flat => None,
    };
    let sigma_y = bonds.yield_stress.unwrap_or(0.0);
    let modulus = 2.0 * bonds.mu + bonds.lambda;
    // A bond's e^p given the extension it follows (deviatoric for plastic bonds,
    // whole for viscous ones) and that extension's rate (the module documentation).
    let flow = |plastic: &mut f64, extension: f64, rate: f64| {
        let elastic = extension - *plastic;
        match law.flow {
            Flow::Elastic => {}
            Flow::Return => {
                let stress = modulus * elastic;
                if stress.abs() > sigma_y {
                    *plastic += (stress - sigma_y.copysign(stress)) / modulus;
                }
            }
            Flow::Maxwell { decay, tau, dt } => {
                let limit = sigma_y / modulus;
                if elastic.abs() <= limit {
                    return;
                }
                // ds/dt = ε̇ − (s ∓ s_Y)/τ over the last step, ε̇ constant.
                let over = limit.copysign(elastic);
                let mut relaxed =
                    over + decay * (elastic - dt * rate - over) + rate * tau * (1.0 - decay);
                if limit > 0.0 {
                    // It relaxes down to the yield surface, never past the trial.
                    relaxed = over
                        + (relaxed - over)
                            .clamp(0.0_f64.min(elastic - over), 0.0_f64.max(elastic - over));
                }
                *plastic = extension - relaxed;
            }
        }
    };
    // P_μ = Σ 2μ c G ω V (|FX|/|X| − 1 − e^p or − exp e^p) FX ⊗ X / (|X| |FX|) over
    // the intact bonds (the module documentation), a bond at a time.
    let strain = bonds.strain();
    let mut piola = [[0.0; 3]; 3];
    let mut add = |q: usize, bond: &Bond, xi: [f64; 3], average: [f64; 3], plastic: f64| {
        let (length, average_length) = (bond.length, norm(average));
        let magnitude = 2.0 * bonds.mu * c * bond.correction * delta / length
            * volume[q]
            * strain.elastic(average_length, length, plastic)
            / (length * average_length);
        for a in 0..3 {
            for b in 0..3 {
                piola[a][b] += magnitude * average[a] * xi[b];
            }
        }
    };
    let intact = || {
        family
            .iter()
            .zip(table)
            .enumerate()
            .filter(|(_, (nb, _))| *nb & BROKEN == 0)
    };
    let n = family.len();
    match (bonds.viscosity, measured) {
        // Viscous bonds: a spring's own ln(|Y|/|X|), and the μ term's ln(|F X|/|X|)
        // where F is measured, with their rates from the particles' velocities
        // (Ḟ = Σ ω (v_q − v_p) ⊗ X V K⁻¹); the μ term's force from the same F X.
        (Some(_), measured) => {
            let rates =
                measured.map(|(f, shape_inverse)| (f, mat_mul(&rate_moment, &shape_inverse)));
            for (k, (&nb, bond)) in intact() {
                let q = (nb & INDEX) as usize;
                let (y, dv) = (sub(x[q], x[i]), sub(v[q], v[i]));
                let spring_rate = dot(y, dv) / dot(y, y);
                flow(
                    &mut extensions[k],
                    (norm(y) / bond.length).ln(),
                    spring_rate,
                );
                if let Some((f, f_dot)) = rates {
                    let xi = sub(x0[q], x0[i]);
                    let (average, rate) = (mat_vec(f, xi), mat_vec(f_dot, xi));
                    let shear = (norm(average) / bond.length).ln();
                    let plastic = &mut extensions[n + k];
                    flow(plastic, shear, dot(average, rate) / dot(average, average));
                    add(q, bond, xi, average, *plastic);
                }
            }
        }
        // Plastic bonds: e − ϑ/3, then the μ term's force.
        (None, _) => {
            if plastic_dilatation && weights > 0.0 {
                let theta = 3.0 * dilatation / weights;
                for (k, (&nb, bond)) in intact() {
                    let e = norm(sub(x[(nb & INDEX) as usize], x[i])) / bond.length - 1.0;
                    flow(&mut extensions[k], e - theta / 3.0, 0.0);
                }
            }
            if let Some((f, _)) = measured {
                for (k, (&nb, bond)) in intact() {
                    let q = (nb & INDEX) as usize;
                    let xi = sub(x0[q], x0[i]);
                    add(
                        q,
                        bond,
                        xi,
                        mat_vec(f, xi),
                        extensions.get(k).copied().unwrap_or(0.0),
                    );
                }
            }
        }
    }
    let Some((f, shape_inverse)) = measured else {
        return State {
            measure: Measure::Bonds(p.deformation[i]),
            force: [[0.0; 3]; 3],
            spring,
            strain,
        };
    };
    State {
        measure: Measure::Bonds(f),
        force: mat_mul(&piola, &shape_inverse),
        spring,
        strain,
    }
}

/// The surface correction G_p(n) of each bond of particle `i`'s `family`, for a
/// body whose fullest family has Σ ω V = `full_weight` (the module documentation):
/// the family's uniaxial stiffnesses along the axes fall short by s_a = (full_weight
/// / 5) / Σ ω V n_a⁴, and a bond along n gets G(n) = (Σ_a n_a²/s_a²)^(−1/2).
pub(super) fn surface_corrections(
    i: usize,
    family: &[u32],
    p: &MpmParticles,
    full_weight: f64,
    delta: f64,
) -> Vec<f64> {
    let (x0, volume) = (&p.reference, &p.volume);
    let mut quartic = [0.0; 3];
    for &nb in family {
        let q = (nb & INDEX) as usize;
        let xi = sub(x0[q], x0[i]);
        let length = norm(xi);
        let w = delta / length * volume[q];
        for (m, c) in quartic.iter_mut().zip(xi) {
            *m += w * (c / length).powi(4);
        }
    }
    let scales = quartic.map(|m| {
        if m > 0.0 {
            full_weight / (UNIAXIAL_WEIGHT * m)
        } else {
            1.0
        }
    });
    family
        .iter()
        .map(|&nb| {
            let xi = sub(x0[(nb & INDEX) as usize], x0[i]);
            let length2 = dot(xi, xi);
            let sum: f64 = (0..3)
                .map(|a| xi[a] * xi[a] / (scales[a] * scales[a]))
                .sum();
            (length2 / sum).sqrt()
        })
        .collect()
}

/// T_p⟨q⟩ of the bond X = `xi` now `y` of a member in `state`, with the bond's
/// reference constants `bond` and plastic extension `plastic` (the module
/// documentation), for a horizon `delta`.
pub(super) fn force_state(
    state: &State,
    xi: [f64; 3],
    y: [f64; 3],
    bond: &Bond,
    plastic: f64,
    delta: f64,
) -> [f64; 3] {
    let length = bond.length;
    let omega = delta / length;
    let mut t = mat_vec(state.force, xi);
    if state.spring != 0.0 {
        let current = norm(y);
        let pull = state.spring * bond.correction * state.strain.elastic(current, length, plastic)
            / (length * current);
        t = [0, 1, 2].map(|a| t[a] + pull * y[a]);
    }
    scale(t, omega)
}

impl Patches {
    /// Adds every particle of the bodies with bonds (the integral-based MPM) to
    /// Ω^PD, at the start of a run.
    ///
    /// # Errors
    /// [`crate::error::SimError::Refused`] if the neighbour search cannot be built.
    pub fn join_bonded(&mut self, p: &MpmParticles) -> Result<()> {
        let bonded: Vec<usize> = (0..p.len())
            .filter(|&i| self.bodies[p.body[i] as usize].bonds.is_some())
            .collect();
        if bonded.is_empty() {
            return Ok(());
        }
        self.join(&bonded, p)
    }

    /// e^p of member slot `s`'s bond `k` (0 for elastic bonds).
    pub(super) fn extension(&self, s: usize, k: usize) -> f64 {
        self.extensions[s].get(k).copied().unwrap_or(0.0)
    }

    /// e^p of member slot `s`'s bond `k` seen from its other end `q` (0 for elastic
    /// bonds and outside Ω^PD).
    pub(super) fn extension_back(&self, s: usize, k: usize, q: usize) -> f64 {
        match self.table[s][k].mirror {
            NO_MIRROR => 0.0,
            back => self.extension(self.slot[q] as usize, back as usize),
        }
    }

    /// The first Piola–Kirchhoff stress of integral-based member `i` this step, P =
    /// Σ_q T_p⟨q⟩ ⊗ X_q V_q over its intact bonds (∂ψ_p/∂F where the deformation is
    /// uniform): what the tests compare with the MPM's stress.
    #[cfg(test)]
    pub(crate) fn bond_stress(&self, i: usize, p: &MpmParticles) -> [[f64; 3]; 3] {
        let s = self.slot[i] as usize;
        let mut stress = [[0.0; 3]; 3];
        for (k, &nb) in self.families[s].iter().enumerate() {
            if nb & BROKEN != 0 {
                continue;
            }
            let q = nb as usize;
            let xi = sub(p.reference[q], p.reference[i]);
            let y = sub(p.position[q], p.position[i]);
            let bond = &self.table[s][k];
            let t = force_state(
                &self.states[s],
                xi,
                y,
                bond,
                self.extension(s, k),
                self.horizon,
            );
            for a in 0..3 {
                for b in 0..3 {
                    stress[a][b] += t[a] * xi[b] * p.volume[q];
                }
            }
        }
        stress
    }
}

mod fracture;
#[cfg(test)]
mod tests;
