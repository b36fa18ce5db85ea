//! Every output path of a command checked before the first pass: `render`'s PNGs,
//! and the directories of `sweep`, `attribute`, `optimize`, `reproduce`, `tables` and
//! `envmap-dump`. Each path is checked for its kind (a PNG file name, a directory that
//! is not a file), for a writable place (the nearest existing directory takes a new
//! file), and against the others (two outputs at one path would overwrite each
//! other). Errors name the argument (`out`, `reference`, `dir`) and the path; nothing
//! is written before a refusal but the probe file the writability check creates and
//! removes at once.

use std::path::{Component, Path, PathBuf};

/// What is written at an output path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// A PNG file (its name must end in `.png`).
    Png,
    /// A directory the command fills (created if missing).
    Dir,
    /// A file of any other kind (a CSV, a VCD): not a directory.
    File,
}

/// One output: the argument that names it, its path, and what is written there.
#[derive(Clone, Copy, Debug)]
pub struct Output<'a> {
    pub arg: &'a str,
    pub path: &'a Path,
    pub kind: OutputKind,
}

impl<'a> Output<'a> {
    pub fn png(arg: &'a str, path: &'a Path) -> Self {
        Output {
            arg,
            path,
            kind: OutputKind::Png,
        }
    }

    pub fn dir(arg: &'a str, path: &'a Path) -> Self {
        Output {
            arg,
            path,
            kind: OutputKind::Dir,
        }
    }

    pub fn file(arg: &'a str, path: &'a Path) -> Self {
        Output {
            arg,
            path,
            kind: OutputKind::File,
        }
    }
}

/// Check every output of a command before any work: each is of its kind and writable,
/// and no two are the same path. The first problem found is the error, naming the
/// argument (and both arguments for a clash).
pub fn check_outputs(outputs: &[Output]) -> Result<(), String> {
    for o in outputs {
        check_one(o)?;
    }
    for (i, a) in outputs.iter().enumerate() {
        for b in &outputs[i + 1..] {
            if normalised(a.path) == normalised(b.path) {
                return Err(format!(
                    "{} and {}: both are `{}`; one would overwrite the other: give two different paths",
                    a.arg,
                    b.arg,
                    a.path.display()
                ));
            }
        }
    }
    Ok(())
}

/// One output's kind and writability.
fn check_one(o: &Output) -> Result<(), String> {
    let (arg, path) = (o.arg, o.path);
    let shown = path.display();
    if path.as_os_str().is_empty() {
        return Err(format!("{arg}: an empty path"));
    }
    match o.kind {
        OutputKind::Png => {
            if path.is_dir() {
                return Err(format!(
                    "{arg}: `{shown}` is a directory; give a PNG file path (e.g. {shown}/render.png)"
                ));
            }
            let png = path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| e.eq_ignore_ascii_case("png"));
            if !png {
                return Err(format!(
                    "{arg}: `{shown}`: the file name must end in .png (the image written is a PNG)"
                ));
            }
        }
        OutputKind::Dir => {
            if path.exists() && !path.is_dir() {
                return Err(format!(
                    "{arg}: `{shown}` is a file; a directory is written there"
                ));
            }
        }
        OutputKind::File => {
            if path.is_dir() {
                return Err(format!(
                    "{arg}: `{shown}` is a directory; a file is written there"
                ));
            }
        }
    }
    // The nearest existing directory at or above the place written: it must be a
    // directory and take a new file.
    let start = match o.kind {
        OutputKind::Dir => Some(path),
        OutputKind::Png | OutputKind::File => path.parent(),
    };
    let mut dir = start;
    while let Some(d) = dir.filter(|d| !d.as_os_str().is_empty()) {
        if d.exists() {
            if !d.is_dir() {
                return Err(format!(
                    "{arg}: `{shown}`: `{}` is not a directory",
                    d.display()
                ));
            }
            return writable(arg, path, d);
        }
        dir = d.parent();
    }
    // A relative path under a missing directory: the working directory.
    writable(arg, path, Path::new("."))
}

/// Whether `dir` takes a new file: a probe file is created and removed at once.
fn writable(arg: &str, path: &Path, dir: &Path) -> Result<(), String> {
    static SERIAL: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = SERIAL.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let probe = dir.join(format!(
        ".glare-pipeline-probe.{}-{n}.partial",
        std::process::id()
    ));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(format!(
            "{arg}: `{}`: cannot write in `{}`: {e}",
            path.display(),
            dir.display()
        )),
    }
}

/// `path` made absolute and free of `.` and `..` (by its existing prefix's canonical
/// form where it exists, so two spellings of one place compare equal).
fn normalised(path: &Path) -> PathBuf {
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(path)
    };
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    // The longest existing prefix, canonical (symbolic links resolved).
    let mut rest = Vec::new();
    let mut head = out.clone();
    loop {
        if let Ok(c) = head.canonicalize() {
            let mut p = c;
            for r in rest.iter().rev() {
                p.push(r);
            }
            return p;
        }
        match (head.file_name().map(|n| n.to_os_string()), head.parent()) {
            (Some(n), Some(parent)) => {
                rest.push(n);
                head = parent.to_path_buf();
            }
            _ => return out,
        }
    }
}

/// A command's output directory, checked before any work: not a file, and a place
/// that takes new files.
pub fn check_dir_out(arg: &str, dir: &Path) -> Result<(), String> {
    check_outputs(&[Output::dir(arg, dir)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_spellings_of_one_path_clash_naming_both() {
        let d = std::env::temp_dir().join(format!("outputs-test-{}", std::process::id()));
        let a = d.join("x.png");
        let b = d.join("sub/../x.png");
        let e = check_outputs(&[Output::png("out", &a), Output::png("reference", &b)]).unwrap_err();
        assert!(e.contains("out and reference"), "{e}");
        let c = d.join("y.png");
        check_outputs(&[Output::png("out", &a), Output::png("reference", &c)]).unwrap();
        assert!(!d.exists() || std::fs::read_dir(&d).unwrap().next().is_none());
    }

    #[test]
    fn a_file_where_a_directory_goes_and_a_non_png_are_refused() {
        let d = std::env::temp_dir().join(format!("outputs-test-file-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let f = d.join("file");
        std::fs::write(&f, b"x").unwrap();
        assert!(check_outputs(&[Output::dir("out", &f)])
            .unwrap_err()
            .contains("is a file"));
        assert!(check_outputs(&[Output::png("out", &f.join("a.png"))])
            .unwrap_err()
            .contains("not a directory"));
        assert!(check_outputs(&[Output::png("out", &d.join("a.jpg"))])
            .unwrap_err()
            .contains(".png"));
        std::fs::remove_dir_all(&d).unwrap();
    }
}
