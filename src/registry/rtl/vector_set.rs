//! A unit's RTL vectors: the [`VectorSet`] of stimulus and expected words a unit's
//! model writes for its Verilog, how one is collected from the kernel ([`collect`]),
//! packed ([`pack_hex`]) and written out. The units' vector writers and the table of
//! units with Verilog (`mod.rs`) import this file; it imports none of them.

use super::super::unit_entry::seeded;
use rand::Rng;
use rtl_model::{Counters, Signal, Unit};
use std::fmt::Write as _;
use std::path::Path;

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

pub(super) fn fields(sig: &[Signal]) -> Vec<Field> {
    sig.iter()
        .map(|s| Field {
            name: s.name,
            width: s.width,
        })
        .collect()
}

/// A module's Verilog parameters, by name.
pub(super) type VerilogParams = Vec<(&'static str, u64)>;

/// The vectors of `u` from reset state `state`: `make` builds an input word from field
/// values in `in_signals` order (`probe` is any input word, for the field widths).
#[allow(clippy::too_many_arguments)]
pub(super) fn collect<U: Unit>(
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
pub(super) fn time_batch<U: Unit>(u: &U, state0: &U::State, inputs: &[U::In]) -> f64 {
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
        v.push_str(&self.table_instances(|r| rom_from_file(r, dir)));
        let _ = writeln!(v, "endmodule");
        v
    }

    /// The module `vlmem_<tag>`: the unit at this configuration's parameters behind
    /// flat ports (`clk`, `rst`, `in_valid`, `in_word`, `out_valid`, `out_word`), its
    /// tables attached as in [`Self::cosim_block`] (read from `<dir>/<name>.hex`). The
    /// top of the in-memory Verilator harness (`rtl_model/verilog/tb/tb_memory.cpp`),
    /// which drives the ports from C++.
    pub fn memory_top(&self, dir: &Path) -> String {
        let tag = self.tag();
        let (iw, ow) = (self.in_bits(), self.out_bits());
        let mut v = String::new();
        let _ = writeln!(
            v,
            "// Generated by `glare-pipeline units --rtl-speed` (the in-memory harness's top)."
        );
        let _ = writeln!(v, "module vlmem_{tag} (");
        let _ = writeln!(v, "    input clk,\n    input rst,\n    input in_valid,");
        let _ = writeln!(v, "    input [{}:0] in_word,", iw - 1);
        let _ = writeln!(v, "    output out_valid,");
        let _ = writeln!(v, "    output [{}:0] out_word", ow - 1);
        let _ = writeln!(v, ");");
        v.push_str(&self.table_wires());
        v.push_str(&self.dut_instance());
        v.push_str(&self.table_instances(|r| rom_from_file(r, dir)));
        let _ = writeln!(v, "endmodule");
        v
    }

    // The unit's side of a testbench block, shared by the co-simulation
    // (`cosim_block`) and the DPI-C scoreboard (`dpi::dpi_block`), so a unit's ports
    // are wired the same in both. Only the ROM module differs (`rtl_rom` from the
    // vector set's files, `dpi_rom` from the model).

    /// The wires a block declares: the testbench handshake, the packed words and every
    /// table port (ROM read ports, RAM read/write ports).
    pub(super) fn dut_wires(&self) -> String {
        let mut v = String::new();
        let _ = writeln!(v, "  wire clk, rst, in_valid, out_valid;");
        let _ = writeln!(v, "  wire [{}:0] in_word;", self.in_bits() - 1);
        let _ = writeln!(v, "  wire [{}:0] out_word;", self.out_bits() - 1);
        v.push_str(&self.table_wires());
        v
    }

    /// The wires of every table port (ROM read ports, RAM read/write ports).
    fn table_wires(&self) -> String {
        let mut v = String::new();
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
    pub(super) fn dut_instance(&self) -> String {
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
    pub(super) fn table_instances(&self, rom: impl Fn(&RomPort) -> String) -> String {
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

/// A ROM read port's module: `rtl_rom` loaded from `<dir>/<name>.hex`.
fn rom_from_file(r: &RomPort, dir: &Path) -> String {
    format!(
        "rtl_rom #(.W({}), .DEPTH({}), .AW({}), .FILE(\"{}\"))",
        r.width,
        r.words.len(),
        r.addr_bits(),
        dir.join(format!("{}.hex", r.name)).display()
    )
}

pub(super) fn lines(words: &[String]) -> String {
    let mut s = String::with_capacity(words.iter().map(|w| w.len() + 1).sum());
    for w in words {
        s.push_str(w);
        s.push('\n');
    }
    s
}
