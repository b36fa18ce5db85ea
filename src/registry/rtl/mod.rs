//! RTL beside the model: for every unit with Verilog in `rtl_model/verilog/units/`,
//! the model writes stimulus and expected-response vectors (`trace UNIT --vectors DIR`)
//! and the testbench wiring that runs the Verilog on them under Verilator and Icarus
//! (docs/rtl.md has the flow).
//!
//! A transaction is one input word of the unit: its fields (`Unit::in_signals`, in
//! order) packed into one word, the first field in the most significant bits, written
//! as one hex line; the expected response is the output word (`Unit::out_signals`)
//! packed the same way. The testbench (`rtl_model/verilog/tb/tb_vectors.v`) drives
//! input k on clock k·II and checks the output on clock k·II + latency, on every clock.
//!
//! Inputs are exhaustive when the input word has at most [`EXHAUSTIVE_BITS`] bits;
//! otherwise the first eighth are corner cases (every field drawn from 0, 1, the
//! midpoint ± 0, max − 1 and max) and the rest are uniform, all from a seeded
//! generator. Expected responses come from the unit's kernel in order (a unit with
//! state carries it from one transaction to the next, from its reset state).

mod blend;
mod chaos_map;
mod cube_map_address;
pub mod dpi;
mod gaussian_noise;
mod polygon_interpolator;
mod reflection_vector;
pub mod speed;
mod stream;

use super::seeded;

mod projective_texcoord;
mod shadow_compare;
pub use polygon_interpolator::{polygon_interpolator_mode_sets, polygon_interpolator_mode_vectors};
pub use shadow_compare::shadow_compare_mode_sets;
mod specular_lookup;
mod texture_sampler;
use rand::Rng;
use rtl_model::units::bloom_flare_modulator::{BloomFlareModulatorConfig, LumIn};
use rtl_model::units::glare_combiner::{CombineIn, GlareCombinerConfig};
use rtl_model::units::glare_condition::{ConditionIn, GlareConditionConfig, Material};
use rtl_model::units::halo_modulator::HaloModulatorConfig;
use rtl_model::units::modulate::{Modulate, ModulateIn, ModulateMode};
use rtl_model::{Counters, Signal, Unit};
use std::fmt::Write as _;
use std::path::Path;

mod final_combiner;
mod modulate_chain;
mod register_combiner;
mod texture_combiner;
mod vertex_lighting;
pub use blend::{blend_mode_sets, vectors_of as blend_vectors_of};
pub use specular_lookup::vectors_of as specular_lookup_vectors_of;
pub use texture_combiner::vectors_of as texture_combiner_vectors_of;
pub use vertex_lighting::{light_controls, vertex_lighting_mode_sets};

/// An input word of at most this many bits is enumerated exhaustively.
pub const EXHAUSTIVE_BITS: u32 = 20;

/// Most transactions a random vector set holds (`trace --count`).
pub const MAX_VECTORS: usize = 1 << 22;

/// Which configuration of a unit the vectors exercise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RtlConfig {
    /// The GeForce-era default (as `units` prints it).
    Default,
    /// A narrow configuration, small enough to be exhaustive where the unit allows.
    Narrow,
}

impl RtlConfig {
    pub const ALL: [RtlConfig; 2] = [RtlConfig::Default, RtlConfig::Narrow];

    pub fn name(self) -> &'static str {
        match self {
            RtlConfig::Default => "default",
            RtlConfig::Narrow => "narrow",
        }
    }

    /// Parse `default` or `narrow` (error names `--config`).
    pub fn parse(text: &str) -> Result<Self, String> {
        match text {
            "default" => Ok(RtlConfig::Default),
            "narrow" => Ok(RtlConfig::Narrow),
            _ => Err(format!(
                "config: '{text}' is not a configuration (allowed: default, narrow)"
            )),
        }
    }
}

/// One named field of a packed word.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub width: u32,
}

/// A table the unit reads through ports (`<name>_addr<i>` out, `<name>_data<i>` in,
/// synchronous read: data the clock after the address); the cosim block attaches a
/// `rtl_rom` loaded with `words` to each of the `ports` read ports.
#[derive(Clone, Debug)]
pub struct RomPort {
    pub name: &'static str,
    pub ports: u32,
    pub width: u32,
    pub words: Vec<u64>,
}

impl RomPort {
    /// Address width: ⌈log₂ depth⌉ (at least 1).
    pub fn addr_bits(&self) -> u32 {
        let n = self.words.len().max(2) as u64;
        64 - (n - 1).leading_zeros()
    }
}

/// A read/write RAM the unit holds outside itself (its bits are `ram_bits` in the
/// model's cost, not gates): ports `<name>_raddr` out, `<name>_rdata` in (synchronous
/// read-first: the word before any write on the same clock edge, the clock after the
/// address), `<name>_we`, `<name>_waddr`, `<name>_wdata` and `<name>_clear` out (a
/// one-clock flash clear of every word to `clear_value`). The cosim block attaches a
/// `rtl_ram` (rtl_model/verilog/tb/rtl_rom.v), every word at `clear_value` from reset.
#[derive(Clone, Debug)]
pub struct RamPort {
    pub name: &'static str,
    pub width: u32,
    pub depth: u64,
    pub clear_value: u64,
}

impl RamPort {
    /// Address width: ⌈log₂ depth⌉ (at least 1).
    pub fn addr_bits(&self) -> u32 {
        let n = self.depth.max(2);
        64 - (n - 1).leading_zeros()
    }
}

/// A unit's vectors at one configuration, with what the testbench needs to run them.
#[derive(Clone, Debug)]
pub struct VectorSet {
    pub unit: &'static str,
    pub config: RtlConfig,
    pub latency: u32,
    pub ii: u32,
    /// The Verilog module's parameters at this configuration.
    pub params: Vec<(&'static str, u64)>,
    pub in_fields: Vec<Field>,
    pub out_fields: Vec<Field>,
    /// Every input word was enumerated.
    pub exhaustive: bool,
    /// The unit carries no state (`Unit::State` is zero-sized, `()`), so each
    /// expected word depends on its input word alone and the set may be repeated.
    pub stateless: bool,
    /// Seconds the model's batch kernel (`Unit::kernel_batch`, from the reset state)
    /// took per pass over these inputs (the fastest of a few passes): the model's
    /// side of the speed table (`units --rtl-speed`).
    pub model_batch_secs: f64,
    /// Packed input words, hex.
    pub stimulus: Vec<String>,
    /// Packed expected output words, hex.
    pub expected: Vec<String>,
    /// The model's gate estimate at this configuration (NAND2 equivalents).
    pub gates_model: f64,
    /// Tables the unit reads through ports (none: empty).
    pub roms: Vec<RomPort>,
    /// Read/write RAMs the unit uses through ports (none: empty).
    pub rams: Vec<RamPort>,
    /// A mode beyond the configuration (a non-default config field, as
    /// `shadow_compare`'s compare function), appended to the tag; None for the
    /// configuration itself.
    pub variant: Option<String>,
}

/// One unit with Verilog: its name (= the Verilog module and file stem) and its
/// vector writer.
pub struct RtlEntry {
    pub name: &'static str,
    /// `count` transactions (ignored when exhaustive) from `seed` at `config`.
    pub vectors: fn(config: RtlConfig, count: usize, seed: u64) -> Result<VectorSet, String>,
}

/// Every unit with Verilog, in datasheet order.
pub const RTL_UNITS: &[RtlEntry] = &[
    RtlEntry {
        name: "modulate",
        vectors: modulate_vectors,
    },
    RtlEntry {
        name: "polygon_interpolator",
        vectors: polygon_interpolator::polygon_interpolator_vectors,
    },
    RtlEntry {
        name: "blend",
        vectors: blend::blend_vectors,
    },
    RtlEntry {
        name: "bloom_flare_modulator",
        vectors: bloom_flare_modulator_vectors,
    },
    RtlEntry {
        name: "halo_modulator",
        vectors: halo_modulator_vectors,
    },
    RtlEntry {
        name: "gaussian_noise",
        vectors: gaussian_noise::gaussian_noise_vectors,
    },
    RtlEntry {
        name: "chaos_map",
        vectors: chaos_map::chaos_map_vectors,
    },
    RtlEntry {
        name: "glare_combiner",
        vectors: glare_combiner_vectors,
    },
    RtlEntry {
        name: "glare_condition",
        vectors: glare_condition_vectors,
    },
    RtlEntry {
        name: "shadow_compare",
        vectors: shadow_compare::shadow_compare_vectors,
    },
    RtlEntry {
        name: "texture_sampler",
        vectors: texture_sampler::texture_sampler_vectors,
    },
    RtlEntry {
        name: "projective_texcoord",
        vectors: projective_texcoord::projective_texcoord_vectors,
    },
    RtlEntry {
        name: "texture_combiner",
        vectors: texture_combiner::texture_combiner_vectors,
    },
    RtlEntry {
        name: "specular_lookup",
        vectors: specular_lookup::specular_lookup_vectors,
    },
    RtlEntry {
        name: "modulate_chain",
        vectors: modulate_chain::modulate_chain_vectors,
    },
    RtlEntry {
        name: "final_combiner",
        vectors: final_combiner::final_combiner_vectors,
    },
    RtlEntry {
        name: "register_combiner",
        vectors: register_combiner::register_combiner_vectors,
    },
    RtlEntry {
        name: "cube_map_address",
        vectors: cube_map_address::cube_map_address_vectors,
    },
    RtlEntry {
        name: "reflection_vector",
        vectors: reflection_vector::reflection_vector_vectors,
    },
    RtlEntry {
        name: "vertex_lighting",
        vectors: vertex_lighting::vertex_lighting_vectors,
    },
];

/// The entry of a unit with Verilog; the error names the unit argument.
pub fn rtl_entry(name: &str) -> Result<&'static RtlEntry, String> {
    RTL_UNITS.iter().find(|e| e.name == name).ok_or_else(|| {
        let known: Vec<&str> = RTL_UNITS.iter().map(|e| e.name).collect();
        if super::entry(name).is_some() {
            format!(
                "unit: '{name}' has no Verilog yet (units with Verilog: {})",
                known.join(", ")
            )
        } else {
            format!(
                "unit: unknown unit '{name}' (units with Verilog: {})",
                known.join(", ")
            )
        }
    })
}

/// The vectors of the named unit (errors name `unit`, `count` or the config field).
pub fn vectors(
    name: &str,
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    if count == 0 || count > MAX_VECTORS {
        return Err(format!(
            "count: {count} is out of range (1 ..= {MAX_VECTORS})"
        ));
    }
    (rtl_entry(name)?.vectors)(config, count, seed)
}

/// Pack field values (first field most significant) into a hex word of
/// ⌈Σ widths / 4⌉ digits.
pub fn pack_hex(signals: &[Signal]) -> String {
    let total: u32 = signals.iter().map(|s| s.width).sum();
    let digits = total.div_ceil(4).max(1) as usize;
    // Little-endian 64-bit limbs.
    let mut limbs = vec![0u64; digits.div_ceil(16) + 1];
    let mut pos = 0u32;
    for s in signals.iter().rev() {
        let v = if s.width >= 64 {
            s.value
        } else {
            s.value & ((1u64 << s.width) - 1)
        };
        let (li, off) = ((pos / 64) as usize, pos % 64);
        limbs[li] |= v << off;
        if off + s.width > 64 && off > 0 {
            limbs[li + 1] |= v >> (64 - off);
        }
        pos += s.width;
    }
    let mut out = String::with_capacity(digits);
    for d in (0..digits).rev() {
        let bit = d * 4;
        let nib = (limbs[bit / 64] >> (bit % 64)) & 0xf;
        out.push(char::from_digit(nib as u32, 16).unwrap_or('0'));
    }
    out
}

fn fields(sig: &[Signal]) -> Vec<Field> {
    sig.iter()
        .map(|s| Field {
            name: s.name,
            width: s.width,
        })
        .collect()
}

/// A module's Verilog parameters, by name.
type VerilogParams = Vec<(&'static str, u64)>;

/// The vectors of `u` from reset state `state`: `make` builds an input word from field
/// values in `in_signals` order (`probe` is any input word, for the field widths).
#[allow(clippy::too_many_arguments)]
fn collect<U: Unit>(
    u: &U,
    mut state: U::State,
    config: RtlConfig,
    probe: U::In,
    make: impl Fn(&[u64]) -> U::In,
    params: VerilogParams,
    count: usize,
    seed: u64,
) -> VectorSet {
    let in_f = fields(&u.in_signals(&probe));
    let widths: Vec<u32> = in_f.iter().map(|f| f.width).collect();
    let total: u32 = widths.iter().sum();
    let exhaustive = total <= EXHAUSTIVE_BITS;
    let inputs: Vec<U::In> = if exhaustive {
        (0..1u64 << total)
            .map(|mut x| {
                // The last field holds the least significant bits.
                let mut vals = vec![0u64; widths.len()];
                for (v, &w) in vals.iter_mut().zip(&widths).rev() {
                    *v = x & ((1u64 << w) - 1);
                    x >>= w;
                }
                make(&vals)
            })
            .collect()
    } else {
        let mut rng = seeded(seed);
        let corners = count / 8;
        (0..count)
            .map(|i| {
                let vals: Vec<u64> = widths
                    .iter()
                    .map(|&w| {
                        let max = if w >= 64 { u64::MAX } else { (1u64 << w) - 1 };
                        if i < corners {
                            let mid = 1u64 << (w - 1);
                            let c = [0, 1, mid - 1, mid, max - 1, max];
                            c[rng.random_range(0..c.len())] & max
                        } else {
                            rng.random_range(0..=max)
                        }
                    })
                    .collect();
                make(&vals)
            })
            .collect()
    };
    let state0 = state.clone();
    let mut ctr = Counters::default();
    let mut stimulus = Vec::with_capacity(inputs.len());
    let mut expected = Vec::with_capacity(inputs.len());
    let mut out_f = Vec::new();
    for x in &inputs {
        let y = u.kernel(&mut state, x, &mut ctr);
        let os = u.out_signals(&y);
        if out_f.is_empty() {
            out_f = fields(&os);
        }
        stimulus.push(pack_hex(&u.in_signals(x)));
        expected.push(pack_hex(&os));
    }
    let t = u.timing();
    let model_batch_secs = time_batch(u, &state0, &inputs);
    VectorSet {
        unit: u.name(),
        config,
        latency: t.latency,
        ii: t.ii,
        stateless: std::mem::size_of::<U::State>() == 0,
        params,
        in_fields: in_f,
        out_fields: out_f,
        exhaustive,
        model_batch_secs,
        stimulus,
        expected,
        gates_model: u.cost().gates_nand2(),
        roms: Vec::new(),
        rams: Vec::new(),
        variant: None,
    }
}

/// A rounding mode as the combiners' Verilog `ROUNDING` parameter: its index in
/// `Quant::ALL` (TRN, TRN_ZERO, RND, RND_ZERO, RND_INF, RND_MIN_INF, RND_CONV).
pub(super) fn quant_code(q: rtl_model::fixed_point::Quant) -> u64 {
    rtl_model::fixed_point::Quant::ALL
        .iter()
        .position(|&x| x == q)
        .expect("Quant::ALL lists every rounding mode") as u64
}

/// Seconds per pass of `u`'s batch kernel over `inputs` from `state0`: the fastest
/// of passes repeated for at least 5 ms (at most 16).
fn time_batch<U: Unit>(u: &U, state0: &U::State, inputs: &[U::In]) -> f64 {
    time_batch_walks(u, &[(state0.clone(), inputs)])
}

/// [`time_batch`] over several walks, each from its own start state (a unit whose
/// state is loaded per primitive): the fastest pass over all of them.
pub(super) fn time_batch_walks<U: Unit>(u: &U, walks: &[(U::State, &[U::In])]) -> f64 {
    let mut best = f64::INFINITY;
    let started = std::time::Instant::now();
    let mut out = Vec::new();
    for _ in 0..16 {
        let t = std::time::Instant::now();
        for (state0, inputs) in walks {
            let mut st = state0.clone();
            let mut ctr = Counters::default();
            out.clear();
            u.kernel_batch(&mut st, inputs, &mut out, &mut ctr);
            std::hint::black_box(&out);
        }
        best = best.min(t.elapsed().as_secs_f64());
        if started.elapsed().as_secs_f64() > 0.005 {
            break;
        }
    }
    best
}

impl VectorSet {
    /// The tag of this unit and configuration: `<unit>_<config>`.
    pub fn tag(&self) -> String {
        match &self.variant {
            None => format!("{}_{}", self.unit, self.config.name()),
            Some(v) => format!("{}_{}_{v}", self.unit, self.config.name()),
        }
    }

    pub fn in_bits(&self) -> u32 {
        self.in_fields.iter().map(|f| f.width).sum()
    }

    pub fn out_bits(&self) -> u32 {
        self.out_fields.iter().map(|f| f.width).sum()
    }

    /// The header file: one `key value…` line each.
    pub fn header(&self) -> String {
        let mut h = String::new();
        let _ = writeln!(h, "unit {}", self.unit);
        let _ = writeln!(h, "config {}", self.config.name());
        let _ = writeln!(h, "count {}", self.stimulus.len());
        let _ = writeln!(h, "exhaustive {}", u8::from(self.exhaustive));
        let _ = writeln!(h, "latency {}", self.latency);
        let _ = writeln!(h, "ii {}", self.ii);
        let _ = writeln!(h, "in_bits {}", self.in_bits());
        let _ = writeln!(h, "out_bits {}", self.out_bits());
        for f in &self.in_fields {
            let _ = writeln!(h, "in {} {}", f.name, f.width);
        }
        for f in &self.out_fields {
            let _ = writeln!(h, "out {} {}", f.name, f.width);
        }
        for (k, v) in &self.params {
            let _ = writeln!(h, "param {k} {v}");
        }
        h
    }

    /// The module `cosim_<tag>`: the generic testbench driving the unit's module at
    /// this configuration's parameters, its packed words sliced into the named ports.
    /// Tables are read from `<dir>/<name>.hex`.
    pub fn cosim_block(&self, dir: &Path) -> String {
        let tag = self.tag();
        let (iw, ow) = (self.in_bits(), self.out_bits());
        let mut v = String::new();
        let _ = writeln!(
            v,
            "// Generated by `glare-pipeline trace {} --vectors DIR --config {}`.",
            self.unit,
            self.config.name()
        );
        let _ = writeln!(v, "module cosim_{tag};");
        v.push_str(&self.dut_wires());
        let _ = writeln!(
            v,
            "  tb_vectors #(.IN_W({iw}), .OUT_W({ow}), .LAT({}), .II({}), .TAG(\"{tag}\")) tb (",
            self.latency, self.ii
        );
        let _ = writeln!(
            v,
            "      .clk(clk), .rst(rst), .in_valid(in_valid), .in_word(in_word),"
        );
        let _ = writeln!(v, "      .out_valid(out_valid), .out_word(out_word));");
        v.push_str(&self.dut_instance());
        v.push_str(&self.table_instances(|r| {
            format!(
                "rtl_rom #(.W({}), .DEPTH({}), .AW({}), .FILE(\"{}\"))",
                r.width,
                r.words.len(),
                r.addr_bits(),
                dir.join(format!("{}.hex", r.name)).display()
            )
        }));
        let _ = writeln!(v, "endmodule");
        v
    }

    // The unit's side of a testbench block, shared by the co-simulation
    // (`cosim_block`) and the DPI-C scoreboard (`dpi::dpi_block`), so a unit's ports
    // are wired the same in both. Only the ROM module differs (`rtl_rom` from the
    // vector set's files, `dpi_rom` from the model).

    /// The wires a block declares: the testbench handshake, the packed words and every
    /// table port (ROM read ports, RAM read/write ports).
    fn dut_wires(&self) -> String {
        let mut v = String::new();
        let _ = writeln!(v, "  wire clk, rst, in_valid, out_valid;");
        let _ = writeln!(v, "  wire [{}:0] in_word;", self.in_bits() - 1);
        let _ = writeln!(v, "  wire [{}:0] out_word;", self.out_bits() - 1);
        for r in &self.roms {
            for i in 0..r.ports {
                let _ = writeln!(
                    v,
                    "  wire [{}:0] {}_addr{i};\n  wire [{}:0] {}_data{i};",
                    r.addr_bits() - 1,
                    r.name,
                    r.width - 1,
                    r.name
                );
            }
        }
        for r in &self.rams {
            let (a, w, n) = (r.addr_bits() - 1, r.width - 1, r.name);
            let _ = writeln!(
                v,
                "  wire [{a}:0] {n}_raddr, {n}_waddr;\n  wire [{w}:0] {n}_rdata, {n}_wdata;\n  wire {n}_we, {n}_clear;"
            );
        }
        v
    }

    /// The unit's instance `dut`: this configuration's parameters, the packed words
    /// sliced into the named ports, the table ports to the wires of [`Self::dut_wires`].
    fn dut_instance(&self) -> String {
        let mut v = String::new();
        let params: Vec<String> = self
            .params
            .iter()
            .map(|(k, val)| {
                // Unsized literals are 32-bit signed: wider values are sized.
                if *val >= 1 << 31 {
                    format!(".{k}(64'd{val})")
                } else {
                    format!(".{k}({val})")
                }
            })
            .collect();
        let _ = writeln!(v, "  {} #({}) dut (", self.unit, params.join(", "));
        let _ = writeln!(
            v,
            "      .clk(clk), .rst(rst), .in_valid(in_valid), .out_valid(out_valid),"
        );
        let mut ports = Vec::new();
        let mut hi = self.in_bits();
        for f in &self.in_fields {
            ports.push(format!(".{}(in_word[{}:{}])", f.name, hi - 1, hi - f.width));
            hi -= f.width;
        }
        let mut hi = self.out_bits();
        for f in &self.out_fields {
            // An output named like an input (a unit whose output word is its input
            // word updated, as register_combiner's register set) is the port `o_<name>`.
            let prefix = if self.in_fields.iter().any(|i| i.name == f.name) {
                "o_"
            } else {
                ""
            };
            ports.push(format!(
                ".{prefix}{}(out_word[{}:{}])",
                f.name,
                hi - 1,
                hi - f.width
            ));
            hi -= f.width;
        }
        for r in &self.roms {
            for i in 0..r.ports {
                ports.push(format!(".{0}_addr{i}({0}_addr{i})", r.name));
                ports.push(format!(".{0}_data{i}({0}_data{i})", r.name));
            }
        }
        for r in &self.rams {
            for p in ["raddr", "rdata", "we", "waddr", "wdata", "clear"] {
                ports.push(format!(".{0}_{p}({0}_{p})", r.name));
            }
        }
        let _ = writeln!(v, "      {});", ports.join(",\n      "));
        v
    }

    /// The tables outside the unit: each ROM read port an instance of `rom(port)` (the
    /// module and its parameters: `rtl_rom` from a file, `dpi_rom` from the model), each
    /// RAM an `rtl_ram` (rtl_model/verilog/tb/rtl_rom.v; written by the unit itself, so
    /// the same in every block).
    fn table_instances(&self, rom: impl Fn(&RomPort) -> String) -> String {
        let mut v = String::new();
        for r in &self.roms {
            let m = rom(r);
            for i in 0..r.ports {
                let n = r.name;
                let _ = writeln!(
                    v,
                    "  {m} {n}_rom{i} (.clk(clk), .addr({n}_addr{i}), .data({n}_data{i}));"
                );
            }
        }
        for r in &self.rams {
            let (n, w) = (r.name, r.width);
            let _ = writeln!(
                v,
                "  rtl_ram #(.W({w}), .DEPTH({}), .AW({}), .CLEAR({w}'h{:x})) {n}_ram (.clk(clk), .raddr({n}_raddr), .rdata({n}_rdata), .we({n}_we), .waddr({n}_waddr), .wdata({n}_wdata), .clear({n}_clear));",
                r.depth,
                r.addr_bits(),
                r.clear_value
            );
        }
        v
    }

    /// Write `header.txt`, `stimulus.hex`, `expected.hex` and `cosim_<tag>.v` into
    /// `dir` (created if missing).
    pub fn write(&self, dir: &Path) -> Result<(), String> {
        let io =
            |p: &Path, e: std::io::Error| format!("vectors: cannot write {}: {e}", p.display());
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
        let put = |name: &str, text: String| {
            let p = dir.join(name);
            std::fs::write(&p, text).map_err(|e| io(&p, e))
        };
        put("header.txt", self.header())?;
        put("stimulus.hex", lines(&self.stimulus))?;
        put("expected.hex", lines(&self.expected))?;
        for r in &self.roms {
            let digits = r.width.div_ceil(4) as usize;
            let words: Vec<String> = r.words.iter().map(|w| format!("{w:0digits$x}")).collect();
            put(&format!("{}.hex", r.name), lines(&words))?;
        }
        // The block names the table files by absolute path (one build, any cwd).
        let abs = std::fs::canonicalize(dir).map_err(|e| io(dir, e))?;
        put(&format!("cosim_{}.v", self.tag()), self.cosim_block(&abs))?;
        Ok(())
    }
}

fn lines(words: &[String]) -> String {
    let mut s = String::with_capacity(words.iter().map(|w| w.len() + 1).sum());
    for w in words {
        s.push_str(w);
        s.push('\n');
    }
    s
}

/// A top module instantiating the cosim blocks of `tags` (Verilator wants one top;
/// `+tag=TAG` picks the block that runs).
pub fn cosim_top(tags: &[String]) -> String {
    let mut v =
        String::from("// Generated: one instance of each cosim block.\nmodule cosim_top;\n");
    for t in tags {
        let _ = writeln!(v, "  cosim_{t} u_{t} ();");
    }
    v.push_str("  initial if (!$test$plusargs(\"tag=\")) begin\n");
    v.push_str("    $display(\"COSIM error=no-tag (pass +tag=<unit>_<config>)\");\n");
    v.push_str("    $finish;\n  end\nendmodule\n");
    v
}

// ---- the units ----------------------------------------------------------------------

fn modulate_vectors(config: RtlConfig, count: usize, seed: u64) -> Result<VectorSet, String> {
    let u = match config {
        RtlConfig::Default => Modulate::geforce(),
        RtlConfig::Narrow => Modulate::new(4, ModulateMode::Exact).map_err(|e| e.to_string())?,
    };
    let make = |v: &[u64]| ModulateIn {
        a: v[0] as u32,
        b: v[1] as u32,
    };
    let params = vec![("BITS", u.bits() as u64)];
    Ok(collect(
        &u,
        (),
        config,
        ModulateIn::default(),
        make,
        params,
        count,
        seed,
    ))
}

fn glare_combiner_vectors(config: RtlConfig, count: usize, seed: u64) -> Result<VectorSet, String> {
    let cfg = match config {
        RtlConfig::Default => GlareCombinerConfig::default(),
        RtlConfig::Narrow => GlareCombinerConfig {
            fb_bits: 3,
            lum_bits: 3,
        },
    };
    let u = cfg.build().map_err(|e| e.to_string())?;
    let make = |v: &[u64]| CombineIn {
        fb: std::array::from_fn(|c| v[c] as u32),
        lum: std::array::from_fn(|c| v[3 + c] as u32),
    };
    let params = vec![
        ("FB_BITS", cfg.fb_bits as u64),
        ("LUM_BITS", cfg.lum_bits as u64),
    ];
    Ok(collect(
        &u,
        (),
        config,
        CombineIn::default(),
        make,
        params,
        count,
        seed,
    ))
}

fn glare_condition_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = match config {
        RtlConfig::Default => GlareConditionConfig::default(),
        // 15 input bits: exhaustive.
        RtlConfig::Narrow => GlareConditionConfig {
            int_bits: 2,
            frac_bits: 1,
            coef_bits: 2,
            cos_frac_bits: 2,
            eta: 1.333,
            eta_frac_bits: 2,
            threshold: 3,
            out_bits: 2,
        },
    };
    let u = cfg.build().map_err(|e| e.to_string())?;
    let cw = cfg.cos_frac_bits + 1;
    // Sign-extend an s1.cf wire value.
    let sx = move |v: u64| (((v as u32) << (32 - cw)) as i32) >> (32 - cw);
    let make = move |v: &[u64]| ConditionIn {
        material: if v[0] == 1 {
            Material::Water
        } else {
            Material::Metallic
        },
        intensity: v[1] as u32,
        specular: v[2] as u32,
        cos_alpha: sx(v[3]),
        cos_theta: sx(v[4]),
        ambient: v[5] as u32,
    };
    let params = vec![
        ("INT_BITS", cfg.int_bits as u64),
        ("FRAC_BITS", cfg.frac_bits as u64),
        ("COEF_BITS", cfg.coef_bits as u64),
        ("COS_FRAC_BITS", cfg.cos_frac_bits as u64),
        ("ETA_FRAC_BITS", cfg.eta_frac_bits as u64),
        ("ETA_CODE", u.eta_code() as u64),
        ("THRESHOLD", cfg.threshold as u64),
        ("OUT_BITS", cfg.out_bits as u64),
    ];
    let probe = make(&[0; 6]);
    Ok(collect(&u, (), config, probe, make, params, count, seed))
}

/// The luminance modulators' widths (bloom/flare and halo share them): the GeForce
/// default, or the narrow one with 17 input bits (exhaustive). Radial correction off
/// (the Verilog implements the plain datapath).
fn luminance_widths(config: RtlConfig) -> BloomFlareModulatorConfig {
    match config {
        RtlConfig::Default => BloomFlareModulatorConfig::default(),
        RtlConfig::Narrow => BloomFlareModulatorConfig {
            coord_frac_bits: 2,
            shape_log2: 2,
            shape_bits: 3,
            falloff_log2: 2,
            falloff_bits: 3,
            weight_bits: 2,
            gain_int_bits: 2,
            gain_frac_bits: 1,
            out_bits: 2,
            ..BloomFlareModulatorConfig::default()
        },
    }
}

/// A luminance modulator's input word from the vector fields (u, v sign-extended
/// from coord_frac_bits + 2 bits; the three gains) and its Verilog parameters.
fn luminance_ports(
    cfg: &BloomFlareModulatorConfig,
) -> (impl Fn(&[u64]) -> LumIn + Copy, VerilogParams) {
    let cw = cfg.coord_frac_bits + 2;
    let sx = move |v: u64| (((v as u32) << (32 - cw)) as i32) >> (32 - cw);
    let make = move |v: &[u64]| LumIn {
        u: sx(v[0]),
        v: sx(v[1]),
        gain: [v[2] as u32, v[3] as u32, v[4] as u32],
    };
    let params = vec![
        ("COORD_FRAC_BITS", cfg.coord_frac_bits as u64),
        ("SHAPE_LOG2", cfg.shape_log2 as u64),
        ("SHAPE_BITS", cfg.shape_bits as u64),
        ("FALLOFF_LOG2", cfg.falloff_log2 as u64),
        ("FALLOFF_BITS", cfg.falloff_bits as u64),
        ("WEIGHT_BITS", cfg.weight_bits as u64),
        ("GAIN_INT_BITS", cfg.gain_int_bits as u64),
        ("GAIN_FRAC_BITS", cfg.gain_frac_bits as u64),
        ("OUT_BITS", cfg.out_bits as u64),
    ];
    (make, params)
}

/// Table codes as vector words.
fn rom_words(codes: &[u32]) -> Vec<u64> {
    codes.iter().map(|&c| c as u64).collect()
}

fn bloom_flare_modulator_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let cfg = luminance_widths(config);
    // Random table contents (seeded): every entry matters, not a smooth shape.
    let w = cfg.widths();
    let mut rng = seeded(seed ^ 0x5eed_7ab1e);
    let shape: Vec<f64> = (0..w.shape_len()).map(|_| rng.random::<f64>()).collect();
    let falloff: Vec<f64> = (0..w.falloff_len()).map(|_| rng.random::<f64>()).collect();
    let u = cfg.build(&shape, &falloff).map_err(|e| e.to_string())?;
    let (make, params) = luminance_ports(&cfg);
    let mut v = collect(&u, (), config, make(&[0; 5]), make, params, count, seed);
    v.roms = vec![
        RomPort {
            name: "shape",
            ports: 4,
            width: cfg.shape_bits,
            words: rom_words(u.shape_codes()),
        },
        RomPort {
            name: "falloff",
            ports: 2,
            width: cfg.falloff_bits,
            words: rom_words(u.falloff_codes()),
        },
    ];
    Ok(v)
}

fn halo_modulator_vectors(config: RtlConfig, count: usize, seed: u64) -> Result<VectorSet, String> {
    // The same widths as bloom_flare_modulator's.
    let b = luminance_widths(config);
    let cfg = HaloModulatorConfig::from_widths(b.widths());
    let w = cfg.widths();
    let mut rng = seeded(seed ^ 0x4a10);
    let mut table = |n: usize| (0..n).map(|_| rng.random::<f64>()).collect::<Vec<f64>>();
    let shape = table(w.shape_len());
    let rings = [
        table(w.falloff_len()),
        table(w.falloff_len()),
        table(w.falloff_len()),
    ];
    let u = cfg
        .build(&shape, [&rings[0], &rings[1], &rings[2]])
        .map_err(|e| e.to_string())?;
    let (make, params) = luminance_ports(&b);
    let mut v = collect(&u, (), config, make(&[0; 5]), make, params, count, seed);
    v.roms = vec![RomPort {
        name: "shape",
        ports: 4,
        width: cfg.shape_bits,
        words: rom_words(u.shape_codes()),
    }];
    for (c, name) in ["ring_r", "ring_g", "ring_b"].into_iter().enumerate() {
        v.roms.push(RomPort {
            name,
            ports: 2,
            width: cfg.falloff_bits,
            words: rom_words(u.ring_codes(c)),
        });
    }
    Ok(v)
}

// ---- whole-unit synthesis -------------------------------------------------------------

/// The Verilog file of a unit with Verilog, in the source tree.
pub fn verilog_file(root: &Path, unit: &str) -> std::path::PathBuf {
    root.join("rtl_model/verilog/units")
        .join(format!("{unit}.v"))
}

/// Modules shared by several units' Verilog (`rtl_model/verilog/lib/<name>.v`): the
/// co-simulation compiles them with the units, synthesis reads them before the unit.
pub const VERILOG_LIB: &[&str] = &["luminance_datapath"];

/// The shared modules' files ([`VERILOG_LIB`]), in the source tree.
pub fn verilog_lib_files(root: &Path) -> Vec<std::path::PathBuf> {
    VERILOG_LIB
        .iter()
        .map(|m| root.join("rtl_model/verilog/lib").join(format!("{m}.v")))
        .collect()
}

/// Headers in `rtl_model/verilog/lib/` that units `include` (port lists and wiring
/// shared by several units): the simulators and Yosys (`synth`) get
/// [`verilog_include_arg`].
pub const VERILOG_INCLUDES: &[&str] = &[
    "combiner_register_file.vh",
    "luminance_params.vh",
    "luminance_ports.vh",
    "luminance_dp_params.vh",
    "luminance_dp_ports.vh",
    "leading_one.vh",
    "vertex_lighting_fp.vh",
];

/// The headers' files ([`VERILOG_INCLUDES`]), for build stamps.
pub fn verilog_include_files(root: &Path) -> Vec<std::path::PathBuf> {
    VERILOG_INCLUDES
        .iter()
        .map(|h| root.join("rtl_model/verilog/lib").join(h))
        .collect()
}

/// `-I<root>/rtl_model/verilog/lib`: where Verilator and Icarus find the headers
/// (both search the working directory and `-I`, not the including file's directory).
pub fn verilog_include_arg(root: &Path) -> String {
    format!("-I{}", root.join("rtl_model/verilog/lib").display())
}

/// A unit synthesised by Yosys at one configuration.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Synth {
    pub name: &'static str,
    pub config: &'static str,
    /// The model's `cost()` at this configuration, NAND2 equivalents.
    pub gates_model: f64,
    /// Yosys' cells weighted by `rtl_model::cost::CELL_WEIGHTS`.
    pub gates_yosys: f64,
    /// (model − Yosys) / Yosys.
    pub rel_diff: f64,
    /// Yosys cell counts by cell type.
    pub cells: std::collections::BTreeMap<String, u64>,
    /// A hierarchical unit's kept modules (`(* keep_hierarchy *)`, see [`synth`]): per
    /// module (its name without Yosys' `$paramod…\` prefix), the instances in the
    /// whole unit and the NAND2 equivalents of ONE instance with its own submodules.
    /// Empty for a flattened unit.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub modules: Vec<SynthModule>,
}

/// One kept module of a hierarchical unit ([`Synth::modules`]).
#[derive(Clone, Debug, serde::Serialize)]
pub struct SynthModule {
    pub module: String,
    /// Instances in the whole unit (through every level of the hierarchy).
    pub instances: u64,
    /// NAND2 equivalents of one instance, its submodules included.
    pub gates_yosys: f64,
}

/// NAND2 equivalents of Yosys' gate-level cells under the model's one weight table.
/// Flip-flops with a synchronous reset (`$_SDFF_*`) count as a flip-flop plus an AND
/// gate, with an enable (`$_DFFE_*`) as a flip-flop plus a 2:1 mux.
pub fn weigh_cells(cells: &std::collections::BTreeMap<String, u64>) -> Result<f64, String> {
    let w = rtl_model::cost::CELL_WEIGHTS;
    let mut g = 0.0;
    for (cell, &n) in cells {
        let per = match cell.as_str() {
            "$_AND_" => w.and2,
            "$_NAND_" => w.nand2,
            "$_OR_" => w.or2,
            "$_NOR_" => w.nor2,
            "$_XOR_" => w.xor2,
            "$_XNOR_" => w.xnor2,
            "$_MUX_" => w.mux2,
            "$_NOT_" => w.not,
            "$_BUF_" => 0.0,
            "$_DFF_P_" | "$_DFF_N_" => w.dff,
            c if c.starts_with("$_SDFF_") => w.dff + w.and2,
            c if c.starts_with("$_DFFE_") => w.dff + w.mux2,
            c if c.starts_with("$_SDFFE_") || c.starts_with("$_SDFFCE_") => w.dff + w.and2 + w.mux2,
            other => return Err(format!("synth: Yosys cell {other} has no NAND2 weight")),
        };
        g += per * n as f64;
    }
    Ok(g)
}

/// Synthesise `unit`'s Verilog at `config` with the calibration's pinned script
/// (rtl_model/verilog/calibrate.sh) plus `chparam` for the configured widths:
/// `read_verilog; chparam; synth -flatten -top; abc -g AND,NAND,OR,NOR,XOR,XNOR,MUX;
/// stat`. `-flatten` makes a unit with submodules one module, so `stat` lists its
/// cells once (unflattened it lists each submodule's cells per module and again in the
/// hierarchy total, which the cell sum below would count twice); a single-module unit
/// synthesises the same either way. The shared modules of [`VERILOG_LIB`] are read
/// first.
///
/// Hierarchical units: modules marked `(* keep_hierarchy *)` (vertex_lighting's FP
/// operators) survive `-flatten`; Yosys synthesises each such module ONCE (ABC per
/// module) and `stat` then prints each module's own cells and a `design hierarchy`
/// section whose cell counts are the whole unit's, each submodule's cells times its
/// instance count. Only that section is counted (the per-module sections would count
/// the submodules twice); no logic is optimised across a kept module's ports (a
/// conservative count). The script is the same for every unit.
pub fn synth(root: &Path, unit: &str, config: RtlConfig) -> Result<Synth, String> {
    let e = rtl_entry(unit)?;
    let v = (e.vectors)(config, 1, 1)?;
    let file = verilog_file(root, e.name);
    let tmp = std::env::temp_dir().join(format!(
        "glare_synth_{}_{}_{}.stat",
        e.name,
        config.name(),
        std::process::id()
    ));
    let sets: Vec<String> = v
        .params
        .iter()
        .map(|(k, x)| format!("-set {k} {x}"))
        .collect();
    // The shared modules first; -flatten makes `stat` one module (a hierarchy would
    // list a submodule's cells again in its total).
    let lib: String = verilog_lib_files(root)
        .iter()
        .map(|f| format!("read_verilog {}; ", f.display()))
        .collect();
    let script = format!(
        "{lib}read_verilog {} {}; chparam {} {}; synth -flatten -top {}; abc -g AND,NAND,OR,NOR,XOR,XNOR,MUX; tee -o {} stat",
        verilog_include_arg(root),
        file.display(),
        sets.join(" "),
        e.name,
        e.name,
        tmp.display()
    );
    let out = std::process::Command::new("yosys")
        .args(["-q", "-p", &script])
        .output()
        .map_err(|err| {
            format!("synth: cannot run yosys ({err}); install it (apt-get install yosys)")
        })?;
    if !out.status.success() {
        return Err(format!(
            "synth: yosys failed on {}: {}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let text = std::fs::read_to_string(&tmp).map_err(|err| format!("synth: {err}"))?;
    let _ = std::fs::remove_file(&tmp);
    let hier = text.find("=== design hierarchy ===");
    let modules = match hier {
        Some(_) => synth_modules(&text, e.name)?,
        None => Vec::new(),
    };
    let mut cells = std::collections::BTreeMap::new();
    for line in text[hier.unwrap_or(0)..].lines() {
        if let Some((c, n)) = stat_cell(line) {
            *cells.entry(c.to_string()).or_insert(0) += n;
        }
    }
    let gates_yosys = weigh_cells(&cells)?;
    Ok(Synth {
        name: e.name,
        config: config.name(),
        gates_model: v.gates_model,
        gates_yosys,
        rel_diff: (v.gates_model - gates_yosys) / gates_yosys,
        cells,
        modules,
    })
}

/// A `stat` line's gate-level cell and its count: "     $_AND_     77" (older Yosys)
/// or "  77  $_AND_" (newer); None for any other line.
fn stat_cell(line: &str) -> Option<(&str, u64)> {
    let toks: Vec<&str> = line.split_whitespace().collect();
    let cell = toks
        .iter()
        .find(|t| t.starts_with("$_") && t.ends_with('_'))?;
    let n = toks.iter().find_map(|t| t.parse::<u64>().ok())?;
    Some((cell, n))
}

/// The kept modules of a hierarchical `stat` (per-module sections before `design
/// hierarchy`): each module's own cells weighted, plus its submodules' (recursively),
/// and the instance count of each in the whole of `top`.
fn synth_modules(text: &str, top: &str) -> Result<Vec<SynthModule>, String> {
    use std::collections::BTreeMap;
    // name → (own cells, submodule instances)
    type Mods = BTreeMap<String, (BTreeMap<String, u64>, Vec<(String, u64)>)>;
    let mut mods: Mods = BTreeMap::new();
    let mut cur: Option<String> = None;
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("=== ").and_then(|r| r.strip_suffix(" ===")) {
            if name == "design hierarchy" {
                break;
            }
            mods.entry(name.to_string()).or_default();
            cur = Some(name.to_string());
            continue;
        }
        let Some(m) = cur.as_ref() else { continue };
        let entry = mods.get_mut(m).expect("section entered");
        if let Some((c, n)) = stat_cell(t) {
            *entry.0.entry(c.to_string()).or_insert(0) += n;
            continue;
        }
        // A submodule instance line: "name count".
        let toks: Vec<&str> = t.split_whitespace().collect();
        if let [name, count] = toks[..] {
            if let (Ok(n), false) = (count.parse::<u64>(), t.starts_with("Number of")) {
                entry.1.push((name.to_string(), n));
            }
        }
    }
    fn inclusive(m: &str, mods: &Mods, depth: u32) -> Result<f64, String> {
        let (own, subs) = mods
            .get(m)
            .ok_or_else(|| format!("synth: Yosys stat has no module {m}"))?;
        if depth > 16 {
            return Err("synth: module hierarchy too deep".into());
        }
        let mut g = weigh_cells(own)?;
        for (s, n) in subs {
            g += inclusive(s, mods, depth + 1)? * *n as f64;
        }
        Ok(g)
    }
    fn count(m: &str, times: u64, mods: &Mods, out: &mut BTreeMap<String, u64>) {
        if let Some((_, subs)) = mods.get(m) {
            for (s, n) in subs {
                *out.entry(s.clone()).or_insert(0) += times * n;
                count(s, times * n, mods, out);
            }
        }
    }
    let mut instances = BTreeMap::new();
    count(top, 1, &mods, &mut instances);
    let mut out = Vec::new();
    for (m, n) in instances {
        // `$paramod$<hash>\name` or `$paramod\name\P=…`: the name is the second field.
        let short = m.split('\\').nth(1).unwrap_or(&m).to_string();
        out.push(SynthModule {
            gates_yosys: inclusive(&m, &mods, 0)?,
            module: short,
            instances: n,
        });
    }
    Ok(out)
}
