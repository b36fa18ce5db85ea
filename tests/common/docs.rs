//! Figures the docs quote, checked against what the code computes now: a test that
//! prints a datasheet figure also asserts that the docs still quote it, so a change of
//! the unit's cost, timing or statistics fails the test until the docs are updated.

use std::path::Path;

/// `n` rounded to a whole number, thousands grouped with spaces as the docs write them
/// ("84 235", "-1 200").
pub fn grouped(n: f64) -> String {
    let r = n.round();
    let digits = format!("{}", r.abs() as u64);
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(' ');
        }
        out.push(c);
    }
    if r < 0.0 {
        format!("-{out}")
    } else {
        out
    }
}

/// Runs of whitespace folded to one space, so a quote may cross a line break.
fn folded(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The text of `docs/<file>` from `heading` (a line starting with it) up to the next
/// heading of the same level, whitespace folded.
pub fn section(file: &str, heading: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs")
        .join(file);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let level = heading.chars().take_while(|&c| c == '#').count();
    let start = text
        .lines()
        .position(|l| l.starts_with(heading))
        .unwrap_or_else(|| panic!("docs/{file} has no heading {heading:?}"));
    let body: Vec<&str> = text
        .lines()
        .skip(start)
        .enumerate()
        .take_while(|(i, l)| {
            *i == 0 || {
                let hashes = l.chars().take_while(|&c| c == '#').count();
                !(hashes > 0 && hashes <= level && l[hashes..].starts_with(' '))
            }
        })
        .map(|(_, l)| l)
        .collect();
    folded(&body.join("\n"))
}

/// Panics unless `section` (from [`section`]) contains `quote` (whitespace folded),
/// naming where the docs should say it.
pub fn assert_quotes(section: &str, quote: &str, where_: &str) {
    let q = folded(quote);
    assert!(
        section.contains(&q),
        "{where_} no longer quotes what the code computes: expected the text {q:?}; \
         update the docs from the printed figures (`-- --nocapture`)"
    );
}

/// The gates of the cost part whose name starts with `name`, in thousands as the docs
/// quote the largest parts ("5.7 k").
pub fn kilo(breakdown: &[(String, f64)], name: &str) -> String {
    let g = breakdown
        .iter()
        .find(|(p, _)| p.starts_with(name))
        .unwrap_or_else(|| panic!("no cost part {name:?}"))
        .1;
    format!("{:.1} k", g / 1000.0)
}
