//! A small OSMesa harness for the GL-oracle tests of the Mesa-matching modes
//! (tests/modulate_mesa.rs, tests/texture_sampler_mesa.rs,
//! tests/texture_combiner_mesa.rs): libOSMesa is opened at run time (libloading), every
//! GL entry point comes from `OSMesaGetProcAddress`, an RGBA 8-bit 256 × 256 context
//! draws one GL_POINT per pixel — each with its own colour and texture coordinates,
//! constant over the point, so no interpolation touches an operand — and glReadPixels
//! reads the result back. (The combiner test draws one quad instead, through its own
//! three texture units: [`Context::textures`] holds three texture names.)
//!
//! No libOSMesa → `Ok(None)` from [`Context::open`], and the caller prints a SKIP note
//! (never a silent pass). The library loads but a symbol, the context or a GL call
//! fails → an error, which the tests turn into a failure.
#![allow(dead_code)]

#[path = "../common/tools.rs"]
pub mod tools;

use std::ffi::{c_void, CStr};
use std::io::Write;
use std::os::raw::{c_char, c_float, c_int, c_uint};

pub const SIDE: usize = 256;
pub const PIXELS: usize = SIDE * SIDE;
pub const LIBRARY_NAMES: [&str; 3] = ["libOSMesa.so.8", "libOSMesa.so", "libOSMesa.so.6"];

pub type GLenum = c_uint;

pub mod gl {
    use super::GLenum;
    pub const TEXTURE_2D: GLenum = 0x0DE1;
    pub const TEXTURE_MIN_FILTER: GLenum = 0x2801;
    pub const TEXTURE_MAG_FILTER: GLenum = 0x2800;
    pub const TEXTURE_WRAP_S: GLenum = 0x2802;
    pub const TEXTURE_WRAP_T: GLenum = 0x2803;
    pub const NEAREST: GLenum = 0x2600;
    pub const LINEAR: GLenum = 0x2601;
    pub const REPEAT: GLenum = 0x2901;
    pub const CLAMP_TO_EDGE: GLenum = 0x812F;
    pub const RGBA: GLenum = 0x1908;
    pub const RGBA8: GLenum = 0x8058;
    pub const UNSIGNED_BYTE: GLenum = 0x1401;
    pub const TEXTURE_ENV: GLenum = 0x2300;
    pub const TEXTURE_ENV_MODE: GLenum = 0x2200;
    pub const TEXTURE_ENV_COLOR: GLenum = 0x2201;
    pub const REPLACE: GLenum = 0x1E01;
    pub const MODULATE: GLenum = 0x2100;
    pub const ADD: GLenum = 0x0104;
    pub const COMBINE: GLenum = 0x8570;
    pub const COMBINE_RGB: GLenum = 0x8571;
    pub const COMBINE_ALPHA: GLenum = 0x8572;
    pub const RGB_SCALE: GLenum = 0x8573;
    pub const ADD_SIGNED: GLenum = 0x8574;
    pub const INTERPOLATE: GLenum = 0x8575;
    pub const CONSTANT: GLenum = 0x8576;
    pub const PRIMARY_COLOR: GLenum = 0x8577;
    pub const SUBTRACT: GLenum = 0x84E7;
    pub const DOT3_RGB: GLenum = 0x86AE;
    pub const DOT3_RGBA: GLenum = 0x86AF;
    pub const OPERAND0_RGB: GLenum = 0x8590;
    pub const OPERAND0_ALPHA: GLenum = 0x8598;
    pub const SRC_COLOR: GLenum = 0x0300;
    pub const ONE_MINUS_SRC_COLOR: GLenum = 0x0301;
    pub const SRC_ALPHA: GLenum = 0x0302;
    pub const ONE_MINUS_SRC_ALPHA: GLenum = 0x0303;
    pub const ALPHA_SCALE: GLenum = 0x0D1C;
    pub const FLAT: GLenum = 0x1D00;
    pub const QUADS: GLenum = 0x0007;
    pub const PREVIOUS: GLenum = 0x8578;
    pub const TEXTURE: GLenum = 0x1702;
    pub const SOURCE0_RGB: GLenum = 0x8580;
    pub const SOURCE0_ALPHA: GLenum = 0x8588;
    pub const TEXTURE0: GLenum = 0x84C0;
    pub const PROJECTION: GLenum = 0x1701;
    pub const MODELVIEW: GLenum = 0x1700;
    pub const DITHER: GLenum = 0x0BD0;
    pub const COLOR_BUFFER_BIT: GLenum = 0x4000;
    pub const POINTS: GLenum = 0x0000;
    pub const RENDERER: GLenum = 0x1F01;
    pub const VERSION: GLenum = 0x1F02;
}

/// The GL entry points the harness uses, each from OSMesaGetProcAddress.
macro_rules! gl_functions {
    ($($name:ident : fn($($arg:ty),*) $(-> $ret:ty)?;)*) => {
        #[allow(non_snake_case)]
        pub struct Gl { $(pub $name: unsafe extern "C" fn($($arg),*) $(-> $ret)?,)* }
        impl Gl {
            fn load(lookup: impl Fn(&CStr) -> *const c_void) -> Result<Gl, String> {
                Ok(Gl { $($name: {
                    let name = concat!(stringify!($name), "\0");
                    let p = lookup(CStr::from_bytes_with_nul(name.as_bytes()).unwrap());
                    if p.is_null() {
                        return Err(format!("OSMesaGetProcAddress(\"{}\") returned NULL", stringify!($name)));
                    }
                    // SAFETY: a non-null GL entry point with the C signature declared here.
                    unsafe { std::mem::transmute::<*const c_void, unsafe extern "C" fn($($arg),*) $(-> $ret)?>(p) }
                },)* })
            }
        }
    };
}

gl_functions! {
    glGetString: fn(GLenum) -> *const u8;
    glGetError: fn() -> GLenum;
    glViewport: fn(c_int, c_int, c_int, c_int);
    glMatrixMode: fn(GLenum);
    glLoadIdentity: fn();
    glOrtho: fn(f64, f64, f64, f64, f64, f64);
    glShadeModel: fn(GLenum);
    glDisable: fn(GLenum);
    glEnable: fn(GLenum);
    glGenTextures: fn(c_int, *mut c_uint);
    glBindTexture: fn(GLenum, c_uint);
    glTexParameteri: fn(GLenum, GLenum, c_int);
    glTexImage2D: fn(GLenum, c_int, c_int, c_int, c_int, c_int, GLenum, GLenum, *const c_void);
    glTexEnvi: fn(GLenum, GLenum, c_int);
    glTexEnvfv: fn(GLenum, GLenum, *const c_float);
    glActiveTexture: fn(GLenum);
    glMultiTexCoord2f: fn(GLenum, c_float, c_float);
    glColor4f: fn(c_float, c_float, c_float, c_float);
    glVertex2f: fn(c_float, c_float);
    glBegin: fn(GLenum);
    glEnd: fn();
    glClear: fn(GLenum);
    glFinish: fn();
    glReadPixels: fn(c_int, c_int, c_int, c_int, GLenum, GLenum, *mut c_void);
}

type CreateContextExt =
    unsafe extern "C" fn(GLenum, c_int, c_int, c_int, *mut c_void) -> *mut c_void;
type MakeCurrent = unsafe extern "C" fn(*mut c_void, *mut c_void, GLenum, c_int, c_int) -> u8;
type GetProcAddress = unsafe extern "C" fn(*const c_char) -> *const c_void;
type DestroyContext = unsafe extern "C" fn(*mut c_void);

/// An 8-bit code as the float Mesa's texture fetch makes of it, fl(c · fl(1/255)): a
/// primary colour handed to GL as this float is the texture path's value.
pub fn unorm8_float(c: u8) -> f32 {
    c as f32 * (1.0f32 / 255.0)
}

/// One point per pixel: its colour and the texture coordinates of units 0 and 1.
#[derive(Clone, Copy, Debug, Default)]
pub struct Point {
    pub color: [f32; 4],
    pub tex: [[f32; 2]; 2],
}

pub struct Context {
    pub gl: Gl,
    destroy: DestroyContext,
    ctx: *mut c_void,
    _framebuffer: Vec<u8>,
    _library: libloading::Library,
    pub textures: [c_uint; 3],
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: the context was created by this library and is destroyed once.
        unsafe { (self.destroy)(self.ctx) };
    }
}

impl Context {
    /// Ok(None): no libOSMesa on this machine.
    pub fn open() -> Result<Option<Context>, String> {
        // SAFETY: loading libOSMesa runs its initialisers, which have no preconditions.
        let Some(library) = LIBRARY_NAMES
            .iter()
            .find_map(|n| unsafe { libloading::Library::new(n) }.ok())
        else {
            return Ok(None);
        };
        // SAFETY: the symbols are OSMesa's documented C entry points (GL/osmesa.h).
        let (create, make_current, get_proc, destroy) = unsafe {
            let sym = |e: libloading::Error| format!("libOSMesa lacks a symbol: {e}");
            (
                *library
                    .get::<CreateContextExt>(b"OSMesaCreateContextExt\0")
                    .map_err(sym)?,
                *library
                    .get::<MakeCurrent>(b"OSMesaMakeCurrent\0")
                    .map_err(sym)?,
                *library
                    .get::<GetProcAddress>(b"OSMesaGetProcAddress\0")
                    .map_err(sym)?,
                *library
                    .get::<DestroyContext>(b"OSMesaDestroyContext\0")
                    .map_err(sym)?,
            )
        };
        // SAFETY: OSMESA_RGBA, no depth/stencil/accum, no shared context.
        let ctx = unsafe { create(gl::RGBA, 0, 0, 0, std::ptr::null_mut()) };
        if ctx.is_null() {
            return Err("OSMesaCreateContextExt(OSMESA_RGBA) returned NULL".into());
        }
        let mut framebuffer = vec![0u8; PIXELS * 4];
        // SAFETY: the buffer holds SIDE × SIDE RGBA bytes and lives as long as the context.
        let ok = unsafe {
            make_current(
                ctx,
                framebuffer.as_mut_ptr() as *mut c_void,
                gl::UNSIGNED_BYTE,
                SIDE as c_int,
                SIDE as c_int,
            )
        };
        if ok == 0 {
            // SAFETY: created above, destroyed once.
            unsafe { destroy(ctx) };
            return Err("OSMesaMakeCurrent failed".into());
        }
        // SAFETY: OSMesaGetProcAddress takes a NUL-terminated name.
        let gl = Gl::load(|name| unsafe { get_proc(name.as_ptr()) })?;
        let mut c = Context {
            gl,
            destroy,
            ctx,
            _framebuffer: framebuffer,
            _library: library,
            textures: [0; 3],
        };
        c.setup()?;
        Ok(Some(c))
    }

    pub fn check(&self, what: &str) -> Result<(), String> {
        // SAFETY: a current context exists.
        let e = unsafe { (self.gl.glGetError)() };
        if e == 0 {
            Ok(())
        } else {
            Err(format!("GL error 0x{e:04x} after {what}"))
        }
    }

    pub fn string(&self, name: GLenum) -> String {
        // SAFETY: glGetString returns a static NUL-terminated string or NULL.
        let p = unsafe { (self.gl.glGetString)(name) };
        if p.is_null() {
            return String::new();
        }
        unsafe { CStr::from_ptr(p as *const c_char) }
            .to_string_lossy()
            .into_owned()
    }

    /// "GL_RENDERER | GL_VERSION".
    pub fn renderer(&self) -> String {
        format!(
            "{} | {}",
            self.string(gl::RENDERER),
            self.string(gl::VERSION)
        )
    }

    fn setup(&mut self) -> Result<(), String> {
        let g = &self.gl;
        let side = SIDE as c_int;
        // SAFETY: plain GL state calls on the current context.
        unsafe {
            (g.glViewport)(0, 0, side, side);
            (g.glMatrixMode)(gl::PROJECTION);
            (g.glLoadIdentity)();
            (g.glOrtho)(0.0, SIDE as f64, 0.0, SIDE as f64, -1.0, 1.0);
            (g.glMatrixMode)(gl::MODELVIEW);
            (g.glLoadIdentity)();
            (g.glDisable)(gl::DITHER);
            (g.glGenTextures)(3, self.textures.as_mut_ptr());
        }
        self.check("setup")
    }

    /// Upload an RGBA8 texture of `w` × `h` texels (row 0 at t = 0) to texture unit
    /// `unit`, with its filter and wrap modes, and enable it.
    pub fn texture(
        &self,
        unit: u32,
        w: usize,
        h: usize,
        texels: &[[u8; 4]],
        filter: GLenum,
        wrap: [GLenum; 2],
    ) -> Result<(), String> {
        assert_eq!(texels.len(), w * h, "texture size");
        let g = &self.gl;
        // SAFETY: GL calls on the current context; `texels` holds w × h RGBA texels.
        unsafe {
            (g.glActiveTexture)(gl::TEXTURE0 + unit);
            (g.glBindTexture)(gl::TEXTURE_2D, self.textures[unit as usize]);
            (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, filter as c_int);
            (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, filter as c_int);
            (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_WRAP_S, wrap[0] as c_int);
            (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_WRAP_T, wrap[1] as c_int);
            (g.glTexImage2D)(
                gl::TEXTURE_2D,
                0,
                gl::RGBA8 as c_int,
                w as c_int,
                h as c_int,
                0,
                gl::RGBA,
                gl::UNSIGNED_BYTE,
                texels.as_ptr() as *const c_void,
            );
            (g.glEnable)(gl::TEXTURE_2D);
        }
        self.check("texture upload")
    }

    /// Set a texture-environment parameter of unit `unit`.
    pub fn env(&self, unit: u32, pname: GLenum, value: GLenum) {
        // SAFETY: GL state calls on the current context.
        unsafe {
            (self.gl.glActiveTexture)(gl::TEXTURE0 + unit);
            (self.gl.glTexEnvi)(gl::TEXTURE_ENV, pname, value as c_int);
        }
    }

    /// Draw one point per pixel (pixel p = y · SIDE + x at its centre) with `units`
    /// texture units' coordinates, and read the framebuffer back (row 0 at y = 0).
    pub fn draw_points(&self, points: &[Point], units: u32) -> Result<Vec<[u8; 4]>, String> {
        assert_eq!(points.len(), PIXELS, "one point per pixel");
        let g = &self.gl;
        // SAFETY: GL calls on the current context; the readback buffer holds SIDE × SIDE
        // RGBA pixels.
        unsafe {
            (g.glClear)(gl::COLOR_BUFFER_BIT);
            (g.glBegin)(gl::POINTS);
            for (p, pt) in points.iter().enumerate() {
                let (x, y) = ((p % SIDE) as f32 + 0.5, (p / SIDE) as f32 + 0.5);
                let c = pt.color;
                (g.glColor4f)(c[0], c[1], c[2], c[3]);
                for k in 0..units {
                    let [s, t] = pt.tex[k as usize];
                    (g.glMultiTexCoord2f)(gl::TEXTURE0 + k, s, t);
                }
                (g.glVertex2f)(x, y);
            }
            (g.glEnd)();
            (g.glFinish)();
        }
        self.check("drawing the points")?;
        self.read_pixels()
    }

    /// The framebuffer, RGBA per pixel, row 0 at y = 0.
    pub fn read_pixels(&self) -> Result<Vec<[u8; 4]>, String> {
        let mut out = vec![[0u8; 4]; PIXELS];
        // SAFETY: a current context; the buffer holds SIDE × SIDE RGBA pixels.
        unsafe {
            (self.gl.glReadPixels)(
                0,
                0,
                SIDE as c_int,
                SIDE as c_int,
                gl::RGBA,
                gl::UNSIGNED_BYTE,
                out.as_mut_ptr() as *mut c_void,
            );
        }
        self.check("glReadPixels")?;
        Ok(out)
    }
}

/// Write straight to the process's stderr (bypassing the test harness's capture), so
/// a skip note or a tally shows even when the test passes.
pub fn note(text: &str) {
    let _ = std::io::stderr().write_all(text.as_bytes());
}

/// Run test `child` of this test binary in a child process under Gallium driver
/// `driver` (the driver is chosen once per process), echoing its stderr; panic if it
/// failed.
pub fn run_child(child: &str, driver: &str) {
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = std::process::Command::new(exe)
        .args([
            "--exact",
            child,
            "--include-ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env("GALLIUM_DRIVER", driver)
        .output()
        .expect("spawning the oracle child");
    note(&String::from_utf8_lossy(&out.stderr));
    assert!(
        out.status.success(),
        "OSMesa oracle ({driver}) failed:\n{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

/// Open the context under the current process's driver. Err(skip note) when there is
/// no libOSMesa or it lacks the requested GALLIUM_DRIVER; a failure of the library
/// once loaded panics.
pub fn open_or_skip() -> Result<(Context, String), String> {
    let ctx = match Context::open() {
        Err(e) => panic!("OSMesa oracle failed: {e}"),
        Ok(None) => {
            return Err(format!(
                "libOSMesa not found ({}) — apt-get install libosmesa6-dev",
                LIBRARY_NAMES.join(", ")
            ))
        }
        Ok(Some(c)) => c,
    };
    let renderer = ctx.renderer();
    if let Ok(want) = std::env::var("GALLIUM_DRIVER") {
        if !renderer.starts_with(&want) {
            return Err(format!(
                "GALLIUM_DRIVER={want} is not in this libOSMesa (renderer {renderer}); \
                 apt-get install libosmesa6-dev (Debian's carries llvmpipe and softpipe)"
            ));
        }
    }
    Ok((ctx, renderer))
}

/// [`open_or_skip`], or None after printing the SKIP note (an oracle child with no
/// libOSMesa ends there, and its parent reports the skip).
pub fn open_or_note_skip() -> Option<(Context, String)> {
    match open_or_skip() {
        Ok(c) => Some(c),
        Err(why) => {
            tools::skip(&why);
            None
        }
    }
}
