//! The offscreen renderer: one GL context, its programs and framebuffers, reused for
//! every frame a thread draws. A frame is four timed passes:
//!
//! 1. upload: one vertex and one index buffer for all triangles (surfaces, crack faces,
//!    colliders), one vertex buffer for all points (one vertex a particle);
//! 2. shadow: the key light's depth map (depth only, orthographic, polygon offset);
//! 3. main: meshes, sphere-impostor points and the ground into a 4× MSAA sRGB
//!    framebuffer (two draw calls for the geometry, one for the ground);
//! 4. resolve + readback: `glBlitFramebuffer` to a single-sample sRGB framebuffer,
//!    `glReadPixels`, rows flipped (GL returns them bottom-up).

use std::time::Instant;

use glow::HasContext;
use image::RgbImage;

use super::context::{Backend, Context};
use super::occlusion::visible_points;
use super::shaders;
use super::targets::{Targets, check_size};
use crate::RenderError;
use crate::camera::{Bounds, Camera, Mat4, shadow_view_projection};
use crate::geometry::{FrameGeometry, MESH_STRIDE, POINT_STRIDE, srgb_to_linear};

/// Samples a pixel of the main framebuffer.
pub const SAMPLES: i32 = 4;
/// Side of the square shadow map, in texels.
pub const SHADOW_SIZE: i32 = 1024;

/// What the camera sees and the scene it frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The camera.
    pub camera: Camera,
    /// The bounds the camera was framed on (the shadow map and the ground follow
    /// them, so a sequence's frames share them).
    pub bounds: Bounds,
    /// Ground height.
    pub ground: f32,
    /// Key light intensity (1 by default; the perturbation test changes it).
    pub key_strength: f32,
}

/// Seconds in each pass of one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PassTimes {
    /// Buffer upload.
    pub upload: f64,
    /// Shadow map.
    pub shadow: f64,
    /// Main MSAA pass.
    pub main: f64,
    /// MSAA resolve and pixel readback (with the row flip).
    pub readback: f64,
}

impl PassTimes {
    /// Sum of the passes.
    pub fn total(&self) -> f64 {
        self.upload + self.shadow + self.main + self.readback
    }
}

/// A rendered frame.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// sRGB pixels, top row first.
    pub image: RgbImage,
    /// Pass timings.
    pub times: PassTimes,
    /// Mesh vertices and points of the simulated bodies inside the view volume (0: an
    /// empty frame, whatever colliders remain).
    pub in_view: usize,
}

struct Programs {
    mesh: glow::Program,
    points: glow::Program,
    ground: glow::Program,
    shadow_mesh: glow::Program,
    shadow_points: glow::Program,
}

/// A GL context with everything a frame needs, for one thread.
pub struct Renderer {
    programs: Programs,
    targets: Targets,
    shadow_fbo: glow::Framebuffer,
    shadow_map: glow::Texture,
    mesh_vao: glow::VertexArray,
    mesh_vbo: glow::Buffer,
    mesh_ibo: glow::Buffer,
    point_vao: glow::VertexArray,
    point_vbo: glow::Buffer,
    empty_vao: glow::VertexArray,
    pixels: Vec<u8>,
    sorted_points: Vec<f32>,
    context: Context,
}

/// The backdrop colour (sRGB 0.70, 0.72, 0.75, a light studio grey), linear.
fn background() -> [f32; 3] {
    [0.70, 0.72, 0.75].map(srgb_to_linear)
}

pub(super) fn gl_error(what: &str, message: impl std::fmt::Display) -> RenderError {
    RenderError::Gl(format!("{what}: {message}"))
}

unsafe fn compile(
    gl: &glow::Context,
    vertex: &str,
    fragment: &str,
) -> Result<glow::Program, RenderError> {
    // SAFETY (whole body): plain GL object creation on the current context.
    unsafe {
        let program = gl.create_program().map_err(|e| gl_error("program", e))?;
        let mut shaders = Vec::new();
        for (kind, source) in [
            (glow::VERTEX_SHADER, vertex),
            (glow::FRAGMENT_SHADER, fragment),
        ] {
            let shader = gl.create_shader(kind).map_err(|e| gl_error("shader", e))?;
            gl.shader_source(shader, source);
            gl.compile_shader(shader);
            if !gl.get_shader_compile_status(shader) {
                return Err(gl_error(
                    "shader compilation",
                    gl.get_shader_info_log(shader),
                ));
            }
            gl.attach_shader(program, shader);
            shaders.push(shader);
        }
        gl.link_program(program);
        if !gl.get_program_link_status(program) {
            return Err(gl_error("program link", gl.get_program_info_log(program)));
        }
        for shader in shaders {
            gl.detach_shader(program, shader);
            gl.delete_shader(shader);
        }
        Ok(program)
    }
}

unsafe fn attribute(
    gl: &glow::Context,
    index: u32,
    size: i32,
    stride_floats: usize,
    offset_floats: usize,
) {
    // SAFETY: the caller has bound the VAO and the buffer the attribute reads.
    unsafe {
        gl.enable_vertex_attrib_array(index);
        gl.vertex_attrib_pointer_f32(
            index,
            size,
            glow::FLOAT,
            false,
            (stride_floats * 4) as i32,
            (offset_floats * 4) as i32,
        );
    }
}

fn as_bytes<T: bytemuck::Pod>(data: &[T]) -> &[u8] {
    bytemuck::cast_slice(data)
}

impl Renderer {
    /// A context (EGL, else OSMesa) with the programs compiled and a `width`×`height`
    /// framebuffer.
    pub fn new(width: u32, height: u32) -> Result<Renderer, RenderError> {
        let context = Context::new()?;
        let gl = &context.gl;
        let (w, h) = check_size(width, height)?;
        // SAFETY (whole block): object creation on the context just made current.
        unsafe {
            let programs = Programs {
                mesh: compile(gl, shaders::MESH_VERTEX, &shaders::mesh_fragment())?,
                points: compile(gl, shaders::POINT_VERTEX, &shaders::point_fragment())?,
                ground: compile(gl, shaders::GROUND_VERTEX, &shaders::ground_fragment())?,
                shadow_mesh: compile(
                    gl,
                    shaders::SHADOW_MESH_VERTEX,
                    shaders::SHADOW_MESH_FRAGMENT,
                )?,
                shadow_points: compile(gl, shaders::POINT_VERTEX, shaders::SHADOW_POINT_FRAGMENT)?,
            };
            let targets = Targets::new(gl, w, h)?;
            let shadow_map = gl.create_texture().map_err(|e| gl_error("texture", e))?;
            gl.bind_texture(glow::TEXTURE_2D, Some(shadow_map));
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                0,
                glow::DEPTH_COMPONENT24 as i32,
                SHADOW_SIZE,
                SHADOW_SIZE,
                0,
                glow::DEPTH_COMPONENT,
                glow::UNSIGNED_INT,
                glow::PixelUnpackData::Slice(None),
            );
            for (p, v) in [
                (glow::TEXTURE_MIN_FILTER, glow::LINEAR),
                (glow::TEXTURE_MAG_FILTER, glow::LINEAR),
                (glow::TEXTURE_WRAP_S, glow::CLAMP_TO_BORDER),
                (glow::TEXTURE_WRAP_T, glow::CLAMP_TO_BORDER),
                (glow::TEXTURE_COMPARE_MODE, glow::COMPARE_REF_TO_TEXTURE),
                (glow::TEXTURE_COMPARE_FUNC, glow::LEQUAL),
            ] {
                gl.tex_parameter_i32(glow::TEXTURE_2D, p, v as i32);
            }
            gl.tex_parameter_f32_slice(glow::TEXTURE_2D, glow::TEXTURE_BORDER_COLOR, &[1.0; 4]);
            let shadow_fbo = gl
                .create_framebuffer()
                .map_err(|e| gl_error("framebuffer", e))?;
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(shadow_fbo));
            gl.framebuffer_texture_2d(
                glow::FRAMEBUFFER,
                glow::DEPTH_ATTACHMENT,
                glow::TEXTURE_2D,
                Some(shadow_map),
                0,
            );
            gl.draw_buffers(&[glow::NONE]);
            gl.read_buffer(glow::NONE);
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(gl_error(
                    "shadow framebuffer",
                    format!("incomplete ({status:#x})"),
                ));
            }

            let mesh_vao = gl
                .create_vertex_array()
                .map_err(|e| gl_error("vertex array", e))?;
            let mesh_vbo = gl.create_buffer().map_err(|e| gl_error("buffer", e))?;
            let mesh_ibo = gl.create_buffer().map_err(|e| gl_error("buffer", e))?;
            gl.bind_vertex_array(Some(mesh_vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(mesh_vbo));
            gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(mesh_ibo));
            attribute(gl, 0, 3, MESH_STRIDE, 0);
            attribute(gl, 1, 3, MESH_STRIDE, 3);
            attribute(gl, 2, 3, MESH_STRIDE, 6);
            attribute(gl, 3, 1, MESH_STRIDE, 9);
            let point_vao = gl
                .create_vertex_array()
                .map_err(|e| gl_error("vertex array", e))?;
            let point_vbo = gl.create_buffer().map_err(|e| gl_error("buffer", e))?;
            gl.bind_vertex_array(Some(point_vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(point_vbo));
            attribute(gl, 0, 3, POINT_STRIDE, 0);
            attribute(gl, 1, 1, POINT_STRIDE, 3);
            attribute(gl, 2, 3, POINT_STRIDE, 4);
            let empty_vao = gl
                .create_vertex_array()
                .map_err(|e| gl_error("vertex array", e))?;
            gl.bind_vertex_array(None);
            gl.enable(glow::PROGRAM_POINT_SIZE);
            gl.pixel_store_i32(glow::PACK_ALIGNMENT, 1);
            Ok(Renderer {
                programs,
                targets,
                shadow_fbo,
                shadow_map,
                mesh_vao,
                mesh_vbo,
                mesh_ibo,
                point_vao,
                point_vbo,
                empty_vao,
                pixels: Vec::new(),
                sorted_points: Vec::new(),
                context,
            })
        }
    }

    /// Which library the context came from.
    pub fn backend(&self) -> Backend {
        self.context.backend
    }

    /// The renderer string of the GL implementation (for example `llvmpipe (LLVM 15.0.6,
    /// 256 bits)`).
    pub fn gl_renderer(&self) -> String {
        // SAFETY: a query on the current context.
        unsafe { self.context.gl.get_parameter_string(glow::RENDERER) }
    }

    /// Image size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.targets.width as u32, self.targets.height as u32)
    }

    /// Changes the image size (reallocates the framebuffers).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        let (w, h) = check_size(width, height)?;
        if (w, h) == (self.targets.width, self.targets.height) {
            return Ok(());
        }
        let gl = &self.context.gl;
        // SAFETY: deleting objects this renderer owns, then making new ones.
        unsafe {
            self.targets.delete(gl);
            self.targets = Targets::new(gl, w, h)?;
        }
        Ok(())
    }

    /// Renders `geometry` as `view` sees it.
    pub fn render(
        &mut self,
        geometry: &FrameGeometry,
        view: &View,
    ) -> Result<Rendered, RenderError> {
        let gl = &self.context.gl;
        let (w, h) = (self.targets.width, self.targets.height);
        let mut times = PassTimes::default();
        let camera = view.camera;
        let view_proj = camera.view_projection();
        let lights = camera.lights();
        let center = view.bounds.center();
        let radius = view.bounds.radius().max(1e-3);
        let light_view_proj = shadow_view_projection(lights.key, center, 1.05 * radius);
        let in_view = geometry.count_in_view(&view_proj);
        let triangles = geometry.mesh_indices.len() as i32;
        let shadow_pixels_per_unit = SHADOW_SIZE as f32 / (2.0 * 1.05 * radius);
        let camera_pixels_per_unit = camera.projection()[1][1] * 0.5 * h as f32;
        let background = background();

        // SAFETY (whole block): GL calls on this renderer's current context, with
        // objects it created; buffer uploads copy from live slices.
        unsafe {
            // 1. Upload: the points the key light sees, then those the camera sees
            // (front to back, hidden ones dropped: see `visible_points`).
            let t = Instant::now();
            self.sorted_points.clear();
            visible_points(
                &geometry.points,
                &light_view_proj,
                shadow_pixels_per_unit,
                false,
                (SHADOW_SIZE, SHADOW_SIZE),
                &mut self.sorted_points,
            );
            let shadow_points = (self.sorted_points.len() / POINT_STRIDE) as i32;
            visible_points(
                &geometry.points,
                &view_proj,
                camera_pixels_per_unit,
                true,
                (w, h),
                &mut self.sorted_points,
            );
            let camera_points = (self.sorted_points.len() / POINT_STRIDE) as i32 - shadow_points;
            gl.bind_vertex_array(Some(self.mesh_vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.mesh_vbo));
            gl.buffer_data_u8_slice(
                glow::ARRAY_BUFFER,
                as_bytes(&geometry.mesh_vertices),
                glow::STREAM_DRAW,
            );
            gl.buffer_data_u8_slice(
                glow::ELEMENT_ARRAY_BUFFER,
                as_bytes(&geometry.mesh_indices),
                glow::STREAM_DRAW,
            );
            gl.bind_vertex_array(Some(self.point_vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.point_vbo));
            gl.buffer_data_u8_slice(
                glow::ARRAY_BUFFER,
                as_bytes(&self.sorted_points),
                glow::STREAM_DRAW,
            );
            gl.finish();
            times.upload = t.elapsed().as_secs_f64();

            // 2. Shadow map: depth only, from the key light.
            let t = Instant::now();
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(self.shadow_fbo));
            gl.viewport(0, 0, SHADOW_SIZE, SHADOW_SIZE);
            gl.enable(glow::DEPTH_TEST);
            gl.depth_func(glow::LESS);
            gl.clear(glow::DEPTH_BUFFER_BIT);
            gl.enable(glow::POLYGON_OFFSET_FILL);
            gl.polygon_offset(1.5, 2.0);
            if triangles > 0 {
                let p = self.programs.shadow_mesh;
                gl.use_program(Some(p));
                set_mat4(gl, p, "u_view_proj", &light_view_proj);
                gl.bind_vertex_array(Some(self.mesh_vao));
                gl.draw_elements(glow::TRIANGLES, triangles, glow::UNSIGNED_INT, 0);
            }
            if shadow_points > 0 {
                let p = self.programs.shadow_points;
                gl.use_program(Some(p));
                set_mat4(gl, p, "u_view_proj", &light_view_proj);
                set_f32(gl, p, "u_pixels_per_unit", shadow_pixels_per_unit);
                set_f32(gl, p, "u_perspective", 0.0);
                gl.bind_vertex_array(Some(self.point_vao));
                gl.draw_arrays(glow::POINTS, 0, shadow_points);
            }
            gl.disable(glow::POLYGON_OFFSET_FILL);
            gl.finish();
            times.shadow = t.elapsed().as_secs_f64();

            // 3. Main pass into the MSAA framebuffer.
            let t = Instant::now();
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(self.targets.msaa));
            gl.viewport(0, 0, w, h);
            gl.enable(glow::FRAMEBUFFER_SRGB);
            gl.clear_color(background[0], background[1], background[2], 1.0);
            gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
            gl.active_texture(glow::TEXTURE0);
            gl.bind_texture(glow::TEXTURE_2D, Some(self.shadow_map));
            let lit = |p: glow::Program| {
                gl.use_program(Some(p));
                set_mat4(gl, p, "u_view_proj", &view_proj);
                set_mat4(gl, p, "u_light_view_proj", &light_view_proj);
                set_vec3(gl, p, "u_eye", camera.eye);
                set_vec3(gl, p, "u_key", lights.key);
                set_vec3(gl, p, "u_fill", lights.fill);
                set_vec3(gl, p, "u_rim", lights.rim);
                set_f32(gl, p, "u_key_strength", view.key_strength);
                set_f32(gl, p, "u_shadow_texel", 1.0 / SHADOW_SIZE as f32);
                set_f32(gl, p, "u_bias", 1.5 / SHADOW_SIZE as f32);
                set_i32(gl, p, "u_shadow", 0);
            };
            if triangles > 0 {
                lit(self.programs.mesh);
                gl.bind_vertex_array(Some(self.mesh_vao));
                gl.draw_elements(glow::TRIANGLES, triangles, glow::UNSIGNED_INT, 0);
            }
            if camera_points > 0 {
                let p = self.programs.points;
                lit(p);
                set_f32(gl, p, "u_pixels_per_unit", camera_pixels_per_unit);
                set_f32(gl, p, "u_perspective", 1.0);
                set_vec3(gl, p, "u_cam_right", camera.right());
                set_vec3(gl, p, "u_cam_up", camera.up());
                gl.bind_vertex_array(Some(self.point_vao));
                gl.draw_arrays(glow::POINTS, shadow_points, camera_points);
            }
            let p = self.programs.ground;
            lit(p);
            set_vec3(gl, p, "u_center", [center[0], view.ground, center[2]]);
            set_f32(gl, p, "u_extent", 40.0 * radius);
            set_f32(gl, p, "u_fade_start", 2.5 * radius);
            set_f32(gl, p, "u_fade_end", 9.0 * radius);
            set_vec3(gl, p, "u_background", background);
            gl.bind_vertex_array(Some(self.empty_vao));
            gl.draw_arrays(glow::TRIANGLE_STRIP, 0, 4);
            gl.finish();
            times.main = t.elapsed().as_secs_f64();

            // 4. Resolve and read back.
            let t = Instant::now();
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.targets.msaa));
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, Some(self.targets.resolve));
            gl.blit_framebuffer(
                0,
                0,
                w,
                h,
                0,
                0,
                w,
                h,
                glow::COLOR_BUFFER_BIT,
                glow::NEAREST,
            );
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.targets.resolve));
            let row = (w * 3) as usize;
            self.pixels.resize(row * h as usize, 0);
            gl.read_pixels(
                0,
                0,
                w,
                h,
                glow::RGB,
                glow::UNSIGNED_BYTE,
                glow::PixelPackData::Slice(Some(&mut self.pixels)),
            );
            gl.disable(glow::FRAMEBUFFER_SRGB);
            let error = gl.get_error();
            if error != glow::NO_ERROR {
                return Err(gl_error("rendering", format!("GL error {error:#x}")));
            }
            // GL's rows run bottom-up; images top-down.
            let mut rgb = Vec::with_capacity(self.pixels.len());
            for line in self.pixels.chunks_exact(row).rev() {
                rgb.extend_from_slice(line);
            }
            times.readback = t.elapsed().as_secs_f64();
            let image = RgbImage::from_raw(w as u32, h as u32, rgb)
                .ok_or_else(|| gl_error("readback", "pixel buffer of the wrong size"))?;
            Ok(Rendered {
                image,
                times,
                in_view,
            })
        }
    }
}

unsafe fn set_mat4(gl: &glow::Context, p: glow::Program, name: &str, m: &Mat4) {
    // SAFETY: `p` is in use on the current context.
    unsafe {
        let loc = gl.get_uniform_location(p, name);
        gl.uniform_matrix_4_f32_slice(loc.as_ref(), false, m.as_flattened());
    }
}

unsafe fn set_vec3(gl: &glow::Context, p: glow::Program, name: &str, v: [f32; 3]) {
    // SAFETY: `p` is in use on the current context.
    unsafe {
        let loc = gl.get_uniform_location(p, name);
        gl.uniform_3_f32(loc.as_ref(), v[0], v[1], v[2]);
    }
}

unsafe fn set_f32(gl: &glow::Context, p: glow::Program, name: &str, v: f32) {
    // SAFETY: `p` is in use on the current context.
    unsafe {
        let loc = gl.get_uniform_location(p, name);
        gl.uniform_1_f32(loc.as_ref(), v);
    }
}

unsafe fn set_i32(gl: &glow::Context, p: glow::Program, name: &str, v: i32) {
    // SAFETY: `p` is in use on the current context.
    unsafe {
        let loc = gl.get_uniform_location(p, name);
        gl.uniform_1_i32(loc.as_ref(), v);
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        let gl = &self.context.gl;
        // SAFETY: deleting objects this renderer created, on its own context.
        unsafe {
            let p = &self.programs;
            for program in [p.mesh, p.points, p.ground, p.shadow_mesh, p.shadow_points] {
                gl.delete_program(program);
            }
            self.targets.delete(gl);
            gl.delete_framebuffer(self.shadow_fbo);
            gl.delete_texture(self.shadow_map);
            for b in [self.mesh_vbo, self.mesh_ibo, self.point_vbo] {
                gl.delete_buffer(b);
            }
            for v in [self.mesh_vao, self.point_vao, self.empty_vao] {
                gl.delete_vertex_array(v);
            }
        }
    }
}
