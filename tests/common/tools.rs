//! A test whose external tool (Verilator, Icarus, Yosys, libOSMesa, a Gallium driver) is
//! missing: under `.ci/run`, which sets `GLARE_REQUIRE_TOOLS`, it fails naming the install
//! line; under a plain `cargo test` it prints a SKIP note straight to stderr (past the
//! harness's capture, so it shows) and passes.
#![allow(dead_code)]

use std::io::Write;

/// Set by `.ci/run`: every tool it installs must be there.
pub const REQUIRE_TOOLS: &str = "GLARE_REQUIRE_TOOLS";

/// `why` says what is missing, what did not run and the install line.
pub fn skip(why: &str) {
    if std::env::var_os(REQUIRE_TOOLS).is_some() {
        panic!("{why} ({REQUIRE_TOOLS} is set, as .ci/run sets it: a missing tool fails the test)");
    }
    let _ = std::io::stderr().write_all(format!("SKIP: {why}\n").as_bytes());
}

/// Whether `cc` builds and links a program against libOSMesa (its headers and library),
/// probed in `dir` (created).
pub fn osmesa_toolchain(dir: &std::path::Path) -> bool {
    std::fs::create_dir_all(dir).unwrap();
    let src = dir.join("probe.c");
    std::fs::write(
        &src,
        "#include <GL/osmesa.h>\nint main(void) { return OSMesaGetCurrentContext() != 0; }\n",
    )
    .unwrap();
    std::process::Command::new("cc")
        .arg(&src)
        .arg("-o")
        .arg(dir.join("probe"))
        .args(["-lOSMesa", "-lm"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}
