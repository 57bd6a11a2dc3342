//! `[T; 3]` and `[[f64; 3]; 3]` arithmetic, and the conversions to nalgebra.
//!
//! Arrays stay the storage type of structure-of-arrays code; these helpers compute in
//! the plain order of operations (`a[0] * b[0] + a[1] * b[1] + a[2] * b[2]`), so a
//! caller that switches to them keeps the same bits.

use nalgebra::{Matrix3, RealField, Vector3};

/// a + b.
#[inline]
pub fn add<T: RealField + Copy>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a − b.
#[inline]
pub fn sub<T: RealField + Copy>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// s a.
#[inline]
pub fn scale<T: RealField + Copy>(a: [T; 3], s: T) -> [T; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// a · b.
#[inline]
pub fn dot<T: RealField + Copy>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b.
#[inline]
pub fn cross<T: RealField + Copy>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// |a|.
#[inline]
pub fn norm<T: RealField + Copy>(a: [T; 3]) -> T {
    dot(a, a).sqrt()
}

/// |a − b|, the distance between two points.
#[inline]
pub fn dist<T: RealField + Copy>(a: [T; 3], b: [T; 3]) -> T {
    norm(sub(a, b))
}

/// a / |a|, or zero when |a| is zero (or not a number).
#[inline]
pub fn normalize<T: RealField + Copy>(a: [T; 3]) -> [T; 3] {
    let n = norm(a);
    if n > T::zero() {
        scale(a, T::one() / n)
    } else {
        [T::zero(); 3]
    }
}

/// a + t (b − a).
#[inline]
pub fn lerp<T: RealField + Copy>(a: [T; 3], b: [T; 3], t: T) -> [T; 3] {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
    ]
}

/// Signed volume of the tetrahedron `abcd`: positive when `d` lies on the side of
/// triangle `abc` that its right-hand normal points to.
#[inline]
pub fn signed_volume(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    dot(sub(b, a), cross(sub(c, a), sub(d, a))) / 6.0
}

/// The 3×3 identity, row-major.
pub const IDENTITY3: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// m v, for a row-major `m`.
#[inline]
pub fn mat_vec(m: [[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

/// a b, for row-major `a` and `b`.
#[inline]
pub fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j]))
}

/// det m (cofactor expansion along the first row).
#[inline]
pub fn det3(m: &[[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// m⁻¹ as the adjugate over `det` (= [`det3`]`(m)`, which the caller has checked is
/// not zero).
#[inline]
pub fn inverse3(m: &[[f64; 3]; 3], det: f64) -> [[f64; 3]; 3] {
    // Cofactor of entry (r, s), with the sign folded in by the cyclic indices.
    let c = |r: usize, s: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (s1, s2) = ((s + 1) % 3, (s + 2) % 3);
        m[r1][s1] * m[r2][s2] - m[r1][s2] * m[r2][s1]
    };
    [0, 1, 2].map(|r| [0, 1, 2].map(|s| c(s, r) / det))
}

/// The nalgebra vector of an array.
#[inline]
pub fn to_vector<T: RealField + Copy>(a: [T; 3]) -> Vector3<T> {
    Vector3::from(a)
}

/// The array of an nalgebra vector.
#[inline]
pub fn from_vector<T: RealField + Copy>(v: &Vector3<T>) -> [T; 3] {
    [v[0], v[1], v[2]]
}

/// The nalgebra matrix of a row-major array.
#[inline]
pub fn to_matrix<T: RealField + Copy>(m: [[T; 3]; 3]) -> Matrix3<T> {
    Matrix3::from_fn(|r, c| m[r][c])
}

/// The row-major array of an nalgebra matrix.
#[inline]
pub fn from_matrix<T: RealField + Copy>(m: &Matrix3<T>) -> [[T; 3]; 3] {
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| m[(r, c)]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helpers_match_nalgebra() {
        let (a, b): ([f64; 3], [f64; 3]) = ([1.0, -2.0, 0.5], [0.25, 3.0, -1.0]);
        let (va, vb) = (to_vector(a), to_vector(b));
        assert_eq!(from_vector(&va.cross(&vb)), cross(a, b));
        assert_eq!(dot(a, b), va.dot(&vb));
        assert_eq!(add(a, b), from_vector(&(va + vb)));
        assert_eq!(sub(a, b), from_vector(&(va - vb)));
        assert!((norm(a) - va.norm()).abs() < 1e-15);
        assert_eq!(normalize([0.0f32; 3]), [0.0; 3]);
        assert_eq!(lerp(a, b, 0.0), a);
        let unit = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(
            signed_volume([0.0; 3], unit[0], unit[1], unit[2]),
            1.0 / 6.0
        );
        let m: [[f64; 3]; 3] = [[2.0, 1.0, 0.0], [0.5, 3.0, -1.0], [0.0, 1.0, 4.0]];
        let nm = to_matrix(m);
        assert_eq!(from_matrix(&nm), m);
        assert!((det3(&m) - nm.determinant()).abs() < 1e-12);
        let inv = inverse3(&m, det3(&m));
        let expected = from_matrix(&nm.try_inverse().unwrap());
        for r in 0..3 {
            for c in 0..3 {
                assert!((inv[r][c] - expected[r][c]).abs() < 1e-14);
            }
        }
        assert_eq!(mat_vec(m, a), from_vector(&(nm * va)));
        let product = from_matrix(&(nm * nm));
        for (row, expected) in mat_mul(&m, &m).iter().zip(product) {
            for (x, y) in row.iter().zip(expected) {
                assert!((x - y).abs() < 1e-12);
            }
        }
    }
}
