//! One glare frame through the units: the polygon-variable generator sets up a quad
//! per primitive (bloom and halo around each source, one per flare line), the polygon
//! interpolator walks it (scissored to the viewport), a luminance modulator turns each
//! fragment's (u, v) into RGB luminance, and the combiner adds it into the framebuffer
//! with saturation. The Gaussian noise generator draws the flare lines, the chaos map
//! drives fluctuating sources, and the glare-condition unit tests highlights. Only the
//! units the scene needs are elaborated.

use super::background::base_image;
use super::host::{glare_of, screen_sources, source_glare, ScreenSource};
use super::tables::{
    bloom_prim, halo_prim, line_falloff_samples, line_shape_samples, profile_samples,
    radial_tables, ring_samples, shape_samples, AreaPrim,
};
use crate::chip::work::{PassKind, PassStats, PassWork, RopWork};
use crate::reference::glare_model::{bloom_at, Bloom, FlareLine, Shape2D, SourceGlare};
use crate::report::elaboration::Elaborated;
use crate::report::image_out::Framebuffer;
use crate::scene::format::Scene;
use crate::scene::glare::GlareSection;
use rayon::prelude::*;
use rtl_model::driver::{run_span, SpanTally};
use rtl_model::units::bloom_flare_modulator::{BloomFlareModulator, BloomFlareModulatorConfig};
use rtl_model::units::gaussian_noise::{GaussState, GaussianNoise, GaussianNoiseConfig};
use rtl_model::units::glare_combiner::GlareCombiner;
use rtl_model::units::halo_modulator::{HaloModulator, HaloModulatorConfig};
use rtl_model::units::luminance_ram::{LumIn, LumOut, LumWidths};
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::units::polygon_variable_generator::{PolygonVariableGenerator, PrimKind, PvgIn};
use rtl_model::{ConfigError, Counters, Unit, UnitSummary};
use std::collections::BTreeMap;

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
    /// What the pass did, for the clocked chip ([`render_glare_with`] with `record`):
    /// `None` unless asked for.
    pub work: Option<PassWork>,
}

impl GlareFrame {
    /// The image in 8-bit levels.
    pub fn levels(&self) -> Vec<[f64; 3]> {
        self.fb.levels()
    }
}

use super::primitives::{
    add, area_input, combine, draw_prim, gains, pos_code, walk_prim, DrawBuffers, Drawn,
    WalkBuffers,
};
pub use super::primitives::{
    fit_area, generator, interpolator, line_fits, lum_widths, scissor, Frag, COORD_LIMIT_PX,
    LINE_MAX_PX,
};

/// Render the glare of a scene over its background.
pub fn render_glare(scene: &Scene) -> Result<GlareFrame, ConfigError> {
    render_glare_over(scene, None)
}

/// Render the glare over a background already drawn for this scene (fb codes, RGB,
/// row-major), or over the scene's own background when `None`. Variants of one scene
/// that differ only in their glare (Fig. 7's panels) share one background this way.
pub fn render_glare_over(
    scene: &Scene,
    base: Option<&[[u32; 3]]>,
) -> Result<GlareFrame, ConfigError> {
    render_glare_with(scene, base, false)
}

/// [`render_glare_over`], and with `record` also what the pass did
/// ([`GlareFrame::work`]): its primitives in draw order (the area primitives, then
/// the flare lines, as the combiner adds them), each one's walked pixels and covered
/// fragments in walk order, and the combiner's read-modify-write per fragment.
/// Recording changes no pixel and no counter; off, it costs a branch per chunk.
pub fn render_glare_with(
    scene: &Scene,
    base: Option<&[[u32; 3]]>,
    record: bool,
) -> Result<GlareFrame, ConfigError> {
    let g = glare_of(scene)?;
    let (w, h) = (scene.image.width, scene.image.height);
    let mut counters = BTreeMap::new();
    let found = find_sources(scene, g, &mut counters)?;
    let sources = &found.sources;
    let (base, mut fb) = starting_framebuffer(scene, g, base, &mut counters)?;
    let (lines, noise) = flare_lines(scene, g, sources, &mut counters)?;
    let u = GlareUnits {
        g,
        lw: lum_widths(g),
        pvg: generator()?,
        ip: interpolator(g.hw.coord_frac_bits)?,
        comb: crate::scene::limits::glare_combiner(&g.hw).build()?,
        width: w,
        height: h,
    };
    // The flare lines' walks and modulation (their fragments kept, a few per cent of
    // the frame's) run beside the area primitives' (rayon::join: two threads when
    // free); the combiner then adds the lines in order after the areas, as one
    // thread would. Counters are integer sums, so the merge order cannot change them.
    let (areas, walked) = rayon::join(
        || draw_area_prims(&u, sources, &mut fb, &mut counters, record),
        || walk_flare_lines(&u, sources, &lines),
    );
    let mut areas = areas?;
    if let Some(wl) = walked? {
        combine_flare_lines(&u, &wl, &mut fb, &mut areas, &mut counters, record);
    }
    let kinds = GlareKinds::of(sources);
    let (elaboration, units) = glare_elaboration(&u, kinds, &areas, &noise, found.summaries)?;
    let work = if record {
        Some(pass_work(
            &areas.prims,
            &areas.frag_pix,
            &counters,
            g.hw.fb_bits,
            w,
            h,
        )?)
    } else {
        None
    };
    Ok(GlareFrame {
        fb,
        base,
        sources: found.sources,
        labels: found.labels,
        lines,
        patch_levels: found.patch_levels,
        prims: areas.prims,
        counters,
        elaboration,
        units,
        work,
    })
}

/// The glare pass's units and widths, built once per frame, shared by its primitives.
struct GlareUnits<'a> {
    g: &'a GlareSection,
    lw: LumWidths,
    pvg: PolygonVariableGenerator,
    ip: PolygonInterpolator,
    comb: GlareCombiner,
    width: u32,
    height: u32,
}

/// The frame's glare sources and what found them.
struct FoundSources {
    sources: Vec<SourceGlare>,
    labels: Vec<String>,
    /// Chaos values S_i(t) of the scene's screen sources.
    patch_levels: Vec<f64>,
    /// The chaos map's and the glare conditions' (used, summary), for the elaboration.
    summaries: [(bool, Option<UnitSummary>); 2],
}

/// The screen sources at their fluctuating levels (the chaos map's S_i(t)), then the
/// highlights the glare conditions pass, each with its glare.
fn find_sources(
    scene: &Scene,
    g: &GlareSection,
    counters: &mut BTreeMap<String, Counters>,
) -> Result<FoundSources, ConfigError> {
    let screens = screen_sources(scene)?;
    let (patch_levels, chaos_summary) =
        super::fluctuation::patch_levels(scene, &screens, counters)?;
    let (hl_sources, cond_summary) = super::condition::highlight_sources(scene, counters)?;
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
    let sources = all
        .iter()
        .zip(&intensities)
        .map(|(s, &i)| source_glare(s, i, &g.determinants, &g.model))
        .collect();
    Ok(FoundSources {
        sources,
        labels: all.iter().map(|s| s.label.clone()).collect(),
        patch_levels,
        summaries: [chaos_summary, cond_summary],
    })
}

/// The background the glare is added to (the given one, checked, or the scene's own)
/// and the framebuffer holding it at full alpha.
fn starting_framebuffer(
    scene: &Scene,
    g: &GlareSection,
    base: Option<&[[u32; 3]]>,
    counters: &mut BTreeMap<String, Counters>,
) -> Result<(Vec<[u32; 3]>, Framebuffer), ConfigError> {
    let (w, h) = (scene.image.width, scene.image.height);
    let base = match base {
        Some(b) if b.len() == (w * h) as usize => b.to_vec(),
        Some(b) => {
            return Err(ConfigError::invalid(
                "glare.background",
                &format!(
                    "the given background has {} pixels, the image {}",
                    b.len(),
                    w * h
                ),
            ))
        }
        None => base_image(scene, counters)?,
    };
    let mut fb = Framebuffer::new(w, h, g.hw.fb_bits);
    for (i, p) in base.iter().enumerate() {
        fb.data[i * 4..i * 4 + 4].copy_from_slice(&[
            p[0],
            p[1],
            p[2],
            rtl_model::unorm::max_code(g.hw.fb_bits),
        ]);
    }
    Ok((base, fb))
}

/// Each source's flare lines: two normals per line from the noise generator (seeded
/// by the scene), decoded; the generator when any source has lines.
fn flare_lines(
    scene: &Scene,
    g: &GlareSection,
    sources: &[SourceGlare],
    counters: &mut BTreeMap<String, Counters>,
) -> Result<(Vec<Vec<FlareLine>>, Option<GaussianNoise>), ConfigError> {
    let mut lines: Vec<Vec<FlareLine>> = vec![Vec::new(); sources.len()];
    if !GlareKinds::of(sources).flare {
        return Ok((lines, None));
    }
    let n = crate::scene::limits::glare_noise(&g.hw).build()?;
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
    add(counters, n.name(), c);
    Ok((lines, Some(n)))
}

/// The area primitives drawn (and the flare lines combined after them): the frame's
/// primitive table, a modulator of each kind to cost the elaboration, the buffers the
/// combiner reuses, and with recording the covered fragments' pixel indices.
struct DrawnAreas {
    prims: Vec<PrimStat>,
    bloom_cost: Option<UnitSummary>,
    halo_cost: Option<UnitSummary>,
    buf: DrawBuffers,
    frag_pix: Vec<u32>,
}

/// Every source's bloom and halo as area primitives through the datapath into `fb`.
fn draw_area_prims(
    u: &GlareUnits<'_>,
    sources: &[SourceGlare],
    fb: &mut Framebuffer,
    counters: &mut BTreeMap<String, Counters>,
    record: bool,
) -> Result<DrawnAreas, ConfigError> {
    let diag = ((u.width as f64).powi(2) + (u.height as f64).powi(2)).sqrt();
    let mut out = DrawnAreas {
        prims: Vec::new(),
        bloom_cost: None,
        halo_cost: None,
        buf: DrawBuffers::default(),
        frag_pix: Vec::new(),
    };
    // An area primitive (bloom or halo) through the datapath, as its row of the
    // frame's primitive table.
    let mut draw = |out: &mut DrawnAreas,
                    kind: &'static str,
                    source: usize,
                    a: &AreaPrim,
                    m: &dyn Unit<In = LumIn, Out = LumOut, State = ()>,
                    table_words: u64,
                    gain: [u32; 3]|
     -> Result<(), ConfigError> {
        let input = area_input(a, &u.pvg)?;
        let d = draw_prim(
            &u.pvg,
            &u.ip,
            input,
            m,
            &u.comb,
            gain,
            fb,
            &mut out.buf,
            counters,
            record.then_some(&mut out.frag_pix),
        )?;
        out.prims.push(PrimStat {
            kind,
            source,
            walked: d.walked,
            fragments: d.fragments,
            table_words,
        });
        Ok(())
    };
    // A source's tables are most of its host work. They depend on its outline and
    // brightness, not on where it is drawn: sources alike share one build
    // ([`TableCache`]), and the builds a chunk of sources needs run in parallel. The
    // primitives are then drawn one by one in source order, as one thread would.
    let mut blooms = TableCache::default();
    let mut halos = TableCache::default();
    for (c, chunk) in sources.chunks(TABLE_CHUNK).enumerate() {
        let plans: Vec<SourcePlan> = chunk
            .par_iter()
            .map(|s| SourcePlan::of(u, s, diag))
            .collect();
        blooms.load(plans.iter().filter_map(|p| p.bloom.as_ref()), |p| {
            bloom_modulator(u, p)
        });
        halos.load(plans.iter().filter_map(|p| p.halo.as_ref()), |p| {
            halo_modulator(u, p)
        });
        // Errors surface in the order one thread meets them.
        for (k, (p, s)) in plans.iter().zip(chunk).enumerate() {
            let i = c * TABLE_CHUNK + k;
            if let Some(b) = &p.bloom {
                let m = blooms.get(&b.key)?;
                let gain = gains(&u.lw, b.gain_l, s.color, "bloom_flare_modulator.gain")?;
                draw(&mut out, "bloom", i, &b.a, &*m, m.table_words(), gain)?;
                out.bloom_cost.get_or_insert_with(|| UnitSummary::of(&*m));
            }
            if let Some(h) = &p.halo {
                let m = halos.get(&h.key)?;
                let gain = gains(&u.lw, h.gain_l, s.color, "halo_modulator.gain")?;
                draw(&mut out, "halo", i, &h.a, &*m, m.table_words(), gain)?;
                out.halo_cost.get_or_insert_with(|| UnitSummary::of(&*m));
            }
        }
        blooms.end_chunk();
        halos.end_chunk();
    }
    Ok(out)
}

/// Sources planned, and their missing tables built (in parallel), at once before they
/// are drawn: a few per thread.
const TABLE_CHUNK: usize = 64;

/// Distinct modulators kept across chunks (about 70 KB each at the default widths); a
/// frame of more distinct sources builds the rest chunk by chunk.
const TABLE_CACHE_ENTRIES: usize = 256;

/// One area primitive of a source, before its tables are built: its quad, what its
/// tables are computed from, its gain and the key of equal tables.
struct AreaPlan<'s, P> {
    a: AreaPrim,
    /// The profile's input: the bloom model, or the halo's cut-off angle.
    profile: P,
    theta_max: f64,
    gain_l: f64,
    shape: &'s Shape2D,
    /// Everything the tables depend on, spelt exactly (f64 in round-trip form).
    key: String,
}

/// A source's bloom and halo primitives, planned.
struct SourcePlan<'s> {
    bloom: Option<AreaPlan<'s, Bloom>>,
    halo: Option<AreaPlan<'s, ()>>,
}

impl<'s> SourcePlan<'s> {
    fn of(u: &GlareUnits<'_>, s: &'s SourceGlare, diag: f64) -> SourcePlan<'s> {
        let (g, lw) = (u.g, u.lw);
        let bloom = s.bloom.as_ref().map(|b| {
            let (a, theta_max) = bloom_prim(s, b, &g.model, 1.5 * diag);
            let a = fit_area(&a);
            let gmax = lw.gain_max() as f64 / (1u64 << lw.gain_frac_bits) as f64;
            let gain_l = bloom_at(b, 0.0, &g.model).min(gmax);
            AreaPlan {
                key: table_key(&s.shape, &a, &[theta_max, gain_l], b),
                a,
                profile: *b,
                theta_max,
                gain_l,
                shape: &s.shape,
            }
        });
        let halo = s.halo.map(|cc| {
            let (a, theta_max) = halo_prim(s, &g.determinants, &g.model);
            let a = fit_area(&a);
            AreaPlan {
                key: table_key(&s.shape, &a, &[theta_max], &()),
                a,
                profile: (),
                theta_max,
                gain_l: cc,
                shape: &s.shape,
            }
        });
        SourcePlan { bloom, halo }
    }
}

/// The key of an area primitive's tables: its outline, its frame's size, angle and
/// reach (not its centre), and what its profile is computed from (`x`: the cut-off
/// angle, and the bloom's gain: the cut-off also depends on the source's colour).
fn table_key(shape: &Shape2D, a: &AreaPrim, x: &[f64], profile: &dyn std::fmt::Debug) -> String {
    format!(
        "{shape:?}|{:?}|{:?}|{:?}|{x:?}|{profile:?}",
        a.half_px, a.phi, a.d_max_px
    )
}

/// A bloom's modulator: its shape and falloff tables loaded.
fn bloom_modulator(
    u: &GlareUnits<'_>,
    p: &AreaPlan<Bloom>,
) -> Result<BloomFlareModulator, ConfigError> {
    let (g, lw) = (u.g, u.lw);
    let b = &p.profile;
    let fall = profile_samples(
        |t| bloom_at(b, t, &g.model),
        p.theta_max,
        p.gain_l,
        lw.falloff_log2,
    );
    let (shape, kappa) = area_shape(p.shape, &p.a, &lw, &[&fall]);
    BloomFlareModulatorConfig::from_widths(lw)
        .build(&shape, &fall)?
        .with_kappa(kappa)
}

/// A halo's modulator: its shape and three ring tables loaded.
fn halo_modulator(u: &GlareUnits<'_>, p: &AreaPlan<'_, ()>) -> Result<HaloModulator, ConfigError> {
    let (g, lw) = (u.g, u.lw);
    let rings: Vec<Vec<f64>> = g
        .determinants
        .wavelengths_nm
        .iter()
        .map(|&l| ring_samples(l, p.theta_max, &g.model, lw.falloff_log2))
        .collect();
    let (shape, kappa) = area_shape(p.shape, &p.a, &lw, &[&rings[0], &rings[1], &rings[2]]);
    HaloModulatorConfig::from_widths(lw)
        .build(&shape, [&rings[0], &rings[1], &rings[2]])?
        .with_kappa(kappa)
}

/// Modulators built once per distinct key: up to [`TABLE_CACHE_ENTRIES`] kept for the
/// frame, the rest for their chunk only.
struct TableCache<M> {
    kept: std::collections::HashMap<String, std::sync::Arc<M>>,
    /// This chunk's builds that are not kept (the cache is full), and failed builds.
    chunk: std::collections::HashMap<String, Result<std::sync::Arc<M>, ConfigError>>,
}

impl<M> Default for TableCache<M> {
    fn default() -> Self {
        TableCache {
            kept: Default::default(),
            chunk: Default::default(),
        }
    }
}

impl<M: Send + Sync> TableCache<M> {
    /// Build, in parallel, the modulators of `plans` that are not there yet.
    fn load<'p, P: Sync + 'p>(
        &mut self,
        plans: impl Iterator<Item = &'p AreaPlan<'p, P>>,
        build: impl Fn(&AreaPlan<'_, P>) -> Result<M, ConfigError> + Sync,
    ) {
        let mut seen = std::collections::HashSet::new();
        let missing: Vec<&AreaPlan<'_, P>> = plans
            .filter(|p| !self.kept.contains_key(&p.key) && seen.insert(p.key.as_str()))
            .collect();
        let built: Vec<_> = missing
            .par_iter()
            .map(|p| build(p).map(std::sync::Arc::new))
            .collect();
        for (p, m) in missing.into_iter().zip(built) {
            match m {
                Ok(m) if self.kept.len() < TABLE_CACHE_ENTRIES => {
                    self.kept.insert(p.key.clone(), m);
                }
                m => {
                    self.chunk.insert(p.key.clone(), m);
                }
            }
        }
    }

    /// The modulator of `key` (loaded by [`TableCache::load`] for this chunk).
    fn get(&self, key: &str) -> Result<std::sync::Arc<M>, ConfigError> {
        match self.kept.get(key) {
            Some(m) => Ok(m.clone()),
            None => match self.chunk.get(key) {
                Some(m) => m.clone(),
                None => Err(ConfigError::invalid(
                    "glare",
                    "internal: an area primitive's tables were not built",
                )),
            },
        }
    }

    fn end_chunk(&mut self) {
        self.chunk.clear();
    }
}

/// Every source's flare lines walked and modulated (not yet combined), their
/// fragments kept in draw order; `None` when no source has lines.
fn walk_flare_lines(
    u: &GlareUnits<'_>,
    sources: &[SourceGlare],
    lines: &[Vec<FlareLine>],
) -> Result<Option<WalkedLines>, ConfigError> {
    if !GlareKinds::of(sources).flare {
        return Ok(None);
    }
    let lw = u.lw;
    // Every line shares one spindle shape and one falloff: loaded once.
    let m = BloomFlareModulatorConfig::from_widths(lw)
        .build(&line_shape(&lw), &line_falloff_samples(lw.falloff_log2))?;
    let mut out = WalkedLines {
        m,
        counters: BTreeMap::new(),
        pix: Vec::new(),
        lum: Vec::new(),
        drawn: Vec::new(),
    };
    let mut wb = WalkBuffers::default();
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
                angle: u.pvg.angle_code(l.angle)?,
            };
            let (pix, lum) = (&mut out.pix, &mut out.lum);
            let d = walk_prim(
                &u.pvg,
                &u.ip,
                input,
                &out.m,
                gain,
                u.width,
                u.height,
                &mut wb,
                &mut out.counters,
                |p, l| {
                    pix.extend_from_slice(p);
                    lum.extend_from_slice(l);
                },
            )?;
            out.drawn.push((i, d, out.pix.len()));
        }
    }
    Ok(Some(out))
}

/// The walked flare lines added by the combiner after the areas, line by line in
/// order, each a row of the primitive table (the shared tables written before the
/// first line only).
fn combine_flare_lines(
    u: &GlareUnits<'_>,
    wl: &WalkedLines,
    fb: &mut Framebuffer,
    areas: &mut DrawnAreas,
    counters: &mut BTreeMap<String, Counters>,
    record: bool,
) {
    if record {
        areas.frag_pix.extend(wl.pix.iter().map(|&i| i as u32));
    }
    for (k, c) in &wl.counters {
        add(counters, k, *c);
    }
    let comb = &u.comb;
    let mut start = 0;
    for (n, &(i, d, end)) in wl.drawn.iter().enumerate() {
        let (mut c, mut t) = (Counters::default(), SpanTally::new());
        for (p, l) in wl.pix[start..end]
            .chunks(LINE_COMBINE_CHUNK)
            .zip(wl.lum[start..end].chunks(LINE_COMBINE_CHUNK))
        {
            let buf = &mut areas.buf;
            combine(
                comb,
                p,
                l,
                fb,
                &mut buf.comb_in,
                &mut buf.comb_out,
                &mut c,
                &mut t,
            );
        }
        t.close(comb.timing(), &mut c);
        add(counters, comb.name(), c);
        areas.prims.push(PrimStat {
            kind: "flare",
            source: i,
            walked: d.walked,
            fragments: d.fragments,
            table_words: if n == 0 { wl.m.table_words() } else { 0 },
        });
        start = end;
    }
    areas
        .bloom_cost
        .get_or_insert_with(|| UnitSummary::of(&wl.m));
}

/// Which glare the frame's sources show (what the elaboration builds for).
#[derive(Clone, Copy)]
struct GlareKinds {
    bloom: bool,
    halo: bool,
    flare: bool,
}

impl GlareKinds {
    fn of(sources: &[SourceGlare]) -> Self {
        GlareKinds {
            bloom: sources.iter().any(|s| s.bloom.is_some()),
            halo: sources.iter().any(|s| s.halo.is_some()),
            flare: sources.iter().any(|s| s.flare.is_some()),
        }
    }

    fn any(self) -> bool {
        self.bloom || self.halo || self.flare
    }
}

/// One unit's row of the elaboration: built (`used`: its summary) or left out (why,
/// and the gates and cycles that saved); nothing when there is no summary.
fn elaborate_unit(
    out: &mut (Vec<Elaborated>, Vec<UnitSummary>),
    name: &str,
    used: bool,
    summary: Result<Option<UnitSummary>, ConfigError>,
    why: &str,
    cycles: u64,
) -> Result<(), ConfigError> {
    let Some(s) = summary? else {
        return Ok(());
    };
    if used {
        out.1.push(s.clone());
        out.0.push(Elaborated {
            name: name.into(),
            summary: Some(s),
            left_out: None,
            gates_saved: 0.0,
            cycles_saved: 0,
        });
    } else {
        out.0.push(Elaborated {
            name: name.into(),
            summary: None,
            left_out: Some(why.into()),
            gates_saved: s.gates_nand2,
            cycles_saved: cycles,
        });
    }
    Ok(())
}

/// The two modulators' rows: each built if the frame's sources need it (its summary
/// from a primitive that built it, else from an empty one at the frame's widths), or
/// left out with the fragments it would have taken.
fn elaborate_modulators(
    o: &mut (Vec<Elaborated>, Vec<UnitSummary>),
    lw: LumWidths,
    kinds: GlareKinds,
    areas: &DrawnAreas,
) -> Result<(), ConfigError> {
    let frags_of = |k: &str| {
        areas
            .prims
            .iter()
            .filter(|p| p.kind == k)
            .map(|p| p.fragments)
            .sum::<u64>()
    };
    let default_mod = || {
        let shape = vec![0.0; lw.shape_len()];
        let fall = vec![0.0; lw.falloff_len()];
        BloomFlareModulatorConfig::from_widths(lw)
            .build(&shape, &fall)
            .map(|m| UnitSummary::of(&m))
    };
    let default_halo = || {
        let shape = vec![0.0; lw.shape_len()];
        let r = vec![0.0; lw.falloff_len()];
        HaloModulatorConfig::from_widths(lw)
            .build(&shape, [&r, &r, &r])
            .map(|m| UnitSummary::of(&m))
    };
    elaborate_unit(
        o,
        "bloom_flare_modulator",
        kinds.bloom || kinds.flare,
        areas
            .bloom_cost
            .clone()
            .map_or_else(default_mod, Ok)
            .map(Some),
        "no bloom and no flare line",
        frags_of("bloom") + frags_of("flare"),
    )?;
    elaborate_unit(
        o,
        "halo_modulator",
        kinds.halo,
        areas
            .halo_cost
            .clone()
            .map_or_else(default_halo, Ok)
            .map(Some),
        "no source shows a halo",
        frags_of("halo"),
    )?;
    Ok(())
}

/// The glare pass's elaboration: each unit built (with its summary) or left out (with
/// why and the gates and cycles that saved), and the summaries of those built.
fn glare_elaboration(
    u: &GlareUnits<'_>,
    kinds: GlareKinds,
    areas: &DrawnAreas,
    noise: &Option<GaussianNoise>,
    [chaos, cond]: [(bool, Option<UnitSummary>); 2],
) -> Result<(Vec<Elaborated>, Vec<UnitSummary>), ConfigError> {
    let any = kinds.any();
    let mut out = (Vec::new(), Vec::new());
    let o = &mut out;
    let none = "no glare source";
    elaborate_unit(
        o,
        "polygon_variable_generator",
        any,
        Ok(Some(UnitSummary::of(&u.pvg))),
        none,
        0,
    )?;
    elaborate_unit(
        o,
        "polygon_interpolator",
        any,
        Ok(Some(UnitSummary::of(&u.ip))),
        none,
        0,
    )?;
    elaborate_modulators(o, u.lw, kinds, areas)?;
    elaborate_unit(
        o,
        "glare_combiner",
        any,
        Ok(Some(UnitSummary::of(&u.comb))),
        none,
        0,
    )?;
    let noise_summary = match noise {
        Some(n) => UnitSummary::of(n),
        None => UnitSummary::of(&GaussianNoiseConfig::geforce().build()?),
    };
    elaborate_unit(
        o,
        "gaussian_noise",
        noise.is_some(),
        Ok(Some(noise_summary)),
        "no flare lines (num = 0 for every source)",
        0,
    )?;
    elaborate_unit(
        o,
        "chaos_map",
        chaos.0,
        Ok(chaos.1),
        "no fluctuating source",
        0,
    )?;
    elaborate_unit(
        o,
        "glare_condition",
        cond.0,
        Ok(cond.1),
        "no specular highlight",
        0,
    )?;
    Ok(out)
}

/// The glare pass's [`PassWork`] from its primitives (draw order), their covered
/// fragments' pixel indices (the same order) and the frame's counters. An
/// inconsistency between them is an error, never a panic.
fn pass_work(
    prims: &[PrimStat],
    frag_pix: &[u32],
    counters: &BTreeMap<String, Counters>,
    fb_bits: u32,
    width: u32,
    height: u32,
) -> Result<PassWork, ConfigError> {
    let fragments: u64 = prims.iter().map(|p| p.fragments).sum();
    if fragments != frag_pix.len() as u64 {
        return Err(ConfigError::invalid(
            "timing",
            &format!(
                "the glare pass recorded {} fragments but its primitives count {fragments}",
                frag_pix.len()
            ),
        ));
    }
    let to_u32 = |v: u64, what: &str| {
        u32::try_from(v).map_err(|_| {
            ConfigError::invalid("timing", &format!("{what} {v} does not fit 32 bits"))
        })
    };
    let mut prim_first_fragment = Vec::with_capacity(prims.len());
    let mut prim_walked = Vec::with_capacity(prims.len());
    let mut first = 0u64;
    for p in prims {
        prim_first_fragment.push(to_u32(first, "fragment index")?);
        prim_walked.push(to_u32(p.walked, "walked pixels")?);
        first += p.fragments;
    }
    // Image sides are at most 4095 (validation), so a position fits 16 bits.
    let side = |v: u32, field: &str| {
        u16::try_from(v).map_err(|_| {
            ConfigError::invalid(field, "the clocked timing records positions in 16 bits")
        })
    };
    side(width.saturating_sub(1), "image.width")?;
    side(height.saturating_sub(1), "image.height")?;
    let frag_xy = frag_pix
        .iter()
        .map(|&i| [(i % width) as u16, (i / width) as u16])
        .collect();
    // The combiner reads and writes the RGB pixel (3·fb_bits bits), as it counts.
    let rgb = rtl_model::memory::bytes_for_bits(3 * fb_bits) as u32;
    let comb = counters.get("glare_combiner").cloned().unwrap_or_default();
    let walked: u64 = prims.iter().map(|p| p.walked).sum();
    let stats = PassStats {
        kind: PassKind::Glare,
        light: 0,
        walked,
        fragments,
        textures_per_fragment: 0,
        triangles: prims.len() as u64,
        texel_bytes: 0,
        fb_bytes: comb.mem_read_bytes + comb.mem_write_bytes,
        // The host's RAM-table words are on-chip writes, not memory traffic: counted
        // per primitive in `GlareFrame::prims` (`table_words`), not here.
        other_bytes: 0,
        depth_tests: 0,
    };
    Ok(PassWork {
        stats: Some(stats),
        width,
        height,
        textures: Vec::new(),
        prim_first_fragment,
        prim_walked,
        // The glare datapath has no depth test.
        prim_depth_killed: Vec::new(),
        frag_xy,
        texels: Vec::new(),
        rop: RopWork {
            depth_read_bytes: 0,
            depth_write_bytes: 0,
            colour_read_bytes: rgb,
            colour_write_bytes: rgb,
        },
        copy_read_bytes: 0,
        copy_write_bytes: 0,
        sample: None,
        unrecorded: false,
    })
}

/// The shape RAM contents and κ of an area primitive: the plain min(1, sdf/d_max)
/// samples with κ = 0, or with radial correction the signed sdf/d_max − κ·|(u, v)|
/// with the host's κ ([`radial_tables`]).
fn area_shape(
    shape: &Shape2D,
    a: &AreaPrim,
    lw: &LumWidths,
    profiles: &[&[f64]],
) -> (Vec<f64>, f64) {
    if lw.radial.on {
        radial_tables(shape, a, lw, profiles)
    } else {
        (shape_samples(shape, a, lw.shape_log2), 0.0)
    }
}

/// The flare lines' shared shape: the plain samples in either mode (with radial
/// correction they are loaded as signed entries with κ = 0, clamped to the entry
/// range; the lines' cone sits at u = −1, not at the frame centre).
fn line_shape(lw: &LumWidths) -> Vec<f64> {
    let t = line_shape_samples(lw.shape_log2);
    if lw.radial.on {
        let (lo, hi) = lw.entry_range();
        t.into_iter().map(|x| x.clamp(lo, hi)).collect()
    } else {
        t
    }
}

/// Combiner inputs per chunk when the flare lines' kept fragments are added.
const LINE_COMBINE_CHUNK: usize = 256;

/// The flare lines walked and modulated ahead of the combiner: the shared modulator,
/// the walk's counters, every line's fragments (framebuffer pixel index and
/// luminance, lines one after another) and per line its source, walk and end index.
struct WalkedLines {
    m: BloomFlareModulator,
    counters: BTreeMap<String, Counters>,
    pix: Vec<usize>,
    lum: Vec<LumOut>,
    drawn: Vec<(usize, Drawn, usize)>,
}
