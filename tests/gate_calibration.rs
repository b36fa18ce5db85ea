//! Gate calibration: the cost model's primitives against Yosys.
//!
//! `rtl_model/verilog/yosys_stat.txt` holds the per-cell counts Yosys gives for each
//! `rtl_model/verilog/*.v` under the pinned command (see `calibrate.sh`):
//!
//! ```text
//! yosys -q -p "read_verilog X.v; synth -top X; abc -g AND,NAND,OR,NOR,XOR,XNOR,MUX; tee -o OUT stat"
//! ```
//!
//! Both sides are weighted with the one mapping `rtl_model::cost::CELL_WEIGHTS`, and the
//! model must be within 25 % of Yosys for each circuit. The file is checked for
//! staleness twice: by the POSIX `cksum` of every `.v` file it records (always), and,
//! when `yosys` is on PATH, by re-running the synthesis into a temporary directory
//! and comparing with the committed counts.
//!
//! Regenerate: `bash rtl_model/verilog/calibrate.sh`, then
//! `cargo test --test gate_calibration -- --nocapture` prints the table of
//! docs/units.md (gate calibration section).

#[path = "common/tools.rs"]
mod tools;

use rtl_model::cost::{prim, Cells, CELL_WEIGHTS};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Allowed |model − Yosys| / Yosys.
const TOLERANCE: f64 = 0.25;

/// The circuits: Verilog module, the model primitive it stands for, and its cells.
fn circuits() -> Vec<(&'static str, &'static str, Cells)> {
    vec![
        ("mul8x8", "prim::multiplier(8, 8)", prim::multiplier(8, 8)),
        (
            "satadd8",
            "prim::saturating_adder(8)",
            prim::saturating_adder(8),
        ),
        ("mux8", "prim::mux(8)", prim::mux(8)),
        ("add8", "prim::adder(8)", prim::adder(8)),
        // The remaining primitives at widths the units use (their `cost()` calls
        // comparators of 13–61 bits, multipliers from 8×8 to 52×19 and 32×38,
        // subtractors of 9–52 bits, leading-zero counters of 23–38 bits, shifters of
        // 19–53 bits over 1–6 stages, 4:1 and 3:1 muxes of 32 and 8 bits, a divider of
        // 39-bit rows).
        ("sub16", "prim::subtractor(16)", prim::subtractor(16)),
        // `a < b` at 16 and 32 bits: n NOT + n XNOR2 + 3n NAND2 (6 NAND2 eq. a bit).
        ("cmp16", "prim::comparator(16)", prim::comparator(16)),
        ("cmp32", "prim::comparator(32)", prim::comparator(32)),
        (
            "mul12x12",
            "prim::multiplier(12, 12)",
            prim::multiplier(12, 12),
        ),
        (
            "mul16x16",
            "prim::multiplier(16, 16)",
            prim::multiplier(16, 16),
        ),
        (
            "mul16x8",
            "prim::multiplier(16, 8)",
            prim::multiplier(16, 8),
        ),
        (
            "mul32x16",
            "prim::multiplier(32, 16)",
            prim::multiplier(32, 16),
        ),
        ("mux4_16", "prim::mux_k(16, 4)", prim::mux_k(16, 4)),
        ("mux3_8", "prim::mux_k(8, 3)", prim::mux_k(8, 3)),
        ("reg16", "prim::register(16)", prim::register(16)),
        ("shl32_5", "prim::shifter(32, 5)", prim::shifter(32, 5)),
        (
            "lzc32",
            "prim::leading_zero_counter(32)",
            prim::leading_zero_counter(32),
        ),
        // An 8-bit divisor: rows of 9 bits (the remainder shifted left by one), 8
        // quotient bits; and the same at 16 bits.
        ("div16_8", "prim::divider(9, 8)", prim::divider(9, 8)),
        ("div32_16", "prim::divider(17, 16)", prim::divider(17, 16)),
    ]
}

fn verilog_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl_model/verilog")
}

/// yosys_stat.txt, parsed.
#[derive(Debug, PartialEq)]
struct Stat {
    version: String,
    /// module → (POSIX cksum, size in bytes) of its .v file.
    sources: BTreeMap<String, (u32, u64)>,
    /// module → cell type → count.
    cells: BTreeMap<String, BTreeMap<String, u64>>,
}

fn parse(text: &str) -> Stat {
    let mut st = Stat {
        version: String::new(),
        sources: BTreeMap::new(),
        cells: BTreeMap::new(),
    };
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let f: Vec<&str> = line.split_whitespace().collect();
        match f[0] {
            "yosys" => st.version = f[1..].join(" "),
            "source" => {
                assert_eq!(f.len(), 4, "line {}: {line}", i + 1);
                st.sources.insert(
                    f[1].to_string(),
                    (f[2].parse().unwrap(), f[3].parse().unwrap()),
                );
            }
            m => {
                assert_eq!(f.len(), 3, "line {}: {line}", i + 1);
                assert!(f[1].starts_with("$_"), "line {}: {line}", i + 1);
                let n: u64 = f[2]
                    .parse()
                    .unwrap_or_else(|_| panic!("line {}: {line}", i + 1));
                st.cells
                    .entry(m.to_string())
                    .or_default()
                    .insert(f[1].to_string(), n);
            }
        }
    }
    st
}

/// Yosys' internal gate cells as the model's cell kinds.
fn to_cells(counts: &BTreeMap<String, u64>) -> Cells {
    let mut c = Cells::default();
    for (cell, &n) in counts {
        let n = n as f64;
        match cell.as_str() {
            "$_AND_" => c.and2 += n,
            "$_NAND_" => c.nand2 += n,
            "$_OR_" => c.or2 += n,
            "$_NOR_" => c.nor2 += n,
            "$_XOR_" => c.xor2 += n,
            "$_XNOR_" => c.xnor2 += n,
            "$_MUX_" => c.mux2 += n,
            "$_NOT_" => c.not += n,
            "$_BUF_" => {}
            // A plain D flip-flop, clocked on the rising or the falling edge. Flops with
            // an enable ($_DFFE_*), a reset ($_SDFF*_, $_DFF_PN0_, …) or set/reset
            // carry logic a bare `dff` weight would drop, so they are not mapped here.
            "$_DFF_P_" | "$_DFF_N_" => c.dff += n,
            other => panic!("cell {other} has no weight in CELL_WEIGHTS"),
        }
    }
    c
}

/// POSIX `cksum`: CRC-32 (poly 0x04C11DB7, MSB first) over the data and then its
/// length (low byte first, as few bytes as needed), complemented.
fn posix_cksum(data: &[u8]) -> u32 {
    fn feed(crc: &mut u32, b: u8) {
        *crc ^= (b as u32) << 24;
        for _ in 0..8 {
            *crc = if *crc & 0x8000_0000 != 0 {
                (*crc << 1) ^ 0x04C1_1DB7
            } else {
                *crc << 1
            };
        }
    }
    let mut crc = 0u32;
    for &b in data {
        feed(&mut crc, b);
    }
    let mut n = data.len();
    while n != 0 {
        feed(&mut crc, (n & 0xff) as u8);
        n >>= 8;
    }
    !crc
}

fn committed() -> Stat {
    let p = verilog_dir().join("yosys_stat.txt");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    parse(&text)
}

/// (Yosys NAND2 eq., model NAND2 eq., difference in %) for one module.
fn compare(st: &Stat, module: &str, model: Cells) -> (f64, f64, f64) {
    let counts = st
        .cells
        .get(module)
        .unwrap_or_else(|| panic!("{module} missing from yosys_stat.txt"));
    let y = to_cells(counts).nand2_eq();
    let m = model.nand2_eq();
    let d = 100.0 * (m - y) / y;
    // Print an exact match as 0.0, not −0.0.
    (y, m, if d.abs() < 1e-9 { 0.0 } else { d })
}

fn assert_within_tolerance(st: &Stat, source: &str) {
    println!("Yosys: {} ({source})", st.version);
    println!("| circuit | model | Yosys cells | Yosys NAND2 eq. | model NAND2 eq. | difference |");
    println!("|---|---|---|---|---|---|");
    for (module, prim_name, cells) in circuits() {
        let (y, m, d) = compare(st, module, cells);
        let list: Vec<String> = st.cells[module]
            .iter()
            .map(|(c, n)| format!("{} {n}", c.trim_start_matches("$_").trim_end_matches('_')))
            .collect();
        println!(
            "| {module} | `{prim_name}` | {} | {y:.2} | {m:.2} | {d:+.1} % |",
            list.join(", ")
        );
        assert!(
            d.abs() <= 100.0 * TOLERANCE,
            "{module}: model {m:.2} vs Yosys {y:.2} NAND2 eq. ({d:+.1} %) exceeds ±{} %",
            100.0 * TOLERANCE
        );
    }
}

#[test]
fn model_within_25_percent_of_committed_yosys_counts() {
    assert_within_tolerance(&committed(), "committed yosys_stat.txt");
}

#[test]
fn weights_are_the_documented_ones() {
    // docs/units.md (gate calibration section) quotes these.
    let w = CELL_WEIGHTS;
    let got = [
        w.nand2, w.nor2, w.and2, w.or2, w.xor2, w.xnor2, w.mux2, w.not, w.dff,
    ];
    let want = [
        1.0,
        1.0,
        4.0 / 3.0,
        4.0 / 3.0,
        7.0 / 3.0,
        7.0 / 3.0,
        7.0 / 3.0,
        2.0 / 3.0,
        16.0 / 3.0,
    ];
    assert_eq!(got, want);
}

#[test]
fn committed_counts_are_not_stale() {
    let st = committed();
    assert!(!st.version.is_empty(), "no yosys version line");
    let mut modules = Vec::new();
    for e in std::fs::read_dir(verilog_dir()).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "v") {
            let m = p.file_stem().unwrap().to_string_lossy().to_string();
            let data = std::fs::read(&p).unwrap();
            let want = (posix_cksum(&data), data.len() as u64);
            assert_eq!(
                st.sources.get(&m),
                Some(&want),
                "{}.v changed since yosys_stat.txt was written: run `bash rtl_model/verilog/calibrate.sh`",
                m
            );
            assert!(st.cells.contains_key(&m), "no cells for {m}");
            modules.push(m);
        }
    }
    modules.sort();
    let recorded: Vec<String> = st.sources.keys().cloned().collect();
    assert_eq!(
        modules, recorded,
        "yosys_stat.txt lists other files than rtl_model/verilog/*.v"
    );
    for (m, _, _) in circuits() {
        assert!(modules.iter().any(|x| x == m), "{m}.v missing");
    }
}

#[test]
fn plain_dff_cells_weigh_as_the_models_register() {
    // reg16.v synthesises to 16 $_DFF_P_; a falling-edge flop is the same cell kind.
    for cell in ["$_DFF_P_", "$_DFF_N_"] {
        let counts = BTreeMap::from([(cell.to_string(), 16)]);
        assert_eq!(to_cells(&counts), prim::register(16), "{cell}");
    }
}

#[test]
#[should_panic(expected = "has no weight")]
fn a_flop_with_enable_is_not_weighed_as_a_bare_dff() {
    to_cells(&BTreeMap::from([("$_DFFE_PP_".to_string(), 1)]));
}

#[test]
fn posix_cksum_matches_known_values() {
    // `printf '' | cksum` and `printf 'abc' | cksum`.
    assert_eq!(posix_cksum(b""), 4294967295);
    assert_eq!(posix_cksum(b"abc"), 1219131554);
}

#[test]
fn live_yosys_reproduces_committed_counts() {
    let version = match Command::new("yosys").arg("-V").output() {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
            .lines()
            .next()
            .unwrap_or("")
            .trim()
            .to_string(),
        _ => {
            tools::skip(
                "yosys not on PATH: live re-synthesis skipped; the committed \
                 yosys_stat.txt is still checked (tolerance, cksums) (apt-get install yosys)",
            );
            return;
        }
    };
    let dir = std::env::temp_dir().join(format!("gate_calibration_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("yosys_stat.txt");
    let script = verilog_dir().join("calibrate.sh");
    let status = Command::new("bash")
        .arg(&script)
        .arg(&out)
        .status()
        .expect("run calibrate.sh");
    assert!(status.success(), "calibrate.sh failed");
    let fresh = parse(&std::fs::read_to_string(&out).unwrap());
    std::fs::remove_dir_all(&dir).ok();
    let old = committed();
    assert_eq!(fresh.version, version);
    if fresh.version == old.version {
        assert_eq!(
            fresh, old,
            "yosys_stat.txt is stale: run `bash rtl_model/verilog/calibrate.sh` and commit it"
        );
    } else {
        // Another Yosys/ABC release maps a little differently: the committed file
        // cannot be compared count for count, but the model must still be within
        // tolerance of what this Yosys gives, and the sources must be the same.
        println!(
            "note: yosys here is '{}', yosys_stat.txt was made with '{}': \
             counts not compared exactly",
            fresh.version, old.version
        );
        assert_eq!(fresh.sources, old.sources, "yosys_stat.txt is stale");
        assert_within_tolerance(&fresh, "live re-synthesis");
    }
}
