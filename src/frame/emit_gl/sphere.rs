//! `render --scene shading-NAME --emit-gl DIR`: a shading sphere whose path is
//! OpenGL 1.3's texture combine, as a C program drawing what the model's units draw.
//! Two terms, each optional, added at the end (the model's saturating ADD, here an
//! additive blend):
//!
//! * the Lambert term: N and L through the normalisation cube map
//!   (ARB_texture_cube_map), DOT3_RGB (ARB_texture_env_dot3), MODULATE by the albedo
//!   constant;
//! * a factored lobe: the factor textures at the coordinates the model's host computes
//!   per pixel, multiplied left to right, times the constant colour, shifted left by
//!   the lobe's scale (RGB_SCALE stages of 2 or 4, exact on 8-bit values).
//!
//! The model shades each covered pixel from vectors its host computes per pixel (no
//! interpolation): the program draws one point per covered pixel, at its centre, with
//! what the model's units receive there — the address unit's input directions, the
//! factor samplers' coordinate words, the constant colour's code. Every modulate is
//! its own draw, with an 8-bit stage register between draws (llvmpipe rounds a chain
//! of stages in one draw once; the model rounds each).

use super::source::{main_text, PRELUDE};
use super::Program;
use crate::pipeline::shading::brdfs::{entry_view, render_sphere, CatalogueEntry, SphereRender};
use crate::pipeline::shading::materials::lobe_kind;
use crate::pipeline::shading::normalize_cube::{normalization_texels, NormalizeCube};
use crate::pipeline::shading::path::PathConfig;
use crate::pipeline::shading::path::ShadingPath;
use crate::pipeline::shading::scene_file::{ShadingFile, DEFAULT_IMAGE};
use crate::pipeline::shading::sphere::SphereView;
use crate::pipeline::shading::sweep::{sweep_view, ShadingScene};
use rtl_model::units::texture_sampler::Filter;
use rtl_model::Counters;
use std::fmt::Write as _;

/// The extensions the sphere's program draws with.
const EXTENSIONS: [&str; 3] = [
    "GL_ARB_texture_cube_map",
    "GL_ARB_texture_env_combine",
    "GL_ARB_texture_env_dot3",
];

/// Why a shading sphere scene has no program (None: it has one; `shading-vertex`'s
/// is [`super::vertex`]).
pub fn not_exportable(f: &ShadingFile) -> Option<String> {
    match f.point.scene() {
        ShadingScene::Vertex => None,
        ShadingScene::Specular => Some(
            "shading-specular's (n·h)^s runs on the register combiners \
             (NV_register_combiners) or the texture shader's dependent lookup \
             (NV_texture_shader): no OpenGL 1.3 form"
                .into(),
        ),
        ShadingScene::Model(e) => (lobe_kind(&e.material) == "lookup").then(|| {
            format!(
                "shading-{}'s specular lobe reads its lookup table at the DOT3's n·h (a \
                     dependent texture read, NV_texture_shader): no OpenGL 1.3 form",
                e.label
            )
        }),
    }
}

/// The sphere scene's program and the model's picture of it (grey 8-bit levels,
/// row-major, `side` × `side`).
pub struct SphereProgram {
    pub program: Program,
    pub side: u32,
    pub model_levels: Vec<f64>,
    /// The model's sphere through its units, wall seconds: the per-pixel shading, its
    /// path (the factorisation, the tables) built before the clock starts, as the GL
    /// program's draw leaves out loading its textures.
    pub model_seconds: f64,
    /// Each covered pixel (x, y) and its normal as the address unit receives it.
    pub normals: Vec<([u32; 2], [f64; 3])>,
    /// The cube's face side, when the sphere has a Lambert term (it reads the cube).
    pub face: Option<u32>,
}

impl SphereProgram {
    /// Write the program's files into `dir` (created), with the model's picture as
    /// model.png.
    pub fn write(&self, dir: &std::path::Path) -> Result<(), String> {
        super::write_files(&self.program, dir, |path| {
            let grey: Vec<[f64; 3]> = self.model_levels.iter().map(|&x| [x; 3]).collect();
            crate::report::image_out::levels_png(&grey, self.side, self.side, path)
        })
    }
}

/// The model's sphere of a catalogue scene, as `render` draws it: its levels, the
/// path that drew them and the shading's wall seconds ([`render_sphere`]: the path —
/// the factorisation, the tables — built before its clock starts).
pub fn model_sphere(f: &ShadingFile) -> Result<(CatalogueEntry, SphereRender), String> {
    let Some((entry, cfg)) = f.point.model() else {
        return Err("--emit-gl: not a catalogue model's sphere".into());
    };
    let view = sweep_view(f.image.unwrap_or(DEFAULT_IMAGE));
    let r = render_sphere(&entry, &view, &cfg).map_err(|e| format!("--emit-gl: {e}"))?;
    Ok((entry, r))
}

/// The program of a shading sphere (refused, with why, for one with no GL 1.3 form).
pub fn sphere_program(f: &ShadingFile) -> Result<SphereProgram, String> {
    if let Some(why) = not_exportable(f) {
        return Err(format!("--emit-gl: {why}"));
    }
    if let Some((entry, cfg)) = f.point.model() {
        check_widths(&entry, &cfg)?;
    }
    let side = f.image.unwrap_or(DEFAULT_IMAGE);
    let (entry, r) = model_sphere(f)?;
    let lit = entry_view(&entry, &sweep_view(side));
    let textures = r
        .path
        .factored()
        .map_or(Vec::new(), |fr| fr.texture_codes());
    let sides: Vec<u32> = textures.iter().map(|t| t.0).collect();
    let data = PixelData::of(&r.path, &lit, &sides)?;
    let bytes = |v: &[u32]| v.iter().map(|&t| t as u8).collect::<Vec<u8>>();
    let mut files = vec![(
        "sphere_pixels.f32".to_string(),
        super::f32_bytes(&data.floats),
    )];
    let diffuse = r.path.diffuse_stages().map(|(cube, albedo)| {
        let c = cube.config();
        files.push((
            "normalize_cube.raw".into(),
            bytes(&normalization_texels(c.face_side, c.texel_bits)),
        ));
        Diffuse {
            face: c.face_side,
            filter: gl_filter(c.filter),
            light: data.light,
            albedo,
        }
    });
    for (i, (_, codes)) in textures.iter().enumerate() {
        files.push((format!("factor_{i}.raw"), bytes(codes)));
    }
    let k = Constants {
        name: f.point.scene().name(),
        side,
        count: data.normals.len(),
        face: diffuse.as_ref().map(|d| d.face),
        diffuse,
        factors: sides,
        shift: r.path.factored().map_or(0, |fr| fr.shift()),
    };
    let mut all = vec![
        ("scene.c".to_string(), scene_c(&k).into_bytes()),
        ("build.sh".to_string(), super::build_script().into_bytes()),
    ];
    all.extend(files);
    Ok(SphereProgram {
        program: Program { files: all },
        side,
        model_levels: r.hardware,
        model_seconds: r.wall_seconds,
        normals: data.normals,
        face: k.face,
    })
}

/// The GL program draws 8-bit textures and 8-bit combiner stages: the cube's texels
/// and a factored lobe's textures must be 8 bits (checked on the configuration,
/// before any work).
fn check_widths(entry: &CatalogueEntry, cfg: &PathConfig) -> Result<(), String> {
    let b = cfg.cube.texel_bits;
    if b != 8 {
        return Err(format!(
            "--emit-gl: the normalisation cube's texels are {b} bits; the GL program's cube map is 8-bit"
        ));
    }
    let factored = !matches!(lobe_kind(&entry.material), "none" | "lookup");
    if factored && cfg.factor_bits != 8 {
        return Err(format!(
            "--emit-gl: factor_bits = {}: the GL program's factor textures are 8-bit; set factor_bits = 8",
            cfg.factor_bits
        ));
    }
    Ok(())
}

fn gl_filter(f: Filter) -> &'static str {
    match f {
        Filter::Nearest => "GL_NEAREST",
        Filter::Linear => "GL_LINEAR",
    }
}

/// What the points carry: per covered pixel x, y (its centre), the normal's
/// direction as the address unit receives it, each factor's (s, t) (normalised: the
/// sampler's coordinate words over the side) and the constant colour's code.
struct PixelData {
    floats: Vec<f32>,
    normals: Vec<([u32; 2], [f64; 3])>,
    light: [f64; 3],
}

impl PixelData {
    /// `sides`: each factor texture's side.
    fn of(path: &ShadingPath, lit: &SphereView, sides: &[u32]) -> Result<PixelData, String> {
        let err = |e: rtl_model::ConfigError| format!("--emit-gl: {e}");
        let cube = path.cube();
        let light = word_direction(cube, lit.light)?;
        let (mut floats, mut normals) = (Vec::new(), Vec::new());
        for p in lit.pixels().into_iter().flatten() {
            let d = word_direction(cube, p.frame.n)?;
            let mut v = vec![p.x as f64 + 0.5, p.y as f64 + 0.5, d[0], d[1], d[2]];
            if let Some(fr) = path.factored() {
                let (coords, constant) = fr.pixel_operands(p.wi, p.wo).map_err(err)?;
                for (c, &side) in coords.iter().zip(sides) {
                    let side = f64::from(side);
                    v.extend([c[0] / side, c[1] / side]);
                }
                v.push(f64::from(constant));
            }
            floats.extend(v.iter().map(|&x| x as f32));
            normals.push(([p.x, p.y], d));
        }
        Ok(PixelData {
            floats,
            normals,
            light,
        })
    }
}

/// The exact direction of the address unit's input words for a host vector (what the
/// unit looks up; exact in float32 at the default s16.8 words).
fn word_direction(cube: &NormalizeCube, v: crate::scene::math::Vec3) -> Result<[f64; 3], String> {
    let words = cube
        .vector_words([v.x, v.y, v.z], &mut Counters::default())
        .map_err(|e| format!("--emit-gl: {e}"))?;
    Ok(cube.word_direction(&words))
}

/// The Lambert term's constants.
struct Diffuse {
    face: u32,
    filter: &'static str,
    light: [f64; 3],
    albedo: [u32; 3],
}

/// What scene.c's text needs.
struct Constants {
    name: String,
    side: u32,
    count: usize,
    /// The cube's face side (with the Lambert term).
    face: Option<u32>,
    diffuse: Option<Diffuse>,
    /// Each factor texture's side.
    factors: Vec<u32>,
    /// The factored lobe's output scale 2^shift.
    shift: u32,
}

/// scene.c: the header comment, the prelude, the constants, the textures, the one
/// pass and `main`.
fn scene_c(k: &Constants) -> String {
    let mut s = String::new();
    header(&mut s, k);
    s.push_str(PRELUDE);
    constants(&mut s, k);
    s.push_str(SPHERE_HELPERS);
    load_textures(&mut s, k);
    s.push_str(SPHERE_PASS);
    main_text(&mut s, &EXTENSIONS, 3, &["pass_sphere".to_string()]);
    s
}

fn header(s: &mut String, k: &Constants) {
    let _ = writeln!(
        s,
        "/* scene.c — `{name}` as an OpenGL 1.3 program.\n *\n * Written by `glare-pipeline render --emit-gl`. It draws the shading sphere as the\n * model's units shade it, one point per covered pixel at its centre (the model's host\n * gives each pixel its own vectors and coordinates: no interpolation), each combiner\n * stage its own draw, rounded to 8 bits as the model's. Offscreen on OSMesa; it writes\n * framebuffer.png ({side} x {side}, 8-bit RGB); the model's own picture is model.png\n * beside it.\n *\n * Build: sh build.sh   Run: GALLIUM_DRIVER=llvmpipe ./scene [out.png]\n *\n * Terms drawn:",
        name = k.name,
        side = k.side,
    );
    if let Some(d) = &k.diffuse {
        let _ = writeln!(
            s,
            " *   Lambert: N^ and L^ from the normalisation cube map, DOT3_RGB, MODULATE by the\n *   albedo constant ({}, {}, {}).",
            d.albedo[0], d.albedo[1], d.albedo[2]
        );
    }
    if !k.factors.is_empty() {
        let _ = writeln!(
            s,
            " *   factored lobe: {} factor textures multiplied left to right, times the constant\n *   colour, times 2^{} (saturating); added to the Lambert term (saturating).",
            k.factors.len(),
            k.shift
        );
    }
    let _ = writeln!(s, " *\n * Data files:");
    if let Some(d) = &k.diffuse {
        let _ = writeln!(
            s,
            " *   normalize_cube.raw  the model's normalisation cube: 6 faces (+x, -x, +y, -y, +z,\n *                       -z) of {f} x {f} RGB texels, 8 bits, the packed direction of\n *                       each texel's centre",
            f = d.face
        );
    }
    for (i, size) in k.factors.iter().enumerate() {
        let _ = writeln!(
            s,
            " *   factor_{i}.raw        factor texture {i}: {size} x {size} luminance texels, 8 bits"
        );
    }
    let _ = writeln!(
        s,
        " *   sphere_pixels.f32   {} covered pixels x PIXEL_FLOATS float32: x, y (y down), the\n *                       normal's direction as the address unit receives it, then\n *                       per factor (s, t) (the sampler's coordinate words over the side)\n *                       and the constant colour's 8-bit code\n */",
        k.count
    );
}

fn constants(s: &mut String, k: &Constants) {
    let nf = k.factors.len();
    let _ = writeln!(
        s,
        "\n/* ---------------------------------------------------------------------------------\n * The scene.\n * ------------------------------------------------------------------------------- */\n\n#define W {side}\n#define H {side}\n/* The buffer: the image in rows 0 .. H, the stage register in rows H .. 2H. */\n#define BUF_W W\n#define BUF_H (2 * H)\n/* The stage texture's power-of-two sides (OpenGL 1.3). */\n#define TEX_W {tex}\n#define TEX_H {tex}\n#define PIXELS {count}\n#define FACTORS {nf}\n#define PIXEL_FLOATS {pf}\n/* The factored lobe's scale: 2^SHIFT. */\n#define SHIFT {shift}",
        side = k.side,
        tex = k.side.next_power_of_two(),
        count = k.count,
        pf = 5 + 2 * nf + usize::from(nf > 0),
        shift = k.shift,
    );
    match &k.diffuse {
        Some(d) => {
            let _ = writeln!(
                s,
                "#define HAS_DIFFUSE 1\n#define FACE {face}\n/* The direction toward the light, as the address unit receives it. */\nstatic const GLfloat LIGHT[3] = {{{l0:?}f, {l1:?}f, {l2:?}f}};\n/* The albedo constant: the model's MODULATE stage's u8 codes. */\nstatic const GLfloat ALBEDO[4] = {{{a0}.0f / 255.0f, {a1}.0f / 255.0f, {a2}.0f / 255.0f, 1.0f}};",
                face = d.face,
                l0 = d.light[0] as f32,
                l1 = d.light[1] as f32,
                l2 = d.light[2] as f32,
                a0 = d.albedo[0],
                a1 = d.albedo[1],
                a2 = d.albedo[2],
            );
        }
        None => {
            let _ = writeln!(
                s,
                "#define HAS_DIFFUSE 0\n#define FACE 1\nstatic const GLfloat LIGHT[3] = {{0.0f, 0.0f, 1.0f}};\nstatic const GLfloat ALBEDO[4] = {{0.0f, 0.0f, 0.0f, 1.0f}};"
            );
        }
    }
    let sides: Vec<String> = k.factors.iter().map(u32::to_string).collect();
    let _ = writeln!(
        s,
        "static const int factor_side[FACTORS + 1] = {{{}0}};\nstatic GLuint tex_cube, tex_stage, tex_factor[FACTORS + 1];\n",
        sides.iter().map(|x| format!("{x}, ")).collect::<String>()
    );
}

fn load_textures(s: &mut String, k: &Constants) {
    let _ = writeln!(
        s,
        "/* The model's textures: the normalisation cube ({}, as the model's sampler), the\n * factor textures (bilinear, clamped), and the stage register's texture. */\nstatic void load_textures(void)\n{{\n    int i;\n    char name[32];\n    if (HAS_DIFFUSE)\n        tex_cube = cube_texture_from_file(\"normalize_cube.raw\", FACE, {});\n    for (i = 0; i < FACTORS; i++) {{\n        sprintf(name, \"factor_%d.raw\", i);\n        tex_factor[i] = texture_from_file(GL_TEXTURE_2D, name, factor_side[i], factor_side[i],\n                                          GL_LUMINANCE, GL_LINEAR, GL_CLAMP_TO_EDGE);\n    }}\n    tex_stage = screen_texture(TEX_W, TEX_H, GL_RGB);\n}}\n",
        k.diffuse.as_ref().map_or("unused", |d| d.filter),
        k.diffuse.as_ref().map_or("GL_LINEAR", |d| d.filter),
    );
}

/// The sphere's draw helpers: the points with what each draw's units read.
const SPHERE_HELPERS: &str = r#"/* What a point gives a texture unit: nothing, the normal (cube map), the light
 * (cube map, the same for every point), the pixel centre in the stage texture, or
 * factor k's (s, t) (k >= 0). */
enum { NONE = -4, NORMAL = -3, LIGHT_DIR = -2, STAGE = -1 };

static void unit_coords(int unit, int what, const float *p)
{
    GLenum u = GL_TEXTURE0 + unit;
    if (what == NORMAL)
        glMultiTexCoord3f(u, p[2], p[3], p[4]);
    else if (what == LIGHT_DIR)
        glMultiTexCoord3f(u, LIGHT[0], LIGHT[1], LIGHT[2]);
    else if (what == STAGE)
        glMultiTexCoord2f(u, p[0] / TEX_W, p[1] / TEX_H);
    else if (what >= 0)
        glMultiTexCoord2f(u, p[5 + 2 * what], p[6 + 2 * what]);
}

/* One point per covered pixel; unit 0 and unit 1 read `u0` and `u1`; with `colour`
 * the primary colour is the constant colour's code. */
static void points(const float *v, int u0, int u1, int colour)
{
    int i;
    glBegin(GL_POINTS);
    for (i = 0; i < PIXELS; i++) {
        const float *p = v + (size_t)i * PIXEL_FLOATS;
        unit_coords(0, u0, p);
        unit_coords(1, u1, p);
        if (colour) {
            GLubyte c = (GLubyte)p[5 + 2 * FACTORS];
            glColor3ub(c, c, c);
        }
        glVertex2f(p[0], p[1]);
    }
    glEnd();
}

/* The points into the stage register. */
static void into_stage(const float *v, int u0, int u1, int colour)
{
    stage_region(W, H);
    points(v, u0, u1, colour);
    stage_copy(tex_stage, W, H);
}

/* Texture unit `unit`: texture `tex` times 2^log2_scale (RGB_SCALE 2 or 4; exact on
 * an 8-bit value, saturating at 1). */
static void unit_scale(int unit, GLuint tex, int log2_scale)
{
    unit_replace(unit, GL_TEXTURE_2D, tex);
    glTexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE_ARB, (GLfloat)(1 << log2_scale));
}
"#;

/// The pass: the Lambert term into the image, then the factored lobe added.
const SPHERE_PASS: &str = r#"
/* The sphere. The Lambert term: DOT3 of the normal's and the light's cube texels into
 * the stage register, then MODULATE by the albedo constant into the image. The
 * factored lobe: factor 0 (times factor 1) into the register, each further factor,
 * the constant colour and the scale (2 bits at a time) one draw each, then added to
 * the image with a saturating additive blend (the model's ADD). */
static void pass_sphere(void)
{
    const float *v = load_floats("sphere_pixels.f32", (size_t)PIXELS * PIXEL_FLOATS);
    int k, shift;
    units_off();
    if (HAS_DIFFUSE) {
        unit_replace(0, GL_TEXTURE_CUBE_MAP, tex_cube);
        unit_dot3(1, GL_TEXTURE_CUBE_MAP, tex_cube);
        into_stage(v, NORMAL, LIGHT_DIR, 0);
        region(0, 0, W, H);
        unit_modulate(0, GL_TEXTURE_2D, tex_stage, GL_TEXTURE, GL_CONSTANT_ARB, ALBEDO);
        points(v, STAGE, NONE, 0);
        units_off();
    }
    if (FACTORS > 0) {
        unit_replace(0, GL_TEXTURE_2D, tex_factor[0]);
        if (FACTORS > 1)
            unit_modulate(1, GL_TEXTURE_2D, tex_factor[1], GL_TEXTURE, GL_PREVIOUS_ARB, NULL);
        into_stage(v, 0, FACTORS > 1 ? 1 : NONE, 0);
        for (k = 2; k < FACTORS; k++) {
            unit_replace(0, GL_TEXTURE_2D, tex_stage);
            unit_modulate(1, GL_TEXTURE_2D, tex_factor[k], GL_TEXTURE, GL_PREVIOUS_ARB, NULL);
            into_stage(v, STAGE, k, 0);
        }
        unit_modulate(0, GL_TEXTURE_2D, tex_stage, GL_TEXTURE, GL_PRIMARY_COLOR, NULL);
        into_stage(v, STAGE, NONE, 1);
        for (shift = SHIFT; shift > 0; shift -= 2) {
            unit_scale(0, tex_stage, shift >= 2 ? 2 : 1);
            into_stage(v, STAGE, NONE, 0);
        }
        region(0, 0, W, H);
        unit_replace(0, GL_TEXTURE_2D, tex_stage);
        additive(1);
        points(v, STAGE, NONE, 0);
        additive(0);
        units_off();
    }
    free((void *)v);
}
"#;
