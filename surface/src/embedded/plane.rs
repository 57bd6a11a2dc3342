//! Planes fitted through a vertex's ring on the crack surface: the target of a rim
//! vertex's smoothing move (`rim_move`) and the measure of how far a crack zig-zags
//! (`SmoothingStats::roughness`).

use perifrac_math::{add, dot, from_vector, sub, to_matrix};

/// The unit normal of the plane fitted through points around their centroid `mean`
/// (the direction of their least spread), or `None` when they lie on a line.
pub(super) fn plane_normal(
    mean: [f64; 3],
    points: impl Iterator<Item = [f64; 3]>,
) -> Option<[f64; 3]> {
    let mut spread = [[0.0; 3]; 3];
    for p in points {
        let d = sub(p, mean);
        for (a, row) in spread.iter_mut().enumerate() {
            for (b, e) in row.iter_mut().enumerate() {
                *e += d[a] * d[b];
            }
        }
    }
    let eigen = to_matrix(spread).symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    (eigen.eigenvalues[order[1]] > 0.0)
        .then(|| from_vector(&eigen.eigenvectors.column(order[0]).into_owned()))
}

/// The median distance of the vertices of `movable` from the plane fitted through
/// their rings on the crack surface (`rings`, at `x`; vertices whose ring has fewer
/// than three others are left out): the height of the zig-zag a crack along tet faces
/// makes, about 0.3λ before smoothing on the demo, 0 on a flat crack.
pub(super) fn roughness(x: &[[f64; 3]], movable: &[u32], rings: &[Vec<u32>]) -> f64 {
    let mut heights: Vec<f64> = movable
        .iter()
        .zip(rings)
        .filter(|(_, ring)| ring.len() >= 3)
        .filter_map(|(&v, ring)| {
            let points = ring.iter().map(|&w| x[w as usize]);
            let mean = points
                .clone()
                .fold([0.0; 3], add)
                .map(|c| c / ring.len() as f64);
            let n = plane_normal(mean, points)?;
            Some(dot(sub(x[v as usize], mean), n).abs())
        })
        .collect();
    heights.sort_unstable_by(f64::total_cmp);
    heights.get(heights.len() / 2).copied().unwrap_or(0.0)
}
