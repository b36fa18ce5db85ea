//! `render --scene test --emit-gl DIR`: the foundation test scene (a checkered floor
//! under a spotlight cut by a window-frame occluder's shadow) as an OpenGL 1.3 program
//! drawing what the model's units draw:
//!
//! * the shadow map: the occluder's quads seen from the light into a depth region,
//!   copied into a depth texture (ARB_depth_texture), compared with ARB_shadow (lit
//!   where r/q − bias ≤ stored; the bias the model's 8 steps of its 16-bit map);
//! * the floor: its 8 × 8 cells with the host's window positions, the checker's
//!   (u, v)/w and 1/w and the light's (s, t, r, q)/w as projective texture
//!   coordinates (GL divides per fragment, as the model's projective units), the
//!   per-vertex Lambert term as the primary colour (interpolated linearly on the
//!   screen, as the model's interpolator);
//! * the model's modulates, each rounded to 8 bits, in its order: the ambient
//!   albedo · AMBIENT into the image; light map · Lambert into the stage register;
//!   that · lit · the light's colour into it again; albedo · that added into the image
//!   (saturating, as the model's additive blend).

use super::source::{main_text, PRELUDE};
use super::Program;
use crate::pipeline::test_scene::{
    floor_attributes, floor_corner, occluder_window, FLOOR_CELLS, SHADOW_BIAS, SHADOW_DEPTH_BITS,
    SHADOW_SIZE,
};
use crate::scene::test_scene::{
    checker_texels, lightmap_texels, occluder_quads, views, AMBIENT, CHECKER_SIZE, HEIGHT,
    LIGHTMAP_SIZE, LIGHT_RGB, WIDTH,
};
use std::fmt::Write as _;

/// Floats per floor vertex: x, y (window, y down), the Lambert term, the checker's
/// (u/w, v/w, 1/w), the light's (s/w, t/w, r/w, q/w).
pub const FLOOR_FLOATS: usize = 10;

/// The extensions the program draws with.
const EXTENSIONS: [&str; 3] = [
    "GL_ARB_depth_texture",
    "GL_ARB_shadow",
    "GL_ARB_texture_env_combine",
];

/// The occluder's quads in the shadow map, as the model's host computes them: x, y
/// (texels, y down) and window depth.
fn occluder_vertices() -> Vec<f32> {
    let v = views();
    occluder_quads()
        .into_iter()
        .flatten()
        .flat_map(|p| {
            let (x, y, z) = occluder_window(&v, p);
            [x, y, z].map(|a| a as f32)
        })
        .collect()
}

/// The floor's cells, four corners each ([`FLOOR_FLOATS`] per corner), with the
/// attributes the model's host hands its interpolator (the 1/w scale cancels in GL's
/// per-fragment divide).
fn floor_vertices() -> Vec<f32> {
    let v = views();
    let n = FLOOR_CELLS;
    let mut out = Vec::new();
    for j in 0..n {
        for i in 0..n {
            for (a, b) in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)] {
                let (p, tu, tv) = floor_corner(a, b);
                let (x, y, at) = floor_attributes(&v, p, (tu, tv));
                // The model's modulate reads the interpolated Lambert term as the code
                // ⌊l·256⌋ of 255: the primary colour carries l·256/255 (GL clamps it).
                let lambert = at[7] * 256.0 / 255.0;
                let row = [
                    x, y, lambert, at[0], at[1], at[2], at[3], at[4], at[5], at[6],
                ];
                out.extend(row.map(|a| a as f32));
            }
        }
    }
    out
}

/// The test scene's program: its files' names and bytes.
pub fn test_scene_program() -> Program {
    let bytes = |v: Vec<u32>| v.into_iter().map(|t| t as u8).collect::<Vec<u8>>();
    let occ = occluder_vertices();
    let floor = floor_vertices();
    let source = scene_c(occ.len() / 3, floor.len() / FLOOR_FLOATS);
    Program {
        files: vec![
            ("scene.c".into(), source.into_bytes()),
            ("build.sh".into(), super::build_script().into_bytes()),
            ("checker.raw".into(), bytes(checker_texels())),
            ("light_map.raw".into(), bytes(lightmap_texels())),
            ("occluder.f32".into(), super::f32_bytes(&occ)),
            ("floor.f32".into(), super::f32_bytes(&floor)),
        ],
    }
}

fn scene_c(occluder_vertices: usize, floor_vertices: usize) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "/* scene.c — the foundation test scene as an OpenGL 1.3 program.\n *\n * Written by `glare-pipeline render --emit-gl`. A checkered floor under a spotlight\n * whose beam a window-frame occluder cuts: the shadow map from the occluder's quads,\n * then the floor's ambient and spot passes, the model's modulates each its own draw\n * (rounded to 8 bits between draws, as the model's), added into the framebuffer.\n * Offscreen on OSMesa; it writes framebuffer.png ({w} x {h}, 8-bit RGB); the model's\n * own picture is model.png beside it.\n *\n * Build: sh build.sh   Run: GALLIUM_DRIVER=llvmpipe ./scene [out.png]\n *\n * Data files:\n *   checker.raw     the checker texture, {cs} x {cs} RGBA, 8 bits (repeat, bilinear)\n *   light_map.raw   the spot's light map, {ls} x {ls} luminance, 8 bits (clamp, bilinear)\n *   occluder.f32    {ov} vertices (quads) x 3 float32: x, y in the shadow map (texels,\n *                   y down), window depth\n *   floor.f32       {fv} vertices (quads) x {ff} float32: x, y (window, y down), the\n *                   Lambert term, the checker's (u/w, v/w, 1/w), the light's\n *                   (s/w, t/w, r/w, q/w)\n */\n{prelude}\n/* ---------------------------------------------------------------------------------\n * The scene.\n * ------------------------------------------------------------------------------- */\n\n#define W {w}\n#define H {h}\n/* The buffer: the image at (0, 0), the shadow map at (W, 0), the stage register at\n * (0, H). */\n#define BUF_W (W + SHADOW_RES)\n#define BUF_H (2 * H)\n#define TEX_W {tw}\n#define TEX_H {th}\n#define SHADOW_RES {sr}\n/* Lit where r/q - bias <= stored: the model's bias, {bias} steps of its 16-bit map. */\n#define SHADOW_BIAS {bias_f:.9}f\n#define CHECKER_SIZE {cs}\n#define LIGHT_MAP_SIZE {ls}\n#define OCCLUDER_VERTICES {ov}\n#define FLOOR_VERTICES {fv}\n#define FLOOR_FLOATS {ff}\nstatic const GLfloat AMBIENT_RGB[4] = {{{amb}.0f / 255.0f, {amb}.0f / 255.0f, {amb}.0f / 255.0f, 1.0f}};\nstatic const GLfloat LIGHT_COLOUR[4] = {{{l0}.0f / 255.0f, {l1}.0f / 255.0f, {l2}.0f / 255.0f, 1.0f}};\n\nstatic GLuint tex_checker, tex_light_map, tex_shadow, tex_stage;",
        prelude = PRELUDE,
        w = WIDTH,
        h = HEIGHT,
        tw = WIDTH.next_power_of_two(),
        th = HEIGHT.next_power_of_two(),
        sr = SHADOW_SIZE,
        bias = SHADOW_BIAS,
        bias_f = f64::from(SHADOW_BIAS) / ((1u64 << SHADOW_DEPTH_BITS) - 1) as f64,
        cs = CHECKER_SIZE,
        ls = LIGHTMAP_SIZE,
        ov = occluder_vertices,
        fv = floor_vertices,
        ff = FLOOR_FLOATS,
        amb = AMBIENT,
        l0 = LIGHT_RGB[0],
        l1 = LIGHT_RGB[1],
        l2 = LIGHT_RGB[2],
    );
    s.push_str(TEST_SCENE_C);
    let passes = ["pass_shadow_map", "pass_floor"].map(String::from);
    main_text(&mut s, &EXTENSIONS, 3, &passes);
    s
}

/// The textures, the floor's draw helper and the two passes.
const TEST_SCENE_C: &str = r#"
/* The checker and the light map (the model's texels, bilinear as its samplers), the
 * shadow map's depth texture and the stage register's texture. */
static void load_textures(void)
{
    tex_checker = texture_from_file(GL_TEXTURE_2D, "checker.raw", CHECKER_SIZE, CHECKER_SIZE,
                                    GL_RGBA, GL_LINEAR, GL_REPEAT);
    tex_light_map = texture_from_file(GL_TEXTURE_2D, "light_map.raw", LIGHT_MAP_SIZE,
                                      LIGHT_MAP_SIZE, GL_LUMINANCE, GL_LINEAR, GL_CLAMP_TO_EDGE);
    tex_shadow = shadow_texture(SHADOW_RES);
    tex_stage = screen_texture(TEX_W, TEX_H, GL_RGB);
}

/* What a floor vertex gives a texture unit. */
enum { NOTHING, CHECKER, LIGHT, STAGE };

static void floor_coords(int unit, int what, const float *a)
{
    GLenum u = GL_TEXTURE0 + unit;
    if (what == CHECKER)
        glMultiTexCoord4f(u, a[3], a[4], 0.0f, a[5]);
    else if (what == LIGHT)
        glMultiTexCoord4f(u, a[6], a[7], a[8], a[9]);
    else if (what == STAGE)
        glMultiTexCoord2f(u, a[0] / TEX_W, a[1] / TEX_H);
}

/* The floor's cells (quads); units 0, 1 and 2 read `u0`, `u1`, `u2`; the primary colour
 * is the Lambert term. */
static void draw_floor(const float *v, int u0, int u1, int u2)
{
    int i;
    glBegin(GL_QUADS);
    for (i = 0; i < FLOOR_VERTICES; i++) {
        const float *a = v + (size_t)i * FLOOR_FLOATS;
        glColor3f(a[2], a[2], a[2]);
        floor_coords(0, u0, a);
        floor_coords(1, u1, a);
        floor_coords(2, u2, a);
        glVertex2f(a[0], a[1]);
    }
    glEnd();
}

/* Pass: the shadow map. The occluder's quads from the light into a depth region
 * (keep the nearer), copied into the depth texture. */
static void pass_shadow_map(void)
{
    const float *v = load_floats("occluder.f32", (size_t)OCCLUDER_VERTICES * 3);
    int i;
    units_off();
    region(W, 0, SHADOW_RES, SHADOW_RES);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glClear(GL_DEPTH_BUFFER_BIT);
    glBegin(GL_QUADS);
    for (i = 0; i < OCCLUDER_VERTICES; i++)
        glVertex3f(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    glEnd();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_DEPTH_TEST);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex_shadow);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, W, 0, SHADOW_RES, SHADOW_RES);
    free((void *)v);
}

/* The floor into the stage register. */
static void floor_into_stage(const float *v, int u0, int u1, int u2)
{
    stage_region(W, H);
    draw_floor(v, u0, u1, u2);
    stage_copy(tex_stage, W, H);
}

/* Pass: the floor. Ambient: albedo x AMBIENT into the image. Spot: light map x
 * Lambert into the register; x lit (0 or 1) x the light's colour into it again;
 * albedo x that added into the image (saturating). */
static void pass_floor(void)
{
    const float *v = load_floats("floor.f32", (size_t)FLOOR_VERTICES * FLOOR_FLOATS);
    units_off();
    region(0, 0, W, H);
    additive(0);
    unit_modulate(0, GL_TEXTURE_2D, tex_checker, GL_TEXTURE, GL_CONSTANT_ARB, AMBIENT_RGB);
    draw_floor(v, CHECKER, NOTHING, NOTHING);
    units_off();

    unit_modulate(0, GL_TEXTURE_2D, tex_light_map, GL_TEXTURE, GL_PRIMARY_COLOR, NULL);
    floor_into_stage(v, LIGHT, NOTHING, NOTHING);

    unit_replace(0, GL_TEXTURE_2D, tex_stage);
    unit_modulate(1, GL_TEXTURE_2D, tex_shadow, GL_TEXTURE, GL_PREVIOUS_ARB, NULL);
    glMatrixMode(GL_TEXTURE);
    glLoadIdentity();
    glTranslatef(0.0f, 0.0f, -SHADOW_BIAS);
    glMatrixMode(GL_MODELVIEW);
    unit_modulate(2, GL_TEXTURE_2D, tex_stage, GL_PREVIOUS_ARB, GL_CONSTANT_ARB, LIGHT_COLOUR);
    floor_into_stage(v, STAGE, LIGHT, STAGE);

    region(0, 0, W, H);
    unit_replace(0, GL_TEXTURE_2D, tex_stage);
    unit_modulate(1, GL_TEXTURE_2D, tex_checker, GL_TEXTURE, GL_PREVIOUS_ARB, NULL);
    additive(1);
    draw_floor(v, STAGE, CHECKER, NOTHING);
    additive(0);
    units_off();
    free((void *)v);
}
"#;
