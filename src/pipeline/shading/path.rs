//! One material's per-fragment shading datapath through the units, GeForce3 style.
//!
//! ```text
//!  N, L, (L+V)/2 ─► cube_map_address ─► texture_sampler (normalisation cube) ─► N̂, L̂, Ĥ  (RGB u8)
//!  N̂·L̂, N̂·Ĥ     ─► texture_combiner DOT3_RGB (4·Σ(a−½)(b−½), clamped to [0, 1]) ─► n·l, n·h (u8)
//!  diffuse       ─► texture_combiner MODULATE(n·l, albedo·E/π)                     ─► u8 RGB
//!  specular:  Blinn–Phong  ─► specular_lookup(n·h) = clamp(K·x^s / S) ─► MODULATE(·, n·l), RGB_SCALE S
//!             other models ─► factor textures (texture_sampler × modulate × scale), R·cos θ_i·E
//!  total         ─► texture_combiner ADD(diffuse, specular), saturating                ─► u8 RGB
//! ```
//!
//! What is host f64 and what is hardware: the vectors N, L, V arrive as the
//! interpolator's fixed-point words (here: the host's f64 vectors quantised to the
//! address unit's s16.8 input words per pixel); everything after that is the units'
//! integer kernels, except the factor textures' coordinates, which the host computes
//! per pixel from (ω_i, ω_o) (on a GeForce3 the vertex program computes them per vertex
//! and the rasteriser interpolates them — per pixel is the quality's upper bound; see
//! `factor`).
//!
//! Levels: a pixel's 8-bit level is 255 · clamp(R · cos θ_i · E), the same scale as
//! [`super::sphere::SphereView::reference_levels`].

use super::factor::{homomorphic, svd, FactorMethod, FactorRenderer, FactorTarget};
use super::normalize_cube::{NormalizeCube, NormalizeCubeConfig, NormalizeCubeCounters};
use crate::reference::brdf::{Brdf, ShadingFrame};
use crate::report::elaboration::Elaborated;
use crate::scene::limits::GlRounding;
use crate::scene::math::Vec3;
use rtl_model::units::specular_lookup::{SpecularLookup, SpecularLookupConfig};
use rtl_model::units::texture_combiner::{
    CombineFunction, CombineSource, TextureCombiner, TextureCombinerConfig, TextureCombinerIn,
};
use rtl_model::units::texture_sampler::{TextureSampler, TextureSamplerConfig};
use rtl_model::{ConfigError, Counters, Timing, Unit, UnitSummary};
use std::collections::BTreeMap;

/// The specular part of a material, as the hardware renders it.
pub enum SpecularLobe {
    /// No specular term (Lambert).
    None,
    /// k·c^s by the specular lookup table, modulated by n·l: the lobe R = k·c^s whose
    /// radiance is R·cos θ_i·E (`k` includes any normalisation). c = n·h for
    /// Blinn–Phong ([`LobeVector::Half`]), c = r·l for Phong ([`LobeVector::Mirror`]).
    Lookup {
        k: f64,
        exponent: f64,
        vector: LobeVector,
    },
    /// Any model, by factor textures: separable (SVD, Kautz–McCool) or homomorphic
    /// (McCool et al.), of R·cos θ_i (`FactorTarget::BrdfCosine`, the specular lobes)
    /// or of R alone with cos θ_i·E as the constant colour (`FactorTarget::Brdf`, the
    /// per-vertex diffuse colour of GL lighting, here per pixel from the host: the
    /// diffuse Oren–Nayar, whose R·cos θ_i is far from a product of h and d factors).
    Factored(Box<dyn Brdf>, FactorMethod, FactorTarget),
}

/// The pair of vectors whose DOT3 indexes the specular lookup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LobeVector {
    /// N̂ · Ĥ, H = (L + V)/2 as the interpolator delivers it (Blinn–Phong).
    Half,
    /// R̂ · L̂, R = 2(n·v)n − v the view's mirror direction, as GL_REFLECTION_MAP
    /// texgen delivers it per vertex (Phong).
    Mirror,
}

/// Widths and sizes of the shading path (what a sweep changes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathConfig {
    pub cube: NormalizeCubeConfig,
    /// The specular lookup's table (its `exponent` field is replaced by the lobe's).
    pub lookup: SpecularLookupConfig,
    /// Factor textures: side (texels) and texel bits.
    pub factor_resolution: u32,
    pub factor_bits: u32,
    /// Which factorisation a non-Blinn–Phong lobe gets.
    pub factor_method: FactorMethod,
    /// E: the light's irradiance at normal incidence (level = 255·R·cos θ_i·E).
    pub irradiance: f64,
    /// The factored lobes' chain and filter rounding and the normalisation cube's
    /// filter rounding (the scene's `[rounding]`; default the GeForce-style per-stage
    /// chain and product-weight filter).
    pub rounding: GlRounding,
}

impl Default for PathConfig {
    /// GeForce defaults: 64² × 6 normalisation cube of 8-bit RGB, 256 × 8-bit lookup
    /// with linear interpolation, 64² factor textures of 8 bits, E = π (a white
    /// Lambert surface lit head-on is full scale).
    fn default() -> Self {
        PathConfig {
            cube: NormalizeCubeConfig::geforce(),
            lookup: SpecularLookupConfig::geforce(),
            factor_resolution: 64,
            factor_bits: 8,
            factor_method: FactorMethod::Svd,
            irradiance: std::f64::consts::PI,
            rounding: GlRounding::default(),
        }
    }
}

/// The specular datapath, built.
enum SpecularPath {
    None,
    Lookup {
        lut: SpecularLookup,
        /// MODULATE(lut, n·l) with RGB_SCALE = K's power-of-two headroom.
        modulate: TextureCombiner,
        vector: LobeVector,
    },
    Factored(FactorRenderer),
}

/// One fragment's result: RGB levels and the specular term alone (what the glare
/// conditions read as the highlight's I_s).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shaded {
    pub rgb: [u32; 3],
    pub specular: u32,
}

/// A material's datapath: the normalisation cube, the DOT3 stage, the diffuse and
/// specular stages and the final ADD.
pub struct ShadingPath {
    cube: NormalizeCube,
    dot3: TextureCombiner,
    /// MODULATE(n·l, albedo) and the albedo·E/π constant colour (u8 RGB).
    diffuse: Option<(TextureCombiner, [u32; 3])>,
    specular: SpecularPath,
    add: TextureCombiner,
}

/// Counters of a shading pass, per unit (the normalisation cube's two units apart).
pub type PathCounters = BTreeMap<String, Counters>;

/// Stage names: the counters' keys and the elaboration rows.
pub const CUBE_ADDRESS: &str = "cube_map_address (normalisation cube)";
pub const CUBE_SAMPLER: &str = "texture_sampler (normalisation cube)";
pub const DOT3: &str = "texture_combiner (DOT3_RGB)";
pub const MODULATE_DIFFUSE: &str = "texture_combiner (MODULATE diffuse)";
pub const LOOKUP: &str = "specular_lookup";
pub const MODULATE_SPECULAR: &str = "texture_combiner (MODULATE specular)";
pub const FACTORS: &str = "factor textures (texture_sampler × modulate)";
pub const ADD: &str = "texture_combiner (ADD)";

/// A stage's counters, counting one more word in and out (the kernels count their
/// events; the words and, in [`ShadingPath::close_counters`], the clocks are the
/// driver's part).
fn stage_counters<'a>(ctr: &'a mut PathCounters, stage: &str) -> &'a mut Counters {
    let c = ctr.entry(stage.to_string()).or_default();
    c.pixels_in += 1;
    c.pixels_out += 1;
    c
}

/// An 8-bit combiner stage (the path's width).
fn stage(f: CombineFunction, scale: u32) -> Result<TextureCombiner, ConfigError> {
    combiner_stage(8, f, scale)
}

/// A `bits`-wide combiner stage reading Arg0 = TEXTURE, Arg1 = PREVIOUS,
/// Arg2 = CONSTANT, with RGB_SCALE `scale` (the shading reproductions and the sweep
/// build their DOT3 stages here too).
pub fn combiner_stage(
    bits: u32,
    f: CombineFunction,
    scale: u32,
) -> Result<TextureCombiner, ConfigError> {
    TextureCombinerConfig {
        bits,
        combine_rgb: f,
        combine_alpha: CombineFunction::Replace,
        source_rgb: [
            CombineSource::Texture,
            CombineSource::Previous,
            CombineSource::Constant,
        ],
        rgb_scale: scale,
        ..TextureCombinerConfig::geforce()
    }
    .build()
}

/// round(x · 255), x clamped to [0, 1].
fn code8(x: f64) -> u32 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u32
}

/// The smallest GL scale S ∈ {1, 2, 4} with K/S ≤ 1 (4 when none is: the lookup's
/// entries then clamp near the peak, where the image saturates anyway).
fn headroom(k: f64) -> u32 {
    [1u32, 2, 4]
        .into_iter()
        .find(|&s| k <= s as f64)
        .unwrap_or(4)
}

impl ShadingPath {
    /// Build the path of a material: an optional Lambert albedo (RGB in [0, 1]) and a
    /// specular lobe. Errors name the field (`shading.<unit>.<field>`).
    pub fn new(
        albedo: Option<[f64; 3]>,
        lobe: SpecularLobe,
        cfg: &PathConfig,
    ) -> Result<Self, ConfigError> {
        let e = rtl_model::error::check_finite("shading.irradiance", cfg.irradiance)?;
        let specular = match lobe {
            SpecularLobe::None => SpecularPath::None,
            SpecularLobe::Lookup {
                k,
                exponent,
                vector,
            } => {
                let k = rtl_model::error::check_finite("shading.specular.k", k * e)?.max(0.0);
                let s = headroom(k);
                let mut lut = SpecularLookupConfig {
                    exponent: exponent.clamp(1.0, 1e4),
                    ..cfg.lookup
                }
                .build()
                .map_err(|e| e.within("shading"))?;
                // The host writes clamp(K/S · x^s) so that the RGB_SCALE S stage
                // restores K (entries round half up, as the unit's own generator).
                let (log2, bits) = (cfg.lookup.table_log2, cfg.lookup.entry_bits);
                let top = ((1u64 << bits) - 1) as f64;
                let n = ((1u64 << log2) - 1) as f64;
                let words: Vec<u64> = (0..1u64 << log2)
                    .map(|j| {
                        let x = j as f64 / n;
                        ((k / s as f64 * x.powf(exponent)).min(1.0) * top + 0.5).floor() as u64
                    })
                    .collect();
                lut.load_table(&words).map_err(|e| e.within("shading"))?;
                SpecularPath::Lookup {
                    lut,
                    modulate: stage(CombineFunction::Modulate, s)?,
                    vector,
                }
            }
            SpecularLobe::Factored(brdf, method, target) => {
                // Values above 1/E saturate the 8-bit output: fitting them as 1/E keeps
                // a sharp peak from stretching the textures' range (and the scale).
                let ceiling = if e > 0.0 { 1.0 / e } else { f64::INFINITY };
                let (b, t, r) = (brdf.as_ref(), target, cfg.factor_resolution);
                let fact = match method {
                    FactorMethod::Svd => svd::factorise(
                        b,
                        t,
                        r,
                        &svd::SvdParams {
                            ceiling,
                            ..svd::SvdParams::default()
                        },
                    ),
                    FactorMethod::Homomorphic => homomorphic::factorise(
                        b,
                        t,
                        r,
                        &homomorphic::HomomorphicParams {
                            ceiling,
                            ..homomorphic::HomomorphicParams::default()
                        },
                        None,
                    )
                    .map(|(f, _)| f),
                }
                .map_err(|e| e.within("shading.factor"))?;
                SpecularPath::Factored(FactorRenderer::with_rounding(
                    &fact,
                    cfg.factor_bits,
                    e,
                    cfg.rounding,
                )?)
            }
        };
        let diffuse = match albedo {
            Some(a) => {
                let mut k = [0u32; 3];
                for (c, (&x, out)) in a.iter().zip(k.iter_mut()).enumerate() {
                    let x = rtl_model::error::check_finite(&format!("shading.albedo[{c}]"), x)?;
                    *out = code8(x * e / std::f64::consts::PI);
                }
                Some((stage(CombineFunction::Modulate, 1)?, k))
            }
            None => None,
        };
        Ok(ShadingPath {
            cube: NormalizeCube::with_rounding(cfg.cube, &cfg.rounding)?,
            dot3: stage(CombineFunction::Dot3Rgb, 1)?,
            diffuse,
            specular,
            add: stage(CombineFunction::Add, 1)?,
        })
    }

    /// The path's factored specular lobe, if it has one.
    pub fn factored(&self) -> Option<&FactorRenderer> {
        match &self.specular {
            SpecularPath::Factored(f) => Some(f),
            _ => None,
        }
    }

    /// The diffuse term's stages — normalisation cube, DOT3, MODULATE by the albedo
    /// constant — when the path has one: the cube and the albedo's u8 codes.
    pub fn diffuse_stages(&self) -> Option<(&NormalizeCube, [u32; 3])> {
        self.diffuse
            .as_ref()
            .map(|(_, albedo)| (&self.cube, *albedo))
    }

    /// The normalisation cube every term reads its vectors through.
    pub fn cube(&self) -> &NormalizeCube {
        &self.cube
    }

    /// The normalised direction of a world vector (components in [−1, 1]) through the
    /// cube map, as RGBA8 with alpha 255.
    fn normalised(&self, v: Vec3, ctr: &mut PathCounters) -> Result<[u32; 4], ConfigError> {
        let mut cc = NormalizeCubeCounters::default();
        let words = self.cube.vector_words([v.x, v.y, v.z], &mut cc.address)?;
        let rgb = self.cube.normalize(&words, &mut cc);
        *stage_counters(ctr, CUBE_ADDRESS) += cc.address;
        *stage_counters(ctr, CUBE_SAMPLER) += cc.sampler;
        Ok([rgb[0], rgb[1], rgb[2], 255])
    }

    /// DOT3_RGB of two packed vectors: the clamped dot product as a u8 code.
    fn dot(&self, a: [u32; 4], b: [u32; 4], ctr: &mut PathCounters) -> u32 {
        let c = stage_counters(ctr, DOT3);
        let input = TextureCombinerIn {
            texture: a,
            previous: b,
            ..TextureCombinerIn::default()
        };
        self.dot3.combine(&input, c)[0]
    }

    /// One fragment: the frame at the surface point (world), the unit vectors toward
    /// the light and the viewer (world).
    pub fn shade(
        &self,
        frame: &ShadingFrame,
        light: Vec3,
        view: Vec3,
        ctr: &mut PathCounters,
    ) -> Result<Shaded, ConfigError> {
        let n = self.normalised(frame.n, ctr)?;
        let l = self.normalised(light, ctr)?;
        let nl = self.dot(n, l, ctr);
        let diffuse = match &self.diffuse {
            Some((modulate, albedo)) => {
                let c = stage_counters(ctr, MODULATE_DIFFUSE);
                let input = TextureCombinerIn {
                    texture: [nl, nl, nl, 255],
                    previous: [albedo[0], albedo[1], albedo[2], 255],
                    ..TextureCombinerIn::default()
                };
                let o = modulate.combine(&input, c);
                [o[0], o[1], o[2]]
            }
            None => [0; 3],
        };
        let specular = match &self.specular {
            SpecularPath::None => 0,
            SpecularPath::Lookup {
                lut,
                modulate,
                vector,
            } => {
                let nh = match vector {
                    LobeVector::Half => {
                        let h = self.normalised((light + view) * 0.5, ctr)?;
                        self.dot(n, h, ctr)
                    }
                    LobeVector::Mirror => {
                        let nn = frame.n;
                        let r = self.normalised(nn * (2.0 * nn.dot(view)) - view, ctr)?;
                        self.dot(r, l, ctr)
                    }
                };
                let t = lut.lookup(nh as i32, stage_counters(ctr, LOOKUP));
                let c = stage_counters(ctr, MODULATE_SPECULAR);
                let input = TextureCombinerIn {
                    texture: [t, t, t, 255],
                    previous: [nl, nl, nl, 255],
                    ..TextureCombinerIn::default()
                };
                modulate.combine(&input, c)[0]
            }
            SpecularPath::Factored(f) => {
                let c = stage_counters(ctr, FACTORS);
                f.shade(frame.to_local(light), frame.to_local(view), c)?
            }
        };
        let c = stage_counters(ctr, ADD);
        let input = TextureCombinerIn {
            texture: [specular, specular, specular, 255],
            previous: [diffuse[0], diffuse[1], diffuse[2], 255],
            ..TextureCombinerIn::default()
        };
        let o = self.add.combine(&input, c);
        Ok(Shaded {
            rgb: [o[0], o[1], o[2]],
            specular,
        })
    }

    /// Which of the shading units this material's path elaborates, and which it leaves
    /// out (with the gates that saves). `fragments` is the number of fragments shaded
    /// (the cycles a left-out unit would have run).
    pub fn elaboration(&self, fragments: u64) -> Vec<Elaborated> {
        let used = |summary: UnitSummary, name: &str| Elaborated {
            name: name.to_string(),
            summary: Some(summary),
            left_out: None,
            gates_saved: 0.0,
            cycles_saved: 0,
        };
        let left = |summary: UnitSummary, name: &str, why: &str| Elaborated {
            name: name.to_string(),
            gates_saved: summary.gates_nand2,
            summary: None,
            left_out: Some(why.to_string()),
            cycles_saved: fragments,
        };
        let mut out = vec![
            used(UnitSummary::of(self.cube.address_unit()), CUBE_ADDRESS),
            used(UnitSummary::of(self.cube.sampler()), CUBE_SAMPLER),
            used(UnitSummary::of(&self.dot3), DOT3),
        ];
        match &self.diffuse {
            Some((m, _)) => out.push(used(UnitSummary::of(m), MODULATE_DIFFUSE)),
            None => out.push(left(
                UnitSummary::of(&self.add),
                MODULATE_DIFFUSE,
                "no diffuse term",
            )),
        }
        match &self.specular {
            SpecularPath::Lookup { lut, modulate, .. } => {
                out.push(used(UnitSummary::of(lut), LOOKUP));
                out.push(used(UnitSummary::of(modulate), MODULATE_SPECULAR));
            }
            _ => {
                let why = "no Phong or Blinn–Phong lobe";
                out.push(left(
                    UnitSummary::of(&SpecularLookup::geforce()),
                    LOOKUP,
                    why,
                ));
                out.push(left(UnitSummary::of(&self.add), MODULATE_SPECULAR, why));
            }
        }
        match &self.specular {
            SpecularPath::Factored(f) => {
                let units = f.summaries();
                let n = units.len();
                for (i, s) in units.into_iter().enumerate() {
                    let name = if i + 1 == n {
                        "modulate_chain (factor product)".to_string()
                    } else {
                        format!("texture_sampler (factor {i})")
                    };
                    out.push(used(s, &name));
                }
            }
            _ => {
                // Two 64² factor textures of 8 bits and their modulate chain, at the defaults.
                let sampler = TextureSampler::new(
                    TextureSamplerConfig::geforce_2d(64, 64),
                    &vec![0; 64 * 64],
                )
                .map(|t| UnitSummary::of(&t).gates_nand2)
                .unwrap_or(0.0);
                out.push(Elaborated {
                    name: FACTORS.into(),
                    summary: None,
                    left_out: Some("no factored BRDF".into()),
                    gates_saved: 2.0 * sampler
                        + GlRounding::default()
                            .chain(8)
                            .map(|c| UnitSummary::of(&c).gates_nand2)
                            .unwrap_or(0.0),
                    cycles_saved: fragments,
                });
            }
        }
        out.push(used(UnitSummary::of(&self.add), ADD));
        out
    }

    /// Fill in each stage's clocks and stalls from its unit's timing, for the words it
    /// streamed (one stage instance per row; a stage used several times per fragment,
    /// like the cube map for N, L and H, takes a clock per use): cycles =
    /// (n − 1)·II + latency + 1, as the span driver counts them.
    pub fn close_counters(&self, ctr: &mut PathCounters) {
        let lut_timing = match &self.specular {
            SpecularPath::Lookup { lut, modulate, .. } => Some((lut.timing(), modulate.timing())),
            _ => None,
        };
        for (name, c) in ctr.iter_mut() {
            let t = match name.as_str() {
                CUBE_ADDRESS => self.cube.address_unit().timing(),
                CUBE_SAMPLER => self.cube.sampler().timing(),
                LOOKUP => match lut_timing {
                    Some((t, _)) => t,
                    None => continue,
                },
                MODULATE_SPECULAR => match lut_timing {
                    Some((_, t)) => t,
                    None => continue,
                },
                // The factor product: the samplers read in parallel, then the modulates.
                FACTORS => Timing {
                    latency: self.cube.sampler().timing().latency + self.dot3.timing().latency,
                    ii: 1,
                },
                _ => self.dot3.timing(),
            };
            c.cycles = t.span_cycles(c.pixels_in);
            c.stalls = t.span_stalls(c.pixels_in);
        }
    }

    /// The derived bound (8-bit levels) on the Lambert term's error against
    /// 255·(ρE/π)·max(n·l, 0) for unit f64 vectors n, l, when the material has no
    /// specular term:
    /// - each vector reaches the DOT3 stage with per-component error ≤ κ codes (the
    ///   normalisation cube's derived component bound, edge band included) plus the
    ///   quantisation of its input words (≤ √3/2·2^−Fi texels on a vector of length
    ///   s/2 texels): |a' − a| ≤ V = √3·2κ/255 + √3·2^−Fi/s;
    /// - |a'·b' − a·b| ≤ V·|b'| + |a|·V ≤ V(2 + V); DOT3_RGB evaluates a'·b' exactly
    ///   and rounds once (½ LSB); the clamp to [0, 1] is 1-Lipschitz: the n·l code is
    ///   off by ε₁ ≤ 255·V(2 + V) + ½;
    /// - MODULATE(n·l, A), A = round(255·k), k = ρE/π ≤ 1: (255c + ε₁)(255k + ε₂)/255
    ///   with |ε₂| ≤ ½ is off by ≤ ½ + k·ε₁ + ε₁/510, plus ½ for its rounding;
    /// - ADD of a zero specular is exact.
    ///
    /// Total ≤ 1 + ε₁·(k + 1/510).
    pub fn diffuse_error_bound(&self) -> Option<f64> {
        let (_, albedo) = self.diffuse.as_ref()?;
        if !matches!(self.specular, SpecularPath::None) {
            return None;
        }
        let b = self.cube.bounds();
        let a = self.cube.config().address;
        let s = (a.side_log2 as f64).exp2();
        let sqrt3 = 3f64.sqrt();
        let v =
            sqrt3 * 2.0 * b.component_edge / 255.0 + sqrt3 * (-(a.in_frac_bits as f64)).exp2() / s;
        let eps1 = 255.0 * v * (2.0 + v) + 0.5;
        let k = albedo.iter().copied().max().unwrap_or(0) as f64 / 255.0 + 0.5 / 255.0;
        Some(1.0 + eps1 * (k + 1.0 / 510.0))
    }

    /// The stages, in a line (for tables): e.g.
    /// `cube 64² → DOT3 → MODULATE diffuse + lookup 256×8b → MODULATE ×2 → ADD`.
    pub fn describe(&self) -> String {
        let c = self.cube.config();
        let mut s = format!("cube {}² → DOT3", c.face_side);
        if self.diffuse.is_some() {
            s.push_str(" → MODULATE diffuse");
        }
        match &self.specular {
            SpecularPath::None => {}
            SpecularPath::Lookup {
                lut,
                modulate,
                vector,
            } => {
                let l = lut.config();
                s.push_str(&format!(
                    " + lookup({}) {}×{}b → MODULATE ×{}",
                    match vector {
                        LobeVector::Half => "n·h",
                        LobeVector::Mirror => "r·l",
                    },
                    1u32 << l.table_log2,
                    l.entry_bits,
                    modulate.config().rgb_scale
                ));
            }
            SpecularPath::Factored(f) => {
                s.push_str(&format!(
                    " + {} factors {}b (×2^{})",
                    f.method().name(),
                    f.texel_bits(),
                    f.shift()
                ));
            }
        }
        s.push_str(" → ADD");
        s
    }
}
