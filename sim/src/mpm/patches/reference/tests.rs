//! What the patches keep from the reference configuration against a fresh computation.

use super::*;
use crate::mpm::patch_tests::{colliding_balls, mpm};
use crate::mpm::tests::prepared;

/// Two balls of `[materials.jelly.mpm]` line `keys` (Poisson's ratio 1/4) collide
/// head-on without gravity for `seconds`; then every bond of a member to a member
/// has its mirror (the same bond in the other end's family), broken alike where
/// `pairs` (the integral-based MPM breaks pairs together), and every kept [`Shape`]
/// is that of the member's intact bonds now. Returns the directed bonds that broke.
fn check_kept(keys: &str, seconds: f64, pairs: bool) -> usize {
    let text = colliding_balls(0.25, &format!("{keys}\n"));
    let mut prepared = prepared(&text);
    let mut broken = 0;
    for _ in 0..(seconds / prepared.world.dt) as usize {
        broken += prepared.world.step().expect("steps");
    }
    let m = mpm(&prepared);
    let patches = m.patches.as_ref().expect("patches");
    let (mut kept, mut stale, mut mirrors) = (0, 0, 0);
    for (s, (&i, family)) in patches.members.iter().zip(&patches.families).enumerate() {
        let table = &patches.table[s];
        for (bond, &nb) in table.iter().zip(family) {
            let t = patches.slot[(nb & INDEX) as usize];
            if t == OUTSIDE {
                continue;
            }
            let back = patches.families[t as usize][bond.mirror as usize];
            assert_eq!(back & INDEX, i, "member {i}'s mirror");
            if pairs {
                assert_eq!(back & BROKEN, nb & BROKEN, "member {i}'s pair");
            }
            mirrors += 1;
        }
        let member = Member {
            i: i as usize,
            family,
            table,
        };
        match patches.shapes[s] {
            Shape::Stale => stale += 1,
            now => {
                assert_eq!(now, shape(member, &m.particles, patches.horizon));
                kept += 1;
            }
        }
    }
    eprintln!(
        "{broken} directed bonds broke; {mirrors} mirrors; {kept} shapes kept, {stale} stale"
    );
    assert!(kept > 0 && mirrors > 0, "{kept} kept, {mirrors} mirrors");
    broken
}

/// After bonds break in a collision, of the integral-based MPM (all particles
/// members from the start) and of SPB-MPM (members joining as the grid erodes), the
/// kept mirrors and shapes are what a fresh computation gives. A shape kept past a
/// break, or a mirror to the wrong bond, fails here.
#[test]
fn the_kept_shapes_and_mirrors_match_a_fresh_computation_after_bonds_break() {
    let integral = check_kept("bonds = { critical_stretch = 0.03 }", 0.02, true);
    assert!(integral > 100, "{integral} bonds broke");
    let spb = check_kept("energy_release_rate = 0.05", 0.04, false);
    assert!(spb > 100, "{spb} bonds broke");
}
