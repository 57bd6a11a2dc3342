//! A parallel sum that does not depend on the thread count.

use rayon::prelude::*;

/// Terms a chunk of [`det_sum`]: fixed, so chunk boundaries never depend on threads.
const CHUNK: usize = 4096;

/// Σ f(i) for i in 0..n, summed in fixed chunks of 4096 terms in parallel and then in
/// chunk order, so the result has the same bits whatever the number of threads.
pub fn det_sum(n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
    let partial: Vec<f64> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| (c * CHUNK..((c + 1) * CHUNK).min(n)).map(&f).sum())
        .collect();
    partial.into_iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_in_chunk_order() {
        let f = |i: usize| 1.0 / (i as f64 + 1.0);
        let n = 3 * CHUNK + 17;
        let chunked: f64 = (0..n.div_ceil(CHUNK))
            .map(|c| (c * CHUNK..((c + 1) * CHUNK).min(n)).map(f).sum::<f64>())
            .sum();
        assert_eq!(det_sum(n, f).to_bits(), chunked.to_bits());
        assert_eq!(det_sum(0, f), 0.0);
    }
}
