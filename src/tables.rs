//! RAM/ROM images as `$readmemh` hex files plus a manifest.
//!
//! Every table a unit holds in its default configuration (and every texture of the
//! built-in scene) is written by `cargo run --release -- tables`; a test regenerates
//! them and fails on any difference with the committed `tables/`.

use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// One RAM/ROM image: `depth` words of `width` bits.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// File stem, e.g. `projective_texcoord.recip_rom`.
    pub name: String,
    /// Entry width in bits.
    pub width: u32,
    pub words: Vec<u64>,
    /// Which unit holds it and the parameters it was generated from.
    pub unit: String,
    pub params: BTreeMap<String, String>,
}

/// Manifest entry (serialised to `tables/manifest.json`).
#[derive(Serialize)]
struct ManifestEntry<'a> {
    name: &'a str,
    file: String,
    unit: &'a str,
    depth: usize,
    width: u32,
    bits: u64,
    params: &'a BTreeMap<String, String>,
}

impl Table {
    /// `$readmemh` text: a comment header, then one word per line in ⌈width/4⌉ hex digits.
    pub fn to_readmemh(&self) -> String {
        let digits = self.width.div_ceil(4) as usize;
        let mut s = String::with_capacity(self.words.len() * (digits + 1) + 128);
        let _ = writeln!(
            s,
            "// {}: {} x {} bits, held by {}",
            self.name,
            self.words.len(),
            self.width,
            self.unit
        );
        for (k, v) in &self.params {
            let _ = writeln!(s, "// {k} = {v}");
        }
        for w in &self.words {
            let _ = writeln!(s, "{w:0digits$x}");
        }
        s
    }

    pub fn file_name(&self) -> String {
        format!("{}.hex", self.name)
    }
}

/// The manifest text for a set of tables (JSON, stable order).
pub fn manifest(tables: &[Table]) -> String {
    let entries: Vec<ManifestEntry> = tables
        .iter()
        .map(|t| ManifestEntry {
            name: &t.name,
            file: t.file_name(),
            unit: &t.unit,
            depth: t.words.len(),
            width: t.width,
            bits: t.words.len() as u64 * t.width as u64,
            params: &t.params,
        })
        .collect();
    let mut s = serde_json::to_string_pretty(&entries).expect("manifest serialises");
    s.push('\n');
    s
}

/// Every file `tables/` should hold: (file name, contents).
pub fn expected_files(tables: &[Table]) -> Vec<(String, String)> {
    let mut files: Vec<(String, String)> = tables
        .iter()
        .map(|t| (t.file_name(), t.to_readmemh()))
        .collect();
    files.push(("manifest.json".to_string(), manifest(tables)));
    files
}

/// Write the tables and manifest into `dir` (created if missing).
pub fn write_all(dir: &Path, tables: &[Table]) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    for (name, text) in expected_files(tables) {
        // Atomically (`report::atomic`): each image is the old one or the whole new one.
        crate::report::atomic::write_bytes(&dir.join(name), text.as_bytes())
            .map_err(std::io::Error::other)?;
    }
    Ok(())
}
