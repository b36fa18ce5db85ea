//! Resumable reproductions (docs/sweep.md, "Interrupted sweeps and --resume"): the one
//! mechanism every long `reproduce NAME` uses to keep the items it finished and to
//! continue from them with `--resume`.
//!
//! A reproduction is a list of items (a row, a few rows, a table line, an image and
//! its row), each named by a key (`seed=17/unit`, `pattern/th=0.01`). An
//! [`ItemJournal`] holds every finished item's result and saves them to
//! `DIR/<reproduction>.resume.jsonl`: the first line the record of the run (the
//! reproduction, the settings its results depend on — environment variables such as
//! `ENVMAP_TABLE3_S` as resolved, thresholds, sizes — and the binary's version), then
//! one line per item, `{"key":…,"item":…}`. The file is rewritten whole through
//! `report::atomic` (temporary file, synced, renamed), so a run stopped at any instant
//! leaves whole items only.
//!
//! Saving is batched for reproductions of many tiny items: the file is rewritten when
//! [`ItemJournal::batch`] items are waiting, or when a second has passed since the
//! last save, whichever comes first (a batch of 1, the default, saves every item). A
//! `kill -9` loses at most the items of the batch not yet saved; SIGINT and SIGTERM
//! lose none: the run saves every finished item, prints what was kept and how to
//! continue, and exits 130 / 143 (`report::interrupt`).
//!
//! With `--resume`, the record must be the one this command would write (else the run
//! is refused, naming the setting that differs and both values); the items found are
//! taken as they are and only the others computed, and the reproduction then writes
//! its outputs from all of them: the bytes of an uninterrupted run but for its
//! wall-time columns. Without `--resume` an old journal is removed first. The journal
//! stays beside the outputs when the run is complete, so `--resume` after a complete
//! run only writes the outputs again. Finite floats round-trip exactly (serde_json with
//! `float_roundtrip`; a unit test below checks awkward values). JSON has no infinity
//! or NaN: serde_json writes a non-finite f64 as `null`, which does not read back as
//! an f64 (`--resume` then refused the journal). A field that can be non-finite is
//! marked `#[serde(with = "crate::report::items::nonfinite")]` ([`nonfinite`]: the
//! strings `"inf"`, `"-inf"`, `"NaN"`), or the item keeps bit patterns
//! (shading-factorization's ceilings).

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The journal's format, in its record.
const FORMAT: u32 = 1;
/// Longest time finished items wait before they are saved.
const FLUSH_AFTER: Duration = Duration::from_secs(1);

/// The first line of a journal: which run its items belong to.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Record {
    format: u32,
    reproduction: String,
    settings: BTreeMap<String, String>,
    version: String,
}

/// One item line.
#[derive(Serialize, Deserialize)]
struct Line<T> {
    key: String,
    item: T,
}

struct State<T> {
    items: BTreeMap<String, T>,
    /// Items finished since the last save.
    waiting: usize,
    last_save: Instant,
}

/// The finished items of one reproduction run, saved as they come (see the module).
pub struct ItemJournal<T> {
    path: PathBuf,
    record: Record,
    /// Items the run has in all (for the messages).
    total: usize,
    batch: usize,
    resumed: usize,
    state: Mutex<State<T>>,
}

/// `DIR/<reproduction>.resume.jsonl`.
pub fn journal_path(out: &Path, reproduction: &str) -> PathBuf {
    out.join(format!("{reproduction}.resume.jsonl"))
}

impl<T: Serialize + DeserializeOwned + Clone> ItemJournal<T> {
    /// The journal of `reproduction` writing into `out`, whose results depend on
    /// `settings` (name, value as resolved); `total` items in all. With `resume`, the
    /// items of an earlier run of the same settings are loaded (a journal of other
    /// settings is refused); without, an old journal is removed. Installs the SIGINT /
    /// SIGTERM handlers (`report::interrupt`) and prints the resume note.
    pub fn open(
        out: &Path,
        reproduction: &str,
        settings: &[(&str, String)],
        total: usize,
        resume: bool,
    ) -> Result<ItemJournal<T>, String> {
        crate::report::interrupt::arm();
        let path = journal_path(out, reproduction);
        let record = Record {
            format: FORMAT,
            reproduction: reproduction.to_string(),
            settings: settings
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect(),
            version: env!("CARGO_PKG_VERSION").to_string(),
        };
        let mut items = BTreeMap::new();
        if resume {
            crate::report::atomic::remove_stale_partials(&path);
        }
        if resume && path.exists() {
            items = load(&path, &record)?;
        } else if path.exists() {
            std::fs::remove_file(&path)
                .map_err(|e| format!("{}: cannot remove the old journal: {e}", path.display()))?;
        }
        let j = ItemJournal {
            resumed: items.len(),
            path,
            record,
            total,
            batch: 1,
            state: Mutex::new(State {
                items,
                waiting: 0,
                last_save: Instant::now(),
            }),
        };
        if j.resumed > 0 {
            eprintln!(
                "resume: {} of {} items of reproduce {reproduction} already in {}; running the other {}",
                j.resumed,
                total,
                j.path.display(),
                total.saturating_sub(j.resumed)
            );
        }
        // The record is on file from the start: a run stopped before its first item
        // still resumes (from nothing) without a refusal.
        j.state.lock().map(|s| j.save(&s)).map_err(poisoned)??;
        Ok(j)
    }

    /// Save only when `n` items are waiting or a second has passed (for many tiny
    /// items; see the module).
    pub fn batch(mut self, n: usize) -> Self {
        self.batch = n.max(1);
        self
    }

    /// The journal's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Items found by `--resume`.
    pub fn resumed(&self) -> usize {
        self.resumed
    }

    /// Whether item `key` is finished.
    pub fn has(&self, key: &str) -> bool {
        self.state
            .lock()
            .map(|s| s.items.contains_key(key))
            .unwrap_or(false)
    }

    /// Whether every one of `keys` is finished.
    pub fn has_all<'a>(&self, keys: impl IntoIterator<Item = &'a str>) -> bool {
        keys.into_iter().all(|k| self.has(k))
    }

    /// Item `key`'s result: the journal's if it is finished, else `compute`'s, which
    /// is then recorded ([`ItemJournal::record`]). Nothing new starts once SIGINT or
    /// SIGTERM has come: the run saves and exits instead.
    pub fn item(
        &self,
        key: &str,
        compute: impl FnOnce() -> Result<T, String>,
    ) -> Result<T, String> {
        if let Some(t) = self.state.lock().map_err(poisoned)?.items.get(key).cloned() {
            return Ok(t);
        }
        self.stop_if_requested()?;
        let t = compute()?;
        self.record(key, t.clone())?;
        Ok(t)
    }

    /// Record item `key` and save it (with its batch). If SIGINT or SIGTERM came
    /// meanwhile, every finished item is saved and the process exits with 130 / 143
    /// after saying what was kept and how to continue.
    pub fn record(&self, key: &str, item: T) -> Result<(), String> {
        {
            let mut s = self.state.lock().map_err(poisoned)?;
            s.items.insert(key.to_string(), item);
            s.waiting += 1;
            if s.waiting >= self.batch || s.last_save.elapsed() >= FLUSH_AFTER {
                self.save(&s)?;
                s.waiting = 0;
                s.last_save = Instant::now();
            }
        }
        self.stop_if_requested()
    }

    /// Save what is waiting: call once every item is finished, before the outputs are
    /// written.
    pub fn finish(&self) -> Result<(), String> {
        let mut s = self.state.lock().map_err(poisoned)?;
        if s.waiting > 0 {
            self.save(&s)?;
            s.waiting = 0;
        }
        Ok(())
    }

    /// If a signal asked to stop: save, print what was kept, exit 128 + signal.
    fn stop_if_requested(&self) -> Result<(), String> {
        if let Some(sig) = crate::report::interrupt::requested() {
            // Held to the exit: no other thread records or saves meanwhile.
            let s = self.state.lock().map_err(poisoned)?;
            self.save(&s)?;
            crate::report::interrupt::exit_with(sig, Some(&self.stopped_line(&s)));
        }
        Ok(())
    }

    /// What a run stopped now says: the items on file and how to continue.
    fn stopped_line(&self, s: &State<T>) -> String {
        format!(
            "interrupted after {} of {} items of reproduce {}; rerun the same command \
             with --resume to continue\n(the items are saved in {})",
            s.items.len(),
            self.total,
            self.record.reproduction,
            self.path.display()
        )
    }

    fn save(&self, s: &State<T>) -> Result<(), String> {
        self.write(s)?;
        // What a second signal prints (`report::interrupt`): the items now on file.
        crate::report::interrupt::saved(self.stopped_line(s));
        Ok(())
    }

    fn write(&self, s: &State<T>) -> Result<(), String> {
        let p = &self.path;
        crate::report::atomic::write_with(p, |w| {
            let io = |e: serde_json::Error| std::io::Error::other(e.to_string());
            serde_json::to_writer(&mut *w, &self.record).map_err(io)?;
            w.write_all(b"\n")?;
            for (key, item) in &s.items {
                serde_json::to_writer(
                    &mut *w,
                    &Line {
                        key: key.clone(),
                        item,
                    },
                )
                .map_err(io)?;
                w.write_all(b"\n")?;
            }
            Ok(())
        })
    }
}

/// A non-finite `f64` in JSON: `#[serde(with = "crate::report::items::nonfinite")]`
/// on a field writes a finite value as the number it is and ±∞ and NaN as the strings
/// `"inf"`, `"-inf"` and `"NaN"` (what the csv crate writes for them, so a CSV of the
/// same rows keeps its bytes), and reads either form back: a finite value to the same
/// bits, ±∞ to ±∞, `"NaN"` to a NaN.
pub mod nonfinite {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if x.is_finite() {
            s.serialize_f64(*x)
        } else if x.is_nan() {
            s.serialize_str("NaN")
        } else if *x > 0.0 {
            s.serialize_str("inf")
        } else {
            s.serialize_str("-inf")
        }
    }

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Form {
        Number(f64),
        Text(String),
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        match Form::deserialize(d)? {
            Form::Number(x) => Ok(x),
            Form::Text(t) => match t.as_str() {
                "inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                "NaN" => Ok(f64::NAN),
                _ => Err(serde::de::Error::custom(format!(
                    "'{t}' is not a number (a number, \"inf\", \"-inf\" or \"NaN\")"
                ))),
            },
        }
    }
}

fn poisoned<E>(_: E) -> String {
    "a reproduction thread failed while saving its journal".to_string()
}

/// The items of the journal at `path`, refused unless its record is `want`.
fn load<T: DeserializeOwned>(path: &Path, want: &Record) -> Result<BTreeMap<String, T>, String> {
    let refuse = |why: String| {
        format!(
            "{}: cannot resume: {why}; run without --resume to start over, or give another --out",
            path.display()
        )
    };
    let text = std::fs::read_to_string(path).map_err(|e| refuse(e.to_string()))?;
    let mut lines = text.lines();
    let got: Record = lines
        .next()
        .ok_or_else(|| refuse("the journal is empty".into()))
        .and_then(|l| {
            serde_json::from_str(l)
                .map_err(|e| refuse(format!("line 1 is not a journal record: {e}")))
        })?;
    if let Some(d) = difference(want, &got) {
        return Err(refuse(format!(
            "it holds the items of another run: {d} (the journal's first, then this command's)"
        )));
    }
    let mut items = BTreeMap::new();
    for (n, l) in lines.enumerate() {
        let line: Line<T> = serde_json::from_str(l)
            .map_err(|e| refuse(format!("line {} is not an item of this run: {e}", n + 2)))?;
        items.insert(line.key, line.item);
    }
    Ok(items)
}

/// The first field where `got` differs from `want`, named, with both values.
fn difference(want: &Record, got: &Record) -> Option<String> {
    if got.format != want.format {
        return Some(format!("journal format {} vs {}", got.format, want.format));
    }
    if got.reproduction != want.reproduction {
        return Some(format!(
            "reproduction {:?} vs {:?}",
            got.reproduction, want.reproduction
        ));
    }
    let names: std::collections::BTreeSet<&String> =
        got.settings.keys().chain(want.settings.keys()).collect();
    for k in names {
        let (g, w) = (got.settings.get(k), want.settings.get(k));
        if g != w {
            let show = |v: Option<&String>| v.map_or("(not set)".to_string(), |v| format!("{v:?}"));
            return Some(format!("{k} {} vs {}", show(g), show(w)));
        }
    }
    (got.version != want.version).then(|| {
        format!(
            "glare-pipeline version {:?} vs {:?}",
            got.version, want.version
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("items-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn items_and_awkward_floats_come_back_exactly() {
        let d = dir("floats");
        let xs = [
            0.1 + 0.2,
            1e-308,
            5e-324,
            f64::MAX,
            std::f64::consts::PI,
            2.0f64.sqrt() / 3.0,
            -0.0,
            123456.789e-12,
        ];
        let set = [("S", "4".to_string())];
        let j: ItemJournal<Vec<f64>> = ItemJournal::open(&d, "t", &set, 2, false).unwrap();
        j.record("a", xs.to_vec()).unwrap();
        j.finish().unwrap();
        let k: ItemJournal<Vec<f64>> = ItemJournal::open(&d, "t", &set, 2, true).unwrap();
        assert_eq!(k.resumed(), 1);
        let back = k.item("a", || panic!("recomputed a saved item")).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&xs));
        assert_eq!(k.item("b", || Ok(vec![1.0])).unwrap(), vec![1.0]);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[derive(Clone, Serialize, Deserialize)]
    struct Marked {
        #[serde(with = "nonfinite")]
        x: f64,
        plain: f64,
    }

    /// A non-finite float in a marked field is written as valid JSON (a string, where
    /// serde_json alone writes `null`) and comes back the same on --resume; an
    /// unmarked one is still `null`, which does not read back (what `nonfinite` is for).
    #[test]
    fn non_finite_floats_in_marked_fields_are_valid_json_and_come_back() {
        let d = dir("nonfinite");
        let xs = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            0.1 + 0.2,
            -0.0,
            5e-324,
            f64::MAX,
        ];
        let j: ItemJournal<Marked> = ItemJournal::open(&d, "t", &[], xs.len(), false).unwrap();
        for (i, &x) in xs.iter().enumerate() {
            j.record(&format!("k{i}"), Marked { x, plain: 1.5 })
                .unwrap();
        }
        let text = std::fs::read_to_string(j.path()).unwrap();
        for line in text.lines() {
            assert!(!line.contains("null"), "{line}");
            serde_json::from_str::<serde_json::Value>(line).expect("each line is JSON");
        }
        assert!(text.contains(r#""x":"inf""#), "{text}");
        assert!(text.contains(r#""x":"-inf""#), "{text}");
        assert!(text.contains(r#""x":"NaN""#), "{text}");
        let k: ItemJournal<Marked> = ItemJournal::open(&d, "t", &[], xs.len(), true).unwrap();
        assert_eq!(k.resumed(), xs.len());
        for (i, &x) in xs.iter().enumerate() {
            let back = k.item(&format!("k{i}"), || panic!("recomputed")).unwrap();
            if x.is_nan() {
                assert!(back.x.is_nan());
            } else {
                assert_eq!(back.x.to_bits(), x.to_bits(), "{x}");
            }
        }
        // Unmarked, serde_json writes null and the value cannot be read back.
        let line = serde_json::to_string(&Marked {
            x: 1.0,
            plain: f64::INFINITY,
        })
        .unwrap();
        assert!(line.contains(r#""plain":null"#), "{line}");
        assert!(serde_json::from_str::<Marked>(&line).is_err());
        // A string that is not one of the three is refused, naming it.
        let e = serde_json::from_str::<Marked>(r#"{"x":"infinity","plain":0.0}"#)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("'infinity' is not a number"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn other_settings_are_refused_by_name_and_a_fresh_run_starts_over() {
        let d = dir("settings");
        let j: ItemJournal<u32> =
            ItemJournal::open(&d, "t", &[("ENV_S", "16".into())], 1, false).unwrap();
        j.record("x", 7).unwrap();
        let e = ItemJournal::<u32>::open(&d, "t", &[("ENV_S", "32".into())], 1, true)
            .err()
            .unwrap();
        assert!(e.contains("ENV_S \"16\" vs \"32\""), "{e}");
        assert!(e.contains("cannot resume"), "{e}");
        // Without --resume the old items go.
        let k = ItemJournal::<u32>::open(&d, "t", &[("ENV_S", "32".into())], 1, false).unwrap();
        assert!(!k.has("x"));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_batch_waits_until_finish() {
        let d = dir("batch");
        let j = ItemJournal::<u32>::open(&d, "t", &[], 3, false)
            .unwrap()
            .batch(100);
        j.record("a", 1).unwrap();
        let on_file = || std::fs::read_to_string(j.path()).unwrap().lines().count();
        // Unless the machine stalled for a second, "a" waits in memory.
        if on_file() == 1 {
            j.finish().unwrap();
        }
        assert_eq!(on_file(), 2);
        let _ = std::fs::remove_dir_all(&d);
    }
}
