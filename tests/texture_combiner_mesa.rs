//! texture_combiner's Mesa mode against Mesa's software GL (OSMesa), bit for bit.
//!
//! libOSMesa is opened at run time (libloading) and every GL entry point comes from
//! `OSMesaGetProcAddress`. An RGBA 8-bit OSMesa context renders a 256 × 256 quad at
//! pixel-exact coordinates with three RGBA8 NEAREST textures holding Arg0, Arg1 and
//! Arg2 per texel; texture unit 2 runs the COMBINE stage under test and reads the three
//! through GL_ARB_texture_env_crossbar's TEXTURE0..TEXTURE2 sources (units 0 and 1 only
//! REPLACE), so no vertex interpolation or filtering touches an operand and every draw
//! puts 65 536 fragments (× 4 channels) through. One pass also reads CONSTANT and
//! PRIMARY_COLOR (flat shaded) instead of textures. glReadPixels reads the result, and
//! each channel must equal `TextureCombiner::combine` in `CombinerRounding::MesaFloat32`.
//!
//! Each Gallium driver runs in its own child process (the driver is chosen once per
//! process from GALLIUM_DRIVER): llvmpipe (OSMesa's default) and softpipe.
//!
//! No libOSMesa → a SKIP note on stderr and a pass (`apt-get install libosmesa6-dev`).
//! The library loads but a symbol, the context or a GL call fails → FAIL.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::units::texture_combiner::{
    CombineFunction, CombinerRounding, OperandAlpha, OperandRgb, TextureCombinerConfig,
    TextureCombinerIn,
};
use rtl_model::Counters;
use std::collections::BTreeMap;
use std::ffi::{c_void, CStr};
use std::io::Write;
use std::os::raw::{c_char, c_float, c_int, c_uint};

const SIDE: usize = 256;
const PIXELS: usize = SIDE * SIDE;
const CHILD_ENV: &str = "TEXCOMB_ORACLE_DRIVER";
const LIBRARY_NAMES: [&str; 3] = ["libOSMesa.so.8", "libOSMesa.so", "libOSMesa.so.6"];

type GLenum = c_uint;

mod gl {
    use super::GLenum;
    pub const TEXTURE_2D: GLenum = 0x0DE1;
    pub const TEXTURE_MIN_FILTER: GLenum = 0x2801;
    pub const TEXTURE_MAG_FILTER: GLenum = 0x2800;
    pub const NEAREST: GLenum = 0x2600;
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
    pub const SOURCE0_RGB: GLenum = 0x8580;
    pub const SOURCE0_ALPHA: GLenum = 0x8588;
    pub const OPERAND0_RGB: GLenum = 0x8590;
    pub const OPERAND0_ALPHA: GLenum = 0x8598;
    pub const SRC_COLOR: GLenum = 0x0300;
    pub const ONE_MINUS_SRC_COLOR: GLenum = 0x0301;
    pub const SRC_ALPHA: GLenum = 0x0302;
    pub const ONE_MINUS_SRC_ALPHA: GLenum = 0x0303;
    pub const ALPHA_SCALE: GLenum = 0x0D1C;
    pub const TEXTURE0: GLenum = 0x84C0;
    pub const PROJECTION: GLenum = 0x1701;
    pub const MODELVIEW: GLenum = 0x1700;
    pub const FLAT: GLenum = 0x1D00;
    pub const DITHER: GLenum = 0x0BD0;
    pub const COLOR_BUFFER_BIT: GLenum = 0x4000;
    pub const QUADS: GLenum = 0x0007;
    pub const RENDERER: GLenum = 0x1F01;
    pub const VERSION: GLenum = 0x1F02;
}

/// The GL entry points the oracle uses, each from OSMesaGetProcAddress.
macro_rules! gl_functions {
    ($($name:ident : fn($($arg:ty),*) $(-> $ret:ty)?;)*) => {
        #[allow(non_snake_case)]
        struct Gl { $($name: unsafe extern "C" fn($($arg),*) $(-> $ret)?,)* }
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

/// Where an argument of the stage under test comes from in GL.
#[derive(Clone, Copy, Debug)]
enum GlSource {
    /// TEXTUREk through the crossbar (k = 0, 1, 2).
    Texture(u32),
    /// TEXTURE_ENV_COLOR holding this colour.
    Constant([u8; 4]),
    /// The flat-shaded primary colour.
    Primary([u8; 4]),
}

/// One draw: the stage's functions, operands, scales, sources and the three textures.
struct Draw {
    label: &'static str,
    rgb: CombineFunction,
    alpha: CombineFunction,
    operand_rgb: [OperandRgb; 3],
    operand_alpha: [OperandAlpha; 3],
    rgb_scale: u32,
    alpha_scale: u32,
    sources: [GlSource; 3],
    textures: [Vec<[u8; 4]>; 3],
}

fn gl_function(f: CombineFunction) -> GLenum {
    match f {
        CombineFunction::Replace => gl::REPLACE,
        CombineFunction::Modulate => gl::MODULATE,
        CombineFunction::Add => gl::ADD,
        CombineFunction::AddSigned => gl::ADD_SIGNED,
        CombineFunction::Interpolate => gl::INTERPOLATE,
        CombineFunction::Subtract => gl::SUBTRACT,
        CombineFunction::Dot3Rgb => gl::DOT3_RGB,
        CombineFunction::Dot3Rgba => gl::DOT3_RGBA,
    }
}

fn gl_operand_rgb(o: OperandRgb) -> GLenum {
    match o {
        OperandRgb::SrcColor => gl::SRC_COLOR,
        OperandRgb::OneMinusSrcColor => gl::ONE_MINUS_SRC_COLOR,
        OperandRgb::SrcAlpha => gl::SRC_ALPHA,
        OperandRgb::OneMinusSrcAlpha => gl::ONE_MINUS_SRC_ALPHA,
    }
}

fn gl_operand_alpha(o: OperandAlpha) -> GLenum {
    match o {
        OperandAlpha::SrcAlpha => gl::SRC_ALPHA,
        OperandAlpha::OneMinusSrcAlpha => gl::ONE_MINUS_SRC_ALPHA,
    }
}

/// An 8-bit code as the float Mesa's texture fetch makes of it, fl(c · fl(1/255)): the
/// constant and primary colours are handed to GL as the same floats.
fn unorm8_float(c: u8) -> f32 {
    c as f32 * (1.0f32 / 255.0)
}

struct Context {
    gl: Gl,
    destroy: DestroyContext,
    ctx: *mut c_void,
    _framebuffer: Vec<u8>,
    _library: libloading::Library,
    textures: [c_uint; 3],
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: the context was created by this library and is destroyed once.
        unsafe { (self.destroy)(self.ctx) };
    }
}

impl Context {
    /// Ok(None): no libOSMesa on this machine.
    fn open() -> Result<Option<Context>, String> {
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

    fn check(&self, what: &str) -> Result<(), String> {
        // SAFETY: a current context exists.
        let e = unsafe { (self.gl.glGetError)() };
        if e == 0 {
            Ok(())
        } else {
            Err(format!("GL error 0x{e:04x} after {what}"))
        }
    }

    fn string(&self, name: GLenum) -> String {
        // SAFETY: glGetString returns a static NUL-terminated string or NULL.
        let p = unsafe { (self.gl.glGetString)(name) };
        if p.is_null() {
            return String::new();
        }
        unsafe { CStr::from_ptr(p as *const c_char) }
            .to_string_lossy()
            .into_owned()
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
            (g.glShadeModel)(gl::FLAT);
            (g.glDisable)(gl::DITHER);
            (g.glGenTextures)(3, self.textures.as_mut_ptr());
            for (k, &t) in self.textures.iter().enumerate() {
                (g.glActiveTexture)(gl::TEXTURE0 + k as GLenum);
                (g.glBindTexture)(gl::TEXTURE_2D, t);
                (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_MIN_FILTER, gl::NEAREST as c_int);
                (g.glTexParameteri)(gl::TEXTURE_2D, gl::TEXTURE_MAG_FILTER, gl::NEAREST as c_int);
                (g.glEnable)(gl::TEXTURE_2D);
                (g.glTexEnvi)(gl::TEXTURE_ENV, gl::TEXTURE_ENV_MODE, gl::REPLACE as c_int);
            }
        }
        self.check("setup")
    }

    /// Render one draw and read the framebuffer back (RGBA per pixel, row 0 at y = 0).
    fn render(&self, d: &Draw) -> Result<Vec<[u8; 4]>, String> {
        let g = &self.gl;
        let env = |p: GLenum, v: GLenum| unsafe { (g.glTexEnvi)(gl::TEXTURE_ENV, p, v as c_int) };
        // SAFETY: GL calls on the current context; the texture and readback buffers
        // hold SIDE × SIDE RGBA texels.
        unsafe {
            for (k, tex) in d.textures.iter().enumerate() {
                (g.glActiveTexture)(gl::TEXTURE0 + k as GLenum);
                (g.glTexImage2D)(
                    gl::TEXTURE_2D,
                    0,
                    gl::RGBA8 as c_int,
                    SIDE as c_int,
                    SIDE as c_int,
                    0,
                    gl::RGBA,
                    gl::UNSIGNED_BYTE,
                    tex.as_ptr() as *const c_void,
                );
            }
            (g.glActiveTexture)(gl::TEXTURE0 + 2);
            env(gl::TEXTURE_ENV_MODE, gl::COMBINE);
            env(gl::COMBINE_RGB, gl_function(d.rgb));
            env(gl::COMBINE_ALPHA, gl_function(d.alpha));
            let mut primary = [1.0f32; 4];
            for (i, s) in d.sources.iter().enumerate() {
                let src = match *s {
                    GlSource::Texture(k) => gl::TEXTURE0 + k,
                    GlSource::Constant(c) => {
                        let f = c.map(unorm8_float);
                        (g.glTexEnvfv)(gl::TEXTURE_ENV, gl::TEXTURE_ENV_COLOR, f.as_ptr());
                        gl::CONSTANT
                    }
                    GlSource::Primary(c) => {
                        primary = c.map(unorm8_float);
                        gl::PRIMARY_COLOR
                    }
                };
                env(gl::SOURCE0_RGB + i as GLenum, src);
                env(gl::SOURCE0_ALPHA + i as GLenum, src);
                env(
                    gl::OPERAND0_RGB + i as GLenum,
                    gl_operand_rgb(d.operand_rgb[i]),
                );
                env(
                    gl::OPERAND0_ALPHA + i as GLenum,
                    gl_operand_alpha(d.operand_alpha[i]),
                );
            }
            env(gl::RGB_SCALE, d.rgb_scale);
            env(gl::ALPHA_SCALE, d.alpha_scale);
            (g.glClear)(gl::COLOR_BUFFER_BIT);
            (g.glColor4f)(primary[0], primary[1], primary[2], primary[3]);
            (g.glBegin)(gl::QUADS);
            for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                for k in 0..3 {
                    (g.glMultiTexCoord2f)(gl::TEXTURE0 + k, x, y);
                }
                (g.glVertex2f)(x * SIDE as f32, y * SIDE as f32);
            }
            (g.glEnd)();
            (g.glFinish)();
        }
        self.check(&format!("drawing {}", d.label))?;
        let mut out = vec![[0u8; 4]; PIXELS];
        unsafe {
            (g.glReadPixels)(
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

/// The unit in its Mesa mode, configured as the draw's stage: Arg0..Arg2 on the
/// texture, constant and primary-colour buses.
fn unit_config(d: &Draw) -> TextureCombinerConfig {
    let mut cfg =
        TextureCombinerConfig::with_functions(8, d.rgb, d.alpha, CombinerRounding::MesaFloat32);
    cfg.operand_rgb = d.operand_rgb;
    cfg.operand_alpha = d.operand_alpha;
    cfg.rgb_scale = d.rgb_scale;
    cfg.alpha_scale = d.alpha_scale;
    cfg
}

fn unit_input(d: &Draw, p: usize) -> TextureCombinerIn {
    let arg = |i: usize| -> [u32; 4] {
        match d.sources[i] {
            GlSource::Texture(k) => d.textures[k as usize][p],
            GlSource::Constant(c) | GlSource::Primary(c) => c,
        }
        .map(u32::from)
    };
    TextureCombinerIn {
        texture: arg(0),
        constant: arg(1),
        primary_color: arg(2),
        previous: [0; 4],
    }
}

/// Every (a, b) pair: Arg0 = [a, b, 255 − a, a], Arg1 = [b, a, b, 255 − b] at texel
/// (a, b), so each channel sees all 65 536 pairs.
fn pair_textures(arg2: Vec<[u8; 4]>) -> [Vec<[u8; 4]>; 3] {
    let mut t0 = vec![[0u8; 4]; PIXELS];
    let mut t1 = vec![[0u8; 4]; PIXELS];
    for y in 0..SIDE {
        for x in 0..SIDE {
            let (a, b) = (x as u8, y as u8);
            t0[y * SIDE + x] = [a, b, 255 - a, a];
            t1[y * SIDE + x] = [b, a, b, 255 - b];
        }
    }
    [t0, t1, arg2]
}

fn random_texture(rng: &mut ChaCha8Rng) -> Vec<[u8; 4]> {
    (0..PIXELS).map(|_| rng.random()).collect()
}

const CROSSBAR: [GlSource; 3] = [
    GlSource::Texture(0),
    GlSource::Texture(1),
    GlSource::Texture(2),
];

fn draw(label: &'static str, f: CombineFunction, scale: u32, textures: [Vec<[u8; 4]>; 3]) -> Draw {
    Draw {
        label,
        rgb: f,
        alpha: if f.is_dot3() {
            CombineFunction::Modulate
        } else {
            f
        },
        operand_rgb: [OperandRgb::SrcColor; 3],
        operand_alpha: [OperandAlpha::SrcAlpha; 3],
        rgb_scale: scale,
        alpha_scale: scale,
        sources: CROSSBAR,
        textures,
    }
}

/// The draws: every 8-bit pair for the two-argument functions at every scale; every
/// ADD_SIGNED operand mapping; every INTERPOLATE triple at scale 1; ≥ 10⁶ random DOT3
/// cases; CONSTANT and PRIMARY_COLOR sources; random whole configurations.
fn draws(rng: &mut ChaCha8Rng, interpolate_stride: usize) -> Vec<Draw> {
    let mut v = Vec::new();
    let two = [
        ("REPLACE", CombineFunction::Replace),
        ("MODULATE", CombineFunction::Modulate),
        ("ADD", CombineFunction::Add),
        ("ADD_SIGNED", CombineFunction::AddSigned),
        ("SUBTRACT", CombineFunction::Subtract),
    ];
    for (label, f) in two {
        for s in [1, 2, 4] {
            v.push(draw(label, f, s, pair_textures(random_texture(rng))));
        }
    }
    for o0 in OperandRgb::ALL {
        for o1 in OperandRgb::ALL {
            let mut d = draw(
                "ADD_SIGNED",
                CombineFunction::AddSigned,
                1,
                pair_textures(random_texture(rng)),
            );
            d.operand_rgb = [o0, o1, OperandRgb::SrcColor];
            let alpha = |o: OperandRgb| match o {
                OperandRgb::SrcColor | OperandRgb::SrcAlpha => OperandAlpha::SrcAlpha,
                _ => OperandAlpha::OneMinusSrcAlpha,
            };
            d.operand_alpha = [alpha(o0), alpha(o1), OperandAlpha::SrcAlpha];
            v.push(d);
        }
    }
    // INTERPOLATE: channel k's Arg2 runs over codes 64k .. 64k + 63 in 64 draws, so
    // every (Arg0, Arg1, Arg2) triple goes through once; `interpolate_stride` 8 (the
    // slower softpipe) takes every 8th draw, 2²¹ triples.
    for c in (0..64u8).step_by(interpolate_stride) {
        let arg2 = vec![[c, c + 64, c + 128, c + 192]; PIXELS];
        v.push(draw(
            "INTERPOLATE",
            CombineFunction::Interpolate,
            1,
            pair_textures(arg2),
        ));
    }
    for s in [2, 4] {
        for _ in 0..2 {
            let t = [
                random_texture(rng),
                random_texture(rng),
                random_texture(rng),
            ];
            v.push(draw("INTERPOLATE", CombineFunction::Interpolate, s, t));
        }
    }
    for (label, f) in [
        ("DOT3_RGB", CombineFunction::Dot3Rgb),
        ("DOT3_RGBA", CombineFunction::Dot3Rgba),
    ] {
        let per_scale = if f == CombineFunction::Dot3Rgb { 6 } else { 1 };
        for s in [1, 2, 4] {
            for _ in 0..per_scale {
                let t = [
                    random_texture(rng),
                    random_texture(rng),
                    random_texture(rng),
                ];
                let mut d = draw(label, f, s, t);
                d.alpha_scale = [4, 1, 2][s.trailing_zeros() as usize];
                v.push(d);
            }
        }
    }
    for (label, f) in [
        ("ADD_SIGNED", CombineFunction::AddSigned),
        ("MODULATE", CombineFunction::Modulate),
        ("INTERPOLATE", CombineFunction::Interpolate),
    ] {
        for _ in 0..4 {
            let mut d = draw(label, f, 1, pair_textures(random_texture(rng)));
            d.sources = [
                GlSource::Texture(0),
                GlSource::Constant(rng.random()),
                GlSource::Primary(rng.random()),
            ];
            v.push(d);
        }
    }
    for _ in 0..16 {
        let rgb = CombineFunction::ALL[rng.random_range(0..8)];
        let alpha = CombineFunction::ALPHA[rng.random_range(0..6)];
        let t = [
            random_texture(rng),
            random_texture(rng),
            random_texture(rng),
        ];
        let mut d = draw("random configuration", rgb, 1, t);
        d.alpha = alpha;
        d.operand_rgb = std::array::from_fn(|_| OperandRgb::ALL[rng.random_range(0..4)]);
        d.operand_alpha = std::array::from_fn(|_| OperandAlpha::ALL[rng.random_range(0..2)]);
        d.rgb_scale = [1, 2, 4][rng.random_range(0..3)];
        d.alpha_scale = [1, 2, 4][rng.random_range(0..3)];
        v.push(d);
    }
    v
}

#[derive(Default)]
struct Tally {
    cases: u64,
    mismatches: u64,
    examples: Vec<String>,
}

enum Outcome {
    Skipped(String),
    Ran(String, BTreeMap<&'static str, Tally>),
}

/// Run every draw under the current process's driver.
fn run_oracle() -> Result<Outcome, String> {
    let Some(ctx) = Context::open()? else {
        return Ok(Outcome::Skipped(format!(
            "libOSMesa not found ({}) — apt-get install libosmesa6-dev",
            LIBRARY_NAMES.join(", ")
        )));
    };
    let renderer = format!("{} | {}", ctx.string(gl::RENDERER), ctx.string(gl::VERSION));
    if let Ok(want) = std::env::var("GALLIUM_DRIVER") {
        // A libOSMesa built without this driver falls back to another: not a failure
        // of the GL calls, so a skip of this driver (the other child still runs).
        if !renderer.starts_with(&want) {
            return Ok(Outcome::Skipped(format!(
                "GALLIUM_DRIVER={want} is not in this libOSMesa (renderer {renderer})"
            )));
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    // softpipe interprets each fragment (≈ 2.5× llvmpipe's time): a sample of the
    // exhaustive INTERPOLATE sweep keeps the test file within its time budget.
    let stride = if renderer.starts_with("softpipe") {
        8
    } else {
        1
    };
    let mut tallies: BTreeMap<&'static str, Tally> = BTreeMap::new();
    for d in draws(&mut rng, stride) {
        let got = ctx.render(&d)?;
        let unit = unit_config(&d).build().map_err(|e| e.to_string())?;
        let t = tallies.entry(d.label).or_default();
        let mut ctr = Counters::default();
        for (p, g) in got.iter().enumerate() {
            let input = unit_input(&d, p);
            let want = unit.combine(&input, &mut ctr);
            for ch in 0..4 {
                t.cases += 1;
                if want[ch] != g[ch] as u32 {
                    t.mismatches += 1;
                    if t.examples.len() < 5 {
                        t.examples.push(format!(
                            "rgb {:?} alpha {:?} ops {:?}/{:?} scales {}/{} ch {ch}: {input:?} → Mesa {} unit {}",
                            d.rgb, d.alpha, d.operand_rgb, d.operand_alpha, d.rgb_scale, d.alpha_scale, g[ch], want[ch]
                        ));
                    }
                }
            }
        }
    }
    Ok(Outcome::Ran(renderer, tallies))
}

/// Write straight to the process's stderr (bypassing the test harness's capture), so
/// a skip note or the agreement table shows even when the test passes.
fn note(text: &str) {
    let _ = std::io::stderr().write_all(text.as_bytes());
}

#[test]
#[ignore = "run by llvmpipe_is_bit_exact / softpipe_is_bit_exact in a child process"]
fn oracle_child() {
    match run_oracle() {
        Err(e) => panic!("OSMesa oracle failed: {e}"),
        Ok(Outcome::Skipped(why)) => note(&format!("SKIP: {why}\n")),
        Ok(Outcome::Ran(renderer, tallies)) => {
            let mut text = format!("texture_combiner vs OSMesa [{renderer}]\n");
            let mut total = 0;
            for (label, t) in &tallies {
                text += &format!(
                    "  {label:<22} {:>10} channel results, {} mismatches\n",
                    t.cases, t.mismatches
                );
                for e in &t.examples {
                    text += &format!("      {e}\n");
                }
                total += t.mismatches;
            }
            note(&text);
            assert_eq!(total, 0, "the unit's Mesa mode differs from OSMesa");
        }
    }
}

fn run_child(driver: &str) {
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = std::process::Command::new(exe)
        .args([
            "--exact",
            "oracle_child",
            "--include-ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env("GALLIUM_DRIVER", driver)
        .env(CHILD_ENV, driver)
        .output()
        .expect("spawning the oracle child");
    note(&String::from_utf8_lossy(&out.stderr));
    assert!(
        out.status.success(),
        "OSMesa oracle ({driver}) failed:\n{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

#[test]
fn llvmpipe_is_bit_exact() {
    run_child("llvmpipe");
}

#[test]
fn softpipe_is_bit_exact() {
    run_child("softpipe");
}
