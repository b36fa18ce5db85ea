//! The house follows the data (DESIGN §1): this test reads every file of `src/` and
//! builds the module graph from its `crate::…` paths (grouped `use crate::{a, b::{c}}`
//! expanded; comments stripped), with one node per top-level module and one per
//! `pipeline::<name>`. It asserts that no pipeline imports another, that `reference`,
//! `report` and `scene` import nothing from `pipeline`, `frame` or `optimize`, that
//! nothing but the CLI imports the CLI or `optimize` (a tool over scenes, above the
//! frame), that nothing in `pipeline` imports `frame` (the CLI, `optimize` and the
//! frame only call inward), and that the graph has no circle.
//!
//! Below the modules, the files: a graph of file → files it imports (`crate::`,
//! `super::` and `self::` paths, a declared module's bare name, a re-exported name led
//! on to the file that defines it) must have no circle either: no file imports a file
//! that imports it, directly or around a longer circle.

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
    let mut named = Vec::new();
    expand_as(prefix, body, &mut named);
    out.extend(named.into_iter().map(|(p, _)| p));
}

/// As [`expand`], with the name each path is bound to (its last segment, or the
/// name after `as`).
fn expand_as(prefix: &[String], body: &str, out: &mut Vec<(Vec<String>, String)>) {
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
        if let (Some(open), Some(close)) = (it.find('{'), it.rfind('}')) {
            let head: Vec<String> = it[..open]
                .split("::")
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect();
            let p: Vec<String> = prefix.iter().cloned().chain(head).collect();
            expand_as(&p, &it[open + 1..close], out);
        } else {
            let words: Vec<&str> = it.split_whitespace().collect();
            let (it, alias) = match words.iter().position(|w| *w == "as") {
                Some(k) => (words[..k].concat(), words.get(k + 1).copied()),
                None => (words.concat(), None),
            };
            if it.is_empty() {
                continue;
            }
            let p: Vec<String> = prefix
                .iter()
                .cloned()
                .chain(it.split("::").filter(|s| !s.is_empty()).map(String::from))
                .collect();
            let name = alias
                .map(String::from)
                .or_else(|| p.last().cloned())
                .unwrap_or_default();
            out.push((p, name));
        }
    }
}

/// The code of a file: comments removed, the insides of string and character literals
/// blanked (a `crate::` in a message, a `{` in a format string or a `//` in a URL is
/// not code), line breaks kept.
fn strip_comments(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    let mut i = 0;
    while i < c.len() {
        let at = |k: usize| c.get(k).copied().unwrap_or('\0');
        if c[i] == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if c[i] == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if c[i] == '\n' {
                        out.push('\n');
                    }
                    i += 1;
                }
            }
        } else if c[i] == 'r'
            && (at(i + 1) == '"' || at(i + 1) == '#')
            && (i == 0 || !ident(c[i - 1]))
            && {
                let mut k = i + 1;
                while at(k) == '#' {
                    k += 1;
                }
                at(k) == '"'
            }
        {
            // Raw string r#"…"#: ends at a quote followed by as many hashes.
            let mut k = i + 1;
            let mut hashes = 0;
            while c[k] == '#' {
                hashes += 1;
                k += 1;
            }
            k += 1;
            while k < c.len() && !(c[k] == '"' && (1..=hashes).all(|h| at(k + h) == '#')) {
                if c[k] == '\n' {
                    out.push('\n');
                }
                k += 1;
            }
            out.push_str("\"\"");
            i = k + 1 + hashes;
        } else if c[i] == '"' {
            let mut k = i + 1;
            while k < c.len() && c[k] != '"' {
                if c[k] == '\\' {
                    // An escaped character; a `\` before a line break keeps the line.
                    k += 1;
                }
                if at(k) == '\n' {
                    out.push('\n');
                }
                k += 1;
            }
            out.push_str("\"\"");
            i = k + 1;
        } else if c[i] == '\'' && at(i + 1) == '\\' {
            // An escaped character literal: '\n', '\'', '\u{…}'.
            let mut k = i + 2;
            while k < c.len() && !(c[k] == '\'' && k > i + 2) {
                k += 1;
            }
            out.push_str("' '");
            i = k + 1;
        } else if c[i] == '\'' && at(i + 2) == '\'' {
            out.push_str("' '");
            i += 3;
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// Every `crate::` path in the text.
fn crate_paths(text: &str) -> Vec<Vec<String>> {
    paths_after(text, "crate::")
        .into_iter()
        .map(|(_, p)| p)
        .collect()
}

/// Every path after `keyword` (`crate::`, `super::`, `self::` or a module's name and
/// `::`) in the code, without it, with the offset where it starts. `keyword` must
/// begin a word: `my_super::` is not `super::`, `a::b::` is not `b::`.
fn paths_after(text: &str, keyword: &str) -> Vec<(usize, Vec<String>)> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(i) = text[from..].find(keyword).map(|i| i + from) {
        let before = text[..i].chars().next_back();
        let after = &text[i + keyword.len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':' || c == '$')
            && !(keyword == "crate::" && before == Some('$'))
        {
            from = i + keyword.len();
            continue;
        }
        let mut found = Vec::new();
        let used = if after.starts_with('{') {
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
            expand(&[], &after[1..end], &mut found);
            end
        } else {
            let end = after
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':' || c == '*'))
                .unwrap_or(after.len());
            let p: Vec<String> = after[..end]
                .split("::")
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect();
            if !p.is_empty() {
                found.push(p);
            }
            end
        };
        out.extend(found.into_iter().map(|p| (i, p)));
        from = i + keyword.len() + used;
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
            if lower
                && (to.starts_with("pipeline")
                    || ["frame", "optimize", "cli"].contains(&to.as_str()))
            {
                bad.push(format!("{file}: {from} reaches up into {to}"));
            }
            if to == "cli" {
                bad.push(format!("{file}: {from} imports the CLI"));
            }
            if from.starts_with("pipeline") && to == "frame" {
                bad.push(format!("{file}: {from} imports the frame"));
            }
            // `optimize` is a tool over scenes above the frame: it calls the frame and
            // the pipelines, and only the CLI calls it.
            if to == "optimize" && from != "cli" {
                bad.push(format!(
                    "{file}: {from} imports optimize (only the CLI may)"
                ));
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

/// The module path of a file under `src/` (`pipeline/glare/frame.rs` →
/// pipeline, glare, frame; a `mod.rs` is its directory's module, `lib.rs` the crate).
fn module_of_file(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|l| l == "mod" || l == "lib") {
        parts.pop();
    }
    parts
}

/// The inline modules (`mod tests { … }`) open at each point of the code: a list of
/// (offset, names of the open inline modules from there on), in order.
fn inline_modules(code: &str) -> Vec<(usize, Vec<String>)> {
    let mut marks = vec![(0, Vec::new())];
    let mut open: Vec<(String, usize)> = Vec::new();
    let mut depth = 0;
    let mut pending: Option<(usize, String)> = None;
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    for (i, ch) in code.char_indices() {
        if ch == '{' {
            if let Some((_, name)) = pending.take().filter(|(at, _)| *at == i) {
                open.push((name, depth));
                marks.push((i, open.iter().map(|(n, _)| n.clone()).collect()));
            }
            depth += 1;
        } else if ch == '}' {
            depth -= 1;
            if open.last().is_some_and(|(_, d)| *d == depth) {
                open.pop();
                marks.push((i, open.iter().map(|(n, _)| n.clone()).collect()));
            }
        } else if code[i..].starts_with("mod ") && !code[..i].chars().next_back().is_some_and(ident)
        {
            let rest = &code[i + 4..];
            let name_start = rest.len() - rest.trim_start().len();
            let name: String = rest[name_start..]
                .chars()
                .take_while(|c| ident(*c))
                .collect();
            let after = &rest[name_start + name.len()..];
            let gap = after.len() - after.trim_start().len();
            if !name.is_empty() && after[gap..].starts_with('{') {
                pending = Some((i + 4 + name_start + name.len() + gap, name));
            }
        }
    }
    marks
}

/// One source file as the file graph reads it.
struct SrcFile {
    rel: PathBuf,
    module: Vec<String>,
    code: String,
    inline: Vec<(usize, Vec<String>)>,
    /// Modules declared in the file as `mod x;` (files of their own).
    children: Vec<String>,
}

impl SrcFile {
    fn read(src: &Path, f: &Path) -> SrcFile {
        let rel = f.strip_prefix(src).unwrap().to_path_buf();
        let code = strip_comments(&std::fs::read_to_string(f).unwrap());
        let inline = inline_modules(&code);
        let mut children = Vec::new();
        for (i, _) in code.match_indices("mod ") {
            let word_start = !code[..i]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_');
            let rest = code[i + 4..].trim_start();
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if word_start && !name.is_empty() && rest[name.len()..].trim_start().starts_with(';') {
                children.push(name);
            }
        }
        SrcFile {
            module: module_of_file(&rel),
            rel,
            code,
            inline,
            children,
        }
    }

    /// The module at offset `at`: the file's, with the inline modules open there.
    fn module_at(&self, at: usize) -> Vec<String> {
        let open = self
            .inline
            .iter()
            .rev()
            .find(|(o, _)| *o <= at)
            .map(|(_, n)| n.clone())
            .unwrap_or_default();
        self.module.iter().cloned().chain(open).collect()
    }

    /// Every path the file names, made absolute (from the crate root), with its offset:
    /// `crate::a::b`, `super::x` (from the module open there, inline `mod tests`
    /// included), `self::x`, and `x::…` for a module `x` the file declares.
    fn paths(&self) -> Vec<(usize, Vec<String>)> {
        let mut out = paths_after(&self.code, "crate::");
        for (at, p) in paths_after(&self.code, "super::") {
            let mut base = self.module_at(at);
            base.pop();
            let mut p = p.as_slice();
            while p.first().is_some_and(|s| s == "super") {
                base.pop();
                p = &p[1..];
            }
            out.push((at, base.into_iter().chain(p.iter().cloned()).collect()));
        }
        for (at, p) in paths_after(&self.code, "self::") {
            out.push((at, self.module_at(at).into_iter().chain(p).collect()));
        }
        for c in &self.children {
            for (at, p) in paths_after(&self.code, &format!("{c}::")) {
                if self.module_at(at) == self.module {
                    let m = self.module.iter().chain([c]).cloned();
                    out.push((at, m.chain(p).collect()));
                }
            }
        }
        out
    }

    /// The names the file re-exports (`pub use …`, `pub(crate) use …`) → the absolute
    /// path each stands for.
    fn reexports(&self) -> BTreeMap<String, Vec<String>> {
        let mut out = BTreeMap::new();
        for (i, _) in self.code.match_indices("use ") {
            let before = self.code[..i].trim_end();
            let public = before.ends_with("pub")
                || (before.ends_with(')') && {
                    let open = before.rfind('(').unwrap_or(0);
                    before[..open].trim_end().ends_with("pub")
                });
            if !public || self.module_at(i) != self.module {
                continue;
            }
            let end = self.code[i..].find(';').map_or(self.code.len(), |e| e + i);
            let mut named = Vec::new();
            expand_as(&[], &self.code[i + 4..end], &mut named);
            for (p, name) in named {
                let Some(first) = p.first() else { continue };
                let abs: Vec<String> = if first == "crate" {
                    p[1..].to_vec()
                } else if first == "super" {
                    let mut base = self.module.clone();
                    let mut q = p.as_slice();
                    while q.first().is_some_and(|s| s == "super") {
                        base.pop();
                        q = &q[1..];
                    }
                    base.into_iter().chain(q.iter().cloned()).collect()
                } else if first == "self" || self.children.contains(first) {
                    let skip = usize::from(first == "self");
                    self.module.iter().chain(&p[skip..]).cloned().collect()
                } else {
                    continue;
                };
                out.insert(name, abs);
            }
        }
        out
    }
}

/// File → files it imports, relative to `src/`, from the files under `src`. A path
/// leads to the file of the longest module prefix it names; a name that file
/// re-exports leads on to the file the name comes from.
fn file_graph_of(src: &Path) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let mut paths = Vec::new();
    rust_files(src, &mut paths);
    let files: Vec<SrcFile> = paths.iter().map(|f| SrcFile::read(src, f)).collect();
    // `main.rs` is the binary's crate root, not a module of the library.
    let by_module: BTreeMap<Vec<String>, &SrcFile> = files
        .iter()
        .filter(|f| f.rel != Path::new("main.rs"))
        .map(|f| (f.module.clone(), f))
        .collect();
    let reexports: BTreeMap<&Path, BTreeMap<String, Vec<String>>> = files
        .iter()
        .map(|f| (f.rel.as_path(), f.reexports()))
        .collect();
    let resolve = |m: &[String]| -> Option<PathBuf> {
        let mut m = m.to_vec();
        for _ in 0..16 {
            let k = (0..=m.len())
                .rev()
                .find(|k| by_module.contains_key(&m[..*k]))?;
            let f = by_module[&m[..k]];
            match m
                .get(k)
                .and_then(|name| reexports[f.rel.as_path()].get(name))
            {
                Some(to) if to[..] != m[..=k] => {
                    m = to.iter().chain(&m[k + 1..]).cloned().collect();
                }
                _ => return Some(f.rel.clone()),
            }
        }
        None
    };
    files
        .iter()
        .map(|f| {
            let edges = f
                .paths()
                .iter()
                .filter_map(|(_, p)| resolve(p))
                .filter(|t| *t != f.rel)
                .collect();
            (f.rel.clone(), edges)
        })
        .collect()
}

/// File → files it imports, for this crate's `src/`.
fn file_graph() -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    file_graph_of(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"))
}

/// Strongly connected sets of more than one file (Tarjan), each sorted.
fn file_circles(g: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    struct Tarjan<'a> {
        g: &'a BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        index: BTreeMap<&'a PathBuf, usize>,
        low: BTreeMap<&'a PathBuf, usize>,
        stack: Vec<&'a PathBuf>,
        on: BTreeSet<&'a PathBuf>,
        out: Vec<Vec<PathBuf>>,
    }
    impl<'a> Tarjan<'a> {
        fn visit(&mut self, v: &'a PathBuf) {
            let i = self.index.len();
            self.index.insert(v, i);
            self.low.insert(v, i);
            self.stack.push(v);
            self.on.insert(v);
            for w in self.g.get(v).into_iter().flatten() {
                let Some((w, _)) = self.g.get_key_value(w) else {
                    continue;
                };
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.low[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(lw);
                } else if self.on.contains(w) {
                    let iw = self.index[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(iw);
                }
            }
            if self.low[v] == self.index[v] {
                let mut set = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on.remove(w);
                    set.push(w.clone());
                    if w == v {
                        break;
                    }
                }
                if set.len() > 1 {
                    set.sort();
                    self.out.push(set);
                }
            }
        }
    }
    let mut t = Tarjan {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in g.keys() {
        if !t.index.contains_key(v) {
            t.visit(v);
        }
    }
    t.out
}

/// No file imports a file that imports it, directly or around a longer circle:
/// shared types live in the file both use.
#[test]
fn no_file_level_circle() {
    let g = file_graph();
    assert!(g.len() > 100, "the files were read ({})", g.len());
    let circles = file_circles(&g);
    let text: Vec<String> = circles
        .iter()
        .map(|c| {
            let names = |fs: &mut dyn Iterator<Item = &PathBuf>| {
                fs.map(|f| f.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let mut t = c
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(" ↔ ");
            for f in c {
                let to = names(&mut g[f].iter().filter(|t| c.contains(t)));
                t.push_str(&format!("\n    {} → {to}", f.display()));
            }
            t
        })
        .collect();
    assert!(
        circles.is_empty(),
        "file-level circles (each: its files, then what each imports of the others):\n{}",
        text.join("\n")
    );
}

/// The circle finder finds a planted circle and nothing in a chain.
#[test]
fn the_circle_finder_sees_a_circle() {
    let f = |s: &str| PathBuf::from(s);
    let mut g = BTreeMap::new();
    g.insert(f("a.rs"), BTreeSet::from([f("b.rs")]));
    g.insert(f("b.rs"), BTreeSet::from([f("c.rs")]));
    g.insert(f("c.rs"), BTreeSet::new());
    assert!(file_circles(&g).is_empty());
    g.get_mut(&f("c.rs")).unwrap().insert(f("a.rs"));
    assert_eq!(
        file_circles(&g),
        vec![vec![f("a.rs"), f("b.rs"), f("c.rs")]]
    );
}

/// The file reader on a planted tree: `super::` from an inline test module, `self::`,
/// a declared module's bare name, grouped imports with `as`, a re-exported name (led
/// on to the file it comes from), and a path inside a string (not an import).
#[test]
fn the_file_reader_sees_every_kind_of_import() {
    let root = std::env::temp_dir().join(format!("house_reader_{}", std::process::id()));
    let files = [
        ("lib.rs", "pub mod a;\npub mod b;\n"),
        ("a/mod.rs", "mod x;\nmod y;\nmod z;\npub use x::Thing;\n"),
        (
            "a/x.rs",
            "use super::y::{self, Other as O};\npub struct Thing;\n",
        ),
        (
            "a/y.rs",
            "pub struct Other;\n#[cfg(test)]\nmod tests {\n    use super::super::z::Z;\n}\n",
        ),
        (
            "a/z.rs",
            "pub struct Z;\nfn f() { let _ = self::g; } fn g() {}\n",
        ),
        (
            "b.rs",
            "use crate::a::Thing; // crate::a::z\nfn f() { let s = \"crate::a::y::Other\"; }\n",
        ),
    ];
    for (rel, text) in files {
        let f = root.join(rel);
        std::fs::create_dir_all(f.parent().unwrap()).unwrap();
        std::fs::write(f, text).unwrap();
    }
    let g = file_graph_of(&root);
    std::fs::remove_dir_all(&root).unwrap();
    let edges = |f: &str| -> Vec<String> {
        g[Path::new(f)]
            .iter()
            .map(|t| t.display().to_string())
            .collect()
    };
    assert_eq!(edges("a/mod.rs"), ["a/x.rs"]);
    assert_eq!(edges("a/x.rs"), ["a/y.rs"]);
    assert_eq!(edges("a/y.rs"), ["a/z.rs"]);
    assert!(edges("a/z.rs").is_empty());
    assert_eq!(edges("b.rs"), ["a/x.rs"]);
    assert!(edges("lib.rs").is_empty());
    assert!(file_circles(&g).is_empty());
}

/// The module graph drawn in layers, top to bottom: each module imports only modules
/// on lines below its own (the crate roots `lib` and `main` left out). A module's
/// layer is one above the highest module it imports; a module importing nothing is on
/// layer 0.
fn structure_drawing(g: &BTreeMap<String, BTreeMap<String, String>>) -> String {
    fn layer(
        n: &str,
        g: &BTreeMap<String, BTreeMap<String, String>>,
        memo: &mut BTreeMap<String, Option<usize>>,
    ) -> usize {
        match memo.get(n) {
            Some(Some(l)) => return *l,
            // On a circle (which `no_import_circle` reports): stop here.
            Some(None) => return 0,
            None => {}
        }
        memo.insert(n.to_string(), None);
        let l = g
            .get(n)
            .into_iter()
            .flat_map(|m| m.keys())
            .map(|to| layer(to, g, memo) + 1)
            .max()
            .unwrap_or(0);
        memo.insert(n.to_string(), Some(l));
        l
    }
    let shown = |n: &str| n != "lib" && n != "main";
    let mut memo = BTreeMap::new();
    let mut layers: BTreeMap<usize, Vec<&String>> = BTreeMap::new();
    for n in g.keys().filter(|n| shown(n)) {
        layers.entry(layer(n, g, &mut memo)).or_default().push(n);
    }
    let width = g.keys().map(|n| n.len()).max().unwrap_or(0);
    let mut out = String::new();
    for (l, nodes) in layers.iter().rev() {
        for (i, n) in nodes.iter().enumerate() {
            let to: Vec<&str> = g[*n]
                .keys()
                .filter(|t| shown(t))
                .map(String::as_str)
                .collect();
            let head = if i == 0 {
                format!("{l:>2}")
            } else {
                "  ".to_string()
            };
            let mut line = format!("{head}  {n}");
            if !to.is_empty() {
                line = format!("{head}  {n:<width$} → ");
                let indent = line.chars().count();
                let mut col = indent;
                for (k, t) in to.iter().enumerate() {
                    let item = if k + 1 < to.len() {
                        format!("{t}, ")
                    } else {
                        t.to_string()
                    };
                    if col + item.trim_end().len() > 88 && col > indent {
                        line = line.trim_end().to_string();
                        line.push('\n');
                        line.push_str(&" ".repeat(indent));
                        col = indent;
                    }
                    col += item.chars().count();
                    line.push_str(&item);
                }
            }
            out.push_str(&line);
            out.push('\n');
        }
    }
    out
}

const DRAWING_START: &str = "<!-- structure drawing: generated by tests/house.rs -->";
const DRAWING_END: &str = "<!-- end of the structure drawing -->";

/// docs/ARCHITECTURE.md's structure drawing is the one the code gives: on a
/// difference the test fails and prints the drawing (`HOUSE_WRITE_DRAWING=1 cargo test
/// --test house` writes it into the file).
#[test]
fn the_structure_drawing_is_current() {
    let g = graph();
    let drawing = structure_drawing(&g);
    // Every module of the graph but the crate roots is on the drawing, once.
    for n in g.keys().filter(|n| *n != "lib" && *n != "main") {
        let on_line = |l: &str| l.get(4..).is_some_and(|t| t.split(' ').next() == Some(n));
        assert_eq!(drawing.lines().filter(|l| on_line(l)).count(), 1, "{n}");
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/ARCHITECTURE.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let (Some(a), Some(b)) = (text.find(DRAWING_START), text.find(DRAWING_END)) else {
        panic!("docs/ARCHITECTURE.md has no structure drawing between {DRAWING_START} and {DRAWING_END}");
    };
    let want = format!("\n```text\n{drawing}```\n");
    let have = &text[a + DRAWING_START.len()..b];
    if have != want {
        if std::env::var_os("HOUSE_WRITE_DRAWING").is_some() {
            let new = format!("{}{want}{}", &text[..a + DRAWING_START.len()], &text[b..]);
            std::fs::write(&path, new).unwrap();
            return;
        }
        panic!(
            "docs/ARCHITECTURE.md's structure drawing differs from the code's \
             (HOUSE_WRITE_DRAWING=1 cargo test --test house writes it); the code's:\n{want}"
        );
    }
}

/// The drawing puts a module above everything it imports.
#[test]
fn the_drawing_layers_a_chain() {
    let mut g: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    let edge = |to: &str| BTreeMap::from([(to.to_string(), String::new())]);
    g.insert("a".into(), edge("b"));
    g.insert("b".into(), edge("c"));
    g.insert("c".into(), BTreeMap::new());
    g.insert("d".into(), edge("c"));
    let d = structure_drawing(&g);
    assert_eq!(d, " 2  a → b\n 1  b → c\n    d → c\n 0  c\n");
    // A long list of imports wraps under its first entry.
    let many: BTreeMap<String, String> = (0..30)
        .map(|i| (format!("m{i:02}"), String::new()))
        .collect();
    g.insert("z".into(), many);
    let d = structure_drawing(&g);
    assert!(
        d.lines()
            .all(|l| l.chars().count() <= 88 && !l.ends_with(' ')),
        "{d}"
    );
    assert!(d.lines().any(|l| l.starts_with("        m1")), "{d}");
}

// ---------------------------------------------------------------------------------
// Long functions: a function that orchestrates reads like its pass list; past 100
// lines it is split by pass or stage.

/// The most lines a function in `src/` may take, from its `fn` line to its closing
/// brace.
const MAX_FUNCTION_LINES: usize = 100;

/// The name of the function a line (comments and strings stripped) starts, if it does:
/// `fn name` after any of `pub`, `pub(…)`, `const`, `async`, `unsafe`, `extern ""`.
fn fn_name(line: &str) -> Option<&str> {
    let mut rest = line.trim_start();
    loop {
        if rest.starts_with("pub(") {
            rest = rest[rest.find(')')? + 1..].trim_start();
            continue;
        }
        let before = rest;
        for word in ["pub ", "const ", "async ", "unsafe ", "extern \"\" "] {
            if let Some(r) = rest.strip_prefix(word) {
                rest = r.trim_start();
            }
        }
        if rest == before {
            break;
        }
    }
    let name = rest.strip_prefix("fn ")?;
    let end = name
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(name.len());
    (end > 0).then(|| &name[..end])
}

/// The functions under `dir` longer than `limit` lines, as "path:line name (n lines)".
/// A declaration without a body (a trait's `fn f();`) is none.
fn long_functions(dir: &Path, limit: usize) -> Vec<String> {
    let mut files = Vec::new();
    rust_files(dir, &mut files);
    files.sort();
    let mut out = Vec::new();
    for f in files {
        let code = strip_comments(&std::fs::read_to_string(&f).unwrap());
        let lines: Vec<&str> = code.lines().collect();
        for (i, l) in lines.iter().enumerate() {
            let Some(name) = fn_name(l) else { continue };
            let (mut depth, mut opened, mut end) = (0i64, false, None);
            'scan: for (j, m) in lines.iter().enumerate().skip(i) {
                for ch in m.chars() {
                    match ch {
                        '{' => {
                            depth += 1;
                            opened = true;
                        }
                        '}' => {
                            depth -= 1;
                            if opened && depth == 0 {
                                end = Some(j);
                                break 'scan;
                            }
                        }
                        _ => {}
                    }
                }
                if !opened && m.trim_end().ends_with(';') {
                    break;
                }
            }
            if let Some(j) = end.filter(|&j| j - i + 1 > limit) {
                out.push(format!(
                    "{}:{} {name} ({} lines)",
                    f.display(),
                    i + 1,
                    j - i + 1
                ));
            }
        }
    }
    out
}

#[test]
fn no_function_in_src_over_100_lines() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let long = long_functions(&src, MAX_FUNCTION_LINES);
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines (split them by pass or stage):\n{}",
        long.join("\n")
    );
}

#[test]
fn the_length_check_sees_a_long_function() {
    // A planted file: a 101-line function, a 100-line one, a trait declaration and
    // braces inside a string and a comment, which do not count.
    let dir = std::env::temp_dir().join(format!("house-long-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let body = |n: usize| "    let x = 1;\n".repeat(n - 2);
    let text = format!(
        "pub(crate) fn long() {{\n{}}}\n\nconst fn fits() -> u32 {{\n{}}}\n\n\
         trait T {{\n    fn declared(&self);\n}}\n\nfn strings() {{\n    let s = \"{{{{\"; // }}\n}}\n",
        body(101),
        body(100)
    );
    std::fs::write(dir.join("planted.rs"), text).unwrap();
    let long = long_functions(&dir, MAX_FUNCTION_LINES);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(long.len(), 1, "{long:?}");
    assert!(long[0].ends_with(":1 long (101 lines)"), "{long:?}");
}
