//! Many vector sets under one build of each simulator, beside tests/rtl_cosim.rs
//! (tests/rtl_vertex_lighting.rs): the sets' blocks and a `cosim_top` instantiating
//! them, built once with the generic testbench and the unit's sources (Verilator
//! rebuilds only when a source changed), then each set run by its tag, two at a time.

use glare_pipeline::registry::rtl::{self, VectorSet};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The two simulators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sim {
    Verilator,
    Icarus,
}

impl Sim {
    pub fn name(self) -> &'static str {
        match self {
            Sim::Verilator => "verilator",
            Sim::Icarus => "icarus",
        }
    }

    /// The simulator runs (the callers skip with a note otherwise).
    pub fn installed(self) -> bool {
        let (tool, arg) = match self {
            Sim::Verilator => ("verilator", "--version"),
            Sim::Icarus => ("iverilog", "-V"),
        };
        Command::new(tool)
            .arg(arg)
            .output()
            .map(|o| o.status.success())
            .unwrap_or(false)
    }

    /// The apt package line for the skip note.
    pub fn install_line(self) -> &'static str {
        match self {
            Sim::Verilator => "apt-get install verilator g++ make",
            Sim::Icarus => "apt-get install iverilog",
        }
    }
}

/// Write every set of `sets` into `dir/<tag>/` and a `cosim_top` over them; returns the
/// Verilog files to build (the blocks, then the top).
pub fn write_sets(sets: &[VectorSet], dir: &Path) -> Vec<PathBuf> {
    std::fs::create_dir_all(dir).unwrap();
    let mut blocks = Vec::new();
    for v in sets {
        let d = dir.join(v.tag());
        v.write(&d).unwrap();
        blocks.push(d.join(format!("cosim_{}.v", v.tag())));
    }
    let tags: Vec<String> = sets.iter().map(VectorSet::tag).collect();
    let top = dir.join("cosim_top.v");
    std::fs::write(&top, rtl::cosim_top(&tags)).unwrap();
    blocks.push(top);
    blocks
}

fn run_ok(cmd: &mut Command, what: &str) {
    let o = cmd.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        o.status.success(),
        "{what} failed:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Build `sim`'s simulation in `build` of the generic testbench, `sources` (paths under
/// `rtl_model/verilog`) and `blocks` (from [`write_sets`]); returns the command that
/// runs a tag (program and leading arguments).
pub fn build(sim: Sim, build: &Path, sources: &[&str], blocks: &[PathBuf]) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let verilog = root.join("rtl_model/verilog");
    let mut srcs = vec![verilog.join("tb/tb_vectors.v")];
    srcs.extend(sources.iter().map(|s| verilog.join(s)));
    srcs.extend(blocks.iter().cloned());
    std::fs::create_dir_all(build).unwrap();
    match sim {
        Sim::Verilator => {
            let stamp: String = srcs
                .iter()
                .chain(&rtl::verilog_include_files(root))
                .map(|p| std::fs::read_to_string(p).unwrap())
                .collect();
            let obj = build.join("obj");
            let stamp_file = obj.join("sources.stamp");
            let bin = obj.join("Vcosim_top");
            let fresh = bin.exists()
                && std::fs::read_to_string(&stamp_file).ok().as_deref() == Some(&stamp);
            if !fresh {
                let mut c = Command::new("verilator");
                c.args([
                    "--binary",
                    "--timing",
                    "-Wno-fatal",
                    "-Wno-lint",
                    "-Wno-style",
                    "-O1",
                    "--top-module",
                    "cosim_top",
                    "-j",
                    "2",
                    "-Mdir",
                ])
                .arg(&obj)
                .arg(rtl::verilog_include_arg(root))
                .args(&srcs);
                run_ok(&mut c, "verilator build");
                std::fs::write(&stamp_file, &stamp).unwrap();
            }
            vec![bin.to_string_lossy().into_owned()]
        }
        Sim::Icarus => {
            let vvp = build.join("cosim.vvp");
            let mut c = Command::new("iverilog");
            c.args(["-g2005", "-s", "cosim_top", "-o"])
                .arg(&vvp)
                .arg(rtl::verilog_include_arg(root))
                .args(&srcs);
            run_ok(&mut c, "iverilog compile");
            vec![
                "vvp".into(),
                "-n".into(),
                vvp.to_string_lossy().into_owned(),
            ]
        }
    }
}

/// Run every set (written under `dir` by [`write_sets`]) with `run`, two at a time,
/// the longest first; returns each set's summary line (`COSIM tag=… n=… checked=…
/// mismatches=…`, or the whole output when there is none), in set order.
pub fn run_sets(run: &[String], sets: &[VectorSet], dir: &Path) -> Vec<String> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let lines: Vec<std::sync::Mutex<String>> =
        sets.iter().map(|_| std::sync::Mutex::default()).collect();
    let mut order: Vec<usize> = (0..sets.len()).collect();
    order.sort_by_key(|&i| {
        let v = &sets[i];
        std::cmp::Reverse(v.stimulus.len() as u64 * u64::from(v.ii) * u64::from(v.in_bits()))
    });
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(&i) = order.get(k) else { break };
                let v = &sets[i];
                let tag = v.tag();
                let d = dir.join(&tag);
                let o = Command::new(&run[0])
                    .args(&run[1..])
                    .arg(format!("+tag={tag}"))
                    .arg(format!("+n={}", v.stimulus.len()))
                    .arg(format!("+stim={}", d.join("stimulus.hex").display()))
                    .arg(format!("+expect={}", d.join("expected.hex").display()))
                    .output()
                    .unwrap();
                let out = String::from_utf8_lossy(&o.stdout);
                *lines[i].lock().unwrap() = out
                    .lines()
                    .find(|l| l.starts_with("COSIM ") && l.contains(" n="))
                    .map_or_else(|| out.to_string(), str::to_string);
            });
        }
    });
    lines.into_iter().map(|m| m.into_inner().unwrap()).collect()
}
