//! One glare frame through the units: the polygon-variable generator sets up a quad
//! per primitive (bloom and halo around each source, one per flare line), the polygon
//! interpolator walks it (scissored to the viewport), a luminance modulator turns each
//! fragment's (u, v) into RGB luminance, and the combiner adds it into the framebuffer
//! with saturation. The Gaussian noise generator draws the flare lines, the chaos map
//! drives fluctuating sources, and the glare-condition unit tests highlights. Only the
//! units the scene needs are elaborated.

use super::background::base_image;
use super::host::{screen_sources, source_glare, ScreenSource};
use super::tables::{
    bloom_prim, halo_prim, line_falloff_samples, line_shape_samples, profile_samples, ring_samples,
    shape_samples, AreaPrim,
};
use crate::pipeline::shafts::frame::Elaborated;
use crate::reference::glare_model::{bloom_at, FlareLine, SourceGlare};
use crate::report::image_out::Framebuffer;
use crate::scene::format::Scene;
use crate::scene::glare::GlareSection;
use rtl_model::driver::run_span;
use rtl_model::fixed_point::{Format, Overflow, Quant};
use rtl_model::units::bloom_flare_modulator::BloomFlareModulatorConfig;
use rtl_model::units::gaussian_noise::{GaussState, GaussianNoiseConfig};
use rtl_model::units::glare_combiner::{CombineIn, GlareCombiner, GlareCombinerConfig};
use rtl_model::units::halo_modulator::HaloModulatorConfig;
use rtl_model::units::luminance_ram::{LumIn, LumWidths};
use rtl_model::units::polygon_interpolator::{
    PolySetup, PolygonInterpolator, PolygonInterpolatorConfig, Vertex,
};
use rtl_model::units::polygon_variable_generator::{
    PolygonVariableGenerator, PolygonVariableGeneratorConfig, PrimKind, PvgIn,
};
use rtl_model::{ConfigError, Counters, Unit, UnitSummary};
use std::collections::BTreeMap;

/// Sub-pixel bits of glare positions (interpolator and generator agree).
pub const SUBPIXEL_BITS: u32 = 4;
/// Integer bits of glare positions, with the sign: ±8192 px.
pub const COORD_INT_BITS: u32 = 14;
/// Fraction bits of the s2.f attributes the generator hands the interpolator.
pub const ATTR_FRAC_BITS: u32 = 14;

/// One primitive drawn.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PrimStat {
    pub kind: &'static str,
    pub source: usize,
    /// Pixels the walker stepped over (after the scissor).
    pub walked: u64,
    /// Covered fragments inside the viewport.
    pub fragments: u64,
    /// RAM words the host wrote before this primitive (0 when the tables were reused).
    pub table_words: u64,
}

/// The frame: framebuffer, what was drawn, counters, elaboration.
#[derive(Clone, Debug)]
pub struct GlareFrame {
    pub fb: Framebuffer,
    /// The background the glare was added to (fb codes, RGB).
    pub base: Vec<[u32; 3]>,
    /// The sources as rendered (after the fluctuation and the glare conditions).
    pub sources: Vec<SourceGlare>,
    pub labels: Vec<String>,
    /// The flare lines drawn, per source, decoded from the noise generator's codes.
    pub lines: Vec<Vec<FlareLine>>,
    /// Chaos values S_i(t) aligned with the scene's screen sources (1 where a source
    /// does not fluctuate).
    pub patch_levels: Vec<f64>,
    pub prims: Vec<PrimStat>,
    pub counters: BTreeMap<String, Counters>,
    pub elaboration: Vec<Elaborated>,
    /// Units elaborated, with their summaries (for gates).
    pub units: Vec<UnitSummary>,
}

impl GlareFrame {
    /// The image in 8-bit levels.
    pub fn levels(&self) -> Vec<[f64; 3]> {
        let max = rtl_model::unorm::max_code(self.fb.bits) as f64;
        self.fb
            .data
            .chunks(4)
            .map(|p| [0, 1, 2].map(|c| p[c] as f64 * 255.0 / max))
            .collect()
    }
}

fn add(map: &mut BTreeMap<String, Counters>, name: &str, c: Counters) {
    *map.entry(name.to_string()).or_default() += c;
}

/// The glare section, or an error naming `glare`.
pub fn glare_of(scene: &Scene) -> Result<&GlareSection, ConfigError> {
    scene.glare.as_ref().ok_or_else(|| {
        ConfigError::invalid(
            "glare",
            "the scene has no [glare] section (no glare sources)",
        )
    })
}

/// The modulators' widths from the scene.
pub fn lum_widths(g: &GlareSection) -> LumWidths {
    LumWidths {
        coord_frac_bits: g.hw.coord_frac_bits,
        shape_log2: g.hw.shape_log2,
        shape_bits: g.hw.shape_bits,
        falloff_log2: g.hw.falloff_log2,
        falloff_bits: g.hw.falloff_bits,
        weight_bits: g.hw.weight_bits,
        ..LumWidths::default()
    }
}

/// The glare interpolator: two attributes (u, v), s2.14 in, s2.f out.
pub fn interpolator(coord_frac_bits: u32) -> Result<PolygonInterpolator, ConfigError> {
    PolygonInterpolatorConfig {
        attrs: 2,
        subpixel_bits: SUBPIXEL_BITS,
        coord_int_bits: COORD_INT_BITS,
        attr_fmt: Format {
            int_bits: 2,
            frac_bits: ATTR_FRAC_BITS,
            signed: true,
        },
        acc_int_bits: 4,
        acc_frac_bits: 24,
        acc_overflow: Overflow::Wrap,
        out_int_bits: 2,
        out_frac_bits: coord_frac_bits,
        out_quant: Quant::Rnd,
    }
    .build()
}

pub fn generator() -> Result<PolygonVariableGenerator, ConfigError> {
    PolygonVariableGeneratorConfig {
        coord_int_bits: COORD_INT_BITS,
        subpixel_bits: SUBPIXEL_BITS,
        attr_frac_bits: ATTR_FRAC_BITS,
        ..PolygonVariableGeneratorConfig::default()
    }
    .build()
}

/// Move a set-up primitive's walk to the part of its bounding box inside the
/// viewport: the setup engine starts the walker at the clipped corner, its edge and
/// attribute accumulators advanced by Δx·d/dx + Δy·d/dy (multiply-adds, the same
/// values the walk would reach, accumulators wrapping to their width).
pub fn scissor(u: &PolygonInterpolator, s: &PolySetup, width: u32, height: u32) -> PolySetup {
    let Some(b) = s.bbox else {
        return s.clone();
    };
    let (x0, y0) = (b.x0.max(0), b.y0.max(0));
    let (x1, y1) = (b.x1.min(width as i64 - 1), b.y1.min(height as i64 - 1));
    let mut out = s.clone();
    if x0 > x1 || y0 > y1 {
        out.bbox = None;
        return out;
    }
    let (dx, dy) = (x0 - b.x0, y0 - b.y0);
    let st = &mut out.state;
    for i in 0..st.edge.len() {
        st.edge[i] += dx * st.edge_dx[i] + dy * st.edge_dy[i];
    }
    let w = u.acc_int_bits() + u.acc_frac_bits();
    let sh = 64 - w;
    for i in 0..u.attrs() as usize {
        let v = st.acc[i]
            .wrapping_add(dx.wrapping_mul(st.grad_x[i]))
            .wrapping_add(dy.wrapping_mul(st.grad_y[i]));
        st.acc[i] = (v << sh) >> sh;
    }
    st.x = x0;
    st.y = y0;
    out.bbox = Some(rtl_model::units::polygon_interpolator::BBox { x0, y0, x1, y1 });
    out
}

/// Largest |coordinate| (pixels) the host lets a quad corner reach: the position
/// format's range ±2^(COORD_INT_BITS−1), less a pixel for rounding.
pub const COORD_LIMIT_PX: f64 = ((1u64 << (COORD_INT_BITS - 1)) - 1) as f64;

/// An area primitive whose quad fits the coordinate range: the half-side shrunk to
/// COORD_LIMIT_PX − |centre| (0 when the centre itself is out of range, an empty
/// quad). Its RAM tables are computed over the shrunk frame, so the walked part keeps
/// the primitive's true (u, v) → distance mapping; what is cut off lies outside the
/// coordinate range (off screen).
pub fn fit_area(a: &AreaPrim) -> AreaPrim {
    let room = COORD_LIMIT_PX - a.center[0].abs().max(a.center[1].abs());
    AreaPrim {
        half_px: a.half_px.min(room).max(0.0),
        ..a.clone()
    }
}

/// Longest flare line and widest line (pixels) the host sends.
pub const LINE_MAX_PX: f64 = 4000.0;

/// Whether a flare line's rectangle (from `center` along `angle`, `length` long,
/// `half_width` to each side) lies inside the coordinate range with a pixel to
/// spare. The generator saturates each corner on its own, so a line reaching out of
/// range would come out skewed (or its fourth corner overflow the interpolator);
/// the host culls it instead. Its rectangle is at most √2·4000 px across, so on an
/// image of up to 2534 px a side a culled line never reaches the screen.
pub fn line_fits(center: [f64; 2], angle: f64, length: f64, half_width: f64) -> bool {
    let (c, s) = (angle.cos(), angle.sin());
    let lim = COORD_LIMIT_PX - 1.0;
    [(0.0, -1.0), (0.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
        .iter()
        .all(|&(along, side)| {
            let x = center[0] + along * length * c - side * half_width * s;
            let y = center[1] + along * length * s + side * half_width * c;
            x.abs() <= lim && y.abs() <= lim
        })
}

/// Position code of a pixel coordinate (round to nearest sub-pixel).
fn pos_code(x: f64) -> i64 {
    (x * (1u64 << SUBPIXEL_BITS) as f64).round() as i64
}

/// A covered fragment: x, y and the (u, v) codes.
pub type Frag = (u32, u32, i32, i32);

/// The fragments (x, y, u, v) of one primitive from the generator's variables.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn walk_prim(
    pvg: &PolygonVariableGenerator,
    ip: &PolygonInterpolator,
    input: PvgIn,
    width: u32,
    height: u32,
    ctr: &mut BTreeMap<String, Counters>,
) -> Result<(u64, Vec<Frag>), ConfigError> {
    let mut c_pvg = Counters::default();
    let v = run_span(pvg, &mut (), &[input], &mut c_pvg)[0];
    add(ctr, pvg.name(), c_pvg);
    let mut c_ip = Counters::default();
    let verts = v.map(|p| {
        let mut attrs = [0i64; 8];
        attrs[0] = p.u;
        attrs[1] = p.v;
        Vertex {
            x: p.x,
            y: p.y,
            attrs,
        }
    });
    let setup = ip.setup_parallelogram(&verts, &mut c_ip)?;
    let setup = scissor(ip, &setup, width, height);
    let mut st = setup.state.clone();
    let outs = run_span(ip, &mut st, &setup.moves(), &mut c_ip);
    add(ctr, ip.name(), c_ip);
    let frags = outs
        .iter()
        .filter(|f| f.inside && f.x >= 0 && f.y >= 0 && f.x < width as i64 && f.y < height as i64)
        .map(|f| (f.x as u32, f.y as u32, f.attrs[0] as i32, f.attrs[1] as i32))
        .collect();
    Ok((setup.pixels(), frags))
}

/// Modulate and combine one primitive's fragments into the framebuffer.
fn shade<U: Unit<In = LumIn, Out = rtl_model::units::luminance_ram::LumOut, State = ()>>(
    m: &U,
    comb: &GlareCombiner,
    frags: &[Frag],
    gain: [u32; 3],
    fb: &mut Framebuffer,
    ctr: &mut BTreeMap<String, Counters>,
) {
    let ins: Vec<LumIn> = frags
        .iter()
        .map(|&(_, _, u, v)| LumIn { u, v, gain })
        .collect();
    let mut c = Counters::default();
    let lum = run_span(m, &mut (), &ins, &mut c);
    add(ctr, m.name(), c);
    let cin: Vec<CombineIn> = frags
        .iter()
        .zip(&lum)
        .map(|(&(x, y, _, _), l)| {
            let p = fb.pixel(x, y);
            CombineIn {
                fb: [p[0], p[1], p[2]],
                lum: l.lum,
            }
        })
        .collect();
    let mut c = Counters::default();
    let out = run_span(comb, &mut (), &cin, &mut c);
    add(ctr, comb.name(), c);
    for (&(x, y, _, _), o) in frags.iter().zip(&out) {
        let a = fb.pixel(x, y)[3];
        fb.set(x, y, [o[0], o[1], o[2], a]);
    }
}

/// The area primitive's generator input (the quad fitted to the coordinate range).
fn area_input(a: &AreaPrim, pvg: &PolygonVariableGenerator) -> Result<PvgIn, ConfigError> {
    let half = fit_area(a).half_px;
    Ok(PvgIn {
        kind: PrimKind::Area,
        cx: pos_code(a.center[0]),
        cy: pos_code(a.center[1]),
        extent: pos_code(half) as u64,
        half_width: 0,
        angle: pvg.angle_code(a.phi)?,
    })
}

/// Gains (u12.4 codes) of luminance `l` times the source colour.
fn gains(w: &LumWidths, l: f64, color: [f64; 3], field: &str) -> Result<[u32; 3], ConfigError> {
    let max = w.gain_max() as f64 / (1u64 << w.gain_frac_bits) as f64;
    w.gain_from_f64(field, color.map(|c| (l * c).clamp(0.0, max)))
}

/// Render the glare of a scene over its background.
pub fn render_glare(scene: &Scene) -> Result<GlareFrame, ConfigError> {
    let g = glare_of(scene)?;
    let (w, h) = (scene.image.width, scene.image.height);
    let screens = screen_sources(scene)?;
    let mut counters = BTreeMap::new();
    let mut elaboration = Vec::new();
    let mut units = Vec::new();

    // Fluctuation: the chaos map gives each patch its S_i(t).
    let (patch_levels, chaos_summary) =
        super::fluctuation::patch_levels(scene, &screens, &mut counters)?;
    // Highlights through the glare conditions: glare sources or saturated dots.
    let (hl_sources, cond_summary) = super::condition::highlight_sources(scene, &mut counters)?;

    let mut all: Vec<ScreenSource> = screens;
    let mut intensities: Vec<f64> = all
        .iter()
        .zip(&patch_levels)
        .map(|(s, l)| s.intensity * l)
        .collect();
    for (s, i) in hl_sources {
        intensities.push(i);
        all.push(s);
    }
    let sources: Vec<SourceGlare> = all
        .iter()
        .zip(&intensities)
        .map(|(s, &i)| source_glare(s, i, &g.determinants, &g.model))
        .collect();
    let labels = all.iter().map(|s| s.label.clone()).collect();

    let base = base_image(scene, &mut counters)?;
    let mut fb = Framebuffer::new(w, h, g.hw.fb_bits);
    for (i, p) in base.iter().enumerate() {
        fb.data[i * 4..i * 4 + 4].copy_from_slice(&[
            p[0],
            p[1],
            p[2],
            rtl_model::unorm::max_code(g.hw.fb_bits),
        ]);
    }

    let any_bloom = sources.iter().any(|s| s.bloom.is_some());
    let any_halo = sources.iter().any(|s| s.halo.is_some());
    let any_flare = sources.iter().any(|s| s.flare.is_some());
    let any = any_bloom || any_halo || any_flare;
    let lw = lum_widths(g);

    // Flare lines: two normals per line from the noise generator, decoded.
    let mut lines: Vec<Vec<FlareLine>> = vec![Vec::new(); sources.len()];
    let noise = if any_flare {
        let n = GaussianNoiseConfig {
            uniform_bits: g.hw.noise_bits,
            ..GaussianNoiseConfig::geforce()
        }
        .build()?;
        let scale = (1u64 << n.config().out_frac_bits) as f64;
        let mut state = GaussState::from_seed(scene.seed);
        let mut c = Counters::default();
        for (i, s) in sources.iter().enumerate() {
            if let Some(f) = &s.flare {
                let outs = run_span(&n, &mut state, &vec![(); f.num as usize], &mut c);
                let draws: Vec<(f64, f64)> = outs
                    .iter()
                    .map(|o| (o.x as f64 / scale, o.y.unwrap_or(0) as f64 / scale))
                    .collect();
                lines[i] = f.lines(&draws, s.px_per_deg);
            }
        }
        add(&mut counters, n.name(), c);
        Some(n)
    } else {
        None
    };

    let pvg = generator()?;
    let ip = interpolator(g.hw.coord_frac_bits)?;
    let comb = GlareCombinerConfig {
        fb_bits: g.hw.fb_bits,
        lum_bits: lw.out_bits,
    }
    .build()?;
    let diag = ((w as f64).powi(2) + (h as f64).powi(2)).sqrt();
    let mut prims = Vec::new();
    // A modulator to cost the elaboration when no primitive builds one.
    let mut bloom_cost: Option<UnitSummary> = None;
    let mut halo_cost: Option<UnitSummary> = None;

    for (i, s) in sources.iter().enumerate() {
        if let Some(b) = &s.bloom {
            let (a, theta_max) = bloom_prim(s, b, &g.model, 1.5 * diag);
            let a = fit_area(&a);
            let l0 = bloom_at(b, 0.0, &g.model);
            let gmax = lw.gain_max() as f64 / (1u64 << lw.gain_frac_bits) as f64;
            let gain_l = l0.min(gmax);
            let shape = shape_samples(&s.shape, &a, lw.shape_log2);
            let fall = profile_samples(
                |t| bloom_at(b, t, &g.model),
                theta_max,
                gain_l,
                lw.falloff_log2,
            );
            let m = BloomFlareModulatorConfig::from_widths(lw).build(&shape, &fall)?;
            let gain = gains(&lw, gain_l, s.color, "bloom_flare_modulator.gain")?;
            let (walked, frags) = walk_prim(&pvg, &ip, area_input(&a, &pvg)?, w, h, &mut counters)?;
            shade(&m, &comb, &frags, gain, &mut fb, &mut counters);
            prims.push(PrimStat {
                kind: "bloom",
                source: i,
                walked,
                fragments: frags.len() as u64,
                table_words: m.table_words(),
            });
            bloom_cost.get_or_insert_with(|| UnitSummary::of(&m));
        }
        if let Some(cc) = s.halo {
            let (a, theta_max) = halo_prim(s, &g.determinants, &g.model);
            let a = fit_area(&a);
            let shape = shape_samples(&s.shape, &a, lw.shape_log2);
            let rings: Vec<Vec<f64>> = g
                .determinants
                .wavelengths_nm
                .iter()
                .map(|&l| ring_samples(l, theta_max, &g.model, lw.falloff_log2))
                .collect();
            let m = HaloModulatorConfig::from_widths(lw)
                .build(&shape, [&rings[0], &rings[1], &rings[2]])?;
            let gain = gains(&lw, cc, s.color, "halo_modulator.gain")?;
            let (walked, frags) = walk_prim(&pvg, &ip, area_input(&a, &pvg)?, w, h, &mut counters)?;
            shade(&m, &comb, &frags, gain, &mut fb, &mut counters);
            prims.push(PrimStat {
                kind: "halo",
                source: i,
                walked,
                fragments: frags.len() as u64,
                table_words: m.table_words(),
            });
            halo_cost.get_or_insert_with(|| UnitSummary::of(&m));
        }
    }
    if any_flare {
        // Every line shares one spindle shape and one falloff: loaded once.
        let m = BloomFlareModulatorConfig::from_widths(lw).build(
            &line_shape_samples(lw.shape_log2),
            &line_falloff_samples(lw.falloff_log2),
        )?;
        let mut loaded = false;
        for (i, s) in sources.iter().enumerate() {
            for l in &lines[i] {
                let (len, half_w) = (
                    l.length_px.min(LINE_MAX_PX),
                    0.5 * l.width_px.min(LINE_MAX_PX),
                );
                if !line_fits(s.center, l.angle, len, half_w) {
                    continue;
                }
                let gain = gains(&lw, l.intensity, s.color, "bloom_flare_modulator.gain")?;
                let input = PvgIn {
                    kind: PrimKind::Line,
                    cx: pos_code(s.center[0]),
                    cy: pos_code(s.center[1]),
                    extent: pos_code(len).max(0) as u64,
                    half_width: pos_code(half_w).max(0) as u64,
                    angle: pvg.angle_code(l.angle)?,
                };
                let (walked, frags) = walk_prim(&pvg, &ip, input, w, h, &mut counters)?;
                shade(&m, &comb, &frags, gain, &mut fb, &mut counters);
                prims.push(PrimStat {
                    kind: "flare",
                    source: i,
                    walked,
                    fragments: frags.len() as u64,
                    table_words: if loaded { 0 } else { m.table_words() },
                });
                loaded = true;
            }
        }
        bloom_cost.get_or_insert_with(|| UnitSummary::of(&m));
    }

    // Elaboration: what was built, and what was left out with what it saved.
    let frags_of = |k: &str| {
        prims
            .iter()
            .filter(|p| p.kind == k)
            .map(|p| p.fragments)
            .sum::<u64>()
    };
    let default_mod = || {
        let wl = lw;
        let shape = vec![0.0; wl.shape_len()];
        let fall = vec![0.0; wl.falloff_len()];
        BloomFlareModulatorConfig::from_widths(wl)
            .build(&shape, &fall)
            .map(|m| UnitSummary::of(&m))
    };
    let default_halo = || {
        let wl = lw;
        let shape = vec![0.0; wl.shape_len()];
        let r = vec![0.0; wl.falloff_len()];
        HaloModulatorConfig::from_widths(wl)
            .build(&shape, [&r, &r, &r])
            .map(|m| UnitSummary::of(&m))
    };
    let mut push = |name: &str,
                    used: bool,
                    summary: Result<Option<UnitSummary>, ConfigError>,
                    why: &str,
                    cycles: u64|
     -> Result<(), ConfigError> {
        let Some(s) = summary? else {
            return Ok(());
        };
        if used {
            units.push(s.clone());
            elaboration.push(Elaborated {
                name: name.into(),
                summary: Some(s),
                left_out: None,
                gates_saved: 0.0,
                cycles_saved: 0,
            });
        } else {
            elaboration.push(Elaborated {
                name: name.into(),
                summary: None,
                left_out: Some(why.into()),
                gates_saved: s.gates_nand2,
                cycles_saved: cycles,
            });
        }
        Ok(())
    };
    push(
        "polygon_variable_generator",
        any,
        Ok(Some(UnitSummary::of(&pvg))),
        "no glare source",
        0,
    )?;
    push(
        "polygon_interpolator",
        any,
        Ok(Some(UnitSummary::of(&ip))),
        "no glare source",
        0,
    )?;
    push(
        "bloom_flare_modulator",
        any_bloom || any_flare,
        bloom_cost.map_or_else(default_mod, Ok).map(Some),
        "no bloom and no flare line",
        frags_of("bloom") + frags_of("flare"),
    )?;
    push(
        "halo_modulator",
        any_halo,
        halo_cost.map_or_else(default_halo, Ok).map(Some),
        "no source shows a halo",
        frags_of("halo"),
    )?;
    push(
        "glare_combiner",
        any,
        Ok(Some(UnitSummary::of(&comb))),
        "no glare source",
        0,
    )?;
    let noise_summary = match &noise {
        Some(n) => UnitSummary::of(n),
        None => UnitSummary::of(&GaussianNoiseConfig::geforce().build()?),
    };
    push(
        "gaussian_noise",
        noise.is_some(),
        Ok(Some(noise_summary)),
        "no flare lines (num = 0 for every source)",
        0,
    )?;
    let (chaos_used, chaos_s) = chaos_summary;
    push(
        "chaos_map",
        chaos_used,
        Ok(chaos_s),
        "no fluctuating source",
        0,
    )?;
    let (cond_used, cond_s) = cond_summary;
    push(
        "glare_condition",
        cond_used,
        Ok(cond_s),
        "no specular highlight",
        0,
    )?;

    Ok(GlareFrame {
        fb,
        base,
        sources,
        labels,
        lines,
        patch_levels,
        prims,
        counters,
        elaboration,
        units,
    })
}
