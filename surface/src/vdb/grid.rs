//! Safe owners of the shim's OpenVDB objects (`openvdb-sys`): a level set made from
//! spheres, a frame that unions level sets and writes a .vdb file, and mesh
//! extraction. Each call's status and exception text become a
//! [`SurfaceError::OpenVdb`].

use std::ffi::{CString, c_char};
use std::path::Path;
use std::sync::Once;

use openvdb_sys as sys;

use crate::error::{Result, SurfaceError};
use crate::mesh::TriangleMesh;

const MESSAGE_LEN: usize = 1024;

static INITIALIZE: Once = Once::new();

/// Initializes OpenVDB and caps its TBB thread pool at `threads` (OpenVDB runs its
/// own pool beside rayon's; give it the same count). The first call wins.
pub fn initialize(threads: usize) {
    // SAFETY: the shim's initializer takes no pointers and is safe to call at any time.
    INITIALIZE.call_once(|| unsafe { sys::pvdb_initialize(threads) });
}

/// Runs a shim call with a message buffer and turns a non-zero status into an error.
fn call(
    frame: usize,
    operation: &'static str,
    f: impl FnOnce(*mut c_char, usize) -> i32,
) -> Result<()> {
    let mut message = vec![0u8; MESSAGE_LEN];
    let status = f(message.as_mut_ptr().cast(), MESSAGE_LEN);
    if status == sys::STATUS_OK {
        return Ok(());
    }
    let end = message.iter().position(|&b| b == 0).unwrap_or(MESSAGE_LEN);
    let text = String::from_utf8_lossy(&message[..end]).into_owned();
    Err(SurfaceError::OpenVdb {
        frame,
        operation,
        message: if text.is_empty() {
            format!("failed with status {status}")
        } else {
            text
        },
    })
}

/// A narrow-band level set made from spheres.
pub struct LevelSet {
    raw: *mut sys::PvdbLevelSet,
    frame: usize,
}

// SAFETY: a level set is an owned OpenVDB grid with no thread affinity; the shim's
// functions take it by exclusive pointer.
unsafe impl Send for LevelSet {}

/// What [`LevelSet::from_spheres`] rasterized.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RasterCount {
    /// Particles dropped for a radius under 1.5 voxels.
    pub too_small: usize,
    /// Particles dropped for a huge radius (over 100 voxels).
    pub too_large: usize,
}

impl LevelSet {
    /// Rasterizes spheres (OpenVDB `tools::ParticlesToLevelSet`) into a level set of
    /// the given voxel size and narrow-band half width (voxels), renormalized and
    /// trimmed to a narrow band of signed distance (`tools::LevelSetTracker`).
    pub fn from_spheres(
        frame: usize,
        positions: &[[f32; 3]],
        radii: &[f32],
        voxel_size: f64,
        half_width: f64,
    ) -> Result<(LevelSet, RasterCount)> {
        if positions.len() != radii.len() {
            return Err(SurfaceError::Frame {
                frame,
                message: format!("{} positions but {} radii", positions.len(), radii.len()),
            });
        }
        let mut raw = std::ptr::null_mut();
        let mut count = RasterCount::default();
        call(frame, "rasterizing particles", |err, len| {
            // SAFETY: the arrays hold `positions.len()` particles (3 floats and 1 float
            // each) and outlive the call; the out-pointers are valid.
            unsafe {
                sys::pvdb_level_set_from_spheres(
                    positions.as_ptr().cast(),
                    radii.as_ptr(),
                    positions.len(),
                    voxel_size,
                    half_width,
                    &mut raw,
                    &mut count.too_small,
                    &mut count.too_large,
                    err,
                    len,
                )
            }
        })?;
        Ok((LevelSet { raw, frame }, count))
    }

    /// Runs `iterations` passes of a `tools::LevelSetFilter` filter (`sys::FILTER_*`).
    pub fn filter(&mut self, kind: i32, iterations: usize) -> Result<()> {
        let raw = self.raw;
        call(self.frame, "filtering", |err, len| {
            // SAFETY: `raw` is a live level set we hold exclusively.
            unsafe { sys::pvdb_level_set_filter(raw, kind, iterations, err, len) }
        })
    }

    /// Moves the surface outward by `distance` (m; negative: inward).
    pub fn offset(&mut self, distance: f64) -> Result<()> {
        let raw = self.raw;
        call(self.frame, "offsetting", |err, len| {
            // SAFETY: `raw` is a live level set we hold exclusively.
            unsafe { sys::pvdb_level_set_offset(raw, distance, err, len) }
        })
    }

    /// Meshes the zero isosurface (`tools::volumeToMesh`) with the given adaptivity
    /// and returns it as triangles, counter-clockwise from outside.
    pub fn mesh(&self, adaptivity: f64) -> Result<TriangleMesh> {
        let raw = self.raw;
        let mut mesh = std::ptr::null_mut();
        call(self.frame, "meshing", |err, len| {
            // SAFETY: `raw` is a live level set; `mesh` is a valid out-pointer.
            unsafe { sys::pvdb_level_set_mesh(raw, adaptivity, &mut mesh, err, len) }
        })?;
        // SAFETY: `mesh` is the live mesh just made; the arrays are sized from its
        // counts, and it is freed once, here.
        let (points, triangles, quads) = unsafe {
            let mut points = vec![[0f32; 3]; sys::pvdb_mesh_point_count(mesh)];
            let mut triangles = vec![[0u32; 3]; sys::pvdb_mesh_triangle_count(mesh)];
            let mut quads = vec![[0u32; 4]; sys::pvdb_mesh_quad_count(mesh)];
            sys::pvdb_mesh_copy(
                mesh,
                points.as_mut_ptr().cast(),
                triangles.as_mut_ptr().cast(),
                quads.as_mut_ptr().cast(),
            );
            sys::pvdb_mesh_free(mesh);
            (points, triangles, quads)
        };
        let mut mesh = TriangleMesh::from_polygons(points, &triangles, &quads);
        // volumeToMesh winds its polygons clockwise seen from outside.
        mesh.flip();
        Ok(mesh)
    }
}

impl Drop for LevelSet {
    fn drop(&mut self) {
        // SAFETY: `raw` is live and owned by us (ownership moves out in `Frame::add`,
        // which forgets `self`).
        unsafe { sys::pvdb_level_set_free(self.raw) }
    }
}

/// A frame being assembled: the CSG union of its level sets (grid `surface`) and
/// the particles' velocities (grid `v`).
pub struct Frame {
    raw: *mut sys::PvdbFrame,
    frame: usize,
}

// SAFETY: an owned pair of OpenVDB grids with no thread affinity.
unsafe impl Send for Frame {}

impl Frame {
    /// An empty frame of the given voxel size and half width (voxels).
    pub fn new(frame: usize, voxel_size: f64, half_width: f64) -> Result<Frame> {
        let mut raw = std::ptr::null_mut();
        call(frame, "creating grids", |err, len| {
            // SAFETY: `raw` is a valid out-pointer.
            unsafe { sys::pvdb_frame_new(voxel_size, half_width, &mut raw, err, len) }
        })?;
        Ok(Frame { raw, frame })
    }

    /// Unions a level set into the frame (`tools::csgUnion`), and sets the velocity
    /// grid over its rasterized band from `velocities`, the velocities of the
    /// particles it was made from.
    pub fn add(&mut self, level_set: LevelSet, velocities: &[[f32; 3]]) -> Result<()> {
        let raw = self.raw;
        let level_set = std::mem::ManuallyDrop::new(level_set);
        call(self.frame, "adding a level set to the frame", |err, len| {
            // SAFETY: both objects are live; the shim takes ownership of the level set
            // (freeing it also on failure), which is why it is not dropped here.
            unsafe {
                sys::pvdb_frame_add(
                    raw,
                    level_set.raw,
                    velocities.as_ptr().cast(),
                    velocities.len(),
                    err,
                    len,
                )
            }
        })
    }

    /// Active voxels of the `surface` grid.
    pub fn active_voxels(&self) -> usize {
        // SAFETY: `raw` is a live frame.
        unsafe { sys::pvdb_frame_active_voxels(self.raw) }
    }

    /// Writes the grids `surface` and `v` to a .vdb file.
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = path.to_str().ok_or_else(|| SurfaceError::Frame {
            frame: self.frame,
            message: format!("{} is not a UTF-8 path", path.display()),
        })?;
        let c_path = CString::new(text).map_err(|_| SurfaceError::Frame {
            frame: self.frame,
            message: format!("{} contains a NUL byte", path.display()),
        })?;
        let raw = self.raw;
        call(self.frame, "writing the .vdb file", |err, len| {
            // SAFETY: `raw` is live and `c_path` is a NUL-terminated string.
            unsafe { sys::pvdb_frame_write(raw, c_path.as_ptr(), err, len) }
        })?;
        content_uuid(path).map_err(|e| SurfaceError::io(path, e))
    }
}

/// Where a .vdb file's archive UUID sits: after the magic number (8 bytes), the file
/// format version and the library's major and minor versions (4 each) and the
/// grid-offsets flag (1) (`openvdb::io::Archive::writeHeader`), 36 ASCII characters.
const UUID_AT: std::ops::Range<usize> = 21..57;

/// Replaces the random UUID OpenVDB writes into every file's header (a fresh
/// `boost::uuids::random_generator` value each write, so no two writes of one frame
/// had the same bytes) with one made from the file's other bytes, in the UUID
/// layout (version 8, RFC 9562's custom version): the same frame gives the same file,
/// and two files with the same UUID hold the same grids, which is what OpenVDB's
/// readers use it for (recognising a file they have already loaded). A file whose
/// header is not as expected is left as it is.
fn content_uuid(path: &Path) -> std::io::Result<()> {
    use std::io::{Seek, SeekFrom, Write};
    let bytes = std::fs::read(path)?;
    let is_uuid = |b: &[u8]| {
        b.len() == 36
            && b.iter().enumerate().all(|(i, &c)| match i {
                8 | 13 | 18 | 23 => c == b'-',
                _ => c.is_ascii_hexdigit(),
            })
    };
    if bytes.len() < UUID_AT.end || &bytes[..4] != b" BDV" || !is_uuid(&bytes[UUID_AT]) {
        return Ok(());
    }
    // Two FNV-1a 64-bit hashes (different offsets) of everything but the UUID.
    let fnv = |offset: u64| {
        bytes[..UUID_AT.start]
            .iter()
            .chain(&bytes[UUID_AT.end..])
            .fold(offset, |h, &b| {
                (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
            })
    };
    let mut id = [0u8; 16];
    id[..8].copy_from_slice(&fnv(0xcbf2_9ce4_8422_2325).to_be_bytes());
    id[8..].copy_from_slice(&fnv(0x8422_2325_cbf2_9ce4).to_be_bytes());
    id[6] = (id[6] & 0x0f) | 0x80;
    id[8] = (id[8] & 0x3f) | 0x80;
    let hex: String = id.iter().map(|b| format!("{b:02x}")).collect();
    let text = format!(
        "{}-{}-{}-{}-{}",
        &hex[..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..]
    );
    let mut file = std::fs::OpenOptions::new().write(true).open(path)?;
    file.seek(SeekFrom::Start(UUID_AT.start as u64))?;
    file.write_all(text.as_bytes())
}

impl Drop for Frame {
    fn drop(&mut self) {
        // SAFETY: `raw` is live and owned by us.
        unsafe { sys::pvdb_frame_free(self.raw) }
    }
}
