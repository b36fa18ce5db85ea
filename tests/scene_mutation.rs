//! Scene files mutated at random, through parse → validate → elaborate
//! (`frame::check::check_scene_text`, the fuzz target's path): the CI's short run of
//! what `tests/fuzz` (cargo-fuzz, libFuzzer) runs for millions of executions.
//!
//! Each case starts from a built-in scene's TOML text and applies a few mutations: a
//! number replaced by an extreme value (±0, ±1e308, 1e-308, nan, ±inf, 2⁶⁴, …), a line
//! deleted, duplicated or moved, a byte changed, the text truncated, an array grown or
//! shrunk. Properties: nothing panics; a refusal names a field; an accepted scene
//! survives a TOML round trip unchanged and elaborates the same chip. The seed corpus
//! of the fuzz target is the built-ins' TOML, checked here to be current.

use glare_pipeline::frame::check::check_scene_text;
use glare_pipeline::scene::builtin::builtin_toml;
use glare_pipeline::scene::load::builtin_names;
use proptest::prelude::*;
use std::path::Path;

/// Values a mutation puts in place of a number.
const EXTREMES: [&str; 20] = [
    "0",
    "-0.0",
    "-1",
    "1",
    "0.5",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "nan",
    "inf",
    "-inf",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "9223372036854775807",
    "-9223372036854775808",
    "1e9",
    "\"text\"",
    "[]",
];

#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the k-th number (mod the count) with EXTREMES[v].
    Number(usize, usize),
    DeleteLine(usize),
    DuplicateLine(usize),
    MoveLine(usize, usize),
    /// Set the byte at (i mod len) to an ASCII character.
    Byte(usize, u8),
    /// Cut the text at (i mod len).
    Truncate(usize),
    /// Add (true) or remove (false) one element of the k-th inline or multi-line array.
    Array(usize, bool),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), 0..EXTREMES.len()).prop_map(|(k, v)| Mutation::Number(k, v)),
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::MoveLine(a, b)),
        1 => (any::<usize>(), 0x20u8..0x7f).prop_map(|(i, c)| Mutation::Byte(i, c)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        2 => (any::<usize>(), any::<bool>()).prop_map(|(k, grow)| Mutation::Array(k, grow)),
    ]
}

/// Byte ranges of the numeric literals in `text` (a run of digits with its sign,
/// point and exponent, not inside a quoted string).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let (mut i, mut quoted) = (0, false);
    while i < b.len() {
        let c = b[i];
        if c == b'"' {
            quoted = !quoted;
        } else if c == b'#' && !quoted {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        } else if !quoted
            && (c.is_ascii_digit() || (c == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)))
        {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"+-._".contains(&b[i])) {
                i += 1;
            }
            out.push((start, i));
            continue;
        }
        i += 1;
    }
    out
}

fn apply(text: &str, m: &Mutation) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let pick = |k: usize, n: usize| if n == 0 { 0 } else { k % n };
    match *m {
        Mutation::Number(k, v) => {
            let nums = numbers(text);
            if nums.is_empty() {
                return text.to_string();
            }
            let (s, e) = nums[pick(k, nums.len())];
            format!("{}{}{}", &text[..s], EXTREMES[v], &text[e..])
        }
        Mutation::DeleteLine(k) => {
            let i = pick(k, lines.len());
            lines
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, l)| *l)
                .collect::<Vec<_>>()
                .join("\n")
        }
        Mutation::DuplicateLine(k) => {
            let i = pick(k, lines.len());
            let mut v = lines.clone();
            if let Some(l) = lines.get(i) {
                v.insert(i, l);
            }
            v.join("\n")
        }
        Mutation::MoveLine(a, b) => {
            let mut v = lines.clone();
            if v.is_empty() {
                return String::new();
            }
            let l = v.remove(pick(a, v.len()));
            let at = pick(b, v.len() + 1);
            v.insert(at, l);
            v.join("\n")
        }
        Mutation::Byte(i, c) => {
            let mut bytes = text.as_bytes().to_vec();
            if bytes.is_empty() {
                return String::new();
            }
            let at = pick(i, bytes.len());
            bytes[at] = c;
            // Changing one byte of a multi-byte character leaves invalid UTF-8, which
            // `Scene::from_file` refuses before parsing: keep only text cases here.
            String::from_utf8(bytes).unwrap_or_else(|_| text.to_string())
        }
        Mutation::Truncate(i) => {
            let mut at = pick(i, text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            text[..at].to_string()
        }
        Mutation::Array(k, grow) => {
            // An element line of a multi-line array is a number followed by a comma
            // on its own line (`    0.5,`): duplicate one or drop one.
            let elems: Vec<usize> = lines
                .iter()
                .enumerate()
                .filter(|(_, l)| {
                    let t = l.trim();
                    t.ends_with(',') && !t.contains('=') && !t.starts_with('[')
                })
                .map(|(i, _)| i)
                .collect();
            if elems.is_empty() {
                return text.to_string();
            }
            let i = elems[pick(k, elems.len())];
            let mut v = lines.clone();
            if grow {
                v.insert(i, lines[i]);
            } else {
                v.remove(i);
            }
            v.join("\n")
        }
    }
}

fn check(text: &str) -> Result<(), TestCaseError> {
    match check_scene_text(text) {
        Err(e) => prop_assert!(!e.field().is_empty(), "a refusal names no field: {e}"),
        Ok(first) => {
            let again = toml::to_string_pretty(&first.scene).expect("an accepted scene serialises");
            let back = check_scene_text(&again)
                .map_err(|e| TestCaseError::fail(format!("round trip refused: {e}\n{again}")))?;
            prop_assert_eq!(
                &back.scene,
                &first.scene,
                "the TOML round trip changed the scene"
            );
            prop_assert_eq!(
                serde_json::to_string(&back.chip).unwrap(),
                serde_json::to_string(&first.chip).unwrap(),
                "the round trip elaborated another chip"
            );
            prop_assert_eq!(
                back.memory.total(),
                first.memory.total(),
                "the round trip sized another frame"
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 768, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_never_panic_and_refusals_name_a_field(
        which in any::<usize>(),
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let corpus = corpus();
        let mut text = corpus[which % corpus.len()].1.clone();
        for m in &mutations {
            text = apply(&text, m);
        }
        check(&text)?;
    }
}

/// The built-ins the seed corpus holds: every built-in that is a TOML scene.
fn corpus_names() -> Vec<&'static str> {
    builtin_names()
        .into_iter()
        .filter(|n| builtin_toml(n).is_ok())
        .collect()
}

/// Each corpus built-in's name and TOML text, made once for all cases.
fn corpus() -> &'static [(&'static str, String)] {
    static CORPUS: std::sync::OnceLock<Vec<(&'static str, String)>> = std::sync::OnceLock::new();
    CORPUS.get_or_init(|| {
        corpus_names()
            .into_iter()
            .map(|n| (n, builtin_toml(n).unwrap()))
            .collect()
    })
}

#[test]
fn every_builtin_passes_the_check_unchanged() {
    for name in corpus_names() {
        let text = builtin_toml(name).unwrap();
        check(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(check_scene_text(&text).is_ok(), "{name} is refused");
    }
}

#[test]
fn the_fuzz_seed_corpus_is_the_builtins_toml() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz/corpus/scene");
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    let mut want: Vec<String> = corpus_names().iter().map(|n| format!("{n}.toml")).collect();
    want.sort();
    assert_eq!(
        on_disk,
        want,
        "regenerate: for n in …; glare-pipeline scene $n > {}/$n.toml",
        dir.display()
    );
    for name in corpus_names() {
        let file = std::fs::read_to_string(dir.join(format!("{name}.toml"))).unwrap();
        assert_eq!(
            file,
            builtin_toml(name).unwrap(),
            "{name}.toml is stale: regenerate it with `glare-pipeline scene {name}`"
        );
    }
}
