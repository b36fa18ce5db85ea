//! Every file the tool writes goes through here: it is written to a temporary file in
//! the same directory, flushed to the disk, and renamed into place. A reader (a merge
//! started early, a job watching the directory, the next `--resume`) and a run cut
//! short by a signal or `kill -9` see the old file or the whole new one, never half
//! of it.
//!
//! The temporary file is `.<stem>.<pid>-<n>.partial.<ext>`: hidden, unique per process
//! and call, and it keeps the extension, which the PNG writers read the format from.
//! `rtl_model` may not import this crate; its VCD writer takes a `Write` from the
//! caller, and the caller writes the bytes here.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Calls so far, to make each temporary name unique within the process.
static SERIAL: AtomicU64 = AtomicU64::new(0);

/// `path`'s parent directory, created if missing ("" for a bare file name).
fn make_parent(path: &Path) -> Result<PathBuf, String> {
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    if !dir.as_os_str().is_empty() {
        std::fs::create_dir_all(&dir)
            .map_err(|e| format!("{}: cannot create directory: {e}", path.display()))?;
    }
    Ok(dir)
}

/// The temporary file beside `path`.
fn temporary(dir: &Path, path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (stem, ext) = name.rsplit_once('.').unwrap_or((&name, "tmp"));
    let n = SERIAL.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".{stem}.{}-{n}.partial.{ext}", std::process::id()))
}

/// Write `path` through `write`, which is handed the temporary file's path to write
/// (create, fill, close); the file is then synced and renamed into place. A failure
/// leaves the old file as it was and removes the temporary file.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), String> {
    let dir = make_parent(path)?;
    let tmp = temporary(&dir, path);
    let res = write(&tmp)
        .and_then(|()| {
            // The bytes on the disk before the name points at them: after a crash the
            // name holds the old file or the whole new one.
            std::fs::File::open(&tmp)
                .and_then(|f| f.sync_all())
                .map_err(|e| format!("{}: cannot sync: {e}", path.display()))
        })
        .and_then(|()| {
            std::fs::rename(&tmp, path)
                .map_err(|e| format!("{}: cannot rename into place: {e}", path.display()))
        });
    match res {
        Ok(()) => {
            sync_dir(&dir);
            Ok(())
        }
        Err(e) => {
            // Best effort: a failed write leaves no temporary file behind.
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Write `bytes` to `path` atomically (see [`write_atomically`]); a failure names the
/// path.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), String> {
    write_atomically(path, |tmp| {
        std::fs::write(tmp, bytes).map_err(|e| format!("{}: {e}", path.display()))
    })
}

/// Write `path` atomically through a buffered writer handed to `fill`.
pub fn write_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), String> {
    write_atomically(path, |tmp| {
        let f = std::fs::File::create(tmp).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut w = std::io::BufWriter::new(f);
        fill(&mut w)
            .and_then(|()| w.flush())
            .map_err(|e| format!("{}: {e}", path.display()))
    })
}

/// Remove the temporary files of `path` that another process left (killed in the
/// instant of a write): `.<stem>.<pid>-<n>.partial.<ext>` with a pid not this
/// process's. Best effort; returns how many were removed. `--resume` calls it for the
/// file it continues.
pub fn remove_stale_partials(path: &Path) -> usize {
    let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
        return 0;
    };
    let name = name.to_string_lossy();
    let (stem, ext) = name.rsplit_once('.').unwrap_or((&name, "tmp"));
    let (head, tail) = (format!(".{stem}."), format!(".partial.{ext}"));
    let mine = format!("{head}{}-", std::process::id());
    let d = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let Ok(entries) = std::fs::read_dir(d) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let n = e.file_name().to_string_lossy().into_owned();
        let middle = n
            .strip_prefix(&head)
            .and_then(|r| r.strip_suffix(&tail))
            .unwrap_or("");
        // The middle is `<pid>-<n>`: digits and one dash.
        let ours = !middle.is_empty()
            && middle.split_once('-').is_some_and(|(a, b)| {
                [a, b]
                    .iter()
                    .all(|x| !x.is_empty() && x.bytes().all(|c| c.is_ascii_digit()))
            });
        if ours && !n.starts_with(&mine) && std::fs::remove_file(e.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Make a rename in `dir` durable (best effort: not every platform or file system can
/// sync a directory, and the file itself is already whole).
fn sync_dir(dir: &Path) {
    let d = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    if let Ok(f) = std::fs::File::open(d) {
        let _ = f.sync_all();
    }
}
