//! The text of `scene.c`: a header comment (what is exported and what is not, the data
//! files and their layouts), the fixed helpers ([`PRELUDE`]), one function per pass
//! and the pass list in `main`.

use super::data::{subplane_weight, Export, LightData, OBJ_FLOATS, PLANE_FLOATS, SUB_FLOATS};
use crate::pipeline::shafts::frame::{Prepared, ShaftsPass};
use crate::pipeline::shafts::tables::GTables;
use std::fmt::Write as _;

/// The helpers every program shares (file loading, textures, the region set-up, the
/// combine stages, the PNG writer).
pub(super) const PRELUDE: &str = include_str!("prelude.c");

/// Vertex counts of the geometry files, filled while they are written.
#[derive(Default)]
pub struct DataSizes {
    /// Vertices of depth.f32.
    pub depth: usize,
    /// Per light: vertices of shadow_L.f32.
    pub shadow: Vec<(usize, usize)>,
    /// Per light: vertices of objects_L.f32.
    pub objects: Vec<(usize, usize)>,
}

impl DataSizes {
    /// Light `light`'s vertex count in a per-light list (0 when it has none).
    fn of_light(list: &[(usize, usize)], light: usize) -> usize {
        list.iter().find(|x| x.0 == light).map_or(0, |x| x.1)
    }
}

pub struct Ctx<'a> {
    pub p: &'a Prepared,
    pub tables: &'a GTables,
    pub w: u32,
    pub h: u32,
    pub has_objects: bool,
    pub exported: &'a [ShaftsPass],
    pub exports: &'a [Export],
    pub lights: &'a [LightData],
    pub data: &'a DataSizes,
    pub files: &'a [(String, Vec<u8>)],
}

fn pass_name(p: &ShaftsPass) -> String {
    match p {
        ShaftsPass::Depth => "pass_depth".into(),
        ShaftsPass::ShadowMap { light } => format!("pass_shadow_map_{light}"),
        ShaftsPass::Objects { light } => format!("pass_objects_{light}"),
        ShaftsPass::Planes { light } => format!("pass_planes_{light}"),
    }
}

/// The image's regions in the one GL buffer, from the passes exported.
struct Layout {
    has_shadow: bool,
    has_planes: bool,
    has_depth: bool,
    /// A J buffer region: planes with m > 1 sub-planes.
    j_buffer: bool,
    buf_w: u32,
    buf_h: u32,
}

impl Layout {
    fn of(c: &Ctx) -> Layout {
        let (w, h) = (c.w, c.h);
        let m = c.p.scene.shafts.subplanes;
        let res = c.p.scene.shafts.shadow_resolution;
        let has_shadow = c
            .exported
            .iter()
            .any(|e| matches!(e, ShaftsPass::ShadowMap { .. }));
        let has_planes = c
            .exported
            .iter()
            .any(|e| matches!(e, ShaftsPass::Planes { .. }));
        let has_depth = c.exported.contains(&ShaftsPass::Depth);
        let j_buffer = has_planes && m > 1;
        let buf_w = w + if has_shadow { res } else { 0 };
        // Regions stacked up the buffer: the image, the J buffer (m > 1), the stage
        // register (planes); the shadow map beside them.
        let stacked = 1 + u32::from(j_buffer) + u32::from(has_planes);
        let buf_h = (stacked * h).max(if has_shadow { res } else { 0 });
        Layout {
            has_shadow,
            has_planes,
            has_depth,
            j_buffer,
            buf_w,
            buf_h,
        }
    }
}

/// scene.c: the header comment, the prelude, the scene's constants, the pass helpers,
/// the textures, one function per pass, and `main` with the pass list.
pub fn scene_c(c: &Ctx) -> String {
    let layout = Layout::of(c);
    let mut s = String::new();
    header_comment(&mut s, c);
    s.push_str(PRELUDE);
    scene_constants(&mut s, c, &layout);
    s.push_str(COMMON_PASS_HELPERS);
    load_textures(&mut s, c, &layout);
    for e in c.exported {
        match *e {
            ShaftsPass::Depth => depth_pass(&mut s, c, layout.j_buffer),
            ShaftsPass::ShadowMap { light } => shadow_pass(&mut s, c, light),
            ShaftsPass::Objects { light } => objects_pass(&mut s, c, light),
            ShaftsPass::Planes { light } => planes_pass(&mut s, c, light),
        }
    }
    main_function(&mut s, c);
    s
}

/// The header comment: what is exported and what is not, the data files, where the
/// program and the model may differ.
fn header_comment(s: &mut String, c: &Ctx) {
    let sc = &c.p.scene;
    let (w, h) = (c.w, c.h);
    let _ = writeln!(s, "/* scene.c — `{}` as an OpenGL 1.3 program.", sc.name);
    let _ = writeln!(
        s,
        " *\n * Written by `glare-pipeline render --emit-gl`. It draws the scene's pass plan as the\n * model draws it: the same vertices (projected by the model's host, f64, written as\n * float32 files), the same texture contents (the model's F and h tables and light\n * maps) and filters, the same modulates in the same order (one texture-combine\n * stage each), the same additive blend, in the same pass order. Offscreen on OSMesa;\n * it writes framebuffer.png ({w} x {h}, 8-bit RGB, the model's rows top to bottom).\n * The model's own picture of the scene is model.png beside it.\n *\n * Build: sh build.sh   Run: GALLIUM_DRIVER=llvmpipe ./scene [out.png]\n *"
    );
    let _ = writeln!(
        s,
        " * Passes exported (the plan's order; one function each):"
    );
    for e in c.exported {
        let _ = writeln!(s, " *   {}()", pass_name(e));
    }
    let missing: Vec<&Export> = c
        .exports
        .iter()
        .filter(|e| matches!(e, Export::NotExported { .. }))
        .collect();
    if missing.is_empty() {
        let _ = writeln!(s, " * Not exported: none (every pass of the plan is here).");
    } else {
        let _ = writeln!(
            s,
            " * Not exported (so framebuffer.png lacks them and model.png has them):"
        );
        for e in missing {
            if let Export::NotExported { pass, why } = e {
                let _ = writeln!(s, " *   {pass}: {why}");
            }
        }
    }
    let _ = writeln!(
        s,
        " *\n * Data files (little-endian; float32 = 4 bytes, texels = 1 byte each):"
    );
    for (name, bytes) in c.files {
        let what = data_file_doc(c, name);
        let _ = writeln!(s, " *   {name:<18} {:>10} bytes  {what}", bytes.len());
    }
    let _ = writeln!(
        s,
        " *\n * Where the GL program and the model may differ by a level: the bilinear filters'\n * rounding, the interpolation of colours and coordinates (the model's interpolator is\n * s16.16 fixed point), the shadow map's depth (24 bits here, 8 in the model, whose bias\n * is one 8-bit step, as here) and which triangle of a quad owns the pixels on the\n * shared edge.\n */\n"
    );
}

/// The scene's `#define`s and constant tables.
fn scene_constants(s: &mut String, c: &Ctx, layout: &Layout) {
    let cfg = c.p.scene.shafts;
    let (w, h) = (c.w, c.h);
    let (n, m) = (cfg.planes, cfg.subplanes);
    let [cols, rows] = cfg.mesh;
    let res = cfg.shadow_resolution;
    let Layout {
        has_shadow,
        has_planes,
        has_depth,
        j_buffer,
        buf_w,
        buf_h,
    } = *layout;
    let _ = writeln!(
        s,
        "\n/* ---------------------------------------------------------------------------------\n * The scene.\n * ------------------------------------------------------------------------------- */\n"
    );
    let _ = writeln!(s, "#define W {w} /* image width, pixels */");
    let _ = writeln!(s, "#define H {h} /* image height, pixels */");
    let _ = writeln!(
        s,
        "/* The GL buffer: the image at (0, 0){}{}{}. */",
        if j_buffer {
            "; the J buffer at (0, H) (it needs its own copy of the depth buffer)"
        } else {
            ""
        },
        if has_planes {
            "; the stage register (the 8-bit value between two modulates) at (0, STAGE_Y)"
        } else {
            ""
        },
        if has_shadow {
            "; the shadow map's depth at (W, 0)"
        } else {
            ""
        }
    );
    let _ = writeln!(s, "#define BUF_W {buf_w}\n#define BUF_H {buf_h}");
    let _ = writeln!(s, "#define SHADOW_RES {res} /* shafts.shadow_resolution */");
    let _ = writeln!(
        s,
        "#define SHADOW_X W\n#define J_Y H\n#define STAGE_Y {}",
        if j_buffer { "(2 * H)" } else { "H" }
    );
    let _ = writeln!(
        s,
        "#define J_TEX_W {}\n#define J_TEX_H {}",
        w.next_power_of_two(),
        h.next_power_of_two()
    );
    let _ = writeln!(
        s,
        "#define NF {} /* F table texels (shafts.f_texels) */\n#define HW {}\n#define HH {} /* h table texels (shafts.h_texels) */",
        cfg.f_texels, cfg.h_texels[0], cfg.h_texels[1]
    );
    let _ = writeln!(
        s,
        "#define LIGHT_MAP_TEXELS {} /* shafts.light_map_texels */",
        cfg.light_map_texels
    );
    let _ = writeln!(
        s,
        "#define PLANES {n} /* n (shafts.planes) */\n#define SUBPLANES {m} /* m (shafts.subplanes) */\n#define COLS {cols}\n#define ROWS {rows} /* plane mesh cells (shafts.mesh) */\n/* Floats per vertex of objects_L.f32, planes_L.f32 and subplanes_L.f32, and per plane\n * and per sub-plane (its window depth first). */\n#define OBJ_FLOATS {OBJ_FLOATS}\n#define PLANE_FLOATS {PLANE_FLOATS}\n#define SUB_FLOATS {SUB_FLOATS}\n#define PLANE_STRIDE (1 + (COLS + 1) * (ROWS + 1) * PLANE_FLOATS)\n#define SUB_STRIDE (1 + 4 * SUB_FLOATS)"
    );
    let bias = crate::scene::limits::shadow_bias(cfg.shadow_depth_bits) as f64
        / rtl_model::unorm::max_code(cfg.shadow_depth_bits) as f64;
    let _ = writeln!(
        s,
        "/* Shadow bias: one step of the model's {}-bit shadow map (lit where r - bias <= stored). */\n#define SHADOW_BIAS {bias:.9}f",
        cfg.shadow_depth_bits
    );
    let _ = writeln!(
        s,
        "#define HAS_DEPTH {}",
        u8::from(has_depth && c.has_objects)
    );
    let _ = writeln!(s, "#define HAS_SHADOW {}", u8::from(has_shadow));
    light_constants(s, c);
}

/// The per-light tables, the sub-plane weights and the texture names.
fn light_constants(s: &mut String, c: &Ctx) {
    let m = c.p.scene.shafts.subplanes;
    let nl = c.lights.len().max(1);
    let _ = writeln!(s, "#define LIGHTS {nl}");
    let join = |v: Vec<String>| v.join(", ");
    let _ = writeln!(
        s,
        "/* Per light: has a light map (a spot); its colour as texel codes (the model's\n * planes multiply by it; the intensity is in the planes' scale). */"
    );
    let _ = writeln!(
        s,
        "static const int light_has_map[LIGHTS] = {{{}}};",
        join(
            c.lights
                .iter()
                .map(|l| u8::from(l.has_map).to_string())
                .collect()
        )
    );
    let _ = writeln!(
        s,
        "static const GLfloat light_colour[LIGHTS][4] = {{{}}};",
        join(
            c.lights
                .iter()
                .map(|l| format!(
                    "{{{}.0f / 255, {}.0f / 255, {}.0f / 255, 1}}",
                    l.color[0], l.color[1], l.color[2]
                ))
                .collect()
        )
    );
    let _ = writeln!(
        s,
        "static const int light_colour_white[LIGHTS] = {{{}}};",
        join(
            c.lights
                .iter()
                .map(|l| u8::from(l.color == [255; 3]).to_string())
                .collect()
        )
    );
    if m > 1 {
        let ws: Vec<String> = (0..m as u64)
            .map(|j| subplane_weight(j, m as u64).to_string())
            .collect();
        let _ = writeln!(
            s,
            "/* Sub-plane j's blend weight into the J buffer: floor((j+1)255/m) - floor(j 255/m)\n * (they sum to 255, so a fully lit interval's J is full scale). */\nstatic const unsigned char subplane_weight[SUBPLANES] = {{{}}};",
            ws.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "\nstatic GLuint tex_f, tex_h, tex_light_map[LIGHTS], tex_shadow, tex_step, tex_j, tex_stage;\n"
    );
}

/// `load_textures()`: every texture the passes read.
fn load_textures(s: &mut String, c: &Ctx, layout: &Layout) {
    let Layout {
        has_shadow,
        has_planes,
        j_buffer,
        ..
    } = *layout;
    let _ = writeln!(
        s,
        "/* Every texture the passes read: the model's tables and light maps from their files,\n * the shadow map and the J texture (filled by glCopyTexSubImage2D), the step. */\nstatic void load_textures(void)\n{{"
    );
    if has_planes {
        let _ = writeln!(
            s,
            "    /* F(alpha) over [0, 180] degrees and h(s, t): bilinear, clamped, as the model's samplers. */\n    tex_f = texture_from_file(GL_TEXTURE_1D, \"f_table.raw\", NF, 1, GL_LUMINANCE, GL_LINEAR,\n                              GL_CLAMP_TO_EDGE);\n    tex_h = texture_from_file(GL_TEXTURE_2D, \"h_table.raw\", HW, HH, GL_LUMINANCE, GL_LINEAR,\n                              GL_CLAMP_TO_EDGE);"
        );
    }
    for (li, l) in c.lights.iter().enumerate() {
        if l.has_map {
            let _ = writeln!(
                s,
                "    /* Light {li}'s map: bilinear; outside the light's square the border colour 0\n     * (the model: H*I_l = 0 outside [0, 1]^2). */\n    tex_light_map[{li}] = texture_from_file(GL_TEXTURE_2D, \"light_map_{li}.raw\", LIGHT_MAP_TEXELS,\n                                          LIGHT_MAP_TEXELS, GL_LUMINANCE, GL_LINEAR,\n                                          GL_CLAMP_TO_BORDER);"
            );
        }
    }
    let _ = writeln!(s, "    tex_step = step_texture();");
    if has_shadow {
        let _ = writeln!(s, "    tex_shadow = shadow_texture(SHADOW_RES);");
    }
    if j_buffer {
        let _ = writeln!(
            s,
            "    tex_j = screen_texture(J_TEX_W, J_TEX_H, GL_LUMINANCE);"
        );
    }
    if has_planes {
        let _ = writeln!(
            s,
            "    tex_stage = screen_texture(J_TEX_W, J_TEX_H, GL_RGB);"
        );
    }
    let _ = writeln!(s, "}}\n");
}

/// The extensions a shafts program draws with.
const SHAFTS_EXTENSIONS: [&str; 3] = [
    "GL_ARB_depth_texture",
    "GL_ARB_shadow",
    "GL_ARB_texture_env_combine",
];

/// `main`: the context, the pass list timed, the framebuffer read back as PNG.
fn main_function(s: &mut String, c: &Ctx) {
    let passes: Vec<String> = c.exported.iter().map(pass_name).collect();
    main_text(s, &SHAFTS_EXTENSIONS, 3, &passes);
}

/// A program's `main` (W, H, BUF_W and BUF_H defined before it): the context, the
/// extensions and texture `units` it needs checked, `load_textures()`, the pass list
/// timed, the framebuffer's W × H corner read back as PNG.
pub(super) fn main_text(s: &mut String, extensions: &[&str], units: u32, passes: &[String]) {
    let mut ext: Vec<String> = extensions.iter().map(|e| format!("\"{e}\"")).collect();
    ext.push("NULL".into());
    let _ = writeln!(
        s,
        "int main(int argc, char **argv)\n{{\n    static const char *const extensions[] = {{{}}};\n    const char *out = argc > 1 ? argv[1] : \"framebuffer.png\";\n    unsigned char *rgb = malloc((size_t)W * H * 3);\n    double t0, io0;\n#ifdef SCENE_GLUT\n    glutInit(&argc, argv);\n    glutInitDisplayMode(GLUT_RGB | GLUT_DEPTH | GLUT_SINGLE);\n    glutInitWindowSize(BUF_W, BUF_H);\n    glutCreateWindow(\"scene\");\n#else\n    unsigned char *buffer = malloc((size_t)BUF_W * BUF_H * 4);\n    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);\n    if (!ctx || !buffer || !OSMesaMakeCurrent(ctx, buffer, GL_UNSIGNED_BYTE, BUF_W, BUF_H))\n        die(\"no OSMesa context\");\n#endif\n    require_gl(extensions, {units});\n    printf(\"renderer=%s\\n\", (const char *)glGetString(GL_RENDERER));\n    /* Exact 8-bit arithmetic: no dithering; Gouraud colours. */\n    glDisable(GL_DITHER);\n    glShadeModel(GL_SMOOTH);\n    glDisable(GL_SCISSOR_TEST);\n    glClearColor(0, 0, 0, 0);\n    glClearDepth(1.0);\n    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);\n    load_textures();\n\n    /* The pass list, in the plan's order, timed: from a finished GL (glFinish) to a\n     * finished GL, less the time the passes spend reading their data files. */\n    glFinish();\n    t0 = now_seconds();\n    io0 = io_seconds;",
        ext.join(", ")
    );
    for p in passes {
        let _ = writeln!(s, "    {p}();");
    }
    let _ = writeln!(
        s,
        "\n    glFinish();\n    /* One parseable line: the draw's wall time in seconds. */\n    printf(\"draw_seconds=%.6f\\n\", now_seconds() - t0 - (io_seconds - io0));\n\n    /* Row y of the buffer is the model's row y (top to bottom). */\n    glPixelStorei(GL_PACK_ALIGNMENT, 1);\n    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, rgb);\n    write_png(out, W, H, rgb);\n    printf(\"wrote %s (%d x %d)\\n\", out, W, H);\n    return 0;\n}}"
    );
}

/// What each data file holds, for the header comment.
fn data_file_doc(c: &Ctx, name: &str) -> String {
    let cfg = c.p.scene.shafts;
    let [cols, rows] = cfg.mesh;
    let verts = (cols + 1) * (rows + 1);
    if name == "f_table.raw" {
        format!(
            "F(alpha) codes, {} texels over [0, 180] deg (f_max {:.6e})",
            cfg.f_texels, c.tables.f_max
        )
    } else if name == "h_table.raw" {
        format!(
            "h(s, t) codes, {} x {} (s across, t down; s_max {:.4}, t_max {:.4}, h_ref {:.6e})",
            cfg.h_texels[0], cfg.h_texels[1], c.tables.s_max, c.tables.t_max, c.tables.h_ref
        )
    } else if name.starts_with("light_map_") {
        format!(
            "light map, {0} x {0} codes (u across, v down)",
            cfg.light_map_texels
        )
    } else if name == "depth.f32" {
        format!("{} vertices (triangles) x (x, y, z window)", c.data.depth)
    } else if let Some(l) = name.strip_prefix("shadow_") {
        let n = c
            .data
            .shadow
            .iter()
            .find(|(li, _)| format!("{li}.f32") == l)
            .map_or(0, |x| x.1);
        format!("{n} vertices (triangles) x (x, y, z in the light's map)")
    } else if let Some(l) = name.strip_prefix("objects_") {
        let n = c
            .data
            .objects
            .iter()
            .find(|(li, _)| format!("{li}.f32") == l)
            .map_or(0, |x| x.1);
        format!("{n} vertices (triangles) x {OBJ_FLOATS} (x, y, z, r, g, b, s, t, r, q)")
    } else if name.starts_with("planes_") {
        format!(
            "{} planes x (z, {verts} vertices x {PLANE_FLOATS}: x, y, F, h s, h t, S, s, t, r, q)",
            cfg.planes
        )
    } else if name.starts_with("subplanes_") {
        format!(
            "{} x {} sub-planes x (z, 4 corners x {SUB_FLOATS}: x, y, s, t, r, q)",
            cfg.planes, cfg.subplanes
        )
    } else if name == "scene.c" {
        "this program".into()
    } else if name == "build.sh" {
        "the build line".into()
    } else {
        String::new()
    }
}

/// C helpers shared by the passes (they read the scene's constants).
const COMMON_PASS_HELPERS: &str = r#"/* Texture units that compute H*I_l of a light (the model's light map x shadow
 * compare), the first one multiplied by the primary colour (the vertex colour, the
 * sub-plane weight or the plane scale S): [light map x primary] [x shadow compare]
 * [x in front of the light]. -1: unit not used. */
struct hil_units {
    int lm, sm, q, next;
};

static struct hil_units hil_units(int light, int unit)
{
    struct hil_units u = {-1, -1, -1, 0};
    u.next = unit;
    if (light_has_map[light]) {
        unit_modulate(u.next, GL_TEXTURE_2D, tex_light_map[light], GL_TEXTURE, GL_PRIMARY_COLOR,
                      NULL);
        u.lm = u.next++;
    }
    if (HAS_SHADOW) {
        unit_modulate(u.next, GL_TEXTURE_2D, tex_shadow, GL_TEXTURE,
                      u.lm < 0 ? GL_PRIMARY_COLOR : GL_PREVIOUS, NULL);
        /* r' = r - bias q: lit where r/q - bias <= stored. */
        glMatrixMode(GL_TEXTURE);
        glLoadIdentity();
        glTranslatef(0.0f, 0.0f, -SHADOW_BIAS);
        glMatrixMode(GL_MODELVIEW);
        u.sm = u.next++;
    }
    if (u.lm >= 0 || u.sm >= 0) {
        unit_modulate(u.next, GL_TEXTURE_1D, tex_step, GL_TEXTURE, GL_PREVIOUS, NULL);
        u.q = u.next++;
    }
    return u;
}

/* A vertex's light coordinates (s, t, r, q) on the H*I_l units: projective for the
 * light map and the shadow map (the compare reads r/q), the step reads q. */
static void light_coords(struct hil_units u, const float *strq)
{
    if (u.lm >= 0)
        glMultiTexCoord4f(GL_TEXTURE0 + u.lm, strq[0], strq[1], strq[2], strq[3]);
    if (u.sm >= 0)
        glMultiTexCoord4f(GL_TEXTURE0 + u.sm, strq[0], strq[1], strq[2], strq[3]);
    if (u.q >= 0)
        glMultiTexCoord1f(GL_TEXTURE0 + u.q, 0.5f + Q_STEP * strq[3]);
}

/* Depth-test against the camera's depth buffer (when the scene has objects), no depth
 * writes, colour written. */
static void depth_tested(void)
{
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_FALSE);
    if (HAS_DEPTH) {
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
}

/* Depth only: the depth pass and the shadow-map pass (keep the nearer). */
static void depth_only(void)
{
    units_off();
    additive(0);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
}

/* The texture units a plane's draw feeds coordinates to (-1: none): the J texture,
 * the H*I_l units, the stage texture, F and h. */
struct plane_units {
    int j, stage, f, h;
    struct hil_units hil;
};

static struct plane_units no_plane_units(void)
{
    struct plane_units pu = {-1, -1, -1, -1, {-1, -1, -1, 0}};
    return pu;
}

/* The stage texture (the previous modulate's 8-bit result) on unit 0, passed on. */
static struct plane_units stage_units(void)
{
    struct plane_units pu = no_plane_units();
    units_off();
    unit_replace(0, GL_TEXTURE_2D, tex_stage);
    pu.stage = 0;
    return pu;
}

/* A plane's COLS x ROWS mesh, each vertex with the plane scale S as its colour and its
 * coordinates on the units `pu` names. */
static void draw_plane(const float *p, struct plane_units pu)
{
    int k, l, c;
    glBegin(GL_QUADS);
    for (l = 0; l < ROWS; l++)
        for (k = 0; k < COLS; k++)
            for (c = 0; c < 4; c++) {
                /* The cell's corners (k, l), (k+1, l), (k+1, l+1), (k, l+1). */
                int kk = k + (c == 1 || c == 2), ll = l + (c >= 2);
                const float *a = p + 1 + ((size_t)ll * (COLS + 1) + kk) * PLANE_FLOATS;
                GLfloat scale = a[5] > 1.0f ? 1.0f : a[5];
                glColor3f(scale, scale, scale);
                if (pu.j >= 0)
                    glMultiTexCoord2f(GL_TEXTURE0 + pu.j, a[0] / J_TEX_W, a[1] / J_TEX_H);
                if (pu.stage >= 0)
                    glMultiTexCoord2f(GL_TEXTURE0 + pu.stage, a[0] / J_TEX_W, a[1] / J_TEX_H);
                light_coords(pu.hil, a + 6);
                if (pu.f >= 0)
                    glMultiTexCoord1f(GL_TEXTURE0 + pu.f, a[2] / NF);
                if (pu.h >= 0)
                    glMultiTexCoord2f(GL_TEXTURE0 + pu.h, a[3] / HW, a[4] / HH);
                glVertex3f(a[0], a[1], p[0]);
            }
    glEnd();
}

/* One modulate of a plane into the stage region (every pixel of the mesh: no depth
 * test, no blend), copied into the stage texture: the 8-bit register between two
 * modulates. */
static void stage_draw(const float *p, struct plane_units pu)
{
    region(0, STAGE_Y, W, H);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_FALSE);
    glDisable(GL_DEPTH_TEST);
    additive(0);
    draw_plane(p, pu);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex_stage);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, STAGE_Y, W, H);
}

static void draw_triangles_xyz(const float *v, size_t vertices)
{
    size_t i;
    glBegin(GL_TRIANGLES);
    for (i = 0; i < vertices; i++)
        glVertex3f(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    glEnd();
}

"#;

fn depth_pass(s: &mut String, c: &Ctx, j_buffer: bool) {
    let n = c.data.depth;
    let _ = writeln!(
        s,
        "/* Pass: depth. Every object triangle into the camera's depth buffer (keep the\n * nearer; the model's is 24 bits too). Every later pass depth-tests against it. */\nstatic void pass_depth(void)\n{{\n    const float *v = load_floats(\"depth.f32\", {n} * 3);\n    depth_only();\n    region(0, 0, W, H);\n    draw_triangles_xyz(v, {n});"
    );
    if j_buffer {
        let _ = writeln!(
            s,
            "    /* The J buffer's region gets the same depth: the sub-planes are depth-tested too. */\n    region(0, J_Y, W, H);\n    draw_triangles_xyz(v, {n});"
        );
    }
    let _ = writeln!(s, "    free((void *)v);\n}}\n");
}

fn shadow_pass(s: &mut String, c: &Ctx, light: usize) {
    let n = DataSizes::of_light(&c.data.shadow, light);
    let _ = writeln!(
        s,
        "/* Pass: shadow map of light {light}. The occluders seen from the light's square\n * frustum into a depth buffer region, copied into the depth texture (ARB_depth_texture)\n * that the later passes compare against (ARB_shadow). */\nstatic void pass_shadow_map_{light}(void)\n{{\n    const float *v = load_floats(\"shadow_{light}.f32\", {n} * 3);\n    depth_only();\n    region(SHADOW_X, 0, SHADOW_RES, SHADOW_RES);\n    glClear(GL_DEPTH_BUFFER_BIT);\n    draw_triangles_xyz(v, {n});\n    glActiveTexture(GL_TEXTURE0);\n    glBindTexture(GL_TEXTURE_2D, tex_shadow);\n    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, SHADOW_X, 0, SHADOW_RES, SHADOW_RES);\n    free((void *)v);\n}}\n"
    );
}

fn objects_pass(s: &mut String, c: &Ctx, light: usize) {
    let n = DataSizes::of_light(&c.data.objects, light);
    let _ = writeln!(
        s,
        "/* Pass: the objects lit by light {light}. Per-vertex colour (albedo x Lambert x I/s^2 x\n * exp(-rho kappa (s + T)), Gouraud) x light map (projective) x shadow compare, added\n * into the framebuffer where the depth test passes. */\nstatic void pass_objects_{light}(void)\n{{\n    const float *v = load_floats(\"objects_{light}.f32\", (size_t){n} * OBJ_FLOATS);\n    struct hil_units u;\n    size_t i;\n    units_off();\n    region(0, 0, W, H);\n    depth_tested();\n    additive(1);\n    u = hil_units({light}, 0);\n    glBegin(GL_TRIANGLES);\n    for (i = 0; i < {n}; i++) {{\n        const float *a = v + i * OBJ_FLOATS;\n        glColor3f(a[3], a[4], a[5]);\n        light_coords(u, a + 6);\n        glVertex3f(a[0], a[1], a[2]);\n    }}\n    glEnd();\n    free((void *)v);\n}}\n"
    );
}

fn planes_pass(s: &mut String, c: &Ctx, light: usize) {
    let cfg = c.p.scene.shafts;
    let m = cfg.subplanes;
    if m > 1 {
        let _ = writeln!(
            s,
            "/* Interval i's m sub-planes of light {light} into the J buffer: each a full-screen\n * quad whose fragments take H*I_l x its weight, added (depth-tested) into the cleared\n * J region; then the region copied into the J texture (glCopyTexSubImage2D). */\nstatic void j_buffer_{light}(const float *sub, int i)\n{{\n    struct hil_units u;\n    int j, k;\n    units_off();\n    region(0, J_Y, W, H);\n    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);\n    glClear(GL_COLOR_BUFFER_BIT);\n    depth_tested();\n    additive(1);\n    u = hil_units({light}, 0);\n    for (j = 0; j < SUBPLANES; j++) {{\n        const float *p = sub + ((size_t)i * SUBPLANES + j) * SUB_STRIDE;\n        glColor3ub(subplane_weight[j], subplane_weight[j], subplane_weight[j]);\n        glBegin(GL_QUADS);\n        for (k = 0; k < 4; k++) {{\n            const float *a = p + 1 + k * SUB_FLOATS;\n            light_coords(u, a + 2);\n            glVertex3f(a[0], a[1], p[0]);\n        }}\n        glEnd();\n    }}\n    units_off();\n    glBindTexture(GL_TEXTURE_2D, tex_j);\n    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, J_Y, W, H);\n}}\n"
        );
    }
    let j_doc = if m > 1 {
        "J from the J texture at the pixel centre (nearest) x S"
    } else {
        "J = H*I_l on the plane itself (light map x shadow compare) x S"
    };
    let _ = writeln!(
        s,
        "/* Pass: the sample planes of light {light}: n planes parallel to the screen, back to\n * front in the model's order, each a COLS x ROWS mesh whose vertices carry alpha, (s, t),\n * the plane scale S t/r and the light coordinates. Per fragment, one modulate at a\n * time, largest factors first (docs/shafts.md): {j_doc}, x F(alpha), x the light\n * colour, x h(s, t); added into the framebuffer (glBlendFunc(GL_ONE, GL_ONE)). Each\n * modulate rounds to 8 bits, as the model's: it is drawn on its own into the stage\n * region and copied into the stage texture, which the next one reads (a chain of\n * combine stages in one draw may round once at its end: llvmpipe does). */\nstatic void pass_planes_{light}(void)\n{{\n    const float *planes = load_floats(\"planes_{light}.f32\", (size_t)PLANES * PLANE_STRIDE);"
    );
    if m > 1 {
        let _ = writeln!(
            s,
            "    const float *sub = load_floats(\"subplanes_{light}.f32\", (size_t)PLANES * SUBPLANES * SUB_STRIDE);"
        );
    }
    let _ = writeln!(
        s,
        "    int i;\n    for (i = 0; i < PLANES; i++) {{\n        const float *p = planes + (size_t)i * PLANE_STRIDE;\n        struct plane_units pu = no_plane_units();"
    );
    if m > 1 {
        let _ = writeln!(
            s,
            "        j_buffer_{light}(sub, i);\n        /* J x S */\n        units_off();\n        unit_modulate(0, GL_TEXTURE_2D, tex_j, GL_TEXTURE, GL_PRIMARY_COLOR, NULL);\n        pu.j = 0;"
        );
    } else {
        let _ = writeln!(
            s,
            "        /* J x S */\n        units_off();\n        pu.hil = hil_units({light}, 0);"
        );
    }
    let _ = writeln!(
        s,
        "        stage_draw(p, pu);\n        /* x F */\n        pu = stage_units();\n        pu.f = 1;\n        unit_modulate(1, GL_TEXTURE_1D, tex_f, GL_TEXTURE, GL_PREVIOUS, NULL);\n        stage_draw(p, pu);\n        /* x colour (a white light's 255 codes change nothing) */\n        if (!light_colour_white[{light}]) {{\n            pu = stage_units();\n            unit_modulate(0, GL_TEXTURE_2D, tex_stage, GL_TEXTURE, GL_CONSTANT, light_colour[{light}]);\n            stage_draw(p, pu);\n        }}\n        /* x h, added into the framebuffer where the depth test passes */\n        pu = stage_units();\n        pu.h = 1;\n        unit_modulate(1, GL_TEXTURE_2D, tex_h, GL_TEXTURE, GL_PREVIOUS, NULL);\n        region(0, 0, W, H);\n        depth_tested();\n        additive(1);\n        draw_plane(p, pu);\n    }}\n    units_off();\n    free((void *)planes);"
    );
    if m > 1 {
        let _ = writeln!(s, "    free((void *)sub);");
    }
    let _ = writeln!(s, "}}\n");
}
