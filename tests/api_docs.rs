//! The library's API documentation builds without a warning: `cargo doc --workspace
//! --no-deps` under `RUSTDOCFLAGS=-D warnings` (broken intra-doc links, links to private
//! items, stray HTML in prose). It runs cargo in its own target directory,
//! `target/rustdoc-check`, as the outer `cargo test` holds the build lock of `target/`.

use std::path::Path;
use std::process::Command;

#[test]
fn cargo_doc_has_no_warnings() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(["doc", "--workspace", "--no-deps", "--offline", "--quiet"])
        .current_dir(root)
        .env("RUSTDOCFLAGS", "-D warnings")
        .env("CARGO_TARGET_DIR", root.join("target/rustdoc-check"))
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo doc --workspace --no-deps with RUSTDOCFLAGS=-D warnings failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
