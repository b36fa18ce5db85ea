//! Resumable sweeps (docs/sweep.md, "Interrupted sweeps and --resume"): the rows are
//! saved as each point finishes, and `--resume` continues from them.
//!
//! A [`Journal`] is where a sweep (or a reproduction that writes rows) puts each row
//! the moment it is done. After every row the whole file is rewritten atomically
//! (`report::atomic`: a temporary file, synced, renamed into place), so a run stopped
//! at any instant, `kill -9` included, leaves complete rows only: the rows before the
//! one being rendered.
//!
//! - A whole sweep writes its own CSV (`DIR/sweep_<param>.csv`) that way, and before
//!   the first row a record of which sweep it is beside it,
//!   `DIR/sweep_<param>.resume.json` (the shard header of `report::shard`, as shard
//!   1/1: kind, scene, param, every value, the settings that change a row, the
//!   binary's version). A run without `--resume` starts over: it removes the old CSV
//!   before writing the record.
//! - A shard (`--shard K/N`) writes its shard file that way; the file's first line is
//!   already the record.
//!
//! With `--resume`, the record must be the one this command would write (else the
//! run is refused, naming the file and the first field that differs), the file must
//! read back to exactly its bytes, and each row must be the value the record says is
//! at its place; the rows found are kept as they are (wall times included) and only
//! the other values are run. The final CSV is then the uninterrupted run's, byte for
//! byte, but for the wall times of the rows run again. Nothing to resume from (no
//! record, no file) starts the sweep, so a job script may always pass `--resume`.
//! `--resume` also removes the hidden temporary files of its file that a run killed in
//! the instant of a write left (`report::atomic::remove_stale_partials`).

use crate::report::csv_out::write_csv;
use crate::report::shard::{difference, read_shard_rows, shard_bytes, Header, Shard, SweepId};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Where the rows go.
enum Target {
    /// A whole sweep: its CSV, rewritten with every row so far, and its record.
    Plain { csv: PathBuf, record: PathBuf },
    /// One shard: its shard file.
    Shard { path: PathBuf, shard: Shard },
}

/// The rows of one sweep run, saved as they come (see the module's text).
pub struct Journal<R> {
    target: Target,
    id: SweepId,
    /// (value index, row), in index order.
    rows: Vec<(usize, R)>,
    /// How many rows were found on `--resume`.
    resumed: usize,
}

/// `DIR/<stem>.resume.json` beside `DIR/<stem>.csv`.
pub fn record_path(csv: &Path) -> PathBuf {
    let stem = csv
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    csv.with_file_name(format!("{stem}.resume.json"))
}

impl<R: Serialize + DeserializeOwned> Journal<R> {
    /// A whole sweep of `id` writing `csv`. `value_of` gives a row's value as
    /// `id.values` writes it (to check, on `--resume`, that each row is the value at
    /// its place).
    pub fn plain(
        csv: &Path,
        id: &SweepId,
        resume: bool,
        value_of: fn(&R) -> String,
    ) -> Result<Journal<R>, String> {
        crate::report::interrupt::arm();
        let record = record_path(csv);
        let mut j = Journal {
            target: Target::Plain {
                csv: csv.to_path_buf(),
                record: record.clone(),
            },
            id: id.clone(),
            rows: Vec::new(),
            resumed: 0,
        };
        let want = Header::new(id, Shard { k: 1, n: 1 });
        if resume {
            crate::report::atomic::remove_stale_partials(csv);
        }
        if resume && record.exists() {
            let refuse = |why: String| cannot_resume(csv, &why);
            let text = std::fs::read_to_string(&record)
                .map_err(|e| refuse(format!("{}: {e}", record.display())))?;
            let got: Header = serde_json::from_str(&text)
                .map_err(|e| refuse(format!("{} is not a sweep record: {e}", record.display())))?;
            if let Some(d) = difference(&want, &got)
                .or_else(|| (got.format != want.format).then(|| format!("format {}", got.format)))
            {
                return Err(refuse(format!(
                    "it holds rows of another sweep: {d} (recorded in {}), where this command is {}",
                    record.display(),
                    id.describe()
                )));
            }
            if csv.exists() {
                let rows = read_plain(csv)
                    .map_err(|e| refuse(format!("it is not as this sweep writes it: {e}")))?;
                if rows.len() > id.values.len() {
                    return Err(refuse(format!(
                        "it has {} rows, the sweep {} values",
                        rows.len(),
                        id.values.len()
                    )));
                }
                for (i, r) in rows.into_iter().enumerate() {
                    let v = value_of(&r);
                    if v != id.values[i] {
                        return Err(refuse(format!(
                            "row {i} is value {v}, where the sweep has {}",
                            id.values[i]
                        )));
                    }
                    j.rows.push((i, r));
                }
            }
            j.resumed = j.rows.len();
            return Ok(j);
        }
        if resume && csv.exists() {
            return Err(format!(
                "{}: cannot resume: no record of the sweep that wrote it ({} is missing: it \
                 was written by another command or an older glare-pipeline); run without \
                 --resume to start over, or give another --out",
                csv.display(),
                record.display()
            ));
        }
        // Starting over: the old rows go first, so that the new record never stands
        // beside rows of another sweep.
        if csv.exists() {
            std::fs::remove_file(csv)
                .map_err(|e| format!("{}: cannot remove the old file: {e}", csv.display()))?;
        }
        let text =
            serde_json::to_string(&want).map_err(|e| format!("{}: {e}", record.display()))?;
        crate::report::atomic::write_bytes(&record, format!("{text}\n").as_bytes())?;
        Ok(j)
    }

    /// Shard `shard` of `id`, writing its shard file in `out`.
    pub fn shard(
        out: &Path,
        id: &SweepId,
        shard: Shard,
        resume: bool,
    ) -> Result<Journal<R>, String> {
        crate::report::interrupt::arm();
        let path = out.join(shard.file_name(&id.param));
        let mut j = Journal {
            target: Target::Shard {
                path: path.clone(),
                shard,
            },
            id: id.clone(),
            rows: Vec::new(),
            resumed: 0,
        };
        if resume {
            crate::report::atomic::remove_stale_partials(&path);
        }
        if resume && path.exists() {
            let refuse = |why: String| cannot_resume(&path, &why);
            // Reads the header and checks each row's index, param and value.
            let f = read_shard_rows(&path).map_err(|e| format!("cannot resume: {e}"))?;
            let want = Header::new(id, shard);
            if let Some(d) = difference(&want, &f.header)
                .or_else(|| (f.header.k != shard.k).then(|| format!("shard K = {}", f.header.k)))
            {
                return Err(refuse(format!(
                    "it holds rows of another sweep: {d}, where this command is {} shard {shard}",
                    id.describe()
                )));
            }
            for (i, rec) in f.rows {
                let r: R = rec
                    .deserialize(Some(&f.columns))
                    .map_err(|e| refuse(format!("the row of value index {i}: {e}")))?;
                j.rows.push((i, r));
            }
            j.rows.sort_by_key(|(i, _)| *i);
            j.resumed = j.rows.len();
            return Ok(j);
        }
        // The file exists from the start, empty: `sweep merge` calls it incomplete.
        j.save()?;
        Ok(j)
    }

    /// Whether value index `i` already has its row.
    pub fn is_done(&self, i: usize) -> bool {
        self.rows.binary_search_by_key(&i, |(k, _)| *k).is_ok()
    }

    /// Rows found by `--resume`.
    pub fn resumed(&self) -> usize {
        self.rows.len().min(self.resumed)
    }

    /// The file the rows go to.
    pub fn path(&self) -> &Path {
        match &self.target {
            Target::Plain { csv, .. } => csv,
            Target::Shard { path, .. } => path,
        }
    }

    /// The line `--resume` prints (on stderr) before it runs the rest; None when
    /// nothing was found.
    pub fn resume_note(&self, todo: usize) -> Option<String> {
        (self.resumed > 0).then(|| {
            format!(
                "resume: {} rows of {} already in {}; running the other {todo}",
                self.resumed,
                self.id.describe(),
                self.path().display()
            )
        })
    }

    /// The items `only` picks (every item without a shard) that have no row yet, with
    /// their indices, after printing the [`Journal::resume_note`] on stderr: the work
    /// list of every sweep that records into a journal.
    pub fn pending<'a, T>(
        &self,
        items: &'a [T],
        only: Option<crate::report::shard::Shard>,
    ) -> Vec<(usize, &'a T)> {
        let todo: Vec<(usize, &T)> = crate::report::shard::pick(items, only)
            .into_iter()
            .filter(|(i, _)| !self.is_done(*i))
            .collect();
        if let Some(note) = self.resume_note(todo.len()) {
            eprintln!("{note}");
        }
        // What a second signal prints before the next row is saved.
        let (saved, total) = self.saved_of_total();
        crate::report::interrupt::saved(crate::report::interrupt::message(
            saved,
            total,
            self.path(),
        ));
        todo
    }

    /// Add value index `i`'s row and save the rows so far (atomically; a whole sweep's
    /// file takes the gap-free prefix of them). If SIGINT or SIGTERM came meanwhile,
    /// the run stops here, the row saved: `report::interrupt`.
    pub fn record(&mut self, i: usize, row: R) -> Result<(), String> {
        let at = self.rows.partition_point(|(k, _)| *k < i);
        self.rows.insert(at, (i, row));
        self.save()?;
        let (saved, total) = self.saved_of_total();
        crate::report::interrupt::stop_if_requested(saved, total, self.path());
        Ok(())
    }

    /// Rows on file and rows this run writes in all: a whole sweep keeps the gap-free
    /// prefix of its values; a shard, every row of its share.
    fn saved_of_total(&self) -> (usize, usize) {
        match &self.target {
            Target::Plain { .. } => (
                self.rows
                    .iter()
                    .enumerate()
                    .take_while(|(at, (i, _))| at == i)
                    .count(),
                self.id.values.len(),
            ),
            Target::Shard { shard, .. } => {
                (self.rows.len(), shard.indices(self.id.values.len()).len())
            }
        }
    }

    fn save(&self) -> Result<(), String> {
        match &self.target {
            Target::Plain { csv, .. } => {
                // Only the rows of values 0, 1, … without a gap: `--resume` reads the
                // file back as the sweep's first rows. A row that finished ahead of an
                // earlier one (points run side by side) waits in memory for it.
                let rows: Vec<&R> = self
                    .rows
                    .iter()
                    .enumerate()
                    .take_while(|(at, (i, _))| at == i)
                    .map(|(_, (_, r))| r)
                    .collect();
                write_csv(csv, &rows)
            }
            Target::Shard { path, shard } => {
                let text = shard_bytes(path, &self.id, *shard, &self.rows)?;
                crate::report::atomic::write_bytes(path, &text)
            }
        }
    }

    /// The rows, (value index, row) in index order.
    pub fn into_rows(self) -> Vec<(usize, R)> {
        self.rows
    }

    /// The record a whole sweep keeps beside its CSV (None for a shard).
    pub fn record_file(&self) -> Option<&Path> {
        match &self.target {
            Target::Plain { record, .. } => Some(record),
            Target::Shard { .. } => None,
        }
    }
}

/// The rows of a CSV written by `write_csv`, refused unless writing them again gives
/// the file's bytes exactly (a row cut short, a column added or a value edited).
fn read_plain<R: Serialize + DeserializeOwned>(csv: &Path) -> Result<Vec<R>, String> {
    let bytes = std::fs::read(csv).map_err(|e| e.to_string())?;
    let mut r = csv::Reader::from_reader(bytes.as_slice());
    let mut rows = Vec::new();
    for (i, rec) in r.deserialize::<R>().enumerate() {
        rows.push(rec.map_err(|e| format!("row {i}: {e}"))?);
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in &rows {
        w.serialize(r).map_err(|e| e.to_string())?;
    }
    let again = w.into_inner().map_err(|e| e.to_string())?;
    if again != bytes {
        let line = again
            .split(|b| *b == b'\n')
            .zip(bytes.split(|b| *b == b'\n'))
            .position(|(a, b)| a != b)
            .unwrap_or(rows.len() + 1);
        return Err(format!(
            "line {} differs from what the sweep writes",
            line + 1
        ));
    }
    Ok(rows)
}

/// The refusal of a `--resume` that cannot continue from `file`.
fn cannot_resume(file: &Path, why: &str) -> String {
    format!(
        "{}: cannot resume: {why}; run without --resume to start over, or give another --out",
        file.display()
    )
}
