//! The framebuffers a renderer draws into: a 4× MSAA sRGB target and the
//! single-sample target it resolves into for the readback.

use glow::HasContext;

use super::renderer::{SAMPLES, gl_error};
use crate::RenderError;

/// The main pass's framebuffers and their size.
pub(super) struct Targets {
    pub(super) width: i32,
    pub(super) height: i32,
    pub(super) msaa: glow::Framebuffer,
    msaa_color: glow::Renderbuffer,
    msaa_depth: glow::Renderbuffer,
    pub(super) resolve: glow::Framebuffer,
    resolve_color: glow::Renderbuffer,
}

impl Targets {
    /// The 4× MSAA sRGB framebuffer (colour and depth) and the single-sample one it
    /// resolves into, `width`×`height`.
    ///
    /// # Safety
    /// `gl` is current on this thread.
    pub(super) unsafe fn new(
        gl: &glow::Context,
        width: i32,
        height: i32,
    ) -> Result<Targets, RenderError> {
        // SAFETY (whole body): framebuffer objects on the current context.
        unsafe {
            let renderbuffer =
                |samples: i32, format: u32| -> Result<glow::Renderbuffer, RenderError> {
                    let rb = gl
                        .create_renderbuffer()
                        .map_err(|e| gl_error("renderbuffer", e))?;
                    gl.bind_renderbuffer(glow::RENDERBUFFER, Some(rb));
                    gl.renderbuffer_storage_multisample(
                        glow::RENDERBUFFER,
                        samples,
                        format,
                        width,
                        height,
                    );
                    Ok(rb)
                };
            let msaa_color = renderbuffer(SAMPLES, glow::SRGB8_ALPHA8)?;
            let msaa_depth = renderbuffer(SAMPLES, glow::DEPTH_COMPONENT24)?;
            let resolve_color = renderbuffer(0, glow::SRGB8_ALPHA8)?;
            let msaa = gl
                .create_framebuffer()
                .map_err(|e| gl_error("framebuffer", e))?;
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(msaa));
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(msaa_color),
            );
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::DEPTH_ATTACHMENT,
                glow::RENDERBUFFER,
                Some(msaa_depth),
            );
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(gl_error(
                    "MSAA framebuffer",
                    format!("incomplete ({status:#x}) at {width}×{height}"),
                ));
            }
            let resolve = gl
                .create_framebuffer()
                .map_err(|e| gl_error("framebuffer", e))?;
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(resolve));
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(resolve_color),
            );
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(gl_error(
                    "resolve framebuffer",
                    format!("incomplete ({status:#x})"),
                ));
            }
            Ok(Targets {
                width,
                height,
                msaa,
                msaa_color,
                msaa_depth,
                resolve,
                resolve_color,
            })
        }
    }

    /// Deletes the framebuffers and their renderbuffers.
    ///
    /// # Safety
    /// `gl` is the context they were made on, current on this thread.
    pub(super) unsafe fn delete(&self, gl: &glow::Context) {
        // SAFETY: objects this target owns, on its own context.
        unsafe {
            gl.delete_framebuffer(self.msaa);
            gl.delete_framebuffer(self.resolve);
            for rb in [self.msaa_color, self.msaa_depth, self.resolve_color] {
                gl.delete_renderbuffer(rb);
            }
        }
    }
}

pub(super) fn check_size(width: u32, height: u32) -> Result<(i32, i32), RenderError> {
    const MAX: u32 = 8192;
    if width == 0 || height == 0 || width > MAX || height > MAX {
        return Err(RenderError::Size(format!(
            "{width}×{height} is not a valid image size; each side must be 1–{MAX} pixels"
        )));
    }
    Ok((width as i32, height as i32))
}
