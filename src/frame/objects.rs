//! The object pass of the shading units (and environment reflections) inside a frame
//! the shafts pipeline draws: every pixel whose nearest object has a material is
//! shaded by that material's path ([`crate::pipeline::shading::scene_pass`]) once per
//! light, each light's result scaled by its irradiance there, the lights summed, a
//! reflector's environment reflection added, and the result written into the shafts
//! framebuffer before the lights' Lambert and sample-plane passes add to it.
//!
//! Widths: the shading path's output, the irradiance code and the sum are 8-bit unorm
//! (the `modulate` unit and `blend`'s additive datapath at 8 bits); the result is converted to
//! `shafts.fb_bits` (widened to 16 bits and narrowed, as the hardware copies it).
//!
//! Host work (f64, per fragment, as the application processor sets up vertex colours
//! in the shafts object pass): the irradiance scale k_l = I_l · exp(−ρκ(s + T)) / s² ·
//! exposure / 255 × the spot's light map there (clamped to 1; 0 outside a spot's
//! cone), the same factor the shafts object pass gives a Lambert vertex (whose cos θ_i
//! the shading path computes here). Shadows between objects are not cast in this pass
//! (as in the shading pipeline's scene pass). The glare conditions get, per object,
//! its brightest specular fragment *after* this scaling (an unlit sheen never counts).

use crate::chip::{PassKind, PassStats};
use crate::pipeline::shading::scene_pass::{
    highlight, shade_objects, FoundHighlight, SceneShading,
};
use crate::pipeline::shafts::frame::Prepared;
use crate::report::elaboration::Elaborated;
use crate::report::image_out::Framebuffer;
use crate::scene::camera::{vec3, CameraView};
use crate::scene::format::Scene;
use crate::scene::geometry::{Ray, SceneGeometry};
use crate::scene::lightmap::{light_weight, LightMapSampler};
use rtl_model::driver::run_span;
use rtl_model::units::blend::{Blend, BlendIn};
use rtl_model::units::modulate::{Modulate, ModulateIn, ModulateMode};
use rtl_model::{ConfigError, Counters};
use std::collections::BTreeMap;

/// An environment reflection drawn for some objects: 8-bit RGB per pixel where the
/// reflector covers it (the envmap pipeline's image of the reflecting objects).
pub struct Reflection {
    pub object: usize,
    pub pixels: Vec<Option<[u32; 3]>>,
    /// Its f64 reference in levels (when asked for: `reflection::reflections_with`).
    pub reference: Option<Vec<Option<[f64; 3]>>>,
    pub counters: BTreeMap<String, Counters>,
    pub stats: PassStats,
    pub elaboration: Vec<Elaborated>,
}

/// What the pass did.
pub struct ShadedObjects {
    /// Per pixel: the object the pass coloured there.
    pub objects: Vec<Option<usize>>,
    /// Per pixel: the pass's 8-bit result there (before the conversion to fb codes).
    pub levels: Vec<Option<[u32; 3]>>,
    /// Highlights of light `highlight_light`'s shading (for the glare conditions).
    pub highlights: Vec<FoundHighlight>,
    pub counters: BTreeMap<String, Counters>,
    pub elaboration: Vec<Elaborated>,
    /// One pass per light for the time model.
    pub stats: Vec<PassStats>,
    pub fragments: u64,
}

/// Shade the scene's material objects into `fb` (see the module notes). Highlights
/// are those of `highlight` = (light, I, radius) (`glare.shaded_highlights`), if any.
pub fn shaded_objects_pass(
    scene: &Scene,
    p: &Prepared,
    fb: &mut Framebuffer,
    highlight: Option<(usize, f64, f64)>,
    reflections: &[Reflection],
) -> Result<ShadedObjects, ConfigError> {
    let mut pass = ObjectsPass::new(scene, p)?;
    for li in 0..scene.lights.len() {
        pass.light(li, highlight)?;
    }
    for r in reflections {
        pass.reflection(r);
    }
    Ok(pass.finish(fb))
}

/// The pass as it runs: its units, the camera, and per pixel the 8-bit sum, the
/// object coloured and the eye distance.
struct ObjectsPass<'a> {
    scene: &'a Scene,
    p: &'a Prepared,
    modulate: Modulate,
    blend: Blend,
    cam: CameraView,
    geometry: SceneGeometry,
    counters: BTreeMap<String, Counters>,
    sum: Vec<Option<[u32; 3]>>,
    objects: Vec<Option<usize>>,
    eye_t: Vec<Option<f64>>,
    highlights: Vec<FoundHighlight>,
    elaboration: Vec<Elaborated>,
    stats: Vec<PassStats>,
    fragments: u64,
}

/// One light's fragments: their pixels, the (level, irradiance code) pairs of their
/// channels, and the highlight light's (pixel, specular × grey) pairs.
type LightFragments = (Vec<usize>, Vec<ModulateIn>, Vec<(usize, ModulateIn)>);

impl<'a> ObjectsPass<'a> {
    fn new(scene: &'a Scene, p: &'a Prepared) -> Result<Self, ConfigError> {
        let n = (scene.image.width * scene.image.height) as usize;
        Ok(ObjectsPass {
            scene,
            p,
            modulate: Modulate::new(8, ModulateMode::Exact)?,
            blend: Blend::additive(8, 8, false, 8)?,
            cam: CameraView::new(&scene.camera, scene.image),
            geometry: SceneGeometry::without_meshes(&scene.objects)?,
            counters: BTreeMap::new(),
            sum: vec![None; n],
            objects: vec![None; n],
            eye_t: vec![None; n],
            highlights: Vec::new(),
            elaboration: Vec::new(),
            stats: Vec::new(),
            fragments: 0,
        })
    }

    /// Light `li`: the objects shaded, scaled by its irradiance and added to the sum
    /// (and, for the highlight light, its brightest specular fragments found).
    fn light(
        &mut self,
        li: usize,
        highlight: Option<(usize, f64, f64)>,
    ) -> Result<(), ConfigError> {
        let scene = self.scene;
        let light = &scene.lights[li];
        let (intensity, radius) = match highlight {
            Some((l, i, r)) if l == li => (i, r),
            _ => (1.0, 0.03),
        };
        // The shading units shade the objects with a material; a reflector without one
        // shows its reflection alone.
        let selected = |i: usize| scene.objects.get(i).is_some_and(|o| o.material.is_some());
        let sh = shade_objects(scene, li, intensity, radius, &selected)?;
        let finds_highlights = highlight.is_some_and(|(l, _, _)| l == li);
        if li == 0 {
            self.elaboration = sh.elaboration.clone();
        }
        for (k, c) in &sh.counters {
            *self.counters.entry(format!("light {li}: {k}")).or_default() += *c;
        }
        let (at, pairs, spec_pairs) = self.fragments_of(li, &sh, finds_highlights)?;
        if finds_highlights {
            self.highlights = brightest(
                scene,
                &self.modulate,
                &spec_pairs,
                &sh.objects,
                &self.cam,
                &self.geometry,
                vec3(light.position),
                intensity,
                radius,
                &mut self.counters,
            );
        }
        self.accumulate(&at, &pairs);
        self.fragments += sh.fragments;
        self.stats.push(shading_stats(li, sh.fragments));
        Ok(())
    }

    /// Per fragment of light `li`'s shading: the shaded levels × the light's irradiance
    /// code there (and the specular level × its grey code, for the highlight light).
    fn fragments_of(
        &mut self,
        li: usize,
        sh: &SceneShading,
        finds_highlights: bool,
    ) -> Result<LightFragments, ConfigError> {
        let (scene, cam, w) = (self.scene, &self.cam, self.scene.image.width);
        let light = &scene.lights[li];
        let map = LightMapSampler::for_light(light, li)?;
        let lpos = vec3(light.position);
        let mut at = Vec::new();
        let mut pairs = Vec::new();
        let mut spec_pairs = Vec::new();
        for (i, px) in sh.pixels.iter().enumerate() {
            let Some(rgb) = px else { continue };
            self.objects[i] = sh.objects[i];
            let (x, y) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
            let dir = cam.ray_dir(x, y);
            // The eye distance, ray-cast once per pixel whatever the number of lights.
            let geometry = &self.geometry;
            let t = *self.eye_t[i].get_or_insert_with(|| {
                geometry
                    .first_hit(
                        &Ray {
                            origin: cam.eye,
                            dir,
                        },
                        cam.far,
                    )
                    .map_or(0.0, |(_, hit)| hit.t)
            });
            let point = cam.eye + dir * t;
            let (k, grey) = irradiance_code(scene, self.p, light, &map, lpos, point, t);
            if finds_highlights && sh.speculars[i] > 0 {
                spec_pairs.push((
                    i,
                    ModulateIn {
                        a: sh.speculars[i],
                        b: grey,
                    },
                ));
            }
            at.push(i);
            for c in 0..3 {
                pairs.push(ModulateIn { a: rgb[c], b: k[c] });
            }
        }
        Ok((at, pairs, spec_pairs))
    }

    /// The fragments at `at` modulated by their irradiance codes and added to the sum.
    fn accumulate(&mut self, at: &[usize], pairs: &[ModulateIn]) {
        let mut c = Counters::default();
        let lit = run_span(&self.modulate, &mut (), pairs, &mut c);
        *self
            .counters
            .entry("modulate (shaded objects)".into())
            .or_default() += c;
        let ins: Vec<BlendIn> = at
            .iter()
            .zip(lit.chunks(3))
            .map(|(&i, l)| {
                let d = self.sum[i].unwrap_or([0; 3]);
                BlendIn {
                    src: [l[0], l[1], l[2], 0],
                    dst: [d[0], d[1], d[2], 0],
                }
            })
            .collect();
        let mut c = Counters::default();
        let out = run_span(&self.blend, &mut (), &ins, &mut c);
        *self
            .counters
            .entry("additive_blend (shaded objects)".into())
            .or_default() += c;
        for (&i, o) in at.iter().zip(out) {
            self.sum[i] = Some([o[0], o[1], o[2]]);
        }
    }

    /// A reflector's environment reflection added where it is the nearest object.
    fn reflection(&mut self, r: &Reflection) {
        let (cam, w) = (&self.cam, self.scene.image.width);
        for (i, o) in self.objects.iter_mut().enumerate() {
            if o.is_none() && r.pixels[i].is_some() {
                let (x, y) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
                let ray = Ray {
                    origin: cam.eye,
                    dir: cam.ray_dir(x, y),
                };
                if self
                    .geometry
                    .first_hit(&ray, cam.far)
                    .is_some_and(|(k, _)| k == r.object)
                {
                    *o = Some(r.object);
                }
            }
        }
        add_reflection(
            r,
            &self.blend,
            &mut self.sum,
            &self.objects,
            &mut self.counters,
        );
        for (k, c) in &r.counters {
            *self.counters.entry(k.clone()).or_default() += *c;
        }
        self.stats.push(r.stats.clone());
        self.elaboration.extend(r.elaboration.iter().cloned());
    }

    /// The sum written into `fb` (8-bit levels widened to 16 bits and narrowed to the
    /// framebuffer's width, as the hardware copies it).
    fn finish(self, fb: &mut Framebuffer) -> ShadedObjects {
        let w = self.scene.image.width;
        for (i, s) in self.sum.iter().enumerate() {
            if let Some(rgb) = s {
                let q = rgb.map(|v| {
                    rtl_model::unorm::narrow(rtl_model::unorm::widen(v, 8, 16), 16, fb.bits)
                });
                fb.set(i as u32 % w, i as u32 / w, [q[0], q[1], q[2], 0]);
            }
        }
        ShadedObjects {
            objects: self.objects,
            levels: self.sum,
            highlights: self.highlights,
            counters: self.counters,
            elaboration: self.elaboration,
            stats: self.stats,
            fragments: self.fragments,
        }
    }
}

/// The time model's view of one light's shading: every fragment a pass over the
/// normalisation cube map and one specular lookup or factor texture (two textures,
/// 32-bit texels, no cache assumed here: the model applies its hit rate), an RGBA8
/// read-modify-write and a depth test; no triangle set-up (the host resolves
/// visibility).
pub fn shading_stats(light: usize, fragments: u64) -> PassStats {
    PassStats {
        kind: PassKind::Objects,
        light,
        walked: fragments,
        fragments,
        textures_per_fragment: 2,
        triangles: 0,
        texel_bytes: fragments * 2 * 4 * 4,
        fb_bytes: fragments * 8,
        other_bytes: 0,
        depth_tests: fragments,
    }
}

/// The reflection added (saturating) where its object is the one shaded.
fn add_reflection(
    r: &Reflection,
    blend: &Blend,
    sum: &mut [Option<[u32; 3]>],
    objects: &[Option<usize>],
    counters: &mut BTreeMap<String, Counters>,
) {
    let at: Vec<usize> = (0..sum.len())
        .filter(|&i| objects[i] == Some(r.object) && r.pixels[i].is_some())
        .collect();
    let ins: Vec<BlendIn> = at
        .iter()
        .map(|&i| {
            let s = r.pixels[i].unwrap_or([0; 3]);
            let d = sum[i].unwrap_or([0; 3]);
            BlendIn {
                src: [s[0], s[1], s[2], 0],
                dst: [d[0], d[1], d[2], 0],
            }
        })
        .collect();
    let mut c = Counters::default();
    let out = run_span(blend, &mut (), &ins, &mut c);
    *counters
        .entry("additive_blend (environment reflection)".into())
        .or_default() += c;
    for (&i, o) in at.iter().zip(out) {
        sum[i] = Some([o[0], o[1], o[2]]);
    }
}

/// The brightest lit specular fragment of each object (strictly brighter: ties keep
/// the first in raster order), as the glare conditions' highlights: I_s is the
/// specular level after the light's irradiance, so an unlit fragment never counts.
#[allow(clippy::too_many_arguments)]
fn brightest(
    scene: &Scene,
    modulate: &Modulate,
    spec_pairs: &[(usize, ModulateIn)],
    objects: &[Option<usize>],
    cam: &CameraView,
    geometry: &SceneGeometry,
    lpos: crate::scene::math::Vec3,
    intensity: f64,
    radius: f64,
    counters: &mut BTreeMap<String, Counters>,
) -> Vec<FoundHighlight> {
    let ins: Vec<ModulateIn> = spec_pairs.iter().map(|(_, m)| *m).collect();
    let mut c = Counters::default();
    let lit = run_span(modulate, &mut (), &ins, &mut c);
    *counters
        .entry("modulate (highlight levels)".into())
        .or_default() += c;
    let w = scene.image.width;
    let mut best: Vec<Option<(usize, u32)>> = vec![None; scene.objects.len()];
    for (&(i, _), &v) in spec_pairs.iter().zip(&lit) {
        let Some(o) = objects[i] else { continue };
        if v > 0 && best[o].is_none_or(|(_, b)| v > b) {
            best[o] = Some((i, v));
        }
    }
    best.iter()
        .enumerate()
        .filter_map(|(o, b)| {
            let (i, v) = (*b)?;
            let (x, y) = (i as u32 % w, i as u32 / w);
            let dir = cam.ray_dir(x as f64 + 0.5, y as f64 + 0.5);
            let (_, hit) = geometry.first_hit(
                &Ray {
                    origin: cam.eye,
                    dir,
                },
                cam.far,
            )?;
            Some(FoundHighlight {
                object: o,
                pixel: [x, y],
                specular: v,
                highlight: highlight(hit.point, hit.normal, lpos, intensity, v, radius),
            })
        })
        .collect()
}

/// k_l × the light's colour, per channel, and k_l alone (grey), as 8-bit codes
/// (module notes).
fn irradiance_code(
    scene: &Scene,
    p: &Prepared,
    light: &crate::scene::format::Light,
    map: &LightMapSampler,
    lpos: crate::scene::math::Vec3,
    point: crate::scene::math::Vec3,
    t: f64,
) -> ([u32; 3], u32) {
    let to_l = lpos - point;
    let s2 = to_l.dot(to_l).max(1e-12);
    let m = scene.medium;
    let atten = (-m.rho * m.kappa * (s2.sqrt() + t)).exp();
    // I · light map (0 outside a spot's cone), as the ray-marched reference emits it.
    let k = light_weight(light, map, point) * atten / s2 * p.exposure / 255.0;
    let code = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u32;
    (light.color.map(|c| code(k * c)), code(k))
}

/// The pass's f64 reference at the pixels it coloured, in 8-bit levels: per light
/// k_l (unclamped, per channel) × 255 · π · R(ω_i, ω_o) · cos θ_i of the material's
/// reference BRDF with that channel's albedo (E = π, as the shading path is scaled),
/// summed over the lights, plus each reflector's reference reflection, clamped to
/// [0, 255] once at the end (the hardware clamps each light's level and each sum).
pub fn reference_levels(
    scene: &Scene,
    p: &Prepared,
    objects: &[Option<usize>],
    reflections: &[Reflection],
) -> Result<Vec<Option<[f64; 3]>>, ConfigError> {
    use crate::pipeline::shading::materials::MaterialBrdf;
    use crate::reference::brdf::{Brdf, ShadingFrame};
    let (w, _) = (scene.image.width, scene.image.height);
    let cam = CameraView::new(&scene.camera, scene.image);
    let geometry = SceneGeometry::without_meshes(&scene.objects)?;
    // Per object with a material: its reference BRDF per channel.
    let brdfs: Vec<Option<[MaterialBrdf; 3]>> = scene
        .objects
        .iter()
        .map(|o| {
            o.material
                .map(|m| -> Result<[MaterialBrdf; 3], ConfigError> {
                    Ok([
                        MaterialBrdf::new(&m, [o.color[0]; 3])?,
                        MaterialBrdf::new(&m, [o.color[1]; 3])?,
                        MaterialBrdf::new(&m, [o.color[2]; 3])?,
                    ])
                })
                .transpose()
        })
        .collect::<Result<_, _>>()?;
    let maps: Vec<LightMapSampler> = scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| LightMapSampler::for_light(l, i))
        .collect::<Result<_, _>>()?;
    let m = scene.medium;
    let mut out = vec![None; objects.len()];
    for (i, o) in objects.iter().enumerate() {
        let Some(obj) = *o else { continue };
        let (x, y) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
        let dir = cam.ray_dir(x, y);
        let Some((_, hit)) = geometry.first_hit(
            &Ray {
                origin: cam.eye,
                dir,
            },
            cam.far,
        ) else {
            continue;
        };
        let mut acc = [0.0f64; 3];
        if let Some(b) = &brdfs[obj] {
            let frame = ShadingFrame::new(
                hit.normal,
                crate::scene::math::v3(0.0, 1.0, 0.0).cross(hit.normal),
            );
            let wo = frame.to_local(-dir);
            for (li, light) in scene.lights.iter().enumerate() {
                let lpos = vec3(light.position);
                let to_l = lpos - hit.point;
                let s2 = to_l.dot(to_l).max(1e-12);
                let wi = frame.to_local(to_l.normalized());
                if wi.z <= 0.0 || wo.z <= 0.0 {
                    continue;
                }
                let atten = (-m.rho * m.kappa * (s2.sqrt() + hit.t)).exp();
                let k = light_weight(light, &maps[li], hit.point) * atten / s2 * p.exposure / 255.0;
                for c in 0..3 {
                    acc[c] += k
                        * light.color[c]
                        * 255.0
                        * std::f64::consts::PI
                        * b[c].eval(wi, wo)
                        * wi.z;
                }
            }
        }
        for r in reflections.iter().filter(|r| r.object == obj) {
            if let Some(v) = r.reference.as_ref().and_then(|v| v[i]) {
                for c in 0..3 {
                    acc[c] += v[c];
                }
            }
        }
        out[i] = Some(acc.map(|v| v.clamp(0.0, 255.0)));
    }
    Ok(out)
}
