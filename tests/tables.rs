//! `tables/` must match what `cargo run --release -- tables` regenerates, byte for byte.

use glare_pipeline::registry;
use glare_pipeline::tables::expected_files;
use std::path::Path;

#[test]
fn committed_tables_match_regeneration() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tables");
    let files = expected_files(&registry::tables());
    for (name, text) in &files {
        let path = dir.join(name);
        let on_disk = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e} (run `cargo run --release -- tables`)",
                path.display()
            )
        });
        assert!(
            on_disk == *text,
            "{} differs from its regeneration (run `cargo run --release -- tables`)",
            path.display()
        );
    }
    // No stale files either (folders such as tables/conformance/ have their own tests).
    let mut listed: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    listed.sort();
    let mut want: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
    want.sort();
    assert_eq!(
        listed, want,
        "tables/ holds files the generator does not make"
    );
}

#[test]
fn readmemh_words_fit_their_width() {
    for t in registry::tables() {
        assert!(!t.words.is_empty(), "{}: empty table", t.name);
        let digits = t.width.div_ceil(4) as usize;
        for (i, line) in t
            .to_readmemh()
            .lines()
            .filter(|l| !l.starts_with("//"))
            .enumerate()
        {
            assert_eq!(line.len(), digits, "{} word {i}", t.name);
            let v = u64::from_str_radix(line, 16).unwrap();
            assert!(
                t.width >= 64 || v >> t.width == 0,
                "{} word {i} exceeds {} bits",
                t.name,
                t.width
            );
            assert_eq!(v, t.words[i]);
        }
    }
}
