//! An offscreen OpenGL 3.3 core context on Mesa's software rasteriser (llvmpipe), with no
//! display: EGL with the surfaceless platform (`EGL_PLATFORM_SURFACELESS_MESA` through
//! `eglGetPlatformDisplay`) first, OSMesa as the fallback (OSMesa is gone from Mesa 25.1
//! on). Both libraries are loaded at run time, so a machine without them still runs the
//! rest of the pipeline and is told which library is missing.
//!
//! Environment (for tests and for forcing a backend): `PERIFRAC_GL=egl|osmesa` picks one
//! backend; `PERIFRAC_EGL_LIB` and `PERIFRAC_OSMESA_LIB` name the libraries to load
//! instead of `libEGL.so.1` and `libOSMesa.so.8`.

use std::ffi::{CString, c_void};
use std::sync::OnceLock;

use libloading::Library;

use crate::RenderError;

/// Which library the context came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// EGL, surfaceless platform.
    Egl,
    /// OSMesa (the fallback).
    OsMesa,
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Backend::Egl => "EGL (surfaceless)",
            Backend::OsMesa => "OSMesa",
        })
    }
}

type EglDisplay = *mut c_void;
type EglConfig = *mut c_void;
type EglContext = *mut c_void;
type EglInt = i32;
type EglBoolean = u32;

const EGL_NONE: EglInt = 0x3038;
const EGL_RENDERABLE_TYPE: EglInt = 0x3040;
const EGL_OPENGL_BIT: EglInt = 0x0008;
const EGL_OPENGL_API: u32 = 0x30A2;
const EGL_PLATFORM_SURFACELESS_MESA: u32 = 0x31DD;
const EGL_CONTEXT_MAJOR_VERSION: EglInt = 0x3098;
const EGL_CONTEXT_MINOR_VERSION: EglInt = 0x30FB;
const EGL_CONTEXT_OPENGL_PROFILE_MASK: EglInt = 0x30FD;
const EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT: EglInt = 0x1;

const OSMESA_RGBA: i32 = 0x1908;
const OSMESA_FORMAT: i32 = 0x22;
const OSMESA_DEPTH_BITS: i32 = 0x30;
const OSMESA_STENCIL_BITS: i32 = 0x31;
const OSMESA_ACCUM_BITS: i32 = 0x32;
const OSMESA_PROFILE: i32 = 0x33;
const OSMESA_CORE_PROFILE: i32 = 0x34;
const OSMESA_CONTEXT_MAJOR_VERSION: i32 = 0x36;
const OSMESA_CONTEXT_MINOR_VERSION: i32 = 0x37;
const GL_UNSIGNED_BYTE: u32 = 0x1401;

/// The EGL entry points we use, from a loaded `libEGL`, and the initialised
/// surfaceless display (one a process, never terminated: contexts on other threads
/// share it).
struct Egl {
    _lib: Library,
    display: EglDisplay,
    config: EglConfig,
    get_proc_address: unsafe extern "C" fn(*const i8) -> *const c_void,
    bind_api: unsafe extern "C" fn(u32) -> EglBoolean,
    create_context:
        unsafe extern "C" fn(EglDisplay, EglConfig, EglContext, *const EglInt) -> EglContext,
    make_current:
        unsafe extern "C" fn(EglDisplay, *mut c_void, *mut c_void, EglContext) -> EglBoolean,
    destroy_context: unsafe extern "C" fn(EglDisplay, EglContext) -> EglBoolean,
    get_error: unsafe extern "C" fn() -> EglInt,
}

// The display handle is a process-wide EGL object, valid on every thread.
unsafe impl Send for Egl {}
unsafe impl Sync for Egl {}

/// The OSMesa entry points, from a loaded `libOSMesa`.
struct OsMesa {
    _lib: Library,
    create_context: unsafe extern "C" fn(*const i32, *mut c_void) -> *mut c_void,
    make_current: unsafe extern "C" fn(*mut c_void, *mut c_void, u32, i32, i32) -> u8,
    destroy_context: unsafe extern "C" fn(*mut c_void),
    get_proc_address: unsafe extern "C" fn(*const i8) -> *const c_void,
}

fn library_name(var: &str, default: &str) -> String {
    std::env::var(var).unwrap_or_else(|_| default.to_string())
}

/// Copies a symbol out of `lib` as a plain function pointer.
///
/// # Safety
/// `T` must be the symbol's true C signature.
unsafe fn symbol<T: Copy>(lib: &Library, lib_name: &str, name: &str) -> Result<T, String> {
    // SAFETY: the caller states the type; the library outlives the copy (it is kept
    // beside the pointers in the same struct).
    unsafe { lib.get::<T>(name.as_bytes()) }
        .map(|s| *s)
        .map_err(|e| format!("{lib_name} has no {name}: {e}"))
}

impl Egl {
    fn load() -> Result<Egl, String> {
        let name = library_name("PERIFRAC_EGL_LIB", "libEGL.so.1");
        // SAFETY: loading libEGL runs its initialisers, which have no preconditions.
        let lib = unsafe { Library::new(&name) }
            .map_err(|e| format!("cannot load {name} ({e}); Debian: apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri"))?;
        // SAFETY: the signatures below are EGL 1.5's (Khronos egl.h).
        unsafe {
            type GetPlatformDisplay =
                unsafe extern "C" fn(u32, *mut c_void, *const isize) -> EglDisplay;
            type Initialize =
                unsafe extern "C" fn(EglDisplay, *mut EglInt, *mut EglInt) -> EglBoolean;
            type ChooseConfig = unsafe extern "C" fn(
                EglDisplay,
                *const EglInt,
                *mut EglConfig,
                EglInt,
                *mut EglInt,
            ) -> EglBoolean;
            let get_platform_display: GetPlatformDisplay =
                symbol(&lib, &name, "eglGetPlatformDisplay")?;
            let initialize: Initialize = symbol(&lib, &name, "eglInitialize")?;
            let choose_config: ChooseConfig = symbol(&lib, &name, "eglChooseConfig")?;
            let get_error: unsafe extern "C" fn() -> EglInt = symbol(&lib, &name, "eglGetError")?;
            let display = get_platform_display(
                EGL_PLATFORM_SURFACELESS_MESA,
                std::ptr::null_mut(),
                std::ptr::null(),
            );
            if display.is_null() {
                return Err(format!(
                    "{name}: no surfaceless display (EGL error {:#x})",
                    get_error()
                ));
            }
            let (mut major, mut minor) = (0, 0);
            if initialize(display, &mut major, &mut minor) == 0 {
                return Err(format!(
                    "{name}: eglInitialize failed on the surfaceless display (EGL error {:#x}); is libegl-mesa0 installed?",
                    get_error()
                ));
            }
            // Surfaceless Mesa may offer no config for desktop GL; we draw into FBOs,
            // so a context without a config (EGL_KHR_no_config_context) does.
            let attribs = [EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE];
            let mut config: EglConfig = std::ptr::null_mut();
            let mut count = 0;
            if choose_config(display, attribs.as_ptr(), &mut config, 1, &mut count) == 0
                || count == 0
            {
                config = std::ptr::null_mut();
            }
            Ok(Egl {
                display,
                config,
                get_proc_address: symbol(&lib, &name, "eglGetProcAddress")?,
                bind_api: symbol(&lib, &name, "eglBindAPI")?,
                create_context: symbol(&lib, &name, "eglCreateContext")?,
                make_current: symbol(&lib, &name, "eglMakeCurrent")?,
                destroy_context: symbol(&lib, &name, "eglDestroyContext")?,
                get_error,
                _lib: lib,
            })
        }
    }
}

impl OsMesa {
    fn load() -> Result<OsMesa, String> {
        let default = "libOSMesa.so.8";
        let name = library_name("PERIFRAC_OSMESA_LIB", default);
        // SAFETY: loading libOSMesa runs its initialisers, which have no preconditions.
        let lib = match unsafe { Library::new(&name) } {
            Ok(lib) => lib,
            // The development package's unversioned name.
            Err(_) if name == default => unsafe { Library::new("libOSMesa.so") }.map_err(|e| {
                format!("cannot load {default} or libOSMesa.so ({e}); Debian: apt-get install libosmesa6-dev")
            })?,
            Err(e) => return Err(format!("cannot load {name} ({e})")),
        };
        // SAFETY: the signatures are those of Mesa's osmesa.h.
        unsafe {
            Ok(OsMesa {
                create_context: symbol(&lib, &name, "OSMesaCreateContextAttribs")?,
                make_current: symbol(&lib, &name, "OSMesaMakeCurrent")?,
                destroy_context: symbol(&lib, &name, "OSMesaDestroyContext")?,
                get_proc_address: symbol(&lib, &name, "OSMesaGetProcAddress")?,
                _lib: lib,
            })
        }
    }
}

static EGL: OnceLock<Result<Egl, String>> = OnceLock::new();
static OSMESA: OnceLock<Result<OsMesa, String>> = OnceLock::new();

enum Native {
    Egl(EglContext),
    /// The context, and the 1×1 colour buffer OSMesa insists on (we draw into FBOs),
    /// kept alive as long as the context.
    OsMesa {
        context: *mut c_void,
        _buffer: Box<[u8; 4]>,
    },
}

/// A GL 3.3 core context made current on the thread that created it. Not `Send`: each
/// worker thread makes its own.
pub struct Context {
    /// The GL functions.
    pub gl: glow::Context,
    /// Where it came from.
    pub backend: Backend,
    native: Native,
}

impl Context {
    /// Makes a context on this thread: EGL surfaceless, else OSMesa (or the one
    /// `PERIFRAC_GL` names), else an error naming both libraries and why each failed.
    pub fn new() -> Result<Context, RenderError> {
        let forced = std::env::var("PERIFRAC_GL").unwrap_or_default();
        let mut failures = Vec::new();
        if forced.is_empty() || forced == "egl" {
            match Self::egl() {
                Ok(c) => return Ok(c),
                Err(e) => failures.push(format!("EGL: {e}")),
            }
        }
        if forced.is_empty() || forced == "osmesa" {
            match Self::osmesa() {
                Ok(c) => return Ok(c),
                Err(e) => failures.push(format!("OSMesa: {e}")),
            }
        }
        if failures.is_empty() {
            failures.push(format!(
                "PERIFRAC_GL is '{forced}'; it takes 'egl' or 'osmesa' (or unset: try both)"
            ));
        }
        Err(RenderError::NoContext(failures.join("; ")))
    }

    fn egl() -> Result<Context, String> {
        let egl = EGL.get_or_init(Egl::load).as_ref().map_err(Clone::clone)?;
        let attribs = [
            EGL_CONTEXT_MAJOR_VERSION,
            3,
            EGL_CONTEXT_MINOR_VERSION,
            3,
            EGL_CONTEXT_OPENGL_PROFILE_MASK,
            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
            EGL_NONE,
        ];
        // SAFETY: display and config come from a successful eglInitialize/ChooseConfig;
        // the attribute list ends with EGL_NONE.
        unsafe {
            if (egl.bind_api)(EGL_OPENGL_API) == 0 {
                return Err(format!(
                    "eglBindAPI(OpenGL) failed (EGL error {:#x})",
                    (egl.get_error)()
                ));
            }
            let ctx = (egl.create_context)(
                egl.display,
                egl.config,
                std::ptr::null_mut(),
                attribs.as_ptr(),
            );
            if ctx.is_null() {
                return Err(format!(
                    "no OpenGL 3.3 core context (EGL error {:#x})",
                    (egl.get_error)()
                ));
            }
            if (egl.make_current)(egl.display, std::ptr::null_mut(), std::ptr::null_mut(), ctx) == 0
            {
                (egl.destroy_context)(egl.display, ctx);
                return Err(format!(
                    "eglMakeCurrent without a surface failed (EGL error {:#x})",
                    (egl.get_error)()
                ));
            }
            let gl = glow::Context::from_loader_function(|s| {
                let name = CString::new(s).unwrap_or_default();
                (egl.get_proc_address)(name.as_ptr())
            });
            Ok(Context {
                gl,
                backend: Backend::Egl,
                native: Native::Egl(ctx),
            })
        }
    }

    fn osmesa() -> Result<Context, String> {
        let os = OSMESA
            .get_or_init(OsMesa::load)
            .as_ref()
            .map_err(Clone::clone)?;
        let attribs = [
            OSMESA_FORMAT,
            OSMESA_RGBA,
            OSMESA_DEPTH_BITS,
            0,
            OSMESA_STENCIL_BITS,
            0,
            OSMESA_ACCUM_BITS,
            0,
            OSMESA_PROFILE,
            OSMESA_CORE_PROFILE,
            OSMESA_CONTEXT_MAJOR_VERSION,
            3,
            OSMESA_CONTEXT_MINOR_VERSION,
            3,
            0,
        ];
        // SAFETY: the attribute list ends with 0; the buffer lives as long as the
        // context (it is kept in `Native::OsMesa`).
        unsafe {
            let ctx = (os.create_context)(attribs.as_ptr(), std::ptr::null_mut());
            if ctx.is_null() {
                return Err("OSMesaCreateContextAttribs gave no OpenGL 3.3 core context".into());
            }
            let mut buffer = Box::new([0u8; 4]);
            if (os.make_current)(ctx, buffer.as_mut_ptr().cast(), GL_UNSIGNED_BYTE, 1, 1) == 0 {
                (os.destroy_context)(ctx);
                return Err("OSMesaMakeCurrent failed".into());
            }
            let gl = glow::Context::from_loader_function(|s| {
                let name = CString::new(s).unwrap_or_default();
                (os.get_proc_address)(name.as_ptr())
            });
            Ok(Context {
                gl,
                backend: Backend::OsMesa,
                native: Native::OsMesa {
                    context: ctx,
                    _buffer: buffer,
                },
            })
        }
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: the handles were created by the loaded library, which is never
        // unloaded (it lives in a static).
        unsafe {
            match &self.native {
                Native::Egl(ctx) => {
                    if let Some(Ok(egl)) = EGL.get() {
                        (egl.make_current)(
                            egl.display,
                            std::ptr::null_mut(),
                            std::ptr::null_mut(),
                            std::ptr::null_mut(),
                        );
                        (egl.destroy_context)(egl.display, *ctx);
                    }
                }
                Native::OsMesa { context, .. } => {
                    if let Some(Ok(os)) = OSMESA.get() {
                        (os.destroy_context)(*context);
                    }
                }
            }
        }
    }
}
