//! Splitting CSR arrays (a family's bonds, per-bond state) into disjoint mutable rows
//! or blocks of rows, so that a parallel pass owns each particle's bonds: shared by
//! every model with bonds.

/// Splits `data` into the CSR rows given by `offsets`.
pub fn rows_mut<'a, T>(mut data: &'a mut [T], offsets: &[usize]) -> Vec<&'a mut [T]> {
    let mut rows = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (row, rest) = data.split_at_mut(w[1] - w[0]);
        rows.push(row);
        data = rest;
    }
    rows
}

/// Splits `data` into the CSR rows given by `offsets`, `block` rows at a time: for
/// each run of `block` consecutive rows (the last may be shorter), its first row
/// and the slice holding its rows.
pub fn blocks_mut<'a, T>(
    mut data: &'a mut [T],
    offsets: &[usize],
    block: usize,
) -> Vec<(usize, &'a mut [T])> {
    let rows = offsets.len().saturating_sub(1);
    let mut blocks = Vec::with_capacity(rows.div_ceil(block));
    for first in (0..rows).step_by(block) {
        let last = (first + block).min(rows);
        let (part, rest) = data.split_at_mut(offsets[last] - offsets[first]);
        blocks.push((first, part));
        data = rest;
    }
    blocks
}
