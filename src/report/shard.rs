//! Sharding a sweep across processes or machines (docs/sweep.md, "Sharding across
//! machines"), shared by the shafts, glare and shading sweeps.
//!
//! `sweep … --shard K/N` renders only the values whose index i (from 0, in the order
//! given) has `i mod N = K − 1`, and writes `DIR/sweep_<param>.shard-K-of-N.csv`:
//!
//! ```text
//! # glare-pipeline sweep shard: {"format":1,"version":…,"k":2,"n":3,"sweep":{…}}
//! index,<the sweep's CSV columns>
//! 1,<the row of value 1, as the unsharded CSV writes it>
//! 4,…
//! ```
//!
//! The first line identifies the sweep (kind, scene, param, every value, the settings
//! that change the rows, the plot's title), so the merge needs no scene and no
//! command line. Round-robin rather than contiguous blocks: a sweep's cost usually
//! grows with the value (planes, table sizes), and striding spreads the dear values
//! over every shard.
//!
//! `sweep merge DIR…` ([`load`]) reads every shard file, checks that they are one
//! sweep, all of it, once, and hands the rows back in value order ([`ShardSet::rows`]);
//! each sweep then writes its CSV, plot and table exactly as an unsharded run does.
//! Rows go through the CSV as text both ways: floats are written as the shortest
//! decimal that parses back to the same `f64` (`csv_out`), so the merged CSV is the
//! unsharded one byte for byte but for the wall times.

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

pub use crate::report::atomic::write_atomically;

/// The shard file's format; a file of another format is refused.
pub const FORMAT: u32 = 1;
/// Most shards one sweep may be cut into (a sweep has at most 1000 values).
pub const MAX_SHARDS: usize = 1000;
/// The first line of a shard file, before its JSON header.
pub(crate) const MAGIC: &str = "# glare-pipeline sweep shard: ";

/// Shard K of N (1 ≤ K ≤ N).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// `K/N`, two whole numbers of plain digits (no sign, no spaces: a job array's
    /// `$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT` with a variable unset must not
    /// pass for another shard). The message names no argument: clap puts it behind
    /// `--shard <K/N>`.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let bad = |why: String| {
            format!(
                "'{text}': {why} (--shard takes K/N with 1 <= K <= N <= {MAX_SHARDS}, e.g. --shard 2/3)"
            )
        };
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| bad("not of the form K/N".into()))?;
        let num = |s: &str, what: &str| {
            let digits = !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
            digits
                .then(|| s.parse::<usize>().ok())
                .flatten()
                .ok_or_else(|| bad(format!("{what} '{s}' is not a whole number")))
        };
        let (k, n) = (num(k, "K")?, num(n, "N")?);
        if n == 0 || n > MAX_SHARDS {
            return Err(bad(format!("N = {n} is out of range")));
        }
        if k == 0 || k > n {
            return Err(bad(format!(
                "K = {k} is out of range (shards count from 1 to N = {n})"
            )));
        }
        Ok(Shard { k, n })
    }

    /// Whether value index `i` (from 0) is this shard's.
    pub fn owns(self, i: usize) -> bool {
        i % self.n + 1 == self.k
    }

    /// This shard's value indices of a sweep of `len` values (none when K > len).
    pub fn indices(self, len: usize) -> Vec<usize> {
        (self.k - 1..len).step_by(self.n).collect()
    }

    /// `sweep_<param>.shard-K-of-N.csv`.
    pub fn file_name(self, param: &str) -> String {
        format!("sweep_{param}.shard-{}-of-{}.csv", self.k, self.n)
    }
}

/// Whether `name` is a shard file's name, `sweep_<param>.shard-K-of-N.csv`: what
/// `sweep merge` picks out of a directory (a temporary file, dot-prefixed, is not).
fn is_shard_name(name: &str) -> bool {
    let Some(rest) = name
        .strip_prefix("sweep_")
        .and_then(|r| r.strip_suffix(".csv"))
    else {
        return false;
    };
    let Some((_, kn)) = rest.rsplit_once(".shard-") else {
        return false;
    };
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    kn.split_once("-of-")
        .is_some_and(|(k, n)| digits(k) && digits(n))
}

/// What makes two shards parts of the same sweep: everything that changes a row or
/// the plot. Two shards whose identities differ in anything are refused.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SweepId {
    /// Which sweep: `shafts`, `glare` or `shading`.
    pub kind: String,
    /// The scene as given to `--scene`.
    pub scene: String,
    /// The parameter as the CSV names it.
    pub param: String,
    /// Every value of the sweep, in order, as the CSV writes it.
    pub values: Vec<String>,
    /// The other settings the rows depend on (image size, truth samples, a
    /// fingerprint of the scene), by name.
    pub settings: BTreeMap<String, String>,
    /// The plot's title (the merge has no scene to take it from).
    pub title: String,
}

impl SweepId {
    /// The identity of a sweep of `param` over a scene (the glare and environment-map
    /// sweeps): `scene_arg` as given to `--scene`, the image size, and the scene itself
    /// (after `--image`) by fingerprint, so that shards rendered from two different
    /// files of one name are refused.
    pub fn of_scene<T: Serialize>(
        kind: &str,
        scene: &T,
        image: (u32, u32),
        scene_arg: &str,
        param: &str,
        values: &[u32],
        title: String,
    ) -> Result<SweepId, String> {
        Ok(SweepId {
            kind: kind.into(),
            scene: scene_arg.into(),
            param: param.into(),
            values: values.iter().map(u32::to_string).collect(),
            settings: [
                ("image".to_string(), format!("{}x{}", image.0, image.1)),
                ("scene_fingerprint".to_string(), fingerprint(scene)?),
            ]
            .into(),
            title,
        })
    }

    /// "sweep planes on fig4".
    pub fn describe(&self) -> String {
        format!("sweep {} on {}", self.param, self.scene)
    }
}

/// The first line of a shard file (and the record of a resumable sweep,
/// `report::resume`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Header {
    pub(crate) format: u32,
    /// The binary that wrote it: another version may render other numbers.
    pub(crate) version: String,
    pub(crate) k: usize,
    pub(crate) n: usize,
    pub(crate) sweep: SweepId,
}

impl Header {
    /// This binary's header of shard `shard` (1/1 for a whole sweep) of `id`.
    pub(crate) fn new(id: &SweepId, shard: Shard) -> Header {
        Header {
            format: FORMAT,
            version: env!("CARGO_PKG_VERSION").to_string(),
            k: shard.k,
            n: shard.n,
            sweep: id.clone(),
        }
    }
}

/// A fingerprint of `value` (a scene): a 64-bit FNV-1a hash of its JSON, as 16 hex
/// digits. FNV rather than std's hasher, which promises the same hash on no other
/// build; JSON is deterministic for the scene's structs (no hash maps, floats written
/// shortest-exact).
pub fn fingerprint<T: Serialize>(value: &T) -> Result<String, String> {
    let text = serde_json::to_string(value).map_err(|e| format!("scene: {e}"))?;
    let h = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    Ok(format!("{h:016x}"))
}

/// The items `only` picks, with their indices (every item without a shard).
pub fn pick<T>(items: &[T], only: Option<Shard>) -> Vec<(usize, &T)> {
    items
        .iter()
        .enumerate()
        .filter(|(i, _)| only.is_none_or(|s| s.owns(*i)))
        .collect()
}

/// The bytes of shard `shard`'s file holding `rows`, `(value index, row)` in index
/// order: the header line, then `index,<the sweep's columns>` and one line per row.
pub(crate) fn shard_bytes<R: Serialize>(
    path: &Path,
    id: &SweepId,
    shard: Shard,
    rows: &[(usize, R)],
) -> Result<Vec<u8>, String> {
    let at = |e: &dyn fmt::Display| format!("{}: {e}", path.display());
    // The rows exactly as `write_csv` writes them, read back as text records so that
    // the index can stand in front of any row shape.
    let mut w = csv::Writer::from_writer(Vec::new());
    for (_, r) in rows {
        w.serialize(r).map_err(|e| at(&e))?;
    }
    let plain = w.into_inner().map_err(|e| at(&e))?;
    let mut r = csv::Reader::from_reader(plain.as_slice());
    let columns = r.headers().map_err(|e| at(&e))?.clone();
    let header = Header::new(id, shard);
    let mut text = format!(
        "{MAGIC}{}\n",
        serde_json::to_string(&header).map_err(|e| at(&e))?
    )
    .into_bytes();
    let mut w = csv::Writer::from_writer(&mut text);
    w.write_record(std::iter::once("index").chain(columns.iter()))
        .map_err(|e| at(&e))?;
    for ((i, _), rec) in rows.iter().zip(r.records()) {
        let rec = rec.map_err(|e| at(&e))?;
        w.write_record(std::iter::once(i.to_string().as_str()).chain(rec.iter()))
            .map_err(|e| at(&e))?;
    }
    w.flush().map_err(|e| at(&e))?;
    drop(w);
    Ok(text)
}

/// Write shard `shard`'s rows, `(value index, row)` in index order, to
/// `out/sweep_<param>.shard-K-of-N.csv` (atomically), and say what was written: the
/// line a shard run prints before its table.
pub fn finish_shard<R: Serialize>(
    out: &Path,
    id: &SweepId,
    shard: Shard,
    rows: &[(usize, R)],
) -> Result<String, String> {
    let path = out.join(shard.file_name(&id.param));
    let text = shard_bytes(&path, id, shard, rows)?;
    crate::report::atomic::write_bytes(&path, &text)?;
    let idx: Vec<String> = rows.iter().map(|(i, _)| i.to_string()).collect();
    let share = if idx.is_empty() {
        format!("no values: K > the {} values", id.values.len())
    } else {
        format!(
            "value indices {} of 0 ..= {}",
            idx.join(", "),
            id.values.len() - 1
        )
    };
    Ok(format!(
        "{}, shard {shard} ({share}): wrote {}",
        id.describe(),
        path.display()
    ))
}

/// One shard file, read and checked on its own.
pub(crate) struct ShardFile {
    pub(crate) path: PathBuf,
    pub(crate) header: Header,
    /// The row columns (without `index`); empty for a shard without rows.
    pub(crate) columns: csv::StringRecord,
    /// (value index, row) in file order.
    pub(crate) rows: Vec<(usize, csv::StringRecord)>,
}

/// A shard file with all its rows, checked (`sweep merge`).
fn read_shard(path: &Path) -> Result<ShardFile, String> {
    let f = read_shard_rows(path)?;
    let (shard, id) = (
        Shard {
            k: f.header.k,
            n: f.header.n,
        },
        &f.header.sweep,
    );
    let seen: std::collections::BTreeSet<usize> = f.rows.iter().map(|(i, _)| *i).collect();
    let missing: Vec<String> = shard
        .indices(id.values.len())
        .into_iter()
        .filter(|i| !seen.contains(i))
        .map(|i| i.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "{}: incomplete: shard {shard} has no row for value index {} (was its run cut short? \
             rerun it with --resume)",
            path.display(),
            missing.join(", ")
        ));
    }
    Ok(f)
}

/// A shard file's header and the rows it holds, each checked, whether or not every
/// row of the shard is there (`--resume` reads a shard cut short).
pub(crate) fn read_shard_rows(path: &Path) -> Result<ShardFile, String> {
    let at = |m: String| format!("{}: {m}", path.display());
    let text = std::fs::read_to_string(path).map_err(|e| at(e.to_string()))?;
    let (first, body) = text.split_once('\n').unwrap_or((&text, ""));
    let json = first.strip_prefix(MAGIC).ok_or_else(|| {
        at(format!(
            "not a sweep shard file (its first line should start with '{}')",
            MAGIC.trim_end()
        ))
    })?;
    let header: Header =
        serde_json::from_str(json).map_err(|e| at(format!("malformed shard header: {e}")))?;
    if header.format != FORMAT {
        return Err(at(format!(
            "shard format {} (this glare-pipeline reads format {FORMAT})",
            header.format
        )));
    }
    let shard = Shard::parse(&format!("{}/{}", header.k, header.n))
        .map_err(|e| at(format!("malformed shard header: shard {e}")))?;
    let id = &header.sweep;
    let mut r = csv::Reader::from_reader(body.as_bytes());
    let head = r
        .headers()
        .map_err(|e| at(format!("malformed rows: {e}")))?
        .clone();
    if head.get(0) != Some("index") {
        return Err(at(
            "malformed rows: the first column should be 'index'".into()
        ));
    }
    let columns: csv::StringRecord = head.iter().skip(1).collect();
    let col = |name: &str| columns.iter().position(|c| c == name);
    let (param_col, value_col) = (col("param"), col("value"));
    let mut rows = Vec::new();
    let mut seen = vec![false; id.values.len()];
    for (line, rec) in r.records().enumerate() {
        let row = |m: String| at(format!("row {line}: {m}"));
        let rec = rec.map_err(|e| row(e.to_string()))?;
        let cell = rec.get(0).unwrap_or("");
        let i: usize = cell
            .parse()
            .map_err(|_| row(format!("index '{cell}' is not a whole number")))?;
        if i >= id.values.len() {
            return Err(row(format!(
                "index {i} is past the sweep's {} values",
                id.values.len()
            )));
        }
        if !shard.owns(i) {
            return Err(row(format!("value index {i} is not shard {shard}'s")));
        }
        if std::mem::replace(&mut seen[i], true) {
            return Err(row(format!("value index {i} appears twice")));
        }
        let rest: csv::StringRecord = rec.iter().skip(1).collect();
        for (c, want, what) in [
            (param_col, &id.param, "param"),
            (value_col, &id.values[i], "value"),
        ] {
            if let Some(got) = c.and_then(|c| rest.get(c)) {
                if got != want {
                    return Err(row(format!(
                        "{what} is '{got}' where the header says '{want}'"
                    )));
                }
            }
        }
        rows.push((i, rest));
    }
    Ok(ShardFile {
        path: path.to_path_buf(),
        header,
        columns,
        rows,
    })
}

/// The first field in which `b` differs from `a`, as `param "mesh", not "planes"`.
pub(crate) fn difference(a: &Header, b: &Header) -> Option<String> {
    let (x, y) = (&a.sweep, &b.sweep);
    let q = |v: &dyn fmt::Debug| format!("{v:?}");
    // In the order a reader would look for the cause.
    [
        ("kind", q(&x.kind), q(&y.kind)),
        ("scene", q(&x.scene), q(&y.scene)),
        ("param", q(&x.param), q(&y.param)),
        ("values", q(&x.values.join(",")), q(&y.values.join(","))),
        ("N =", a.n.to_string(), b.n.to_string()),
        ("settings", q(&x.settings), q(&y.settings)),
        ("glare-pipeline version", q(&a.version), q(&b.version)),
        ("plot title", q(&x.title), q(&y.title)),
    ]
    .into_iter()
    .find(|(_, want, got)| want != got)
    .map(|(name, want, got)| format!("{name} {got}, not {want}"))
}

/// Every shard of one sweep, checked: the rows in value order.
pub struct ShardSet {
    pub id: SweepId,
    /// N.
    pub n: usize,
    /// The shard files, shard 1 first.
    pub files: Vec<PathBuf>,
    columns: csv::StringRecord,
    /// (file, row) by value index.
    rows: Vec<(usize, csv::StringRecord)>,
}

impl ShardSet {
    /// The rows, in value order, as the sweep's row type; a row that does not read as
    /// one is an error naming its file.
    pub fn rows<R: DeserializeOwned>(&self) -> Result<Vec<R>, String> {
        self.rows
            .iter()
            .enumerate()
            .map(|(i, (f, rec))| {
                rec.deserialize(Some(&self.columns)).map_err(|e| {
                    format!(
                        "{}: the row of value index {i} is not a {} sweep row: {e}",
                        self.files[*f].display(),
                        self.id.kind
                    )
                })
            })
            .collect()
    }
}

impl ShardSet {
    /// The line a merge prints before its table.
    pub fn merged(&self, csv: &Path, png: &Path) -> String {
        format!(
            "{}: merged {} shards: wrote {} and {}",
            self.id.describe(),
            self.n,
            csv.display(),
            png.display()
        )
    }
}

/// The shard files among `inputs`: a directory gives every
/// `sweep_<param>.shard-K-of-N.csv` in it, a file itself. The same file named twice
/// (a directory and a file in it) counts once.
fn shard_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut files: Vec<PathBuf> = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for input in inputs {
        let found = if input.is_dir() {
            let mut v: Vec<PathBuf> = std::fs::read_dir(input)
                .map_err(|e| format!("{}: {e}", input.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.is_file()
                        && p.file_name()
                            .is_some_and(|n| is_shard_name(&n.to_string_lossy()))
                })
                .collect();
            if v.is_empty() {
                return Err(format!(
                    "{}: no sweep shard files (sweep_<param>.shard-K-of-N.csv) in this directory",
                    input.display()
                ));
            }
            v.sort();
            v
        } else if input.is_file() {
            vec![input.clone()]
        } else {
            return Err(format!(
                "{}: no such shard file or directory",
                input.display()
            ));
        };
        for f in found {
            let key = f.canonicalize().unwrap_or_else(|_| f.clone());
            if seen.insert(key) {
                files.push(f);
            }
        }
    }
    if files.is_empty() {
        return Err("merge: no shard directories or files given".into());
    }
    Ok(files)
}

/// Read and check every shard among `inputs` (directories or files): one sweep, N
/// shards, each once, each with all its rows. Every error names the file at fault
/// (or, for a missing shard, the file expected); nothing is written.
pub fn load(inputs: &[PathBuf]) -> Result<ShardSet, String> {
    let files = shard_files(inputs)?
        .iter()
        .map(|p| read_shard(p))
        .collect::<Result<Vec<_>, _>>()?;
    let first = &files[0];
    let n = first.header.n;
    let mut by_k: Vec<Option<usize>> = vec![None; n];
    for (fi, f) in files.iter().enumerate() {
        if let Some(d) = difference(&first.header, &f.header) {
            return Err(format!(
                "{}: a shard of another sweep: {d} as in {} ({})",
                f.path.display(),
                first.path.display(),
                first.header.sweep.describe()
            ));
        }
        let slot = &mut by_k[f.header.k - 1];
        if let Some(other) = *slot {
            return Err(format!(
                "{}: duplicate shard {}/{n} (also {})",
                f.path.display(),
                f.header.k,
                files[other].path.display()
            ));
        }
        *slot = Some(fi);
    }
    let id = first.header.sweep.clone();
    let missing: Vec<String> = (1..=n)
        .filter(|k| by_k[k - 1].is_none())
        .map(|k| Shard { k, n }.file_name(&id.param))
        .collect();
    if !missing.is_empty() {
        let given: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
        return Err(format!(
            "missing shard{} of {} ({n} in all): no {} in {}",
            if missing.len() > 1 { "s" } else { "" },
            id.describe(),
            missing.join(", "),
            given.join(", ")
        ));
    }
    // Shards without rows (K past the number of values) have no columns to compare.
    let with_rows: Vec<&ShardFile> = files.iter().filter(|f| !f.rows.is_empty()).collect();
    let columns = with_rows
        .first()
        .map(|f| f.columns.clone())
        .unwrap_or_default();
    if let Some(f) = with_rows.iter().find(|f| f.columns != columns) {
        return Err(format!(
            "{}: its columns differ from those of {}",
            f.path.display(),
            with_rows[0].path.display()
        ));
    }
    let mut rows: Vec<Option<(usize, csv::StringRecord)>> = vec![None; id.values.len()];
    let order: Vec<usize> = by_k.into_iter().flatten().collect();
    for (slot, &fi) in order.iter().enumerate() {
        for (i, rec) in &files[fi].rows {
            rows[*i] = Some((slot, rec.clone()));
        }
    }
    // Each file was checked to hold all its indices and the shards cover 0..len, so
    // every slot is filled; a hole would still be refused rather than unwrapped.
    let rows = rows
        .into_iter()
        .enumerate()
        .map(|(i, r)| r.ok_or_else(|| format!("merge: no row for value index {i}")))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(ShardSet {
        id,
        n,
        files: order.iter().map(|&fi| files[fi].path.clone()).collect(),
        columns,
        rows,
    })
}
