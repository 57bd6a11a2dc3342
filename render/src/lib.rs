//! perifrac's render stage: surfaces and particles from the cache become files a DCC
//! or a viewer opens, and preview images.
//!
//! | module | main items |
//! |---|---|
//! | [`gltf`] | [`gltf::to_glb`], [`gltf::crack_glb`], [`gltf::animated_glb`], [`gltf::Glb`]: glTF 2.0 binary (.glb) writing of the cache's `SurfaceMesh`, animations at the playback time base; [`gltf::read_glb`], [`gltf::read_surfaces`]: reading them back |
//! | [`cache`] | [`cache::Cache`]: an output directory read for previews (frames, colliders, surfaces, particles) |
//! | [`geometry`] | [`geometry::FrameGeometry`]: what a preview draws, as flat arrays, and the colour maps |
//! | [`camera`] | [`camera::Camera`], [`camera::Bounds`], [`camera::Lights`]: automatic framing, turntables, the studio lights |
//! | `gl` (feature `gl`) | the offscreen OpenGL renderer on Mesa (EGL surfaceless, or OSMesa) |
//! | `preview` (feature `gl`) | `PreviewOptions`: `preview/NNNN.png`, turntables, the contact sheet |
//! | [`movie`] | [`movie::write_apng`], [`movie::write_mp4`]: the previews as an animated PNG and (with ffmpeg) an H.264 MP4 |
//! | [`paint`] | [`paint::paint_surfaces`], [`paint::NearestBody`]: colour by material, meshes painted by the nearest particle's body |
//! | [`sheet`] | PNG writing, contact sheets, a built-in bitmap font for frame numbers |
//!
//! [`RenderError`] is the crate's one error type.
#![warn(missing_docs)]

pub mod cache;
pub mod camera;
pub mod follow;
pub mod geometry;
#[cfg(feature = "gl")]
pub mod gl;
pub mod gltf;
pub mod movie;
pub mod paint;
#[cfg(feature = "gl")]
pub mod preview;
pub mod sheet;

use std::path::{Path, PathBuf};

/// Everything that can go wrong in the render stage.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The data handed to a writer cannot be encoded (mismatched lengths, indices out
    /// of range, non-finite positions, a file over the format's size limit).
    #[error("glTF: {0}")]
    Gltf(String),
    /// No OpenGL context: neither EGL nor OSMesa could be loaded or initialised.
    #[error(
        "no OpenGL context for previews ({0}); install Mesa's software OpenGL with scripts/setup.sh (Debian: libegl1 libegl-mesa0 libgl1-mesa-dri, or libosmesa6)"
    )]
    NoContext(String),
    /// The GL implementation refused something (a shader, a framebuffer).
    #[error("OpenGL: {0}")]
    Gl(String),
    /// An image size that cannot be rendered.
    #[error("image size: {0}")]
    Size(String),
    /// A file of the cache is missing or malformed.
    #[error("{path}: {message}")]
    Input {
        /// The file.
        path: PathBuf,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A cache file (scene, manifest, particles) could not be read or written.
    #[error(transparent)]
    Cache(#[from] perifrac_cache::CacheError),
    /// Reading or writing a file failed.
    #[error("{path}: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause (in the message, not chained: the OS's words once).
        error: std::io::Error,
    },
}

impl RenderError {
    /// An I/O error on `path`.
    pub fn io(path: &Path, error: std::io::Error) -> RenderError {
        RenderError::Io {
            path: path.to_path_buf(),
            error,
        }
    }
}
