//! The registry's one table agrees with itself and with the source tree: every entry
//! names its unit's instance and tables, every unit in `rtl_model/src/units/` has an
//! entry, and every entry has the files a newcomer looks for by the unit's name.

use glare_pipeline::registry::{self, UNITS, UNIT_NAMES};
use std::collections::BTreeSet;
use std::path::Path;

#[test]
fn every_entry_is_named_like_its_unit_its_tables_and_its_files() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut seen = BTreeSet::new();
    for e in UNITS {
        assert!(seen.insert(e.name), "{}: two entries", e.name);
        assert_eq!(
            (e.summary)().name,
            e.name,
            "the summary of entry {}",
            e.name
        );
        for t in (e.tables)() {
            assert_eq!(t.unit, e.name, "table {} of entry {}", t.name, e.name);
        }
        for file in [
            format!("rtl_model/src/units/{}.rs", e.name),
            format!("src/reference/{}.rs", e.name),
            format!("tests/{}.rs", e.name),
            format!("src/registry/{}.rs", e.name),
        ] {
            assert!(root.join(&file).is_file(), "{}: no {file}", e.name);
        }
    }
    assert_eq!(UNIT_NAMES, UNITS.iter().map(|e| e.name).collect::<Vec<_>>());
    let names: Vec<_> = registry::summaries().iter().map(|s| s.name).collect();
    assert_eq!(names, UNIT_NAMES, "summaries() in registry order");
}

#[test]
fn every_unit_in_rtl_model_has_an_entry() {
    // A unit file implements the `Unit` trait; shared parts (luminance_ram) do not.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl_model/src/units");
    let mut units = Vec::new();
    for f in std::fs::read_dir(&dir).unwrap() {
        let path = f.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        if text.contains("impl Unit for ") {
            units.push(path.file_stem().unwrap().to_string_lossy().into_owned());
        }
    }
    assert!(units.len() >= UNITS.len(), "found only {units:?}");
    for u in &units {
        assert!(
            registry::entry(u).is_some(),
            "rtl_model/src/units/{u}.rs has no registry entry (src/registry/mod.rs)"
        );
    }
}

#[test]
fn tables_keep_the_manifest_order_and_hold_every_entrys_tables() {
    let all = registry::tables();
    let from_entries: usize = UNITS.iter().map(|e| (e.tables)().len()).sum();
    assert_eq!(all.len(), from_entries);
    // The manifest lists a unit's tables together.
    let mut order: Vec<&str> = all.iter().map(|t| t.unit.as_str()).collect();
    order.dedup();
    let distinct: BTreeSet<&str> = order.iter().copied().collect();
    assert_eq!(
        order.len(),
        distinct.len(),
        "a unit's tables apart: {order:?}"
    );
}

#[test]
fn unknown_units_are_named_with_the_known_ones() {
    let err = registry::trace("nonesuch", 3, 1, &mut Vec::new()).unwrap_err();
    assert!(err.starts_with("unit: unknown unit 'nonesuch'"), "{err}");
    for n in UNIT_NAMES {
        assert!(err.contains(n), "{err} lacks {n}");
    }
}
