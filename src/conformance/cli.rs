//! The `conformance` command: `extract` and `run` (module notes in `conformance`).
//!
//! The doc comments of the argument structs are the command's `--help` text, where
//! `<model>`, `<suite>` and the like are literal placeholders a user reads, not HTML.
#![allow(rustdoc::invalid_html_tags)]

use super::case::{Chip, Suite};
use super::run::{chip_name, run_suite, SuiteReport};
use super::store::{extract, table_path};
use super::suites;
use crate::report::table::text_table;
use clap::Subcommand;
use std::path::{Path, PathBuf};

#[derive(Subcommand, Debug)]
pub enum ConformanceCommand {
    /// Read a checkout of the hardware captures
    /// (github.com/abaire/nxdk_pgraph_tests_golden_results) and write each suite's
    /// compact expected values (the captures' pixels inside every compared region,
    /// run-length encoded, with provenance) to DIR/<suite>.txt.
    Extract {
        /// The checkout (or its results/ folder).
        #[arg(long, value_name = "DIR")]
        golden: PathBuf,
        /// Only this suite (Combiner, Blend_tests, Texture_shadow_comparator, Specular).
        #[arg(long)]
        suite: Option<String>,
        /// Where the tables go (the program reads them from the repository's
        /// tables/conformance when it is built).
        #[arg(long, value_name = "DIR", default_value = "tables/conformance")]
        dir: PathBuf,
    },
    /// Predict every region of every hardware test through the model's units and
    /// compare with the hardware: per suite, images, pixels compared, exact, off by
    /// one level, worse, the worst region and the mismatch classes (features with
    /// pixels not exact). Against the committed values, or against the full captures
    /// of a checkout (then DIR/<suite>/<image>.diff.png shows hardware, model and
    /// difference for every image with a pixel off).
    Run {
        /// A checkout of the captures to compare against instead of the committed values.
        #[arg(long, value_name = "DIR")]
        golden: Option<PathBuf>,
        /// Only this suite.
        #[arg(long)]
        suite: Option<String>,
        /// The units' modes: nv2a (the captures' chip) or geforce2 (the project's defaults);
        /// the same chip presets a scene's `chip` field selects.
        #[arg(long, default_value = "nv2a")]
        chip: String,
        /// Where difference images go (with --golden).
        #[arg(long, value_name = "DIR", default_value = "out/conformance")]
        out: PathBuf,
        /// JSON (one object per suite) instead of tables.
        #[arg(long)]
        json: bool,
        /// With --golden: a difference image for every image, not only those with a
        /// pixel off.
        #[arg(long, requires = "golden")]
        all_images: bool,
        /// Only the case of this image (a file name of the suite, e.g. CombinerOps.png);
        /// needs --suite.
        #[arg(long, value_name = "IMAGE", requires = "suite")]
        case: Option<String>,
        /// Also rewrite the figures block of this page (docs/conformance.md, between
        /// its `conformance:begin` and `conformance:end` markers) from this run.
        #[arg(long, value_name = "PATH")]
        doc: Option<PathBuf>,
    },
}

impl ConformanceCommand {
    pub fn label(&self) -> String {
        match self {
            ConformanceCommand::Extract { suite, .. } => with_suite("conformance extract", suite),
            ConformanceCommand::Run { suite, .. } => with_suite("conformance run", suite),
        }
    }
}

fn with_suite(cmd: &str, suite: &Option<String>) -> String {
    match suite {
        Some(s) => format!("{cmd} --suite {s}"),
        None => cmd.to_string(),
    }
}

/// The suites a `--suite` names (all without it); an unknown name is refused with the
/// known ones.
fn chosen(suite: Option<&str>) -> Result<Vec<&'static Suite>, String> {
    let all = suites();
    match suite {
        None => Ok(all.to_vec()),
        Some(name) => all
            .iter()
            .find(|s| s.name.eq_ignore_ascii_case(name))
            .map(|s| vec![*s])
            .ok_or_else(|| {
                let known: Vec<&str> = all.iter().map(|s| s.name).collect();
                format!(
                    "--suite: unknown suite '{name}' (known: {})",
                    known.join(", ")
                )
            }),
    }
}

/// The chip preset `--chip` names (case-insensitive), as a scene's `chip` field does.
fn parse_chip(s: &str) -> Result<Chip, String> {
    Chip::parse("--chip", &s.to_ascii_lowercase()).map_err(|e| e.to_string())
}

fn check_golden(dir: &Path) -> Result<(), String> {
    if !dir.is_dir() {
        return Err(format!(
            "--golden: {} is not a directory (a checkout of github.com/abaire/nxdk_pgraph_tests_golden_results)",
            dir.display()
        ));
    }
    Ok(())
}

pub fn conformance_cli(cmd: ConformanceCommand) -> Result<(), String> {
    match cmd {
        ConformanceCommand::Extract { golden, suite, dir } => {
            let chosen = chosen(suite.as_deref())?;
            check_golden(&golden)?;
            std::fs::create_dir_all(&dir).map_err(|e| format!("--dir: {}: {e}", dir.display()))?;
            // Every table is read before any is written: a missing capture loses nothing.
            let mut texts = Vec::new();
            for s in &chosen {
                let cases = (s.cases)(Chip::Nv2a);
                texts.push((s, cases.len(), extract(s, &cases, &golden)?));
            }
            for (s, n, text) in texts {
                let path = table_path(&dir, s.name);
                crate::report::atomic::write_bytes(&path, text.as_bytes())?;
                println!(
                    "wrote {} ({n} images, {} bytes)",
                    path.display(),
                    text.len()
                );
            }
            Ok(())
        }
        ConformanceCommand::Run {
            golden,
            suite,
            chip,
            out,
            json,
            all_images,
            case,
            doc,
        } => {
            let chosen = chosen(suite.as_deref())?;
            let chip = parse_chip(&chip)?;
            if doc.is_some() && case.is_some() {
                return Err("--doc: the figures are of whole suites; drop --case".into());
            }
            if let Some(d) = &doc {
                doc_block_bounds(&read_doc(d)?)
                    .map_err(|e| format!("--doc: {}: {e}", d.display()))?;
            }
            if let Some(g) = &golden {
                check_golden(g)?;
                crate::report::outputs::check_dir_out("--out", &out)?;
            }
            let mut reports = Vec::new();
            for s in chosen {
                reports.push(run_suite(
                    s,
                    chip,
                    golden.as_deref(),
                    golden.as_ref().map(|_| out.as_path()),
                    all_images,
                    case.as_deref(),
                )?);
            }
            if let Some(d) = &doc {
                let text = read_doc(d)?;
                let (a, b) =
                    doc_block_bounds(&text).map_err(|e| format!("--doc: {}: {e}", d.display()))?;
                let new = format!("{}{}{}", &text[..a], doc_block(&reports), &text[b..]);
                crate::report::atomic::write_bytes(d, new.as_bytes())
                    .map_err(|e| format!("--doc: {e}"))?;
                eprintln!("rewrote the figures of {}", d.display());
            }
            if json {
                let text = serde_json::to_string_pretty(&reports).map_err(|e| e.to_string())?;
                println!("{text}");
            } else {
                print!("{}", report_text(&reports, chip));
            }
            Ok(())
        }
    }
}

fn share(n: u64, d: u64) -> String {
    if d == 0 {
        "n/a".into()
    } else {
        format!("{:.2} %", 100.0 * n as f64 / d as f64)
    }
}

/// The per-suite table, then each suite's mismatch classes and worst region.
pub fn report_text(reports: &[SuiteReport], chip: Chip) -> String {
    let header = [
        "suite",
        "images",
        "regions",
        "pixels",
        "exact",
        "off by 1",
        "worse",
        "exact share",
        "max |Δ| (levels)",
    ];
    let rows: Vec<Vec<String>> = reports
        .iter()
        .map(|r| {
            let t = &r.tally;
            if r.images == 0 {
                let mut row = vec![r.suite.clone(), "0".into()];
                row.resize(header.len(), "n/a".into());
                return row;
            }
            vec![
                r.suite.clone(),
                r.images.to_string(),
                t.regions.to_string(),
                t.compared.to_string(),
                t.exact.to_string(),
                t.off1.to_string(),
                t.worse.to_string(),
                share(t.exact, t.compared),
                if t.compared == 0 {
                    "n/a".into()
                } else {
                    t.max_levels.to_string()
                },
            ]
        })
        .collect();
    let against = reports
        .first()
        .map(|r| r.against.as_str())
        .unwrap_or("committed");
    let mut s = format!(
        "Model ({} modes) against NV2A captures ({}):\n",
        chip_name(chip),
        if against == "captures" {
            "the checkout's PNGs"
        } else {
            "the committed expected values"
        }
    );
    s += &text_table(&header, &rows);
    for r in reports {
        s += &suite_details(r);
    }
    s
}

/// One suite's lines under the table: its mismatch classes, halves, worst region and
/// difference images (or that it is exact, or has no cases).
fn suite_details(r: &SuiteReport) -> String {
    let mut s = String::new();
    if r.images == 0 {
        s += &format!("\n{}: no cases described yet.\n", r.suite);
        return s;
    }
    if r.mismatch_classes.is_empty() {
        s += &format!("\n{}: every compared pixel exact.\n", r.suite);
        return s;
    }
    s += &format!(
        "\n{} mismatch classes (feature: pixels off by 1 / worse of compared, max |Δ|):\n",
        r.suite
    );
    for f in &r.mismatch_classes {
        let t = &f.tally;
        s += &format!(
            "  {}: {} / {} of {} (max {} levels)\n",
            f.feature, t.off1, t.worse, t.compared, t.max_levels
        );
    }
    let half = |t: &super::run::Tally| {
        format!(
            "{} of {} exact ({})",
            t.exact,
            t.compared,
            share(t.exact, t.compared)
        )
    };
    s += &format!(
        "  calibration half (even file names): {}; validation half (odd): {}\n",
        half(&r.calibration_half),
        half(&r.validation_half)
    );
    if let Some(w) = &r.worst {
        s += &format!(
            "  worst region: {} {} — {} pixels off, max {} levels (model {}, hardware {})\n",
            w.image, w.region, w.off_pixels, w.max_levels, w.model, w.hardware
        );
    }
    if !r.difference_images.is_empty() {
        s += &format!(
            "  {} difference images under {}\n",
            r.difference_images.len(),
            r.difference_images[0]
                .rsplit_once('/')
                .map(|x| x.0)
                .unwrap_or("")
        );
    }
    s
}

const DOC_BEGIN: &str = "<!-- conformance:begin (written by `conformance run --doc`) -->\n";
const DOC_END: &str = "<!-- conformance:end -->";

fn read_doc(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("--doc: {}: {e}", path.display()))
}

/// The byte range between the page's markers (after the begin line, before the end).
pub fn doc_block_bounds(text: &str) -> Result<(usize, usize), String> {
    let a = text
        .find(DOC_BEGIN)
        .map(|i| i + DOC_BEGIN.len())
        .ok_or("no `<!-- conformance:begin … -->` line")?;
    let b = text[a..]
        .find(DOC_END)
        .map(|i| a + i)
        .ok_or("no `<!-- conformance:end -->` line")?;
    Ok((a, b))
}

/// The figures block of docs/conformance.md: the per-suite table, both halves, and
/// every mismatch class.
pub fn doc_block(reports: &[SuiteReport]) -> String {
    let mut s = String::from(
        "| suite | images | regions | pixels | exact | off by 1 | worse | exact share | calibration half exact | validation half exact |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let half = |t: &super::run::Tally| format!("{} of {}", t.exact, t.compared);
    for r in reports {
        let t = &r.tally;
        if r.images == 0 {
            s += &format!(
                "| {} | 0 | n/a | n/a | n/a | n/a | n/a | n/a | n/a | n/a |\n",
                r.suite
            );
            continue;
        }
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.suite,
            r.images,
            t.regions,
            t.compared,
            t.exact,
            t.off1,
            t.worse,
            share(t.exact, t.compared),
            half(&r.calibration_half),
            half(&r.validation_half)
        );
    }
    s += "\nMismatch classes (features with pixels not exact):\n\n";
    let mut any = false;
    for r in reports {
        for f in &r.mismatch_classes {
            any = true;
            let t = &f.tally;
            s += &format!(
                "- {} / {}: {} off by 1 and {} worse of {} pixels in {} regions (max {} level{})\n",
                r.suite,
                f.feature,
                t.off1,
                t.worse,
                t.compared,
                t.regions,
                t.max_levels,
                if t.max_levels == 1 { "" } else { "s" }
            );
        }
    }
    if !any {
        s += "- none\n";
    }
    s
}
