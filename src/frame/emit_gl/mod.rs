//! `render --scene S --emit-gl DIR`: the scene's pass plan as a self-contained C
//! program on OpenGL 1.3 (ARB_depth_texture, ARB_shadow, ARB_texture_env_combine;
//! nothing vendor-specific) that draws what the model draws — the same vertices as the
//! host hands the model's interpolator, the same texture contents (the F and h tables,
//! the light maps, written as raw files beside it) and filters, the same modulates in
//! the same order, the same additive blend — renders offscreen on OSMesa and writes
//! `framebuffer.png`; beside it the model's own `model.png` of the same scene at the
//! same size.
//!
//! A host piece beside the frame: it reads the shafts pipeline's prepared data and
//! tables through their public functions and recomputes the host's vertex attributes
//! as the pipeline's host does (f64), never touching a unit. Passes with no GL 1.3
//! form (the glare ASIC; the shading units, which are register combiners) are listed
//! as not exported with the reason; a scene with none exportable is refused before any
//! work. The shading spheres whose path is GL 1.3's texture combine ([`sphere`]) and
//! the foundation test scene ([`test_scene`]) have their own programs.

pub mod command;
mod data;
mod source;
pub mod sphere;
pub mod test_scene;
pub mod vertex;

use data::LightData;
pub use data::{subplane_weight, Export, OBJ_FLOATS, PLANE_FLOATS, SUB_FLOATS};

use crate::frame::plan::{plan, Pass, Step};
use crate::pipeline::shafts::frame::{passes as shafts_passes, Prepared, ShaftsPass};
use crate::pipeline::shafts::tables::{unorm_from_unit, GTables};
use crate::pipeline::shafts::view::{vec3, CameraView, LightView};
use crate::scene::format::{PlaneStep, Scene};
use crate::scene::math::Vec3;
use std::path::Path;

/// Why a planned pass of `scene` is not exported (`None`: it is).
pub fn not_exportable(scene: &Scene, pass: &Pass) -> Option<String> {
    match pass.step {
        Step::Shafts(_) => None,
        Step::Glare => Some(
            "the glare pass runs on the glare ASIC (highlight detection, glare conditions, \
             bloom, halo and flare generators): no OpenGL form"
                .into(),
        ),
        Step::ShadedObjects | Step::ShadedHighlights => Some(shading_units_reason(scene)),
        Step::EnvironmentScene => Some(
            "the environment-map pass forms each pixel's reflection vector from the \
             interpolated normal and eye vector (the reflection_vector unit, GeForce3's \
             texture-shader stage, NV_texture_shader); OpenGL 1.3 has no per-pixel \
             reflection (its reflection texgen is per vertex): no OpenGL 1.3 form"
                .into(),
        ),
        Step::TestScene => Some(
            "the foundation test scene has its own program (`render --scene test --emit-gl`)"
                .into(),
        ),
    }
}

/// Why a frame's shading-units pass is not exported: a Phong or Blinn–Phong lobe
/// reads the specular lookup at the DOT3's n·h, a dependent texture read; the other
/// materials' units have an OpenGL 1.3 form (the shading spheres' programs), not
/// written for a frame's objects.
fn shading_units_reason(scene: &Scene) -> String {
    let lookup = scene
        .objects
        .iter()
        .filter_map(|o| o.material.as_ref())
        .any(|m| crate::pipeline::shading::materials::lobe_kind(m) == "lookup");
    if lookup {
        "a Phong or Blinn–Phong lobe reads the specular lookup at the DOT3's n·h (a dependent \
         texture read, NV_texture_shader): no OpenGL 1.3 form"
            .into()
    } else {
        "the shading units' OpenGL 1.3 form (normalisation cube map, DOT3, factor textures) \
         is written for the shading spheres (`shading-*`), not for a frame's objects: not \
         exported"
            .into()
    }
}

/// The limits a shafts scene must meet for the GL program: 8-bit textures, blend
/// weights and framebuffer (what GL 1.3 offers), power-of-two texture sides, and
/// objects that stay inside the camera's planes (the model's host then projects
/// them itself; through the clipper it would not). The first problem names the field.
fn check_shafts(scene: &Scene) -> Result<(), String> {
    let s = &scene.shafts;
    for (field, v) in [
        ("shafts.texel_bits", s.texel_bits),
        ("shafts.fb_bits", s.fb_bits),
        ("shafts.weight_bits", s.weight_bits),
    ] {
        if v != 8 {
            return Err(format!(
                "--emit-gl: {field} = {v}: the GL program draws 8-bit textures and an 8-bit framebuffer; set {field} = 8"
            ));
        }
    }
    for (field, v) in [
        ("shafts.f_texels", s.f_texels),
        ("shafts.h_texels[0]", s.h_texels[0]),
        ("shafts.h_texels[1]", s.h_texels[1]),
        ("shafts.light_map_texels", s.light_map_texels),
        ("shafts.shadow_resolution", s.shadow_resolution),
    ] {
        if !v.is_power_of_two() {
            return Err(format!(
                "--emit-gl: {field} = {v}: OpenGL 1.3 textures have power-of-two sides"
            ));
        }
    }
    if let Some(why) = crate::scene::clip::clip_needed(scene) {
        return Err(format!(
            "--emit-gl: the scene's objects need the clipper ({why}); the GL program draws the host's projected vertices and does not export clipped objects"
        ));
    }
    Ok(())
}

/// `--emit-gl`'s checks on a loaded scene at its final size (valid, a plan with at
/// least one exportable pass, GL 1.3's limits), before any work: every planned pass,
/// exported or not (with why).
pub fn check_exportable(scene: &Scene) -> Result<Vec<Export>, String> {
    scene
        .validate()
        .map_err(|e| format!("--emit-gl: scene: {e}"))?;
    let planned = plan(scene).map_err(|e| e.to_string())?;
    let exports: Vec<Export> = planned
        .passes
        .iter()
        .map(|p| match (p.step, not_exportable(scene, p)) {
            (Step::Shafts(sp), None) => Export::Shafts(sp),
            (_, why) => Export::NotExported {
                pass: p.name.clone(),
                why: why.unwrap_or_default(),
            },
        })
        .collect();
    if !exports.iter().any(|e| matches!(e, Export::Shafts(_))) {
        let list: Vec<String> = exports
            .iter()
            .map(|e| match e {
                Export::NotExported { pass, why } => format!("  {pass}: {why}"),
                Export::Shafts(_) => unreachable!(),
            })
            .collect();
        return Err(format!(
            "--emit-gl: no pass of this scene has an OpenGL 1.3 form:\n{}",
            list.join("\n")
        ));
    }
    check_shafts(scene)?;
    Ok(exports)
}

/// The program (its files' names and bytes) of the scene `frame` rendered.
pub fn program_of(frame: &crate::frame::run::Frame, exports: &[Export]) -> Result<Program, String> {
    let (Some(prepared), Some(shafts)) = (frame.plan.prepared.as_ref(), frame.shafts.as_ref())
    else {
        return Err("--emit-gl: the frame ran no shafts pass".into());
    };
    Ok(build_program(prepared, &shafts.tables, exports))
}

/// Write the program of the scene `frame` rendered (its tables and prepared data)
/// into `dir` (created), with the frame's picture as model.png.
pub fn write_program(
    frame: &crate::frame::run::Frame,
    exports: &[Export],
    dir: &Path,
) -> Result<Program, String> {
    let program = program_of(frame, exports)?;
    write_files(&program, dir, |path| {
        frame.fb.save_png(path).map_err(|e| e.to_string())
    })?;
    Ok(program)
}

/// Write a program's files into `dir` (created) and the model's picture as
/// model.png (`model_png` writes it to the path it is given).
pub fn write_files(
    program: &Program,
    dir: &Path,
    model_png: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("emit-gl: {}: {e}", dir.display()))?;
    model_png(&dir.join("model.png")).map_err(|e| format!("emit-gl: model.png: {e}"))?;
    for (file, bytes) in &program.files {
        std::fs::write(dir.join(file), bytes)
            .map_err(|e| format!("emit-gl: {}: {e}", dir.join(file).display()))?;
    }
    Ok(())
}

/// The program's files: name and bytes (scene.c, build.sh and the data files).
pub struct Program {
    pub files: Vec<(String, Vec<u8>)>,
}

/// Little-endian float32 bytes.
fn f32_bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// The light's projection as the model's host builds it (`frame.rs`: near half the
/// nearest lit distance, far beyond everything the planes reach).
fn light_view(p: &Prepared, li: usize) -> LightView {
    let l = &p.scene.lights[li];
    LightView::new(l, (p.s_near * 0.5).max(0.05), (p.s_max * 1.5).max(1.0))
}

/// The light coordinates (s, t, r, q) the model's host gives a vertex (its
/// interpolator carries them scaled by 16; the scale cancels in s/q, t/q, r/q).
fn light_strq(lv: &LightView, p: Vec3) -> [f64; 4] {
    lv.strq(p).map(|v| v * 16.0)
}

/// Light colour codes and the intensity they leave (as the planes' host: normalised by
/// the largest component).
fn light_color(l: &crate::scene::format::Light) -> ([u32; 3], f64) {
    let m = l.color.iter().cloned().fold(0.0, f64::max);
    if m <= 0.0 {
        return ([0; 3], 0.0);
    }
    (l.color.map(|c| unorm_from_unit(c / m, 8)), l.intensity * m)
}

fn build_program(p: &Prepared, tables: &GTables, exports: &[Export]) -> Program {
    let sc = &p.scene;
    let cfg = sc.shafts;
    let cam = CameraView::new(&sc.camera, sc.image);
    let (w, h) = (sc.image.width, sc.image.height);
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    let has_objects = p.objects.iter().any(|o| !o.triangles.is_empty());
    let all_passes = shafts_passes(p);
    let exported: Vec<ShaftsPass> = exports
        .iter()
        .filter_map(|e| match e {
            Export::Shafts(s) => Some(*s),
            _ => None,
        })
        .collect();
    debug_assert!(exported.iter().all(|e| all_passes.contains(e)));
    // Tables.
    let bytes = |v: &[u32]| v.iter().map(|&x| x as u8).collect::<Vec<u8>>();
    let planes_used = exported
        .iter()
        .any(|e| matches!(e, ShaftsPass::Planes { .. }));
    if planes_used {
        files.push(("f_table.raw".into(), bytes(&tables.f_texels)));
        files.push(("h_table.raw".into(), bytes(&tables.h_texels)));
    }
    let lights: Vec<LightData> = sc
        .lights
        .iter()
        .enumerate()
        .map(|(li, l)| LightData {
            has_map: p.light_maps.get(li).is_some_and(|m| m.is_some()),
            color: light_color(l).0,
        })
        .collect();
    for (li, lm) in p.light_maps.iter().enumerate() {
        if let Some(t) = lm {
            files.push((format!("light_map_{li}.raw"), bytes(t)));
        }
    }
    let mut data = source::DataSizes::default();
    // Geometry per exported pass.
    for pass in &exported {
        match *pass {
            ShaftsPass::Depth => {
                let v = depth_vertices(p, &cam);
                data.depth = v.len() / 3;
                files.push(("depth.f32".into(), f32_bytes(&v)));
            }
            ShaftsPass::ShadowMap { light } => {
                let v = shadow_vertices(p, light);
                data.shadow.push((light, v.len() / 3));
                files.push((format!("shadow_{light}.f32"), f32_bytes(&v)));
            }
            ShaftsPass::Objects { light } => {
                let v = object_vertices(p, &cam, light);
                data.objects.push((light, v.len() / OBJ_FLOATS));
                files.push((format!("objects_{light}.f32"), f32_bytes(&v)));
            }
            ShaftsPass::Planes { light } => {
                let v = plane_vertices(p, &cam, tables, light);
                files.push((format!("planes_{light}.f32"), f32_bytes(&v)));
                if cfg.subplanes > 1 {
                    let s = subplane_vertices(p, &cam, light);
                    files.push((format!("subplanes_{light}.f32"), f32_bytes(&s)));
                }
            }
        }
    }
    let c = source::scene_c(&source::Ctx {
        p,
        tables,
        w,
        h,
        has_objects,
        exported: &exported,
        exports,
        lights: &lights,
        data: &data,
        files: &files,
    });
    let build = build_script();
    files.insert(0, ("build.sh".into(), build.into_bytes()));
    files.insert(0, ("scene.c".into(), c.into_bytes()));
    Program { files }
}

/// build.sh: the one build line, on OSMesa.
fn build_script() -> String {
    "#!/bin/sh\n# Build the scene's GL 1.3 program on OSMesa (offscreen; Mesa's llvmpipe in CI:\n# GALLIUM_DRIVER=llvmpipe ./scene). Needs a C compiler and libOSMesa\n# (Debian/Ubuntu: apt-get install libosmesa6-dev). With -DSCENE_GLUT and -lglut -lGL\n# instead of -lOSMesa it opens a GLUT window on any GL context.\nset -e\ncd \"$(dirname \"$0\")\"\ncc -O1 -o scene scene.c -lOSMesa -lm\n".to_string()
}

/// A world triangle on the screen as the model's host projects it (x, y pixels y
/// down, window depth), `None` when the model skips it (a vertex behind the eye or
/// far outside the guard band).
fn project(cam: &CameraView, tri: &[Vec3; 3]) -> Option<[(f64, f64, f64); 3]> {
    let mut out = [(0.0, 0.0, 0.0); 3];
    for k in 0..3 {
        let (x, y, z) = cam.project(tri[k])?;
        if x.abs() > 8000.0 || y.abs() > 8000.0 {
            return None;
        }
        out[k] = (x, y, z);
    }
    Some(out)
}

fn depth_vertices(p: &Prepared, cam: &CameraView) -> Vec<f32> {
    let mut v = Vec::new();
    for o in &p.objects {
        for (tri, _) in &o.triangles {
            if let Some(s) = project(cam, tri) {
                for (x, y, z) in s {
                    v.extend([x as f32, y as f32, z as f32]);
                }
            }
        }
    }
    v
}

fn shadow_vertices(p: &Prepared, li: usize) -> Vec<f32> {
    let lv = light_view(p, li);
    let res = p.scene.shafts.shadow_resolution as f64;
    let mut v = Vec::new();
    for o in p.objects.iter().filter(|o| o.occluder) {
        'tri: for (tri, _) in &o.triangles {
            let mut hv = [[0.0f64; 3]; 3];
            for k in 0..3 {
                let q = lv.strq(tri[k]);
                if q[3] <= 1e-9 {
                    continue 'tri;
                }
                hv[k] = [q[0] / q[3] * res, q[1] / q[3] * res, q[2] / q[3]];
            }
            if hv
                .iter()
                .any(|a| a[0].abs() > 4000.0 || a[1].abs() > 4000.0)
            {
                continue;
            }
            for a in hv {
                v.extend(a.map(|x| x as f32));
            }
        }
    }
    v
}

fn object_vertices(p: &Prepared, cam: &CameraView, li: usize) -> Vec<f32> {
    let lv = light_view(p, li);
    let light = &p.scene.lights[li];
    let medium = p.scene.medium;
    let mut v = Vec::new();
    for o in &p.objects {
        for (tri, nrm) in &o.triangles {
            let Some(s) = project(cam, tri) else {
                continue;
            };
            for k in 0..3 {
                let pt = tri[k];
                // albedo · max(0, N·L̂) · I / s² · exp(−ρκ(s + T)), as the model's host.
                let to_l = vec3(light.position) - pt;
                let s2 = to_l.dot(to_l).max(1e-12);
                let lambert = nrm[k].dot(to_l.normalized()).max(0.0);
                let tt = (pt - cam.eye).length();
                let atten = (-medium.rho * medium.kappa * (s2.sqrt() + tt)).exp();
                let scale = light.intensity * lambert * atten / s2 * p.exposure / 255.0;
                let la = light_strq(&lv, pt);
                let (x, y, z) = s[k];
                let col = |c: usize| (o.color[c] * scale * light.color[c]).min(1.0);
                v.extend(
                    [x, y, z, col(0), col(1), col(2), la[0], la[1], la[2], la[3]].map(|a| a as f32),
                );
            }
        }
    }
    v
}

/// Plane i's view depth and window depth, for each of the n planes.
fn plane_depths(p: &Prepared, cam: &CameraView) -> Vec<(f64, f64)> {
    let n = p.scene.shafts.planes as usize;
    let (r0, r1) = p.plane_range;
    let dr = (r1 - r0) / n as f64;
    let (w, h) = (cam.width as f64, cam.height as f64);
    (0..n)
        .map(|i| {
            let r = r0 + (i as f64 + 0.5) * dr;
            let z = cam
                .project(cam.point_at(w * 0.5, h * 0.5, r))
                .map_or(1.0, |v| v.2);
            (r, z)
        })
        .collect()
}

/// Per plane: its window depth, then its (cols + 1) × (rows + 1) mesh vertices, row by
/// row ([`PLANE_FLOATS`] each), as the model's host computes them.
fn plane_vertices(p: &Prepared, cam: &CameraView, tables: &GTables, li: usize) -> Vec<f32> {
    let sc = &p.scene;
    let cfg = sc.shafts;
    let lv = light_view(p, li);
    let light = &sc.lights[li];
    let (_, intensity) = light_color(light);
    let n = cfg.planes as usize;
    let dr = (p.plane_range.1 - p.plane_range.0) / n as f64;
    let s_plane = tables.f_max * tables.h_ref * intensity * dr * p.exposure / 255.0;
    let [cols, rows] = cfg.mesh;
    let (nf, hw, hh) = (
        cfg.f_texels as f64,
        cfg.h_texels[0] as f64,
        cfg.h_texels[1] as f64,
    );
    let lpos = vec3(light.position);
    let (w, h) = (sc.image.width as f64, sc.image.height as f64);
    let mut v = Vec::new();
    for (r, z) in plane_depths(p, cam) {
        v.push(z as f32);
        for l in 0..=rows {
            for k in 0..=cols {
                let (x, y) = (k as f64 * w / cols as f64, l as f64 * h / rows as f64);
                let pt = cam.point_at(x, y, r);
                let t = (pt - cam.eye).length();
                let to_l = lpos - pt;
                let s = to_l.length();
                let view = (pt - cam.eye).normalized();
                let cos_a = if s > 0.0 {
                    (to_l * (1.0 / s)).dot(view).clamp(-1.0, 1.0)
                } else {
                    1.0
                };
                let alpha = cos_a.acos();
                let la = light_strq(&lv, pt);
                let scale = match cfg.plane_step {
                    PlaneStep::AlongRay => s_plane * t / r,
                    PlaneStep::PlaneSpacing => s_plane,
                };
                v.extend(
                    [
                        x,
                        y,
                        alpha / std::f64::consts::PI * nf,
                        s / tables.s_max * hw,
                        t / tables.t_max * hh,
                        scale,
                        la[0],
                        la[1],
                        la[2],
                        la[3],
                    ]
                    .map(|a| a as f32),
                );
            }
        }
    }
    v
}

/// Per interval, per sub-plane: its window depth, then its four screen corners (0, 0),
/// (w, 0), (w, h), (0, h) with the light coordinates ([`SUB_FLOATS`] each).
fn subplane_vertices(p: &Prepared, cam: &CameraView, li: usize) -> Vec<f32> {
    let sc = &p.scene;
    let cfg = sc.shafts;
    let lv = light_view(p, li);
    let (n, m) = (cfg.planes as usize, cfg.subplanes as usize);
    let (r0, r1) = p.plane_range;
    let dr = (r1 - r0) / n as f64;
    let (w, h) = (sc.image.width as f64, sc.image.height as f64);
    let mut v = Vec::new();
    for i in 0..n {
        let r = r0 + (i as f64 + 0.5) * dr;
        for j in 0..m {
            let uj = r - dr / 2.0 + (j as f64 + 0.5) * dr / m as f64;
            let z = cam
                .project(cam.point_at(w * 0.5, h * 0.5, uj))
                .map_or(1.0, |c| c.2);
            v.push(z as f32);
            for (x, y) in [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)] {
                let la = light_strq(&lv, cam.point_at(x, y, uj));
                v.extend([x, y, la[0], la[1], la[2], la[3]].map(|a| a as f32));
            }
        }
    }
    v
}
