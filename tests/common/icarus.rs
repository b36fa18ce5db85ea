//! One vector set under Icarus, by hand-sized runs beside tests/rtl_cosim.rs
//! (tests/rtl_specular_lookup.rs, tests/rtl_texture_combiner.rs): write the set,
//! compile it with the generic testbench and the unit's sources, run it.

use glare_pipeline::registry::rtl::{self, VectorSet};
use std::path::Path;
use std::process::Command;

/// `iverilog` runs (the callers print a `SKIP:` line and return otherwise).
pub fn have_iverilog() -> bool {
    Command::new("iverilog")
        .arg("-V")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Write `v` into `dir`, compile its cosim block with `tb/tb_vectors.v` and `sources`
/// (paths under `rtl_model/verilog`), run every transaction under `vvp`, and return
/// the testbench's summary line (`COSIM tag=… n=… checked=… mismatches=…`), or the
/// whole output when there is none.
pub fn run_set(v: &VectorSet, dir: &Path, sources: &[&str]) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let verilog = root.join("rtl_model/verilog");
    v.write(dir).unwrap();
    let tag = v.tag();
    let vvp = dir.join("sim.vvp");
    let mut c = Command::new("iverilog");
    c.args(["-g2005", "-s", &format!("cosim_{tag}"), "-o"])
        .arg(&vvp)
        .arg(rtl::verilog_include_arg(root))
        .arg(verilog.join("tb/tb_vectors.v"));
    for s in sources {
        c.arg(verilog.join(s));
    }
    let c = c.arg(dir.join(format!("cosim_{tag}.v"))).output().unwrap();
    assert!(
        c.status.success(),
        "iverilog: {}",
        String::from_utf8_lossy(&c.stderr)
    );
    let o = Command::new("vvp")
        .arg("-n")
        .arg(&vvp)
        .arg(format!("+tag={tag}"))
        .arg(format!("+n={}", v.stimulus.len()))
        .arg(format!("+stim={}", dir.join("stimulus.hex").display()))
        .arg(format!("+expect={}", dir.join("expected.hex").display()))
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    out.lines()
        .find(|l| l.starts_with("COSIM ") && l.contains(" n="))
        .map_or_else(|| out.to_string(), str::to_string)
}

/// The summary line's tail when all `n` transactions matched on their cycle.
pub fn clean_tail(n: usize) -> String {
    format!("n={n} checked={n} mismatches=0 valid_errors=0 first_bad=-1")
}
