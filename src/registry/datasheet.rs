//! The figures of docs/units.md that the registry knows — each unit's default widths,
//! latency, II, gates (NAND2) and RAM bits — generated into the datasheet so that they
//! cannot drift from it. The prose stays hand-written around them.
//!
//! The datasheet holds generated blocks between marker lines: the summary table between
//! `<!-- registry:summary -->` and `<!-- /registry:summary -->`, wherever the author put
//! it, and under each unit's `## <unit>` heading a block `<!-- registry:<unit> -->` …
//! `<!-- /registry:<unit> -->`. [`refresh`] rewrites the blocks from the summaries
//! (inserting a missing unit block under its heading) and rejects a datasheet whose unit
//! sections are not exactly the registry's, in registry order. A unit section is a
//! level-2 heading that is a bare identifier (`## texture_sampler`); other level-2
//! headings (`## Summary at the GeForce-era defaults`) are prose.

use rtl_model::UnitSummary;

const SUMMARY_TAG: &str = "summary";

fn begin_marker(tag: &str) -> String {
    format!("<!-- registry:{tag} -->")
}

fn end_marker(tag: &str) -> String {
    format!("<!-- /registry:{tag} -->")
}

/// The tag of a begin marker line (`<!-- registry:TAG -->`), if the line is one.
fn begin_tag(line: &str) -> Option<&str> {
    line.trim_end()
        .strip_prefix("<!-- registry:")?
        .strip_suffix(" -->")
}

/// The unit named by a unit-section heading (`## name`, name a lower-case identifier).
fn section_unit(line: &str) -> Option<&str> {
    let name = line.strip_prefix("## ")?.trim_end();
    let mut chars = name.chars();
    let ident = chars.next().is_some_and(|c| c.is_ascii_lowercase())
        && chars.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    ident.then_some(name)
}

/// `1234567` → `1,234,567`.
fn thousands(v: u64) -> String {
    let digits = v.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Gates as `units` prints them (rounded to a whole NAND2), with thousands separators.
fn gates(s: &UnitSummary) -> String {
    let whole = format!("{:.0}", s.gates_nand2);
    whole.parse().map(thousands).unwrap_or(whole)
}

fn widths(s: &UnitSummary) -> String {
    s.widths
        .iter()
        .map(|w| format!("{}={}", w.name, w.bits))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The summary table: one row per unit, linked to its section.
pub fn summary_table(summaries: &[UnitSummary]) -> Vec<String> {
    let mut rows = vec![
        "| unit | latency | II | gates (NAND2) | RAM bits | widths |".to_string(),
        "|---|---|---|---|---|---|".to_string(),
    ];
    rows.extend(summaries.iter().map(|s| {
        format!(
            "| [`{n}`](#{n}) | {} | {} | {} | {} | {} |",
            s.latency,
            s.ii,
            gates(s),
            thousands(s.ram_bits),
            widths(s),
            n = s.name
        )
    }));
    rows
}

/// The figures at the head of a unit's section.
pub fn unit_figures(s: &UnitSummary) -> Vec<String> {
    vec![format!(
        "**At the defaults** (from the registry): latency {}, II {}, {} gates (NAND2), \
         {} RAM bits; widths {}.",
        s.latency,
        s.ii,
        gates(s),
        thousands(s.ram_bits),
        widths(s)
    )]
}

/// A generated block: markers around `body`, blank lines inside so that the markdown
/// around them (a table, a paragraph) ends and starts cleanly.
fn block(tag: &str, body: Vec<String>) -> Vec<String> {
    let mut out = vec![begin_marker(tag), String::new()];
    out.extend(body);
    out.push(String::new());
    out.push(end_marker(tag));
    out
}

/// `doc` with every generated block rewritten from `summaries` (in registry order).
/// Errors name the line or the unit: a unit without a section, a section for no
/// registry unit, a repeated or misordered section, a block without its end marker, no
/// summary block.
pub fn refresh(doc: &str, summaries: &[UnitSummary]) -> Result<String, String> {
    let mut out: Vec<String> = Vec::new();
    let mut sections: Vec<&str> = Vec::new();
    let mut summary_blocks = 0;
    let mut lines = doc.lines().enumerate();
    while let Some((i, line)) = lines.next() {
        if let Some(tag) = begin_tag(line) {
            // Skip the old block, whatever it said, up to its end marker.
            let end = end_marker(tag);
            if !lines.any(|(_, l)| l.trim_end() == end) {
                return Err(format!("line {}: `{line}` has no `{end}`", i + 1));
            }
            if tag == SUMMARY_TAG {
                summary_blocks += 1;
                out.extend(block(SUMMARY_TAG, summary_table(summaries)));
            } else if out.last().is_some_and(|l| l.is_empty()) {
                // A unit block is re-inserted under its heading below; drop the blank
                // line that separated it from the heading.
                out.pop();
            }
            continue;
        }
        out.push(line.to_string());
        if let Some(name) = section_unit(line) {
            let s = summaries.iter().find(|s| s.name == name).ok_or_else(|| {
                format!("line {}: section `## {name}` names no registry unit", i + 1)
            })?;
            if sections.contains(&name) {
                return Err(format!("line {}: a second section `## {name}`", i + 1));
            }
            sections.push(name);
            out.push(String::new());
            out.extend(block(name, unit_figures(s)));
        }
    }
    if summary_blocks != 1 {
        return Err(format!(
            "{summary_blocks} summary blocks (`{}` … `{}`); want exactly one",
            begin_marker(SUMMARY_TAG),
            end_marker(SUMMARY_TAG)
        ));
    }
    let want: Vec<&str> = summaries.iter().map(|s| s.name).collect();
    if let Some(missing) = want.iter().find(|n| !sections.contains(n)) {
        return Err(format!(
            "no section `## {missing}` for registry unit {missing}"
        ));
    }
    if sections != want {
        return Err(format!(
            "unit sections are out of registry order: {} (want {})",
            sections.join(", "),
            want.join(", ")
        ));
    }
    let mut text = out.join("\n");
    if doc.ends_with('\n') {
        text.push('\n');
    }
    Ok(text)
}

/// Rewrite the datasheet at `path` from the registry; says whether it changed.
pub fn refresh_file(path: &std::path::Path) -> Result<String, String> {
    let name = path.display();
    let doc = std::fs::read_to_string(path).map_err(|e| format!("datasheet: {name}: {e}"))?;
    let summaries = super::summaries();
    let new = refresh(&doc, &summaries).map_err(|e| format!("datasheet: {name}: {e}"))?;
    if new == doc {
        return Ok(format!(
            "{name}: the figures of {} units are up to date",
            summaries.len()
        ));
    }
    // Atomically (`report::atomic`): an interrupted rewrite leaves the old document.
    crate::report::atomic::write_bytes(path, new.as_bytes())
        .map_err(|e| format!("datasheet: {e}"))?;
    Ok(format!(
        "{name}: rewrote the figures of {} units from the registry",
        summaries.len()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousands_groups_from_the_right() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(6_291_456), "6,291,456");
    }

    #[test]
    fn only_identifier_headings_are_unit_sections() {
        assert_eq!(section_unit("## texture_sampler"), Some("texture_sampler"));
        assert_eq!(section_unit("## Summary at the defaults"), None);
        assert_eq!(section_unit("### modulate"), None);
        assert_eq!(section_unit("## 2d"), None);
    }
}
