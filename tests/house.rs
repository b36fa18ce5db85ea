//! The house follows the data (DESIGN §1): this test reads every file of `src/` and
//! builds the module graph from its `crate::…` paths (grouped `use crate::{a, b::{c}}`
//! expanded; comments stripped), with one node per top-level module and one per
//! `pipeline::<name>`. It asserts that no pipeline imports another, that `reference`,
//! `report` and `scene` import nothing from `pipeline` or `frame`, that nothing but
//! the CLI imports the CLI and nothing in `pipeline` imports `frame` (the CLI and the
//! frame only call inward), and that the graph has no circle.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const PIPELINES: &[&str] = &["shafts", "glare", "envmap", "shading"];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The node a file belongs to: `pipeline::<first component>` inside `src/pipeline/`,
/// else its top-level module.
fn node_of_file(rel: &Path) -> String {
    let parts: Vec<String> = rel
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts[0] == "pipeline" && parts.len() > 1 && parts[1] != "mod" {
        format!("pipeline::{}", parts[1])
    } else {
        parts[0].clone()
    }
}

fn node_of_path(path: &[String]) -> String {
    if path[0] == "pipeline" && path.len() > 1 {
        format!("pipeline::{}", path[1])
    } else {
        path[0].clone()
    }
}

/// Paths of `crate::<body>`: `a::b::C` or a brace group, expanded.
fn expand(prefix: &[String], body: &str, out: &mut Vec<Vec<String>>) {
    let mut depth = 0;
    let mut cur = String::new();
    let mut items = Vec::new();
    for ch in body.chars() {
        match ch {
            '{' => {
                depth += 1;
                cur.push(ch)
            }
            '}' => {
                depth -= 1;
                cur.push(ch)
            }
            ',' if depth == 0 => items.push(std::mem::take(&mut cur)),
            _ => cur.push(ch),
        }
    }
    items.push(cur);
    for it in items {
        let it: String = it.chars().filter(|c| !c.is_whitespace()).collect();
        if it.is_empty() {
            continue;
        }
        if let Some(open) = it.find('{') {
            let head: Vec<String> = it[..open]
                .split("::")
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect();
            let inner = &it[open + 1..it.len() - 1];
            let p: Vec<String> = prefix.iter().cloned().chain(head).collect();
            expand(&p, inner, out);
        } else {
            let p: Vec<String> = prefix
                .iter()
                .cloned()
                .chain(it.split("::").filter(|s| !s.is_empty()).map(String::from))
                .collect();
            out.push(p);
        }
    }
}

fn strip_comments(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every `crate::` path in the text.
fn crate_paths(text: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        if after.starts_with('{') {
            let mut depth = 0;
            let mut end = 0;
            for (k, ch) in after.char_indices() {
                if ch == '{' {
                    depth += 1;
                } else if ch == '}' {
                    depth -= 1;
                    if depth == 0 {
                        end = k;
                        break;
                    }
                }
            }
            expand(&[], &after[1..end], &mut out);
            rest = &after[end..];
        } else {
            let end = after
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(after.len());
            let p: Vec<String> = after[..end]
                .split("::")
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect();
            if !p.is_empty() {
                out.push(p);
            }
            rest = &after[end..];
        }
    }
    out
}

/// node → (imported node → a file that imports it).
fn graph() -> BTreeMap<String, BTreeMap<String, String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut g: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(&src).unwrap().to_path_buf();
        let from = node_of_file(&rel);
        let text = strip_comments(&std::fs::read_to_string(&f).unwrap());
        let entry = g.entry(from.clone()).or_default();
        for p in crate_paths(&text) {
            let to = node_of_path(&p);
            if to != from {
                entry.entry(to).or_insert_with(|| rel.display().to_string());
            }
        }
    }
    g
}

#[test]
fn no_pipeline_imports_another() {
    let mut bad = Vec::new();
    for (from, tos) in graph() {
        for (to, file) in tos {
            let pipe = |n: &str| {
                n.strip_prefix("pipeline::")
                    .is_some_and(|p| PIPELINES.contains(&p))
            };
            if pipe(&from) && pipe(&to) {
                bad.push(format!("{file}: {from} imports {to}"));
            }
            let lower = ["reference", "report", "scene"].contains(&from.as_str());
            if lower && (to.starts_with("pipeline") || to == "frame" || to == "cli") {
                bad.push(format!("{file}: {from} reaches up into {to}"));
            }
            if to == "cli" {
                bad.push(format!("{file}: {from} imports the CLI"));
            }
            if from.starts_with("pipeline") && to == "frame" {
                bad.push(format!("{file}: {from} imports the frame"));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn no_import_circle() {
    let g = graph();
    // Depth-first search for a back edge; report the circle.
    fn visit(
        n: &str,
        g: &BTreeMap<String, BTreeMap<String, String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for to in g
            .get(n)
            .map(|m| m.keys().cloned().collect::<Vec<_>>())
            .unwrap_or_default()
        {
            match state.get(&to).copied().unwrap_or(0) {
                1 => {
                    let at = stack.iter().position(|s| *s == to).unwrap();
                    let mut c = stack[at..].to_vec();
                    c.push(to);
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(&to, g, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    let nodes: BTreeSet<String> = g.keys().cloned().collect();
    for n in &nodes {
        if state.get(n).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, &g, &mut state, &mut Vec::new()) {
                panic!("import circle: {}", c.join(" → "));
            }
        }
    }
    assert!(
        nodes.len() > 8,
        "the graph was read ({} nodes)",
        nodes.len()
    );
}

/// The reader itself: a grouped import expands to every path in it.
#[test]
fn grouped_imports_expand() {
    let p = crate_paths("use crate::{a::b, c::{d::E, f}};\nlet x = crate::g::h(1);");
    let s: Vec<String> = p.iter().map(|v| v.join("::")).collect();
    assert_eq!(s, ["a::b", "c::d::E", "c::f", "g::h"]);
}
