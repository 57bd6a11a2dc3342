//! perifrac's render stage: surfaces and particles from the cache become files a DCC
//! or a viewer opens.
//!
//! - [`gltf`]: a glTF 2.0 binary (.glb) writer for triangle meshes.
#![warn(missing_docs)]

pub mod gltf;

/// Everything that can go wrong in the render stage.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The data handed to a writer cannot be encoded (mismatched lengths, indices out
    /// of range, non-finite positions, a file over the format's size limit).
    #[error("glTF: {0}")]
    Gltf(String),
}
