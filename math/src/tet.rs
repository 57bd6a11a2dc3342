//! The faces of a tetrahedron.

/// Face `f` of a positively oriented tet (corners 0–3), the one opposite corner `f`,
/// as local corner indices wound so that its right-hand normal points out of the tet.
pub const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_are_opposite_their_corner_and_point_outward() {
        let corners = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        for (f, face) in TET_FACES.iter().enumerate() {
            assert!(!face.contains(&f));
            let [a, b, c] = face.map(|k| corners[k]);
            let n = crate::cross(crate::sub(b, a), crate::sub(c, a));
            assert!(crate::dot(n, crate::sub(corners[f], a)) < 0.0, "face {f}");
        }
    }
}
