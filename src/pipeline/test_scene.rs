//! The built-in test scene: a checkered floor under a spotlight whose beam is cut by
//! the shadow of a window-frame occluder (a "cucoloris" between the light and the
//! floor, outside the camera's view, so no depth test is needed), rendered through
//! every foundation unit:
//!
//! * depth pass: `polygon_interpolator` walks the occluder in the light's view and
//!   `shadow_compare` writes its depths;
//! * floor pass: `polygon_interpolator` walks the floor with 8 attributes —
//!   (u/w, v/w, 1/w) for the perspective-correct checker, (s/w, t/w, r/w, q/w) for the
//!   light's projective coordinates, and the per-vertex Lambert term;
//!   `projective_texcoord` divides them (three instances: checker, light map, depth);
//!   `texture_sampler` filters the RGBA checker (bilinear, repeat) and the luminance
//!   light map (bilinear, clamp); `shadow_compare` tests the light-space depth;
//!   `modulate` combines; `blend` (its additive datapath, GL_ONE, GL_ONE) adds an
//!   ambient pass and the spot pass into the 8-bit RGBA framebuffer.
//!
//! Host work (vertex transforms, in f64 as the application processor would) is here;
//! everything per pixel runs through the units' kernels with the span driver.

use crate::pipeline::raster::{walk, Fragment};
use crate::report::image_out::Framebuffer;
use crate::report::table::text_table;
use crate::scene::math::{v3, Vec3};
pub use crate::scene::test_scene::*;
use rtl_model::driver::run_span;
use rtl_model::error::ConfigError;
use rtl_model::units::blend::{Blend, BlendIn};
use rtl_model::units::modulate::{Modulate, ModulateIn};
use rtl_model::units::polygon_interpolator::{
    PolygonInterpolator, PolygonInterpolatorConfig, Vertex,
};
use rtl_model::units::projective_texcoord::{
    ProjectiveIn, ProjectiveOut, ProjectiveTexcoord, ProjectiveTexcoordConfig,
};
use rtl_model::units::shadow_compare::{
    ShadowCompare, ShadowCompareConfig, ShadowIn, ShadowOut, ShadowState,
};
use rtl_model::units::texture_sampler::{
    AddressMode, TextureSampler, TextureSamplerConfig, TextureSamplerIn,
};
use rtl_model::{Counters, Format};
use serde::Serialize;
use std::path::Path;

/// Shadow map: 128 × 128, 16-bit depths.
pub const SHADOW_SIZE: u32 = 128;
pub const SHADOW_DEPTH_BITS: u32 = 16;
/// The shadow compare's bias, in steps of the 16-bit map.
pub const SHADOW_BIAS: u32 = 8;
/// Floor cells per side (8 × 8 cells, 128 triangles).
pub const FLOOR_CELLS: usize = 8;
/// Scale of the 1/w-weighted attributes (keeps them well inside s16.16).
const PERSPECTIVE_SCALE: f64 = 16.0;

/// Every unit the scene elaborates, configured for it.
pub struct TestSceneUnits {
    pub interp: PolygonInterpolator,
    /// Divides checker (u/w, v/w)/(1/w) and light (s/w, t/w)/(q/w): s4.12 out.
    pub proj: ProjectiveTexcoord,
    /// Divides (r/w)/(q/w) for the light-space depth: s2.16 out (a 16-bit depth).
    pub proj_depth: ProjectiveTexcoord,
    pub checker: TextureSampler,
    pub lightmap: TextureSampler,
    pub shadow: ShadowCompare,
    pub modulate: Modulate,
    pub blend: Blend,
}

/// Counters per unit, in pipeline order.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SceneCounters {
    pub units: Vec<(String, Counters)>,
    /// Predicted clocks: per pass, the busiest unit (units run in a pipeline), summed.
    pub predicted_cycles: u64,
    pub clock_mhz: f64,
    pub covered_pixels: u64,
}

impl TestSceneUnits {
    pub fn new() -> Result<Self, ConfigError> {
        let interp = PolygonInterpolatorConfig {
            attrs: 8,
            out_int_bits: 16,
            out_frac_bits: 16,
            ..PolygonInterpolatorConfig::default()
        }
        .build()?;
        let proj = ProjectiveTexcoordConfig::geforce().build()?;
        let proj_depth = ProjectiveTexcoordConfig {
            out_int_bits: 2,
            out_frac_bits: 16,
            newton_steps: 2,
            newton_frac_bits: 30,
            ..ProjectiveTexcoordConfig::geforce()
        }
        .build()?;
        let checker = TextureSampler::new(
            TextureSamplerConfig {
                channels: 4,
                address: [AddressMode::Wrap; 3],
                ..TextureSamplerConfig::geforce_2d(CHECKER_SIZE, CHECKER_SIZE)
            },
            &checker_texels(),
        )?;
        let lightmap = TextureSampler::new(
            TextureSamplerConfig::geforce_2d(LIGHTMAP_SIZE, LIGHTMAP_SIZE),
            &lightmap_texels(),
        )?;
        let shadow = ShadowCompareConfig {
            width: SHADOW_SIZE,
            height: SHADOW_SIZE,
            depth_bits: SHADOW_DEPTH_BITS,
            bias: SHADOW_BIAS,
            frag_frac_bits: 0,
            ..ShadowCompareConfig::geforce()
        }
        .build()?;
        Ok(TestSceneUnits {
            interp,
            proj,
            proj_depth,
            checker,
            lightmap,
            shadow,
            modulate: Modulate::geforce(),
            blend: Blend::additive(8, 8, false, 8)?,
        })
    }
}

/// Screen position (pixels, y down) of clip coordinates.
pub fn to_screen(c: [f64; 4], w: u32, h: u32) -> (f64, f64) {
    let (x, y) = (c[0] / c[3], c[1] / c[3]);
    ((x * 0.5 + 0.5) * w as f64, (0.5 - y * 0.5) * h as f64)
}

/// Render the scene. Returns the framebuffer and the counters.
pub fn render() -> Result<(Framebuffer, SceneCounters), ConfigError> {
    let units = TestSceneUnits::new()?;
    let v = views();
    let mut c_interp = Counters::default();
    // The per-pixel units' counters, in [`shade`]'s order: projective (u,v and s,t),
    // projective (depth), checker, light map, shadow_compare, modulate, additive_blend.
    let mut c_pixel = [Counters::default(); 7];
    let mut shadow_state: ShadowState = units.shadow.fresh_state();
    let depth_pass_cycles = depth_pass(
        &units,
        &v,
        &mut shadow_state,
        &mut c_interp,
        &mut c_pixel[4],
    )?;
    let mut fb = Framebuffer::new(WIDTH, HEIGHT, units.blend.bits());
    let (floor_pass_cycles, covered) = floor_passes(
        &units,
        &v,
        &mut shadow_state,
        &mut fb,
        &mut c_interp,
        &mut c_pixel,
    )?;
    let [c_proj, c_proj_depth, c_checker, c_lightmap, c_shadow, c_mod, c_blend] = c_pixel;
    let counters = SceneCounters {
        units: vec![
            ("polygon_interpolator".into(), c_interp),
            ("projective_texcoord (u,v and s,t)".into(), c_proj),
            ("projective_texcoord (depth)".into(), c_proj_depth),
            ("texture_sampler (checker RGBA)".into(), c_checker),
            ("texture_sampler (light map)".into(), c_lightmap),
            ("shadow_compare".into(), c_shadow),
            ("modulate".into(), c_mod),
            ("additive_blend".into(), c_blend),
        ],
        predicted_cycles: depth_pass_cycles + floor_pass_cycles,
        clock_mhz: 200.0,
        covered_pixels: covered,
    };
    Ok((fb, counters))
}

/// The depth pass: the occluder in the light's view, into the shadow map (a 1-attribute
/// interpolator of the window depth, s16.16, written as u16). Returns its cycles: per
/// primitive the walk's or the shadow writes', whichever is longer.
fn depth_pass(
    units: &TestSceneUnits,
    v: &Views,
    shadow_state: &mut ShadowState,
    c_interp: &mut Counters,
    c_shadow: &mut Counters,
) -> Result<u64, ConfigError> {
    let mut depth_pass_cycles = 0u64;
    let depth_interp = PolygonInterpolatorConfig {
        attrs: 1,
        out_int_bits: 16,
        out_frac_bits: 16,
        ..PolygonInterpolatorConfig::default()
    }
    .build()?;
    for q in occluder_quads() {
        let mut verts = [Vertex::default(); 4];
        for (i, p) in q.iter().enumerate() {
            let (x, y, z) = occluder_window(v, *p);
            verts[i] = depth_interp.vertex_from_f64(i, x, y, &[z], c_interp)?;
        }
        for s in depth_interp.setup_quad(&verts, c_interp) {
            let mut c_walk = Counters::default();
            let mut frags = Vec::new();
            walk(
                &depth_interp,
                &s,
                SHADOW_SIZE,
                SHADOW_SIZE,
                &mut c_walk,
                &mut frags,
            );
            let writes: Vec<ShadowIn> = frags
                .iter()
                .map(|f| ShadowIn::Write {
                    x: f.x as i32,
                    y: f.y as i32,
                    // s16.16 depth in [0, 1] → u16 (clamped; 1.0 is the far plane).
                    depth: f.attrs[0].clamp(0, (1 << SHADOW_DEPTH_BITS) - 1) as u32,
                })
                .collect();
            let mut c_w = Counters::default();
            run_span(&units.shadow, shadow_state, &writes, &mut c_w);
            depth_pass_cycles += c_walk.cycles.max(c_w.cycles);
            *c_interp += c_walk;
            *c_shadow += c_w;
        }
    }
    Ok(depth_pass_cycles)
}

/// An occluder corner in the shadow map, as the host computes it: x, y (texels, y
/// down) and the window depth in [0, 1].
pub fn occluder_window(v: &Views, p: Vec3) -> (f64, f64, f64) {
    let c = v.light.apply(p);
    let (x, y) = to_screen(c, SHADOW_SIZE, SHADOW_SIZE);
    (x, y, (c[2] / c[3]) * 0.5 + 0.5)
}

/// Floor grid corner (i, j) of the FLOOR_CELLS² cells: its world position and checker
/// coordinates (tu, tv) in [0, 1].
pub fn floor_corner(i: usize, j: usize) -> (Vec3, f64, f64) {
    let n = FLOOR_CELLS;
    let f = |k: usize| -FLOOR_HALF + 2.0 * FLOOR_HALF * k as f64 / n as f64;
    (
        v3(f(i), 0.0, f(j)),
        i as f64 / n as f64,
        j as f64 / n as f64,
    )
}

/// A floor corner as the host hands it to the interpolator (f64): its screen
/// position (pixels, y down) and the 8 attributes — the checker's (u, v)/w, 1/w and
/// the light's projective (s, t, r, q)/w (1/w scaled by PERSPECTIVE_SCALE), and the
/// per-vertex Lambert term.
pub fn floor_attributes(v: &Views, p: Vec3, (tu, tv): (f64, f64)) -> (f64, f64, [f64; 8]) {
    let c = v.cam.apply(p);
    let (x, y) = to_screen(c, WIDTH, HEIGHT);
    let inv_w = PERSPECTIVE_SCALE / c[3];
    let l = v.light.apply(p);
    // Projective light coordinates: s = (x + w)/2, t = (w − y)/2 (y down),
    // r = (z + w)/2, q = w, so that s/q, t/q, r/q lie in [0, 1].
    let (ls, lt, lr, lq) = (
        (l[0] + l[3]) * 0.5,
        (l[3] - l[1]) * 0.5,
        (l[2] + l[3]) * 0.5,
        l[3],
    );
    // Per-vertex Lambert term with inverse-square fall-off (normal +y).
    let to_light = v.light_pos - p;
    let d2 = to_light.dot(to_light);
    let lambert = (to_light.normalized().y * LAMBERT_SCALE / d2).clamp(0.0, 1.0);
    let attrs = [
        tu * CHECKER_REPEAT * inv_w,
        tv * CHECKER_REPEAT * inv_w,
        inv_w,
        ls * inv_w,
        lt * inv_w,
        lr * inv_w,
        lq * inv_w,
        lambert,
    ];
    (x, y, attrs)
}

/// The floor passes: FLOOR_CELLS² cells, each a quad set up, walked and shaded
/// ([`shade`]) into `fb`. Returns (cycles: per primitive the walk's or the shading's,
/// whichever is longer; covered pixels).
fn floor_passes(
    units: &TestSceneUnits,
    v: &Views,
    shadow_state: &mut ShadowState,
    fb: &mut Framebuffer,
    c_interp: &mut Counters,
    c_pixel: &mut [Counters; 7],
) -> Result<(u64, u64), ConfigError> {
    let n = FLOOR_CELLS;
    let grid = floor_corner;
    let mut floor_pass_cycles = 0u64;
    let mut covered = 0u64;
    for j in 0..n {
        for i in 0..n {
            let corners = [
                grid(i, j),
                grid(i + 1, j),
                grid(i + 1, j + 1),
                grid(i, j + 1),
            ];
            let mut verts = [Vertex::default(); 4];
            for (k, &(p, tu, tv)) in corners.iter().enumerate() {
                verts[k] = floor_vertex(units, v, k, p, (tu, tv), c_interp)?;
            }
            for s in units.interp.setup_quad(&verts, c_interp) {
                let mut c_walk = Counters::default();
                let mut frags = Vec::new();
                walk(&units.interp, &s, WIDTH, HEIGHT, &mut c_walk, &mut frags);
                *c_interp += c_walk;
                let pass = shade(units, &frags, shadow_state, fb, c_pixel);
                covered += frags.len() as u64;
                floor_pass_cycles += c_walk.cycles.max(pass);
            }
        }
    }
    Ok((floor_pass_cycles, covered))
}

/// Floor corner `k` at `p` with checker coordinates (tu, tv), as the interpolator's
/// vertex ([`floor_attributes`]).
fn floor_vertex(
    units: &TestSceneUnits,
    v: &Views,
    k: usize,
    p: Vec3,
    tex: (f64, f64),
    c_interp: &mut Counters,
) -> Result<Vertex, ConfigError> {
    let (x, y, attrs) = floor_attributes(v, p, tex);
    units.interp.vertex_from_f64(k, x, y, &attrs, c_interp)
}

/// Shade one primitive's covered fragments through the per-pixel units and blend the
/// ambient and spot passes into `fb`. Returns the busiest unit's cycles.
fn shade(
    u: &TestSceneUnits,
    frags: &[Fragment],
    shadow_state: &mut ShadowState,
    fb: &mut Framebuffer,
    ctrs: &mut [Counters; 7],
) -> u64 {
    if frags.is_empty() {
        return 0;
    }
    let mut c = [Counters::default(); 7];
    let (uv, depth) = project(u, frags, &mut c);
    let n = frags.len();
    let (uv, st) = uv.split_at(n);

    // Texture units take texel-space s16.8: normalised s4.12 × 2^6 texels → shift by 2.
    let to_texel = |p: &ProjectiveOut, log2_size: u32| TextureSamplerIn {
        coord: [
            texel_word(p.u, log2_size, &u.proj),
            texel_word(p.v, log2_size, &u.proj),
            0,
        ],
    };
    let checker_coords: Vec<TextureSamplerIn> = uv.iter().map(|p| to_texel(p, 6)).collect();
    let light_coords: Vec<TextureSamplerIn> = st.iter().map(|p| to_texel(p, 6)).collect();
    let albedo = run_span(&u.checker, &mut (), &checker_coords, &mut c[2]);
    let spot = run_span(&u.lightmap, &mut (), &light_coords, &mut c[3]);

    // Shadow lookup at the light-space texel (nearest) with the s2.16 depth → u16.
    let shift = u.proj.out_format().frac_bits - SHADOW_SIZE.trailing_zeros();
    let dshift = u.proj_depth.out_format().frac_bits - SHADOW_DEPTH_BITS;
    let tests: Vec<ShadowIn> = st
        .iter()
        .zip(&depth)
        .map(|(p, d)| ShadowIn::Test {
            x: p.u >> shift,
            y: p.v >> shift,
            depth: (d.u.max(0) >> dshift).min((1 << SHADOW_DEPTH_BITS) - 1) as u64,
        })
        .collect();
    let lit = run_span(&u.shadow, shadow_state, &tests, &mut c[4]);

    let (m1, m2) = modulate(u, frags, st, &albedo, &spot, &lit, &mut c[5]);
    blend_passes(u, frags, &m1, &m2, fb, &mut c[6]);
    let busiest = c.iter().map(|k| k.cycles).max().unwrap_or(0);
    for (dst, src) in ctrs.iter_mut().zip(c) {
        *dst += src;
    }
    busiest
}

/// The projective divides of every fragment: the checker's (u, v) then the light's
/// (s, t) in one vector (fragment order each), and the light-space depths. The
/// interpolator's outputs are s16.16 raw, the projective inputs' format.
fn project(
    u: &TestSceneUnits,
    frags: &[Fragment],
    c: &mut [Counters; 7],
) -> (Vec<ProjectiveOut>, Vec<ProjectiveOut>) {
    // Attribute indices (s, t, q) of each divide; `None` for t: the depth has no t.
    let inputs = |s: usize, t: Option<usize>, q: usize| -> Vec<ProjectiveIn> {
        frags
            .iter()
            .map(|f| ProjectiveIn {
                s: f.attrs[s],
                t: t.map_or(0, |t| f.attrs[t]),
                q: f.attrs[q],
            })
            .collect()
    };
    let checker_in = inputs(0, Some(1), 2);
    let light_in = inputs(3, Some(4), 6);
    let depth_in = inputs(5, None, 6);
    let mut uv = run_span(&u.proj, &mut (), &checker_in, &mut c[0]);
    let st = run_span(&u.proj, &mut (), &light_in, &mut c[0]);
    uv.extend(st.iter().copied());
    let depth = run_span(&u.proj_depth, &mut (), &depth_in, &mut c[1]);
    (uv, depth)
}

/// The modulate unit's work (counted in `c_mod`): light = light map · Lambert (· 0 in
/// shadow or behind the light); returns the ambient and light products per fragment
/// and channel (`m1`: albedo · ambient at 2ch, light · light colour at 2ch + 1) and
/// the spot colour albedo · that (`m2`, 3 per fragment).
fn modulate(
    u: &TestSceneUnits,
    frags: &[Fragment],
    st: &[ProjectiveOut],
    albedo: &[[u32; 4]],
    spot: &[[u32; 4]],
    lit: &[ShadowOut],
    c_mod: &mut Counters,
) -> (Vec<u32>, Vec<u32>) {
    let n = frags.len();
    let lambert: Vec<u32> = frags
        .iter()
        .map(|f| (f.attrs[7] >> 8).clamp(0, 255) as u32)
        .collect();
    let spot_l: Vec<ModulateIn> = spot
        .iter()
        .zip(&lambert)
        .map(|(s, &l)| ModulateIn { a: s[0], b: l })
        .collect();
    let light = run_span(&u.modulate, &mut (), &spot_l, c_mod);
    let light: Vec<u32> = light
        .iter()
        .zip(lit)
        .zip(st)
        .map(|((&l, s), p)| if s.lit && !p.behind { l } else { 0 })
        .collect();
    let mut mods = Vec::with_capacity(n * 7);
    for (a, &l) in albedo.iter().zip(&light) {
        for ch in 0..3 {
            mods.push(ModulateIn {
                a: a[ch],
                b: AMBIENT,
            });
            mods.push(ModulateIn {
                a: l,
                b: LIGHT_RGB[ch],
            });
        }
    }
    let m1 = run_span(&u.modulate, &mut (), &mods, c_mod);
    let mut mods2 = Vec::with_capacity(n * 3);
    for (k, a) in albedo.iter().enumerate() {
        for ch in 0..3 {
            mods2.push(ModulateIn {
                a: a[ch],
                b: m1[k * 6 + 2 * ch + 1],
            });
        }
    }
    let m2 = run_span(&u.modulate, &mut (), &mods2, c_mod);
    (m1, m2)
}

/// Two additive passes into the framebuffer (counted in `c_blend`): ambient (`m1`'s
/// even products), then the spot (`m2`).
fn blend_passes(
    u: &TestSceneUnits,
    frags: &[Fragment],
    m1: &[u32],
    m2: &[u32],
    fb: &mut Framebuffer,
    c_blend: &mut Counters,
) {
    for pass in 0..2 {
        let blends: Vec<BlendIn> = frags
            .iter()
            .enumerate()
            .map(|(k, f)| {
                let src = |ch: usize| {
                    if pass == 0 {
                        m1[k * 6 + 2 * ch]
                    } else {
                        m2[k * 3 + ch]
                    }
                };
                BlendIn {
                    src: [src(0), src(1), src(2), 0],
                    dst: fb.pixel(f.x, f.y),
                }
            })
            .collect();
        let out = run_span(&u.blend, &mut (), &blends, c_blend);
        for (f, o) in frags.iter().zip(out) {
            fb.set(f.x, f.y, [o[0], o[1], o[2], 255]);
        }
    }
}

/// A projective s4.12 (normalised) coordinate → the sampler's texel-space word for a
/// 2^log2_size texture: multiply by the size and keep the sampler's fraction bits.
fn texel_word(raw: i32, log2_size: u32, proj: &ProjectiveTexcoord) -> i32 {
    let from = proj.out_format().frac_bits as i32;
    let sampler_frac = 8i32;
    let shift = log2_size as i32 + sampler_frac - from;
    if shift >= 0 {
        raw << shift
    } else {
        raw >> -shift
    }
}

/// `render` for the CLI: writes the PNG, prints the counters.
/// `passes`: the test scene's plan as `render --json` lists it (`frame::plan` builds it).
pub fn render_cli(
    out: &Path,
    json: bool,
    reference: Option<&Path>,
    passes: Vec<crate::report::render_json::PassEntry>,
) -> Result<(), String> {
    let t0 = std::time::Instant::now();
    let (fb, ctr) = render().map_err(|e| e.to_string())?;
    fb.save_png(out)
        .map_err(|e| format!("out: {}: {e}", out.display()))?;
    let mut error = None;
    if let Some(path) = reference {
        let r = crate::reference::test_scene::render_reference();
        let mut img = Framebuffer::new(WIDTH, HEIGHT, 8);
        let (mut sum, mut n, mut max) = (0.0f64, 0u64, 0.0f64);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                if let Some(rgb) = r[(y * WIDTH + x) as usize] {
                    let hw = fb.pixel(x, y);
                    for c in 0..3 {
                        let d = (hw[c] as f64 - rgb[c]).abs();
                        sum += d;
                        max = max.max(d);
                    }
                    n += 3;
                    let q = |v: f64| v.round().clamp(0.0, 255.0) as u32;
                    img.set(x, y, [q(rgb[0]), q(rgb[1]), q(rgb[2]), 255]);
                }
            }
        }
        img.save_png(path)
            .map_err(|e| format!("reference: {}: {e}", path.display()))?;
        eprintln!(
            "reference {}: mean |hw - f64| {:.3} levels, max {:.1} (covered channels: {n})",
            path.display(),
            sum / n.max(1) as f64,
            max
        );
        error = Some(serde_json::json!({
            "mean_abs_levels": sum / n.max(1) as f64,
            "max_levels": max,
            "covered_channels": n,
        }));
    }
    if json {
        use crate::report::render_json::{value, Family, RenderJson, Timing};
        let units: serde_json::Map<String, serde_json::Value> = ctr
            .units
            .iter()
            .map(|(name, c)| Ok((name.clone(), value(c)?)))
            .collect::<Result<_, String>>()?;
        let mut j = RenderJson::new("test", Family::Test)
            .image(WIDTH, HEIGHT)
            .outputs(Some(out), reference)
            .family_details(serde_json::json!({ "covered_pixels": ctr.covered_pixels }));
        j.passes = passes;
        j.counters
            .insert("test scene".into(), serde_json::Value::Object(units));
        j.timing = Timing {
            predicted_seconds: Some(ctr.predicted_cycles as f64 / (ctr.clock_mhz * 1e6)),
            gpu: None,
            cycles: Some(ctr.predicted_cycles),
            clock_mhz: Some(ctr.clock_mhz),
            wall_seconds: Some(t0.elapsed().as_secs_f64()),
        };
        j.error = error;
        return j.print();
    }
    println!(
        "test scene {WIDTH}x{HEIGHT}: {} covered pixels; wrote {}",
        ctr.covered_pixels,
        out.display()
    );
    let rows: Vec<Vec<String>> = ctr
        .units
        .iter()
        .map(|(name, c)| {
            let mut r = vec![name.clone()];
            r.extend(c.fields().iter().map(|(_, v)| v.to_string()));
            r
        })
        .collect();
    let mut header = vec!["unit"];
    header.extend(Counters::default().fields().iter().map(|(k, _)| *k));
    print!("{}", text_table(&header, &rows));
    println!(
        "predicted: {} clocks = {:.3} ms at {} MHz (per primitive, the busiest unit; one pipe)",
        ctr.predicted_cycles,
        ctr.predicted_cycles as f64 / (ctr.clock_mhz * 1e3),
        ctr.clock_mhz
    );
    Ok(())
}

/// The s16.16 format the interpolator hands to `projective_texcoord` (checked in tests).
pub fn handoff_format() -> Format {
    Format {
        int_bits: 16,
        frac_bits: 16,
        signed: true,
    }
}
