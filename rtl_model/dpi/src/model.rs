//! A unit behind one handle: config built (the error names the field), state carried
//! from transaction to transaction from the unit's reset state, stepped on the values
//! of its Verilog ports.

use rtl_model::units::bloom_flare_modulator::{BloomFlareModulatorConfig, LumIn};
use rtl_model::units::modulate::{Modulate, ModulateIn, ModulateMode};
use rtl_model::units::texture_sampler::{
    AddressMode, Filter, FilterRounding, TextureSampler, TextureSamplerConfig, TextureSamplerIn,
    WeightRounding,
};
use rtl_model::{Counters, Unit};
use std::collections::BTreeMap;

/// Environment variable naming a transaction (0-based) whose first output field gets
/// its least significant bit flipped: the testbench's own check that a wrong model
/// output is caught. Read when a handle is made.
pub const CORRUPT_ENV: &str = "GLARE_DPI_CORRUPT";

/// What the handle needs of a unit, type-erased.
trait Stepper {
    fn name(&self) -> &'static str;
    fn latency(&self) -> u32;
    fn ii(&self) -> u32;
    /// Port widths, in `in_signals` / `out_signals` order.
    fn in_widths(&self) -> Vec<u32>;
    fn out_widths(&self) -> Vec<u32>;
    /// The kernel on one transaction: input port values in, output port values out.
    fn step(&mut self, ins: &[u64]) -> Vec<u64>;
    /// Entry `index` of the table read through the ports named `table`.
    fn table(&self, table: &str, index: usize) -> Option<u64>;
}

type Make<U> = fn(&U, &[u64]) -> <U as Unit>::In;
type Table<U> = fn(&U, &str, usize) -> Option<u64>;

struct Of<U: Unit> {
    u: U,
    st: U::State,
    ctr: Counters,
    make: Make<U>,
    table: Table<U>,
    in_w: Vec<u32>,
    out_w: Vec<u32>,
}

impl<U: Unit> Of<U> {
    fn new(u: U, st: U::State, n_in: usize, make: Make<U>, table: Table<U>) -> Self {
        let probe = make(&u, &vec![0; n_in]);
        let in_w = u.in_signals(&probe).iter().map(|s| s.width).collect();
        let y = u.kernel(&mut st.clone(), &probe, &mut Counters::default());
        let out_w = u.out_signals(&y).iter().map(|s| s.width).collect();
        Of {
            u,
            st,
            ctr: Counters::default(),
            make,
            table,
            in_w,
            out_w,
        }
    }
}

impl<U: Unit> Stepper for Of<U> {
    fn name(&self) -> &'static str {
        self.u.name()
    }
    fn latency(&self) -> u32 {
        self.u.timing().latency
    }
    fn ii(&self) -> u32 {
        self.u.timing().ii
    }
    fn in_widths(&self) -> Vec<u32> {
        self.in_w.clone()
    }
    fn out_widths(&self) -> Vec<u32> {
        self.out_w.clone()
    }
    fn step(&mut self, ins: &[u64]) -> Vec<u64> {
        let x = (self.make)(&self.u, ins);
        let y = self.u.kernel(&mut self.st, &x, &mut self.ctr);
        self.u.out_signals(&y).iter().map(|s| s.value).collect()
    }
    fn table(&self, table: &str, index: usize) -> Option<u64> {
        (self.table)(&self.u, table, index)
    }
}

/// A unit with its state: what a C handle points to.
pub struct Model {
    unit: Box<dyn Stepper>,
    /// Transactions stepped so far.
    n: u64,
    corrupt: Option<u64>,
}

fn mask(w: u32) -> u64 {
    if w >= 64 {
        u64::MAX
    } else {
        (1u64 << w) - 1
    }
}

/// Sign-extend the low `w` bits of a port value.
fn sx(v: u64, w: u32) -> i32 {
    let sh = 64 - w.clamp(1, 64);
    ((v << sh) as i64 >> sh) as i32
}

fn no_table<U>(_: &U, _: &str, _: usize) -> Option<u64> {
    None
}

impl Model {
    fn wrap(unit: Box<dyn Stepper>) -> Model {
        let corrupt = std::env::var(CORRUPT_ENV)
            .ok()
            .and_then(|s| s.trim().parse().ok());
        Model {
            unit,
            n: 0,
            corrupt,
        }
    }

    pub fn name(&self) -> &'static str {
        self.unit.name()
    }
    pub fn latency(&self) -> u32 {
        self.unit.latency()
    }
    pub fn ii(&self) -> u32 {
        self.unit.ii()
    }
    pub fn in_widths(&self) -> Vec<u32> {
        self.unit.in_widths()
    }
    pub fn out_widths(&self) -> Vec<u32> {
        self.unit.out_widths()
    }
    pub fn in_bits(&self) -> u32 {
        self.unit.in_widths().iter().sum()
    }
    pub fn out_bits(&self) -> u32 {
        self.unit.out_widths().iter().sum()
    }
    pub fn transactions(&self) -> u64 {
        self.n
    }
    pub fn table(&self, table: &str, index: usize) -> Option<u64> {
        self.unit.table(table, index)
    }

    /// One transaction on the input port values (each masked to its port width):
    /// the output port values. With [`CORRUPT_ENV`] set to this transaction's index,
    /// the first output's least significant bit is flipped.
    pub fn step(&mut self, ins: &[u64]) -> Vec<u64> {
        let ins: Vec<u64> = ins
            .iter()
            .zip(self.unit.in_widths())
            .map(|(&v, w)| v & mask(w))
            .collect();
        let mut out = self.unit.step(&ins);
        if self.corrupt == Some(self.n) {
            if let Some(o) = out.first_mut() {
                *o ^= 1;
            }
        }
        self.n += 1;
        out
    }

    /// One transaction on the packed input word (the ports concatenated, the first
    /// in the most significant bits; 32-bit words, least significant word first, as
    /// a SystemVerilog `bit [N-1:0]` reaches C): the packed output word.
    pub fn step_packed(&mut self, in_words: &[u32], out_words: &mut [u32]) {
        let get = |pos: u32, w: u32| -> u64 {
            let mut v = 0u64;
            for b in 0..w.min(64) {
                let p = pos + b;
                let word = in_words.get((p / 32) as usize).copied().unwrap_or(0);
                v |= (((word >> (p % 32)) & 1) as u64) << b;
            }
            v
        };
        let in_w = self.unit.in_widths();
        let mut pos = in_w.iter().sum::<u32>();
        let ins: Vec<u64> = in_w
            .iter()
            .map(|&w| {
                pos -= w;
                get(pos, w)
            })
            .collect();
        let outs = self.step(&ins);
        out_words.iter_mut().for_each(|w| *w = 0);
        let out_w = self.unit.out_widths();
        let mut pos = out_w.iter().sum::<u32>();
        for (&v, &w) in outs.iter().zip(&out_w) {
            pos -= w;
            for b in 0..w.min(64) {
                let p = pos + b;
                if let Some(word) = out_words.get_mut((p / 32) as usize) {
                    *word |= (((v >> b) & 1) as u32) << (p % 32);
                }
            }
        }
    }

    /// modulate at `bits` with `mode` 0 exact, 1 shift, 2 plus_one, 3 trunc_div.
    pub fn modulate(bits: u32, mode: u32) -> Result<Model, String> {
        let mode = *ModulateMode::ALL.get(mode as usize).ok_or_else(|| {
            format!(
                "modulate.mode: {mode} is not a mode (0 exact, 1 shift, 2 plus_one, 3 trunc_div)"
            )
        })?;
        let u = Modulate::new(bits, mode).map_err(|e| e.to_string())?;
        let make: Make<Modulate> = |_, v| ModulateIn {
            a: v[0] as u32,
            b: v[1] as u32,
        };
        Ok(Model::wrap(Box::new(Of::new(u, (), 2, make, no_table))))
    }

    /// bloom_flare_modulator (radial correction off) with its shape table
    /// ((2^k+1)² entries in [0, 1], v index major) and falloff table (2^m+1 entries).
    pub fn bloom_flare_modulator(
        cfg: BloomFlareModulatorConfig,
        shape: &[f64],
        falloff: &[f64],
    ) -> Result<Model, String> {
        let u = cfg.build(shape, falloff).map_err(|e| e.to_string())?;
        // The coordinate width is a config field: read from the unit.
        let make: Make<rtl_model::units::bloom_flare_modulator::BloomFlareModulator> = |u, v| {
            let cw = u.lum_widths().coord_frac_bits + 2;
            LumIn {
                u: sx(v[0], cw),
                v: sx(v[1], cw),
                gain: [v[2] as u32, v[3] as u32, v[4] as u32],
            }
        };
        let table: Table<rtl_model::units::bloom_flare_modulator::BloomFlareModulator> =
            |u, name, i| {
                let codes = match name {
                    "shape" => u.shape_codes(),
                    "falloff" => u.falloff_codes(),
                    _ => return None,
                };
                codes.get(i).map(|&c| c as u64)
            };
        Ok(Model::wrap(Box::new(Of::new(u, (), 5, make, table))))
    }

    /// texture_sampler with its texels (w·h·d·channels codes, texel (x, y, z)
    /// channel c at ((z·h + y)·w + x)·channels + c).
    pub fn texture_sampler(cfg: TextureSamplerConfig, texels: &[u32]) -> Result<Model, String> {
        let dims = cfg.dims as usize;
        let u = TextureSampler::new(cfg, texels).map_err(|e| e.to_string())?;
        let make: Make<TextureSampler> = |u, v| {
            let w = u.coord_bits();
            let mut coord = [0i32; 3];
            for (c, &x) in coord.iter_mut().zip(v) {
                *c = sx(x, w);
            }
            TextureSamplerIn { coord }
        };
        let table: Table<TextureSampler> = |u, name, i| {
            if name != "texels" && name != "texel" {
                return None;
            }
            let [w, h, d] = u.size();
            let ch = u.channels() as usize;
            let (t, c) = (i / ch, (i % ch) as u32);
            let (x, y, z) = (
                t % w as usize,
                (t / w as usize) % h as usize,
                t / (w * h) as usize,
            );
            (z < d as usize).then(|| u.texel(x as u32, y as u32, z as u32, c) as u64)
        };
        Ok(Model::wrap(Box::new(Of::new(u, (), dims, make, table))))
    }

    /// A unit from a text spec, `key=value` pairs separated by blanks (the form a
    /// SystemVerilog parameter carries): the config fields by name (missing fields
    /// keep the unit's GeForce default) and `seed`, from which the tables are drawn
    /// (uniform in [0, 1] for the luminance tables, uniform codes for texels). An
    /// unknown key or a bad value is an error naming it.
    pub fn open(unit: &str, spec: &str) -> Result<Model, String> {
        let mut kv = Spec::parse(unit, spec)?;
        let seed = kv.take("seed", 1u64)?;
        let mut rng = SplitMix(seed);
        let m = match unit {
            "modulate" => {
                let bits = kv.take("bits", 8u32)?;
                let mode = kv.take_enum("mode", &["exact", "shift", "plus_one", "trunc_div"], 0)?;
                Model::modulate(bits, mode as u32)?
            }
            "bloom_flare_modulator" => {
                let d = BloomFlareModulatorConfig::default();
                let cfg = BloomFlareModulatorConfig {
                    coord_frac_bits: kv.take("coord_frac_bits", d.coord_frac_bits)?,
                    shape_log2: kv.take("shape_log2", d.shape_log2)?,
                    shape_bits: kv.take("shape_bits", d.shape_bits)?,
                    falloff_log2: kv.take("falloff_log2", d.falloff_log2)?,
                    falloff_bits: kv.take("falloff_bits", d.falloff_bits)?,
                    weight_bits: kv.take("weight_bits", d.weight_bits)?,
                    gain_int_bits: kv.take("gain_int_bits", d.gain_int_bits)?,
                    gain_frac_bits: kv.take("gain_frac_bits", d.gain_frac_bits)?,
                    out_bits: kv.take("out_bits", d.out_bits)?,
                    ..d
                };
                // Table lengths before build (a bad width is the build's error).
                let side = 1usize << cfg.shape_log2.min(16);
                let shape: Vec<f64> = (0..(side + 1) * (side + 1)).map(|_| rng.unit()).collect();
                let falloff: Vec<f64> = (0..(1usize << cfg.falloff_log2.min(16)) + 1)
                    .map(|_| rng.unit())
                    .collect();
                Model::bloom_flare_modulator(cfg, &shape, &falloff)?
            }
            "texture_sampler" => {
                let d = TextureSamplerConfig::geforce();
                let wr = ["round", "truncate", "round_half_even"];
                let fr = ["product_weights", "successive_lerps"];
                let am = ["clamp", "wrap"];
                let cfg = TextureSamplerConfig {
                    dims: kv.take("dims", d.dims)?,
                    size: [
                        kv.take("size_w", d.size[0])?,
                        kv.take("size_h", d.size[1])?,
                        kv.take("size_d", d.size[2])?,
                    ],
                    channels: kv.take("channels", d.channels)?,
                    texel_bits: kv.take("texel_bits", d.texel_bits)?,
                    coord_int_bits: kv.take("coord_int_bits", d.coord_int_bits)?,
                    coord_frac_bits: kv.take("coord_frac_bits", d.coord_frac_bits)?,
                    weight_bits: kv.take("weight_bits", d.weight_bits)?,
                    weight_rounding: [
                        WeightRounding::Round,
                        WeightRounding::Truncate,
                        WeightRounding::RoundHalfEven,
                    ][kv.take_enum("weight_rounding", &wr, 0)?],
                    filter_rounding: [
                        FilterRounding::ProductWeights,
                        FilterRounding::SuccessiveLerps,
                    ][kv.take_enum("filter_rounding", &fr, 0)?],
                    filter: [Filter::Nearest, Filter::Linear]
                        [kv.take_enum("filter", &["nearest", "linear"], 1)?],
                    address: [
                        [AddressMode::Clamp, AddressMode::Wrap][kv.take_enum("address_s", &am, 0)?],
                        [AddressMode::Clamp, AddressMode::Wrap][kv.take_enum("address_t", &am, 0)?],
                        [AddressMode::Clamp, AddressMode::Wrap][kv.take_enum("address_r", &am, 0)?],
                    ],
                    texels_per_clock: kv.take("texels_per_clock", d.texels_per_clock)?,
                };
                cfg.validate().map_err(|e| e.to_string())?;
                let n = cfg.texel_count() as usize * cfg.channels as usize;
                let max = mask(cfg.texel_bits);
                let texels: Vec<u32> = (0..n).map(|_| (rng.next() & max) as u32).collect();
                Model::texture_sampler(cfg, &texels)?
            }
            _ => {
                return Err(format!(
                    "unit: '{unit}' has no DPI model (modulate, bloom_flare_modulator, texture_sampler)"
                ))
            }
        };
        kv.finish()?;
        Ok(m)
    }
}

/// `key=value` pairs of [`Model::open`].
struct Spec {
    unit: String,
    kv: BTreeMap<String, String>,
}

impl Spec {
    fn parse(unit: &str, spec: &str) -> Result<Spec, String> {
        let mut kv = BTreeMap::new();
        for tok in spec.split_whitespace() {
            let (k, v) = tok
                .split_once('=')
                .ok_or_else(|| format!("spec: '{tok}' is not key=value"))?;
            kv.insert(k.to_string(), v.to_string());
        }
        Ok(Spec {
            unit: unit.to_string(),
            kv,
        })
    }

    fn take<T: std::str::FromStr>(&mut self, key: &str, default: T) -> Result<T, String> {
        match self.kv.remove(key) {
            None => Ok(default),
            Some(v) => v
                .parse()
                .map_err(|_| format!("{}.{key}: '{v}' is not a number", self.unit)),
        }
    }

    fn take_enum(&mut self, key: &str, names: &[&str], default: usize) -> Result<usize, String> {
        match self.kv.remove(key) {
            None => Ok(default),
            // By name, or by its code (the index, as a Verilog parameter holds it).
            Some(v) => names
                .iter()
                .position(|n| *n == v)
                .or_else(|| v.parse::<usize>().ok().filter(|&i| i < names.len()))
                .ok_or_else(|| {
                    format!(
                        "{}.{key}: '{v}' is not one of {} (or its code 0 ..= {})",
                        self.unit,
                        names.join(", "),
                        names.len() - 1
                    )
                }),
        }
    }

    fn finish(self) -> Result<(), String> {
        match self.kv.keys().next() {
            None => Ok(()),
            Some(k) => Err(format!("{}.{k}: unknown field", self.unit)),
        }
    }
}

/// SplitMix64: the tables of [`Model::open`], from its `seed`.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1].
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / ((1u64 << 53) - 1) as f64
    }
}
