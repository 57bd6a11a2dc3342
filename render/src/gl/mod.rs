//! Offscreen OpenGL previews on Mesa's software rasteriser (feature `gl`): the context
//! ([`context`]), the shaders ([`shaders`]) and the renderer ([`renderer`]).

pub mod context;
pub mod renderer;
pub mod shaders;

pub use context::{Backend, Context};
pub use renderer::{PassTimes, Rendered, Renderer, View};
