//! Offscreen OpenGL previews on Mesa's software rasteriser (feature `gl`): the context
//! ([`context`]), the shaders ([`shaders`]), the renderer ([`renderer`]), its
//! framebuffers (`targets`) and its culling of hidden points (`occlusion`).

pub mod context;
mod occlusion;
pub mod renderer;
pub mod shaders;
mod targets;

pub use context::{Backend, Context};
pub use renderer::{PassTimes, Rendered, Renderer, View};
