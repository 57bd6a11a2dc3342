//! Raw bindings to perifrac's C++ shim over the system OpenVDB (`shim/shim.cpp`).
//!
//! OpenVDB (MPL-2.0) is linked dynamically from the system (Debian `libopenvdb-dev`).
//! The shim wraps, for `FloatGrid` level sets only: `tools::ParticlesToLevelSet`
//! (spheres, with the closest particle's index as attribute), `tools::LevelSetTracker`,
//! `tools::LevelSetFilter` (mean curvature, Gaussian, Laplacian, offset),
//! `tools::volumeToMesh`, `tools::csgUnion` and `io::File`. Every function that can
//! fail returns a status (0 for success, see the `STATUS_*` constants) and writes
//! a message into the caller's buffer; no C++ exception crosses into Rust.
//!
//! These are the raw functions; `perifrac-surface` wraps them in safe types.
#![warn(missing_docs)]

use std::ffi::c_char;
use std::marker::{PhantomData, PhantomPinned};

/// Success.
pub const STATUS_OK: i32 = 0;
/// An argument was rejected before OpenVDB was called (no particles, NaN, …).
pub const STATUS_INVALID_ARGUMENT: i32 = 1;
/// OpenVDB threw an `openvdb::Exception`.
pub const STATUS_OPENVDB_ERROR: i32 = 2;
/// OpenVDB threw another `std::exception` (for example `std::bad_alloc`).
pub const STATUS_STD_ERROR: i32 = 3;
/// Something that is not a `std::exception` was thrown.
pub const STATUS_UNKNOWN_ERROR: i32 = 4;

/// Filter kind for [`pvdb_level_set_filter`]: mean-curvature flow.
pub const FILTER_MEAN_CURVATURE: i32 = 0;
/// Filter kind for [`pvdb_level_set_filter`]: Gaussian convolution of width 1.
pub const FILTER_GAUSSIAN: i32 = 1;
/// Filter kind for [`pvdb_level_set_filter`]: Laplacian flow.
pub const FILTER_LAPLACIAN: i32 = 2;

/// A narrow-band level set (`FloatGrid`) made from particles, with the index of the
/// particle that made each voxel of the rasterized band.
#[repr(C)]
pub struct PvdbLevelSet {
    _private: [u8; 0],
    _marker: PhantomData<(*mut u8, PhantomPinned)>,
}

/// A frame being assembled: the union of level sets (grid `surface`) and a velocity
/// grid (`v`).
#[repr(C)]
pub struct PvdbFrame {
    _private: [u8; 0],
    _marker: PhantomData<(*mut u8, PhantomPinned)>,
}

/// A polygon mesh from `tools::volumeToMesh`: points, triangles and quads.
#[repr(C)]
pub struct PvdbMesh {
    _private: [u8; 0],
    _marker: PhantomData<(*mut u8, PhantomPinned)>,
}

unsafe extern "C" {
    /// Calls `openvdb::initialize()` (once) and caps TBB's thread pool at `threads`
    /// (0: no cap). Call before any other function.
    pub fn pvdb_initialize(threads: usize);

    /// Rasterizes `count` spheres (positions: 3 floats each; radii: world units) into a
    /// level set of the given voxel size and narrow-band half width (voxels), then
    /// renormalizes it and trims it to the narrow band (`LevelSetTracker::track`). Spheres under 1.5 voxels of radius are
    /// dropped and counted in `dropped_small`; huge ones in `dropped_large`.
    pub fn pvdb_level_set_from_spheres(
        positions: *const f32,
        radii: *const f32,
        count: usize,
        voxel_size: f64,
        half_width: f64,
        out: *mut *mut PvdbLevelSet,
        dropped_small: *mut usize,
        dropped_large: *mut usize,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;

    /// Frees a level set.
    pub fn pvdb_level_set_free(level_set: *mut PvdbLevelSet);

    /// Runs `iterations` passes of a filter (`FILTER_*`) over a level set.
    pub fn pvdb_level_set_filter(
        level_set: *mut PvdbLevelSet,
        kind: i32,
        iterations: usize,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;

    /// Moves a level set's surface outward by `distance` (world units; negative:
    /// inward).
    pub fn pvdb_level_set_offset(
        level_set: *mut PvdbLevelSet,
        distance: f64,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;

    /// Meshes the zero isosurface with the given adaptivity in [0, 1].
    pub fn pvdb_level_set_mesh(
        level_set: *const PvdbLevelSet,
        adaptivity: f64,
        out: *mut *mut PvdbMesh,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;

    /// Points in a mesh.
    pub fn pvdb_mesh_point_count(mesh: *const PvdbMesh) -> usize;
    /// Triangles in a mesh.
    pub fn pvdb_mesh_triangle_count(mesh: *const PvdbMesh) -> usize;
    /// Quads in a mesh.
    pub fn pvdb_mesh_quad_count(mesh: *const PvdbMesh) -> usize;

    /// Copies a mesh into caller-owned arrays of 3 floats a point, 3 indices a
    /// triangle and 4 indices a quad, sized from the counts.
    pub fn pvdb_mesh_copy(
        mesh: *const PvdbMesh,
        points: *mut f32,
        triangles: *mut u32,
        quads: *mut u32,
    );

    /// Frees a mesh.
    pub fn pvdb_mesh_free(mesh: *mut PvdbMesh);

    /// Starts an empty frame of the given voxel size and half width (voxels).
    pub fn pvdb_frame_new(
        voxel_size: f64,
        half_width: f64,
        out: *mut *mut PvdbFrame,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;

    /// Frees a frame.
    pub fn pvdb_frame_free(frame: *mut PvdbFrame);

    /// Unions a level set into the frame and takes ownership of it (it is freed, also
    /// on failure); `velocities` (3 floats for each of the `count` particles it was
    /// made from) fill the velocity grid over its rasterized band.
    pub fn pvdb_frame_add(
        frame: *mut PvdbFrame,
        level_set: *mut PvdbLevelSet,
        velocities: *const f32,
        count: usize,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;

    /// Active voxels of the frame's `surface` grid.
    pub fn pvdb_frame_active_voxels(frame: *const PvdbFrame) -> usize;

    /// Writes the frame's grids to a .vdb file at `path` (a NUL-terminated string).
    pub fn pvdb_frame_write(
        frame: *const PvdbFrame,
        path: *const c_char,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;
}
