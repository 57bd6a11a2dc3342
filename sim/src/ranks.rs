//! The processes of a distributed run (issue 35): what a model needs from the others
//! (gathers in rank order, an agreement), without naming the transport. The `perifrac`
//! binary implements [`Ranks`] over MPI behind its `mpi` feature; `sim` has no MPI in
//! its build.
//!
//! This first cut splits the work and the bonds' constants, not the particles: every
//! rank keeps all particles (positions, velocities) and every bond's neighbour word
//! (the broken bits), steps everything that is cheap (the integrator, contact,
//! colliders, the rigid phase) itself, and the bond work of peridynamics — dilatation,
//! return mapping, forces and fracture, most of a step — is split into contiguous
//! particle ranges of about equal bond count ([`split_by_bonds`]), each rank building
//! and keeping the per-bond constants of its own range alone
//! ([`crate::pd::Coefficients`]). A membrane's pass over its bonds is split the same
//! way ([`crate::membrane::MembraneModel::share`]). After each stage a rank sends what
//! it changed in its range (θ; forces and damage; the bonds it broke, crushed or
//! yielded) and receives the others'. Each particle still gathers over its own family
//! in the same order, so a run gives the same bytes on any number of ranks. Keeping ghost copies within δ
//! instead of every particle is not done yet; see docs/ranks.md.

use std::fmt::Debug;
use std::ops::Range;
use std::sync::Arc;

/// The ranks of a run, seen from one of them. Every method is collective: all ranks
/// call it, in the same order, with their own part.
pub trait Ranks: Debug + Send + Sync {
    /// This rank, from 0.
    fn rank(&self) -> usize;
    /// How many ranks run.
    fn size(&self) -> usize;
    /// Every rank's `mine`, in rank order (MPI_Allgatherv).
    fn gather(&self, mine: &[f64]) -> Vec<Vec<f64>>;
    /// Whether any rank says `flag` (MPI_Allreduce with a logical or).
    fn any(&self, flag: bool) -> bool;
}

/// A model's share of the work over `ranks`: rank r owns the particles
/// `bounds[r]..bounds[r + 1]`.
#[derive(Debug, Clone)]
pub struct Share {
    /// The ranks.
    pub ranks: Arc<dyn Ranks>,
    /// Range starts, one more than there are ranks.
    pub bounds: Vec<usize>,
}

impl Share {
    /// The share of a model whose particles have the bond rows `offsets` (CSR).
    pub fn by_bonds(ranks: Arc<dyn Ranks>, offsets: &[usize]) -> Share {
        let bounds = split_by_bonds(offsets, ranks.size());
        Share { ranks, bounds }
    }

    /// The particles this rank owns.
    pub fn owned(&self) -> Range<usize> {
        let r = self.ranks.rank();
        self.bounds[r]..self.bounds[r + 1]
    }

    /// Every rank's `mine` ([`Ranks::gather`]), in rank order, each with the particles
    /// that rank owns.
    pub fn gather(&self, mine: &[f64]) -> Vec<(Range<usize>, Vec<f64>)> {
        let all = self.ranks.gather(mine).into_iter().enumerate();
        all.map(|(r, values)| (self.bounds[r]..self.bounds[r + 1], values))
            .collect()
    }
}

/// Splits the rows of `offsets` (one more than there are rows) into `parts`
/// contiguous ranges of about equal weight, a row weighing its bonds plus one (the
/// particle's own work); returns the range starts, `parts + 1` of them, from 0 to the
/// row count.
pub fn split_by_bonds(offsets: &[usize], parts: usize) -> Vec<usize> {
    if offsets.is_empty() {
        return vec![0; parts + 1];
    }
    let rows = offsets.len() - 1;
    let weight = |i: usize| offsets[i] - offsets[0] + i;
    let total = weight(rows);
    let mut bounds = vec![0; parts + 1];
    for p in 1..parts {
        // The row start whose cumulative weight is nearest p/parts of the total.
        let target = (total as u128 * p as u128 / parts as u128) as usize;
        let (mut lo, mut hi) = (0, rows);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if weight(mid) < target {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        if lo > 0 && target - weight(lo - 1) < weight(lo) - target {
            lo -= 1;
        }
        bounds[p] = lo.max(bounds[p - 1]);
    }
    bounds[parts] = rows;
    bounds
}

/// What a rank sends after a stage: its particles' values, then changes to per-bond
/// state, all as `f64` (bond indices below 2⁵³ and `u32` or `f32` states convert
/// exactly), so that a stage costs one gather.
#[derive(Debug, Default)]
pub struct Message(pub Vec<f64>);

impl Message {
    /// Appends values.
    pub fn put(&mut self, values: &[f64]) {
        self.0.extend_from_slice(values);
    }

    /// Appends the entries of `now` that differ from `before`, which held
    /// `now[first..]` before the stage: their count, then (bond index, value) pairs.
    pub fn put_changes<T: Copy + PartialEq + Into<f64>>(
        &mut self,
        first: usize,
        before: &[T],
        now: &[T],
    ) {
        let at = self.0.len();
        self.0.push(0.0);
        for (k, (b, n)) in before.iter().zip(&now[first..]).enumerate() {
            if b != n {
                self.0.push((first + k) as f64);
                self.0.push((*n).into());
            }
        }
        self.0[at] = ((self.0.len() - at - 1) / 2) as f64;
    }
}

/// Reads a [`Message`] in the order it was written.
#[derive(Debug)]
pub struct Reader<'a> {
    rest: &'a [f64],
}

impl<'a> Reader<'a> {
    /// A reader of one rank's message.
    pub fn new(message: &'a [f64]) -> Reader<'a> {
        Reader { rest: message }
    }

    /// The next `n` values.
    pub fn take(&mut self, n: usize) -> &'a [f64] {
        let (head, rest) = self.rest.split_at(n);
        self.rest = rest;
        head
    }

    /// The next changes, as (bond index, value) pairs.
    pub fn changes(&mut self) -> impl Iterator<Item = (usize, f64)> + 'a {
        let count = self.take(1)[0] as usize;
        self.take(2 * count)
            .chunks_exact(2)
            .map(|pair| (pair[0] as usize, pair[1]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_cover_the_rows_with_about_equal_bonds() {
        // Rows of 0, 10, 10, 0, 30, 10 bonds.
        let offsets = [0, 0, 10, 20, 20, 50, 60];
        assert_eq!(split_by_bonds(&offsets, 1), vec![0, 6]);
        let two = split_by_bonds(&offsets, 2);
        assert_eq!((two[0], two[2]), (0, 6));
        // Weights (bonds + 1): 1, 11, 11, 1, 31, 11; rows 0..4 weigh 24, 0..5 weigh 55:
        // 24 is the nearer to half of 66.
        assert_eq!(two[1], 4);
        // More parts than rows: empty ranges, still in order, still covering.
        let many = split_by_bonds(&offsets, 9);
        assert_eq!(many.len(), 10);
        assert!(many.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!((many[0], many[9]), (0, 6));
        assert_eq!(split_by_bonds(&[0], 3), vec![0, 0, 0, 0]);
    }

    #[test]
    fn a_message_reads_back_what_was_put() {
        let before = [1u32, 2, 3];
        let now = [9u32, 9, 1, 5, 3, 9];
        let mut message = Message::default();
        message.put(&[0.5, 1.5]);
        message.put_changes(2, &before, &now);
        message.put_changes(0, &[1.0f32], &[1.0f32]);
        message.put(&[7.0]);
        let mut reader = Reader::new(&message.0);
        assert_eq!(reader.take(2), &[0.5, 1.5]);
        assert_eq!(reader.changes().collect::<Vec<_>>(), vec![(3, 5.0)]);
        assert_eq!(reader.changes().count(), 0);
        assert_eq!(reader.take(1), &[7.0]);
    }
}
