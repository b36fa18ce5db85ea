//! docs/units.md holds the registry's figures (widths, latency, II, gates, RAM bits)
//! exactly as the registry generates them, and one section per registry unit.

use glare_pipeline::registry::{self, datasheet};
use std::path::Path;

fn committed() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/units.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn committed_datasheet_equals_its_regeneration() {
    let doc = committed();
    let regenerated = datasheet::refresh(&doc, &registry::summaries())
        .unwrap_or_else(|e| panic!("docs/units.md: {e}"));
    if let Some((i, (have, want))) = doc
        .lines()
        .zip(regenerated.lines())
        .enumerate()
        .find(|(_, (a, b))| a != b)
    {
        panic!(
            "docs/units.md line {} differs from the registry (run `cargo run -- units \
             --datasheet docs/units.md`):\n  have: {have}\n  want: {want}",
            i + 1
        );
    }
    assert_eq!(
        doc, regenerated,
        "docs/units.md differs from the registry in its length (run `cargo run -- units \
         --datasheet docs/units.md`)"
    );
}

#[test]
fn every_registry_unit_has_its_figures_in_its_section() {
    let doc = committed();
    for s in registry::summaries() {
        let heading = format!("\n## {}\n", s.name);
        let at = doc
            .find(&heading)
            .unwrap_or_else(|| panic!("no section `## {}`", s.name));
        let section = &doc[at + heading.len()..];
        let section = &section[..section.find("\n## ").unwrap_or(section.len())];
        let figures = datasheet::unit_figures(&s).join("\n");
        assert!(
            section.contains(&figures),
            "section `## {}` lacks its figures: {figures}",
            s.name
        );
    }
}

#[test]
fn a_stale_figure_is_rewritten() {
    let doc = committed();
    let s = registry::summaries();
    let stale = doc.replacen(
        "latency 2, II 1, 872 gates",
        "latency 3, II 1, 871 gates",
        1,
    );
    assert_ne!(
        stale, doc,
        "the modulate figures were not found to make stale"
    );
    assert_eq!(datasheet::refresh(&stale, &s).unwrap(), doc);
    let stale_row = doc.replacen(
        "| 2 | 1 | 872 | 0 | bits=8 |",
        "| 2 | 1 | 870 | 0 | bits=8 |",
        1,
    );
    assert_ne!(stale_row, doc);
    assert_eq!(datasheet::refresh(&stale_row, &s).unwrap(), doc);
}

#[test]
fn a_missing_block_is_inserted_under_its_heading() {
    let doc = committed();
    let s = registry::summaries();
    let start = doc.find("<!-- registry:modulate -->").unwrap();
    let end_marker = "<!-- /registry:modulate -->\n\n";
    let end = doc.find(end_marker).unwrap() + end_marker.len();
    let without = format!("{}{}", &doc[..start], &doc[end..]);
    // (`registry:modulate_chain` stays: only `modulate`'s own block is cut.)
    assert!(!without.contains("registry:modulate -->"));
    assert_eq!(datasheet::refresh(&without, &s).unwrap(), doc);
}

#[test]
fn sections_must_be_exactly_the_registry_units_in_order() {
    let doc = committed();
    let s = registry::summaries();

    let missing = doc.replacen("\n## chaos_map\n", "\n## Chaos map\n", 1);
    let err = datasheet::refresh(&missing, &s).unwrap_err();
    assert!(err.contains("no section `## chaos_map`"), "{err}");

    let extra = format!("{doc}\n## nonesuch\n\nA unit the registry does not know.\n");
    let err = datasheet::refresh(&extra, &s).unwrap_err();
    assert!(
        err.contains("`## nonesuch` names no registry unit"),
        "{err}"
    );

    let twice = format!("{doc}\n## modulate\n");
    let err = datasheet::refresh(&twice, &s).unwrap_err();
    assert!(err.contains("a second section `## modulate`"), "{err}");

    let mut reordered = s.clone();
    reordered.swap(0, 1);
    let err = datasheet::refresh(&doc, &reordered).unwrap_err();
    assert!(err.contains("out of registry order"), "{err}");
}

#[test]
fn broken_markers_are_errors_naming_the_line() {
    let doc = committed();
    let s = registry::summaries();
    let unterminated = doc.replacen("<!-- /registry:modulate -->", "", 1);
    let err = datasheet::refresh(&unterminated, &s).unwrap_err();
    assert!(err.contains("<!-- registry:modulate -->` has no"), "{err}");
    assert!(err.starts_with("line "), "{err}");

    let no_summary = doc.replacen("<!-- registry:summary -->", "", 1).replacen(
        "<!-- /registry:summary -->",
        "",
        1,
    );
    let err = datasheet::refresh(&no_summary, &s).unwrap_err();
    assert!(err.contains("0 summary blocks"), "{err}");
}
