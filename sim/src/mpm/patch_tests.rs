//! SPB-MPM (Lyu ch. 6): eigenerosion, bond failure and the peridynamic region.

use super::Mpm;
use super::patches::Measure;
use super::tests::{prepared, same_bytes_on_one_and_two_threads, state_bytes};
use crate::run::Prepared;

pub(super) fn mpm(p: &Prepared) -> &Mpm {
    p.world.model::<Mpm>().expect("an MPM model")
}

/// A 4 × 20 × 4 cm bar of jelly (E = 100 kPa), its bottom held and its top pulled at
/// `pull` m/s, notched halfway across at mid-height from the −x side, on a grid of
/// spacing `dx`; `fracture` goes into its `[materials.jelly.mpm]`.
pub(super) fn notched_bar(dx: f64, pull: f64, fracture: &str) -> String {
    format!(
        "[scene]\nduration = 0.3\nfps = 100\ngravity = [0, 0, 0]\n\
         [materials.jelly]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = 0.2\n\
         [materials.jelly.mpm]\n{fracture}\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"jelly\"\nresolution = {dx}\n\
         shape = {{ type = \"difference\", \
           base = {{ type = \"box\", center = [0, 0.1, 0], size = [0.08, 0.2, 0.06] }}, \
           minus = {{ type = \"box\", center = [-0.04, 0.1, 0], size = [0.08, 0.012, 0.08] }} }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0, 0.01, 0], size = [0.1, 0.02, 0.1] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0, 0.19, 0], size = [0.1, 0.02, 0.1] }}\n\
         velocity = [0, {pull}, 0]\n\
         [output]\ntets = false\nsurface = \"none\"\npreview = false\n"
    )
}

/// What pulling a notched bar showed.
#[derive(Debug)]
pub(super) struct Pulled {
    /// Reference heights of the first particles to turn peridynamic (lowest, highest).
    pub(super) first_members: (f64, f64),
    /// Particles in each piece of over 5% of them, largest first.
    pub(super) pieces: Vec<usize>,
    /// The lowest and highest reference height of the two largest pieces, lower first.
    pub(super) extents: Vec<(f64, f64)>,
    /// The largest share of the bar's stretch taken up within 2 cm of its height, in
    /// its unnotched half (x > 0), from the mean displacement of each centimetre.
    pub(super) localized: f64,
    /// Simulated time at the end (s).
    pub(super) time: f64,
}

/// Pulls the notched bar for `seconds` or, with `stop`, until it is in two pieces.
pub(super) fn pull(dx: f64, fracture: &str, seconds: f64, stop: bool) -> Pulled {
    let mut p = prepared(&notched_bar(dx, 0.05, fracture));
    let steps = (seconds / p.world.dt) as usize;
    let mut first_members = (f64::NAN, f64::NAN);
    let pieces = |m: &Mpm| {
        let fragments = m.patches.as_ref().map_or_else(
            || m.particles.body.clone(),
            |patches| patches.fragments(&m.particles).expect("fragments"),
        );
        let mut count = std::collections::BTreeMap::<u32, usize>::new();
        for &f in &fragments {
            *count.entry(f).or_default() += 1;
        }
        let n = fragments.len();
        let mut big: Vec<(usize, u32)> = count
            .iter()
            .filter(|&(_, &c)| c * 20 > n)
            .map(|(&f, &c)| (c, f))
            .collect();
        big.sort_unstable_by(|a, b| b.cmp(a));
        (fragments, big)
    };
    for step in 0..steps {
        p.world.step().expect("steps");
        let m = mpm(&p);
        let Some(patches) = &m.patches else {
            continue;
        };
        if first_members.0.is_nan() && !patches.members().is_empty() {
            let heights = patches
                .members()
                .iter()
                .map(|&i| m.particles.reference[i as usize][1]);
            first_members = heights.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
                (lo.min(y), hi.max(y))
            });
        }
        if stop && step % 20 == 0 && pieces(m).1.len() >= 2 {
            break;
        }
    }
    let m = mpm(&p);
    let (fragments, big) = pieces(m);
    let x0 = &m.particles.reference;
    let mut extents: Vec<(f64, f64)> = big
        .iter()
        .take(2)
        .map(|&(_, f)| {
            (0..x0.len())
                .filter(|&i| fragments[i] == f)
                .map(|i| x0[i][1])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
                    (lo.min(y), hi.max(y))
                })
        })
        .collect();
    extents.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let displacement = row_displacements(m);
    let stretch = displacement[19] - displacement[0];
    let localized = displacement
        .windows(3)
        .map(|w| w[2] - w[0])
        .fold(0.0, f64::max)
        / stretch;
    Pulled {
        first_members,
        pieces: big.iter().map(|&(c, _)| c).collect(),
        extents,
        localized,
        time: p.world.time,
    }
}

/// Lyu Fig. 6.5: the bar breaks at its notch on grids of 2, 1 and 0.5 cm (the thesis'
/// claim against CD-MPM), and the first particles to turn peridynamic lie at the notch.
#[test]
fn a_notched_bar_turns_peridynamic_at_its_notch_and_breaks_there_at_three_grid_spacings() {
    for (dx, seconds) in [(0.02, 0.4), (0.01, 0.2), (0.005, 0.1)] {
        let out = pull(dx, "energy_release_rate = 0.5", seconds, true);
        eprintln!("Δx = {dx}: in two pieces at {:.3} s, {out:?}", out.time);
        let (lo, hi) = out.first_members;
        assert!(
            (0.09..=0.115).contains(&lo) && (0.09..=0.115).contains(&hi),
            "Δx = {dx}: the first peridynamic particles lie at heights {lo}..{hi}, the notch at 0.1"
        );
        assert_eq!(out.pieces.len(), 2, "Δx = {dx}: {out:?}");
        let n: usize = out.pieces.iter().sum();
        assert!(out.pieces[1] * 4 > n, "Δx = {dx}: {out:?}");
        let (below, above) = (out.extents[0], out.extents[1]);
        assert!(
            (0.095..0.12).contains(&below.1) && (0.095..0.12).contains(&above.0),
            "Δx = {dx}: the pieces meet between {} and {}, not at the notch",
            below.1,
            above.0
        );
    }
}

/// The contrast of Fig. 6.5: plain MLS-MPM stretches the same bar, pulled as long,
/// without opening it; SPB-MPM opens it at the notch.
#[test]
fn plain_mls_mpm_stretches_the_notched_bar_without_opening_it() {
    let plain = pull(0.01, "", 0.25, false);
    let spb = pull(0.01, "energy_release_rate = 0.5", 0.25, false);
    eprintln!("plain {plain:?}\nSPB {spb:?}");
    assert_eq!(plain.pieces.len(), 1);
    assert_eq!(spb.pieces.len(), 2);
    assert!(
        plain.localized < 0.3 && spb.localized > 0.7,
        "the most stretched 2 cm took {:.0}% of the stretch with SPB-MPM, {:.0}% without",
        100.0 * spb.localized,
        100.0 * plain.localized
    );
}

/// W_c of Eq. 6.12 for G_p = 0.5 J/m² and δ = 1.5 cm: 4 · 0.5 / (π · 0.015⁴) =
/// 1.2575205 · 10⁷ J/m⁶.
#[test]
fn the_critical_bond_energy_matches_its_hand_worked_value() {
    let p = prepared(&notched_bar(0.01, 0.05, "energy_release_rate = 0.5"));
    let patches = mpm(&p).patches.as_ref().expect("patches");
    let hand = 4.0 * 0.5 / (std::f64::consts::PI * 0.015f64.powi(4));
    assert!((hand - 1.257_520_5e7).abs() < 10.0, "{hand}");
    assert!((patches.critical_energy(0) - hand).abs() < 1e-9 * hand);
}

/// A bar whose upper half is made peridynamic at the start (its material erodes
/// nowhere and cannot break: huge thresholds), pulled slowly: no bond breaks, and the
/// two halves carry the same stress σ_yy (within 2%).
#[test]
fn a_bar_half_peridynamic_keeps_its_bonds_below_failure_and_stretches_as_its_mpm_half() {
    let (mpm_stress, pd_stress, _) = half_peridynamic_bar("");
    // 6 mm on 16 cm between the anchors, E = 100 kPa: about 3.7 kPa.
    assert!((2e3..6e3).contains(&mpm_stress), "{mpm_stress}");
    assert!((pd_stress - mpm_stress).abs() < 0.02 * mpm_stress.abs());
}

/// The same bar of a J2 material (yield stress 1.5 kPa, hardening to 2 kPa at
/// ε^p = 2%), pulled past yield: the peridynamic half flows as the MPM half does, σ_yy
/// within 2% and ε^p within 5%. Elastic, it would carry about 3.7 kPa; without its
/// flow counted its ε^p would be 0, counted twice 2×, and without hardening σ_yy
/// 1.5 kPa. ε^p is the small difference of two larger strains (3.6% in all, 1.9%
/// elastic), so the 0.7% more total strain the peridynamic half takes (measured:
/// 3.596% against 3.571%) shows as 3% more ε^p (0.0163 against 0.0158).
#[test]
fn a_plastic_bar_half_peridynamic_flows_as_its_mpm_half() {
    let j2 = "plasticity = { type = \"johnson-cook\", yield_stress = 1500, hardening = 25000, \
              exponent = 1 }\n";
    let (mpm_stress, pd_stress, [mpm_plastic, pd_plastic]) = half_peridynamic_bar(j2);
    assert!((1.5e3..2.5e3).contains(&mpm_stress), "{mpm_stress}");
    assert!((pd_stress - mpm_stress).abs() < 0.02 * mpm_stress.abs());
    assert!(mpm_plastic > 0.005, "{mpm_plastic}");
    assert!(
        (pd_plastic - mpm_plastic).abs() < 0.05 * mpm_plastic,
        "{pd_plastic}"
    );
}

/// Two jelly balls (density 1000 kg/m³, E = 100 kPa, Poisson's ratio
/// `poisson_ratio`, 5 cm across on a 2 cm grid) meeting head-on at 6 m/s without
/// gravity; `mpm_keys` (whole lines) go into `[materials.jelly.mpm]`.
pub(super) fn colliding_balls(poisson_ratio: f64, mpm_keys: &str) -> String {
    format!(
        "[scene]\nduration = 1\nfps = 100\ngravity = [0, 0, 0]\n\
         [materials.jelly]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = {poisson_ratio}\n\
         [materials.jelly.mpm]\n{mpm_keys}\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"jelly\"\nresolution = 0.02\nvelocity = [4, 0, 0]\n\
         shape = {{ type = \"sphere\", center = [-0.06, 0.0, 0.0], radius = 0.05 }}\n\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"jelly\"\nresolution = 0.02\nvelocity = [-2, 0.5, 0]\n\
         shape = {{ type = \"sphere\", center = [0.06, 0.01, 0.0], radius = 0.05 }}\n\
         [output]\ntets = false\nsurface = \"none\"\npreview = false\n"
    )
}

/// A 6 × 20 × 4 cm bar of material `material` (density 1000 kg/m³, E = 100 kPa,
/// Poisson's ratio `poisson_ratio`) on a 1 cm grid, its bottom and top 2 cm held and
/// the top pulled at 2 cm/s, without gravity; `mpm_keys` (whole lines) go into its
/// `[materials.<material>.mpm]`.
/// The mean vertical displacement of each 1 cm row of the bar's unnotched half (x >
/// 0; reference heights k to k + 1 cm, k = 0..20).
pub(super) fn row_displacements(m: &Mpm) -> Vec<f64> {
    let (x0, x) = (&m.particles.reference, &m.particles.position);
    (0..20)
        .map(|k| {
            let band = (0.01 * k as f64)..(0.01 * (k + 1) as f64);
            let (sum, count) = (0..x0.len())
                .filter(|&i| x0[i][0] > 0.0 && band.contains(&x0[i][1]))
                .fold((0.0, 0.0), |(s, c), i| (s + x[i][1] - x0[i][1], c + 1.0));
            sum / count
        })
        .collect()
}

pub(super) fn pulled_bar(material: &str, poisson_ratio: f64, mpm_keys: &str) -> String {
    format!(
        "[scene]\nduration = 1\nfps = 100\ngravity = [0, 0, 0]\n\
         [materials.{material}]\ndensity = 1000\nyoungs_modulus = 1e5\npoisson_ratio = {poisson_ratio}\n\
         [materials.{material}.mpm]\n{mpm_keys}\
         [[body]]\nmodel = \"mpm\"\nmaterial = \"{material}\"\nresolution = 0.01\n\
         shape = {{ type = \"box\", center = [0, 0.1, 0], size = [0.06, 0.2, 0.04] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0, 0.01, 0], size = [0.1, 0.02, 0.1] }}\n\
         [[body.anchor]]\nregion = {{ type = \"box\", center = [0, 0.19, 0], size = [0.1, 0.02, 0.1] }}\n\
         velocity = [0, 0.02, 0]\n\
         [output]\ntets = false\nsurface = \"none\"\npreview = false\n"
    )
}

/// Pulls a bar 6 mm on 16 cm in 0.3 s with its upper half made peridynamic at the
/// start, of `plasticity` (a line of `[materials.bonded.mpm]`), and returns σ_yy of
/// the MPM and peridynamic halves (averaged over the last 0.1 s, away from the
/// anchors and the interface) and their mean ε^p at the end.
fn half_peridynamic_bar(plasticity: &str) -> (f64, f64, [f64; 2]) {
    let text = pulled_bar(
        "bonded",
        0.2,
        &format!("energy_release_rate = 1e30\nerosion_release_rate = 1e30\n{plasticity}"),
    );
    let mut p = prepared(&text);
    let model = p.world.model_mut::<Mpm>().expect("an MPM model");
    let upper: Vec<usize> = (0..model.particles.len())
        .filter(|&i| model.particles.reference[i][1] > 0.1)
        .collect();
    let patches = model.patches.as_mut().expect("patches");
    patches.join(&upper, &model.particles).expect("joins");
    let steps = (0.3 / p.world.dt) as usize;
    let average_from = steps - (0.1 / p.world.dt) as usize;
    let (mut mpm_stress, mut pd_stress, mut samples) = (0.0, 0.0, 0);
    for step in 0..steps {
        p.world.step().expect("steps");
        if step < average_from {
            continue;
        }
        let m = mpm(&p);
        let patches = m.patches.as_ref().expect("patches");
        // σ_yy averaged over each half away from the anchors and the interface.
        let (mut sums, mut counts) = ([0.0; 2], [0; 2]);
        for i in 0..m.particles.len() {
            let y = m.particles.reference[i][1];
            let half = usize::from(y > 0.1);
            if !(0.04..0.08).contains(&y) && !(0.12..0.16).contains(&y) {
                continue;
            }
            let f = match patches.measure(i) {
                Some(Measure::Bonds(f)) => f,
                None => m.particles.deformation[i],
                other => panic!("particle {i} measures {other:?}"),
            };
            let material = &m.materials[m.particles.body[i] as usize];
            let tau = material.kirchhoff(&f, 0.0);
            sums[half] += tau[1][1] / super::constitutive::determinant(&f);
            counts[half] += 1;
        }
        mpm_stress += sums[0] / f64::from(counts[0]);
        pd_stress += sums[1] / f64::from(counts[1]);
        samples += 1;
    }
    let m = mpm(&p);
    let patches = m.patches.as_ref().expect("patches");
    let (mut plastic, mut counts) = ([0.0; 2], [0.0; 2]);
    for i in 0..m.particles.len() {
        let y = m.particles.reference[i][1];
        if (0.04..0.08).contains(&y) || (0.12..0.16).contains(&y) {
            let half = usize::from(y > 0.1);
            plastic[half] += m.particles.plastic[i];
            counts[half] += 1.0;
        }
    }
    let plastic = [plastic[0] / counts[0], plastic[1] / counts[1]];
    assert_eq!(
        patches.members().len(),
        upper.len(),
        "no other particle joined"
    );
    assert_eq!(patches.broken_bonds(), 0);
    let (mpm_stress, pd_stress) = (
        mpm_stress / f64::from(samples),
        pd_stress / f64::from(samples),
    );
    let difference = (pd_stress - mpm_stress).abs() / mpm_stress.abs();
    eprintln!(
        "σ_yy: MPM half {mpm_stress:.1} Pa, peridynamic half {pd_stress:.1} Pa ({:.2}%); \
         ε^p {:.4} and {:.4}",
        100.0 * difference,
        plastic[0],
        plastic[1]
    );
    (mpm_stress, pd_stress, plastic)
}

/// Two fracturing jelly balls collide head-on without gravity: bonds break and the
/// halo reactions and pairwise bond forces keep the momentum.
#[test]
fn bonds_breaking_in_a_collision_keep_momentum() {
    let text = colliding_balls(0.3, "energy_release_rate = 0.05\n");
    let mut p = prepared(&text);
    let before = mpm(&p).momentum();
    let mut broken = 0;
    for _ in 0..(0.04 / p.world.dt) as usize {
        broken += p.world.step().expect("steps");
    }
    let m = mpm(&p);
    let after = m.momentum();
    let scale = perifrac_math::norm(before);
    let error = perifrac_math::dist(after, before) / scale;
    eprintln!(
        "{broken} bonds broke, {} members; momentum change {error:.2e}",
        m.patches.as_ref().map_or(0, |p| p.members().len())
    );
    assert!(broken > 100, "{broken}");
    assert!(error < 1e-12, "{error}");
}

/// The same bytes with 1 and 2 threads while particles join and bonds break.
#[test]
fn spb_mpm_gives_the_same_bytes_with_one_and_two_threads() {
    let text = notched_bar(0.01, 0.05, "energy_release_rate = 0.5");
    same_bytes_on_one_and_two_threads(|| {
        let mut p = prepared(&text);
        let mut broken = 0;
        for _ in 0..(0.09 / p.world.dt) as usize {
            broken += p.world.step().expect("steps");
        }
        assert!(broken > 0);
        state_bytes(&p.world)
    });
}
