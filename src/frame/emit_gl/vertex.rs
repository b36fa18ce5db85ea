//! `render --scene shading-vertex --emit-gl DIR`: the vertex-lighting sphere as an
//! OpenGL program. The model lights the vertices of a tessellated sphere (the
//! `vertex_lighting` unit, GL 1.x's lighting equation in a float format) and has no
//! image; so the program lights the same vertices with GL's fixed-function lighting
//! (the same light, material and light model), reads the lit colours back in feedback
//! mode, and draws vertex (ring i, segment j) as pixel (j, i): a rings × segments
//! picture of vertex colours, beside the model's own (`model.png`, the unit's codes in
//! the same layout).

use super::source::{main_text, PRELUDE};
use super::Program;
use crate::pipeline::shading::scene_file::ShadingFile;
use crate::pipeline::shading::sweep::{VERTEX_RINGS, VERTEX_SEGMENTS};
use crate::pipeline::shading::vertex_float::{light_codes, one_light, sphere_vertices};
use crate::report::image_out::Framebuffer;
use rtl_model::lighting_state::LightingSetup;
use std::fmt::Write as _;

/// The vertex sphere's program and the model's picture of its vertex colours.
pub struct VertexProgram {
    pub program: Program,
    pub model: Framebuffer,
    /// The unit built and lighting every vertex, wall seconds.
    pub model_seconds: f64,
}

impl VertexProgram {
    /// Write the program's files into `dir` (created), with the model's vertex colours
    /// as model.png.
    pub fn write(&self, dir: &std::path::Path) -> Result<(), String> {
        super::write_files(&self.program, dir, |path| {
            self.model.save_png(path).map_err(|e| e.to_string())
        })
    }
}

/// The program of `shading-vertex` at the file's widths (refused, naming why, for the
/// NV2A preset's light-control modes or colours other than 8 bits).
pub fn vertex_program(f: &ShadingFile) -> Result<VertexProgram, String> {
    let Some(cfg) = f.point.vertex_config() else {
        return Err("--emit-gl: not the vertex-lighting sphere".into());
    };
    if cfg.light_control.is_some() {
        return Err(
            "--emit-gl: the NV2A preset's light-control modes are not exported (chip = \"geforce2\" is)"
                .into(),
        );
    }
    if cfg.color_bits != 8 {
        return Err(format!(
            "--emit-gl: the vertex colours are {} bits; the GL program's framebuffer is 8-bit",
            cfg.color_bits
        ));
    }
    let setup = one_light();
    let verts = sphere_vertices(VERTEX_RINGS, VERTEX_SEGMENTS);
    let t0 = std::time::Instant::now();
    let (_, codes, _) = light_codes(cfg, &setup, &verts).map_err(|e| format!("--emit-gl: {e}"))?;
    let mut model = Framebuffer::new(VERTEX_SEGMENTS, VERTEX_RINGS, 8);
    for (i, c) in codes.iter().enumerate() {
        let (x, y) = (i as u32 % VERTEX_SEGMENTS, i as u32 / VERTEX_SEGMENTS);
        model.set(x, y, [c[0], c[1], c[2], 255]);
    }
    let model_seconds = t0.elapsed().as_secs_f64();
    let floats: Vec<f32> = verts
        .iter()
        .flat_map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]].map(|v| v as f32))
        .collect();
    let source = scene_c(&setup, cfg.normalize, cfg.local_viewer, verts.len());
    Ok(VertexProgram {
        program: Program {
            files: vec![
                ("scene.c".into(), source.into_bytes()),
                ("build.sh".into(), super::build_script().into_bytes()),
                ("vertices.f32".into(), super::f32_bytes(&floats)),
            ],
        },
        model,
        model_seconds,
    })
}

/// A C float array's initialiser.
fn floats(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{:?}f", *x as f32)).collect();
    format!("{{{}}}", parts.join(", "))
}

fn scene_c(setup: &LightingSetup, normalize: bool, local_viewer: bool, count: usize) -> String {
    let m = &setup.material;
    let rgba = |c: [f64; 3]| floats(&[c[0], c[1], c[2], 1.0]);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "/* scene.c — `shading-vertex` as an OpenGL program.\n *\n * Written by `glare-pipeline render --emit-gl`. The model lights the vertices of a\n * {rings} x {segs} sphere in its vertex_lighting unit (GL 1.x's lighting equation) and has\n * no image: this program lights the same vertices with GL's fixed-function lighting\n * (the same light, material and light model), reads the lit colours back in feedback\n * mode and draws vertex (ring i, segment j) as pixel (j, i), so framebuffer.png\n * ({segs} x {rings}) holds GL's vertex colours and model.png the unit's, in the same\n * layout. Offscreen on OSMesa.\n *\n * Build: sh build.sh   Run: GALLIUM_DRIVER=llvmpipe ./scene [out.png]\n * On softpipe: GALLIUM_DRIVER=softpipe DRAW_USE_LLVM=0 ./scene (Mesa 22.3's LLVM\n * vertex path crashed compiling this program's feedback draw there).\n *\n * Data files:\n *   vertices.f32  {count} vertices x 6 float32: the eye-space position, the normal\n */\n{prelude}\n/* ---------------------------------------------------------------------------------\n * The scene.\n * ------------------------------------------------------------------------------- */\n\n#define W {segs}\n#define H {rings}\n#define BUF_W W\n#define BUF_H H\n#define VERTICES {count}\n#define NORMALIZE {normalize}\n#define LOCAL_VIEWER {local}\nstatic const GLfloat MATERIAL_EMISSION[4] = {emission};\nstatic const GLfloat MATERIAL_AMBIENT[4] = {m_ambient};\nstatic const GLfloat MATERIAL_DIFFUSE[4] = {m_diffuse};\nstatic const GLfloat MATERIAL_SPECULAR[4] = {m_specular};\n#define MATERIAL_SHININESS {shininess:?}f\nstatic const GLfloat SCENE_AMBIENT[4] = {scene_ambient};",
        rings = VERTEX_RINGS,
        segs = VERTEX_SEGMENTS,
        count = count,
        prelude = PRELUDE,
        normalize = u8::from(normalize),
        local = u8::from(local_viewer),
        emission = rgba(m.emission),
        m_ambient = rgba(m.ambient),
        m_diffuse = floats(&m.diffuse),
        m_specular = rgba(m.specular),
        shininess = m.shininess as f32,
        scene_ambient = rgba(setup.scene_ambient),
    );
    let _ = writeln!(
        s,
        "#define LIGHTS {}\n/* Per light: position (4), ambient (4), diffuse (4), specular (4), spot direction\n * (3), spot exponent, spot cutoff, attenuation (3). */",
        setup.lights.len()
    );
    let _ = writeln!(s, "static const GLfloat LIGHT_PARAMS[LIGHTS + 1][24] = {{");
    for l in &setup.lights {
        let mut v: Vec<f64> = l.position.to_vec();
        v.extend(l.ambient);
        v.push(1.0);
        v.extend(l.diffuse);
        v.push(1.0);
        v.extend(l.specular);
        v.push(1.0);
        v.extend(l.spot_direction);
        v.extend([l.spot_exponent, l.spot_cutoff]);
        v.extend(l.attenuation);
        let _ = writeln!(s, "    {},", floats(&v));
    }
    let _ = writeln!(s, "    {{0}}}};");
    s.push_str(VERTEX_C);
    main_text(&mut s, &[], 1, &["pass_vertex_lighting".to_string()]);
    s
}

/// The lighting state, the feedback pass and the drawing of the colours.
const VERTEX_C: &str = r#"
/* No textures. */
static void load_textures(void)
{
}

/* GL's lighting state: the material, the light model, the lights (eye space: the
 * modelview is the identity when they are set). */
static void lighting_state(void)
{
    int i;
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glEnable(GL_LIGHTING);
    glMaterialfv(GL_FRONT_AND_BACK, GL_EMISSION, MATERIAL_EMISSION);
    glMaterialfv(GL_FRONT_AND_BACK, GL_AMBIENT, MATERIAL_AMBIENT);
    glMaterialfv(GL_FRONT_AND_BACK, GL_DIFFUSE, MATERIAL_DIFFUSE);
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, MATERIAL_SPECULAR);
    glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, MATERIAL_SHININESS);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, SCENE_AMBIENT);
    glLightModeli(GL_LIGHT_MODEL_LOCAL_VIEWER, LOCAL_VIEWER);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, 0);
    if (NORMALIZE)
        glEnable(GL_NORMALIZE);
    for (i = 0; i < LIGHTS; i++) {
        const GLfloat *p = LIGHT_PARAMS[i];
        GLenum l = GL_LIGHT0 + i;
        glEnable(l);
        glLightfv(l, GL_POSITION, p);
        glLightfv(l, GL_AMBIENT, p + 4);
        glLightfv(l, GL_DIFFUSE, p + 8);
        glLightfv(l, GL_SPECULAR, p + 12);
        glLightfv(l, GL_SPOT_DIRECTION, p + 16);
        glLightf(l, GL_SPOT_EXPONENT, p[19]);
        glLightf(l, GL_SPOT_CUTOFF, p[20]);
        glLightf(l, GL_CONSTANT_ATTENUATION, p[21]);
        glLightf(l, GL_LINEAR_ATTENUATION, p[22]);
        glLightf(l, GL_QUADRATIC_ATTENUATION, p[23]);
    }
}

/* Pass: light every vertex (feedback mode: GL returns each point's lit colour; the
 * projection holds the whole sphere, so no point is clipped), then draw vertex
 * (ring i, segment j) as pixel (j, i) in its colour. */
static void pass_vertex_lighting(void)
{
    const float *v = load_floats("vertices.f32", (size_t)VERTICES * 6);
    GLint size = VERTICES * 8 + 16, n;
    GLfloat *fb = malloc(sizeof(GLfloat) * (size_t)size);
    int i, k = 0;
    lighting_state();
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(-4.0, 4.0, -4.0, 4.0, 0.0, 16.0);
    glMatrixMode(GL_MODELVIEW);
    glFeedbackBuffer(size, GL_3D_COLOR, fb);
    glRenderMode(GL_FEEDBACK);
    glBegin(GL_POINTS);
    for (i = 0; i < VERTICES; i++) {
        glNormal3f(v[6 * i + 3], v[6 * i + 4], v[6 * i + 5]);
        glVertex3f(v[6 * i], v[6 * i + 1], v[6 * i + 2]);
    }
    glEnd();
    n = glRenderMode(GL_RENDER);
    if (n != VERTICES * 8)
        die("feedback: not one lit point per vertex");
    glDisable(GL_LIGHTING);
    glDisable(GL_NORMALIZE);
    region(0, 0, W, H);
    glBegin(GL_POINTS);
    for (i = 0; i < VERTICES; i++, k += 8) {
        if (fb[k] != GL_POINT_TOKEN)
            die("feedback: a token other than a point");
        glColor4f(fb[k + 4], fb[k + 5], fb[k + 6], 1.0f);
        glVertex2f((float)(i % W) + 0.5f, (float)(i / W) + 0.5f);
    }
    glEnd();
    free(fb);
    free((void *)v);
}
"#;
