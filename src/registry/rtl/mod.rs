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

use super::unit_entry::seeded;

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
use std::fmt::Write as _;
use std::path::Path;

mod final_combiner;
mod modulate_chain;
mod register_combiner;
mod texture_combiner;
mod vector_set;
mod vertex_lighting;
pub use blend::{blend_mode_sets, vectors_of as blend_vectors_of};
pub use specular_lookup::vectors_of as specular_lookup_vectors_of;
pub use texture_combiner::vectors_of as texture_combiner_vectors_of;
pub use vertex_lighting::{light_controls, vertex_lighting_mode_sets};

use vector_set::{collect, VerilogParams};
pub use vector_set::{
    pack_hex, Field, RamPort, RomPort, RtlConfig, VectorSet, EXHAUSTIVE_BITS, MAX_VECTORS,
};

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
