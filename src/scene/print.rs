//! A scene as compact, commented TOML (what `glare-pipeline scene NAME` writes):
//! arrays of numbers on one line, a comment above each section saying what it is and
//! the unit after each value that has one, all taken from the field table
//! ([`super::fields`]). The text loads back to the same scene, and printing that
//! again gives the same bytes.

use super::fields::{field, section_comment, unit_comment, Ty};
use super::format::Scene;
use rtl_model::error::ConfigError;

/// The compact, commented TOML of `scene`, after `header` (comment lines, each
/// starting with `#`; may be empty).
pub fn scene_toml(scene: &Scene, header: &str) -> Result<String, ConfigError> {
    let body = toml::to_string(scene)
        .map_err(|e| ConfigError::invalid("scene", &format!("cannot write TOML: {e}")))?;
    Ok(format!("{header}{}", annotate(&body)))
}

/// The generic field path (`lights[].light_map`) of a dotted header path
/// (`lights.light_map`): `[]` after each prefix that is an array of tables.
fn header_path(dotted: &str) -> String {
    let mut out = String::new();
    for part in dotted.split('.') {
        if !out.is_empty() {
            out.push('.');
        }
        out.push_str(part.trim());
        if field(&out).is_some_and(|f| f.ty == Ty::Tables) {
            out.push_str("[]");
        }
    }
    out.trim_end_matches("[]").to_string()
}

/// Comment lines before headers, units after values.
fn annotate(body: &str) -> String {
    let mut out = String::new();
    let mut table = String::new();
    // Sections already described, and the count of each array of tables so far.
    let mut seen: Vec<String> = Vec::new();
    let mut counts: Vec<(String, usize)> = Vec::new();
    for line in body.lines() {
        let t = line.trim();
        let header = t
            .strip_prefix("[[")
            .and_then(|r| r.strip_suffix("]]"))
            .or_else(|| t.strip_prefix('[').and_then(|r| r.strip_suffix(']')));
        if let Some(h) = header.filter(|_| !t.contains('=')) {
            let path = header_path(h);
            if !out.is_empty() && !out.ends_with("\n\n") {
                out.push('\n');
            }
            let array = field(&path).is_some_and(|f| f.ty == Ty::Tables);
            let first = !seen.contains(&path);
            let comment = first.then(|| section_comment(&path)).flatten();
            if array {
                let n = match counts.iter_mut().find(|(p, _)| *p == path) {
                    Some((_, n)) => {
                        *n += 1;
                        *n
                    }
                    None => {
                        counts.push((path.clone(), 0));
                        0
                    }
                };
                match comment {
                    Some(c) => out.push_str(&format!("# {path}[{n}]: {c}\n")),
                    None => out.push_str(&format!("# {path}[{n}]\n")),
                }
            } else if let Some(c) = comment {
                out.push_str(&format!("# {c}\n"));
            }
            if first {
                seen.push(path.clone());
            }
            out.push_str(line);
            out.push('\n');
            table = if array { format!("{path}[]") } else { path };
            continue;
        }
        if t.is_empty() {
            continue;
        }
        let key = t.split('=').next().unwrap_or("").trim();
        let path = if table.is_empty() {
            key.to_string()
        } else {
            format!("{table}.{key}")
        };
        let inline_table = t
            .split_once('=')
            .is_some_and(|(_, v)| v.trim_start().starts_with('{'));
        match unit_comment(&path) {
            Some(u) if !inline_table => out.push_str(&format!("{line}  # {u}\n")),
            _ => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    out
}
