//! perifrac's shared maths, the ground under `perifrac-sim`, `perifrac-surface` and
//! `perifrac-render`: each helper here is written once, and the crates call it instead
//! of keeping their own copy.
//!
//! | item | what it is |
//! |---|---|
//! | [`Vector3`], [`Matrix3`], [`RealField`], … | nalgebra, the project's named maths crate (re-exported), for 3×3 SVD, polar and symmetric eigen decompositions |
//! | [`to_vector`], [`from_vector`], [`to_matrix`], [`from_matrix`] | between the arrays kept in structure-of-arrays storage and nalgebra |
//! | [`add`], [`sub`], [`scale`], [`dot`], [`cross`], [`norm`], [`dist`], [`normalize`], [`lerp`] | `[T; 3]` arithmetic for `f32` and `f64`, in the plain order of operations (same bits as the written-out expressions) |
//! | [`signed_volume`] | a tet's volume, signed by its orientation |
//! | [`mat_vec`], [`mat_mul`], [`det3`], [`inverse3`], [`mul_transpose`] | 3×3 arithmetic on row-major `[[f64; 3]; 3]` |
//! | [`rotation_svd`], [`RotationSvd`] | the inversion-safe SVD F = U Σ Vᵀ (U, V rotations), for MPM's energies and the embedded mesh |
//! | [`TET_FACES`] | the tet face table: face `f` lies opposite corner `f`, wound outward |
//! | [`UnionFind`] | disjoint sets with path compression and deterministic labels |
//! | [`det_sum`] | a parallel sum with the same bits for any thread count |
//! | [`SplitMix64`] | the seeded random number generator behind the scene's `seed` |
//!
//! The PD force kernels (`perifrac-sim`'s `pd::kernel`) keep their hand-written
//! arithmetic: this crate is for everything outside them.

#![warn(missing_docs)]

mod decompose;
mod random;
mod sum;
mod tet;
mod union_find;
mod vector;

pub use decompose::{RigidFit, RotationSvd, mul_transpose, rigid_fit, rotation_svd};
pub use nalgebra::{
    Matrix3, Quaternion, RealField, Rotation3, SVD, SymmetricEigen, UnitQuaternion, Vector3,
};
pub use random::SplitMix64;
pub use sum::det_sum;
pub use tet::TET_FACES;
pub use union_find::UnionFind;
pub use vector::{
    IDENTITY3, add, cross, det3, dist, dot, from_matrix, from_vector, inverse3, lerp, mat_mul,
    mat_vec, norm, normalize, scale, signed_volume, sub, to_matrix, to_vector,
};
