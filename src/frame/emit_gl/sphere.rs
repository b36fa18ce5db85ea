//! `render --scene shading-lambert --emit-gl DIR`: the shading sphere whose path is
//! OpenGL 1.3's texture combine — the Lambert term, N̂ and L̂ from the normalisation
//! cube map (ARB_texture_cube_map), DOT3_RGB (ARB_texture_env_dot3), MODULATE by the
//! albedo constant — as a C program drawing what the model's units draw.
//!
//! The model shades each covered pixel of the sphere from vectors its host computes
//! per pixel (no interpolation): so the program draws one point per covered pixel, at
//! the pixel's centre, with the vectors the model's address unit receives (its input
//! words' exact directions, d = c − s/2) as the cube map's texture coordinates. The
//! cube's texels are the model's; the stages are the model's, in its order.

use super::source::{main_text, PRELUDE};
use super::Program;
use crate::pipeline::shading::brdfs::entry_view;
use crate::pipeline::shading::normalize_cube::{normalization_texels, NormalizeCube};
use crate::pipeline::shading::scene_file::{ShadingFile, DEFAULT_IMAGE};
use crate::pipeline::shading::sweep::ShadingScene;
use crate::pipeline::shading::sweep::{measure_point, shading_reference, sweep_view};
use rtl_model::units::texture_sampler::Filter;
use rtl_model::Counters;
use std::fmt::Write as _;

/// Floats per covered pixel in `sphere_pixels.f32`: x, y (the pixel), then the
/// normal's direction as the address unit's words encode it.
pub const PIXEL_FLOATS: usize = 5;

/// The extensions the sphere's program draws with.
const EXTENSIONS: [&str; 3] = [
    "GL_ARB_texture_cube_map",
    "GL_ARB_texture_env_combine",
    "GL_ARB_texture_env_dot3",
];

/// Why a shading sphere scene has no program (None: it has one, the Lambert path).
pub fn not_exportable(f: &ShadingFile) -> Option<String> {
    match f.point.scene() {
        ShadingScene::Vertex => Some(
            "shading-vertex lights sphere vertices and has no image: its fixed-function GL \
             lighting form (vertex colours read back by feedback) is not written"
                .into(),
        ),
        ShadingScene::Specular => Some(
            "shading-specular's (n·h)^s runs on the register combiners \
             (NV_register_combiners) or the texture shader's dependent lookup \
             (NV_texture_shader): no OpenGL 1.3 form"
                .into(),
        ),
        ShadingScene::Model(e) => match crate::pipeline::shading::materials::lobe_kind(&e.material)
        {
            "none" => None,
            "lookup" => Some(format!(
                "shading-{}'s specular lobe reads its lookup table at the DOT3's n·h (a \
                 dependent texture read, NV_texture_shader): no OpenGL 1.3 form",
                e.label
            )),
            _ => Some(format!(
                "shading-{}'s factor textures (host-computed coordinates, a modulate chain \
                 with a saturating scale) are not exported",
                e.label
            )),
        },
    }
}

/// The sphere scene's program and the model's picture of it (grey 8-bit levels,
/// row-major, `side` × `side`).
pub struct SphereProgram {
    pub program: Program,
    pub side: u32,
    pub model_levels: Vec<f64>,
    /// The model's sphere through its units, wall seconds (the reference drawn apart).
    pub model_seconds: f64,
    /// Each covered pixel (x, y) and its normal as the address unit receives it.
    pub normals: Vec<([u32; 2], [f64; 3])>,
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

/// The program of a Lambert shading sphere (refused, with why, for any other).
pub fn sphere_program(f: &ShadingFile) -> Result<SphereProgram, String> {
    if let Some(why) = not_exportable(f) {
        return Err(format!("--emit-gl: {why}"));
    }
    let Some((entry, cfg)) = f.point.model() else {
        return Err("--emit-gl: not a catalogue model's sphere".into());
    };
    let side = f.image.unwrap_or(DEFAULT_IMAGE);
    let view = sweep_view(side);
    let path =
        crate::pipeline::shading::materials::material_path(&entry.material, entry.color, &cfg)
            .map_err(|e| format!("--emit-gl: {e}"))?;
    let Some((cube, albedo)) = path.lambert_stages() else {
        return Err("--emit-gl: the path is not the Lambert term alone".into());
    };
    let c = cube.config();
    if c.texel_bits != 8 {
        return Err(format!(
            "--emit-gl: the normalisation cube's texels are {} bits; the GL program's cube map is 8-bit",
            c.texel_bits
        ));
    }
    // The model's picture, as `render` writes it.
    let reference = shading_reference(&f.point, &view)?;
    let t0 = std::time::Instant::now();
    let model_levels = measure_point(&f.point, &view, &reference)?.levels;
    let model_seconds = t0.elapsed().as_secs_f64();
    // The light and each covered pixel's normal as the address unit receives them.
    let lit = entry_view(&entry, &view);
    let light = word_direction(cube, lit.light)?;
    let mut pixels = Vec::new();
    let mut normals = Vec::new();
    for p in lit.pixels().into_iter().flatten() {
        let d = word_direction(cube, p.frame.n)?;
        pixels.extend([p.x as f64 + 0.5, p.y as f64 + 0.5, d[0], d[1], d[2]].map(|v| v as f32));
        normals.push(([p.x, p.y], d));
    }
    let count = pixels.len() / PIXEL_FLOATS;
    // The texels the model's cube sampler holds (its constructor's own function).
    let texels: Vec<u8> = normalization_texels(c.face_side, c.texel_bits)
        .iter()
        .map(|&t| t as u8)
        .collect();
    let filter = match c.filter {
        Filter::Nearest => "GL_NEAREST",
        Filter::Linear => "GL_LINEAR",
    };
    let source = scene_c(&Constants {
        name: f.point.scene().name(),
        side,
        face: c.face_side,
        filter,
        light,
        albedo,
        count,
    });
    let build = super::build_script();
    Ok(SphereProgram {
        program: Program {
            files: vec![
                ("scene.c".into(), source.into_bytes()),
                ("build.sh".into(), build.into_bytes()),
                ("normalize_cube.raw".into(), texels),
                ("sphere_pixels.f32".into(), super::f32_bytes(&pixels)),
            ],
        },
        side,
        model_levels,
        model_seconds,
        normals,
    })
}

/// The exact direction of the address unit's input words for a host vector (what the
/// unit looks up; exact in float32 at the default s16.8 words).
fn word_direction(cube: &NormalizeCube, v: crate::scene::math::Vec3) -> Result<[f64; 3], String> {
    let words = cube
        .vector_words([v.x, v.y, v.z], &mut Counters::default())
        .map_err(|e| format!("--emit-gl: {e}"))?;
    Ok(cube.word_direction(&words))
}

/// What scene.c's text needs.
struct Constants {
    name: String,
    side: u32,
    face: u32,
    filter: &'static str,
    light: [f64; 3],
    albedo: [u32; 3],
    count: usize,
}

/// scene.c: the header comment, the prelude, the constants, the textures, the one
/// pass and `main`.
fn scene_c(k: &Constants) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "/* scene.c — `{name}` as an OpenGL 1.3 program.\n *\n * Written by `glare-pipeline render --emit-gl`. It draws the shading sphere as the\n * model's units shade it: per covered pixel (the model's host gives each pixel its\n * own vectors: no interpolation), the normal N and the light L through the\n * normalisation cube map (the model's texels), DOT3_RGB of the two, MODULATE by the\n * albedo constant ({a0}, {a1}, {a2}), each stage rounded to 8 bits as the model's (the\n * model's ADD of a zero specular term changes nothing and is left out). One point per\n * covered pixel, at its centre. Offscreen on\n * OSMesa; it writes framebuffer.png ({side} x {side}, 8-bit RGB); the model's own\n * picture is model.png beside it.\n *\n * Build: sh build.sh   Run: GALLIUM_DRIVER=llvmpipe ./scene [out.png]\n *\n * Data files:\n *   normalize_cube.raw  the model's normalisation cube: 6 faces (+x, -x, +y, -y, +z, -z)\n *                       of {face} x {face} RGB texels, 8 bits, the packed direction of\n *                       each texel's centre ({cube_bytes} bytes)\n *   sphere_pixels.f32   {count} covered pixels x 5 float32: the pixel's centre x, y\n *                       (y down), then the normal's direction as the model's address\n *                       unit receives it (its input words, d = c - s/2)\n */",
        name = k.name,
        a0 = k.albedo[0],
        a1 = k.albedo[1],
        a2 = k.albedo[2],
        side = k.side,
        face = k.face,
        cube_bytes = 6 * k.face * k.face * 3,
        count = k.count,
    );
    s.push_str(PRELUDE);
    let _ = writeln!(
        s,
        "\n/* ---------------------------------------------------------------------------------\n * The scene.\n * ------------------------------------------------------------------------------- */\n\n#define W {side}\n#define H {side}\n/* The buffer: the image in rows 0 .. H, the stage register in rows H .. 2H. */\n#define BUF_W W\n#define BUF_H (2 * H)\n/* The stage texture's power-of-two sides (OpenGL 1.3). */\n#define TEX_W {tex}\n#define TEX_H {tex}\n#define FACE {face}\n#define PIXELS {count}\n/* The direction toward the light, as the address unit receives it. */\nstatic const GLfloat LIGHT[3] = {{{l0:?}f, {l1:?}f, {l2:?}f}};\n/* The albedo constant: the model's MODULATE stage's u8 codes. */\nstatic const GLfloat ALBEDO[4] = {{{a0}.0f / 255.0f, {a1}.0f / 255.0f, {a2}.0f / 255.0f, 1.0f}};\n\nstatic GLuint tex_cube, tex_stage;\n\n/* The normalisation cube ({filter}, as the model's sampler) and the stage texture. */\nstatic void load_textures(void)\n{{\n    tex_cube = cube_texture_from_file(\"normalize_cube.raw\", FACE, {filter});\n    tex_stage = screen_texture(TEX_W, TEX_H, GL_RGB);\n}}\n\n/* The sphere, one point per covered pixel, in two draws: the model rounds each\n * combiner stage to 8 bits, and a chain of stages in one draw rounds once at its end\n * on llvmpipe (docs/gl.md). Draw 1, into the stage region: unit 0 the normal's cube\n * texel (N^), unit 1 DOT3_RGB with the light's (L^): n.l. It is copied into the stage\n * texture (the 8-bit register between the stages). Draw 2, into the image: MODULATE\n * of the register, read at the pixel centre, by the albedo constant. */\nstatic void pass_sphere(void)\n{{\n    const float *v = load_floats(\"sphere_pixels.f32\", (size_t)PIXELS * 5);\n    int i;\n    region(0, H, W, H);\n    units_off();\n    unit_replace(0, GL_TEXTURE_CUBE_MAP, tex_cube);\n    unit_dot3(1, GL_TEXTURE_CUBE_MAP, tex_cube);\n    glBegin(GL_POINTS);\n    glMultiTexCoord3f(GL_TEXTURE1, LIGHT[0], LIGHT[1], LIGHT[2]);\n    for (i = 0; i < PIXELS; i++) {{\n        const float *p = v + (size_t)i * 5;\n        glMultiTexCoord3f(GL_TEXTURE0, p[2], p[3], p[4]);\n        glVertex2f(p[0], p[1]);\n    }}\n    glEnd();\n    units_off();\n    glBindTexture(GL_TEXTURE_2D, tex_stage);\n    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, H, W, H);\n\n    region(0, 0, W, H);\n    unit_modulate(0, GL_TEXTURE_2D, tex_stage, GL_TEXTURE, GL_CONSTANT_ARB, ALBEDO);\n    glBegin(GL_POINTS);\n    for (i = 0; i < PIXELS; i++) {{\n        const float *p = v + (size_t)i * 5;\n        glMultiTexCoord2f(GL_TEXTURE0, p[0] / TEX_W, p[1] / TEX_H);\n        glVertex2f(p[0], p[1]);\n    }}\n    glEnd();\n    units_off();\n    free((void *)v);\n}}\n",
        side = k.side,
        tex = k.side.next_power_of_two(),
        face = k.face,
        count = k.count,
        l0 = k.light[0] as f32,
        l1 = k.light[1] as f32,
        l2 = k.light[2] as f32,
        a0 = k.albedo[0],
        a1 = k.albedo[1],
        a2 = k.albedo[2],
        filter = k.filter,
    );
    main_text(&mut s, &EXTENSIONS, 3, &["pass_sphere".to_string()]);
    s
}
