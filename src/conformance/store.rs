//! The compact expected values: per region, the capture's pixels run-length encoded,
//! one text file per suite in `tables/conformance/` with its provenance.
//!
//! ```text
//! # captures: github.com/abaire/nxdk_pgraph_tests_golden_results commit … (CC0) results/Combiner/
//! image CombinerOps.png
//! bias/rgb 204 150 24 56 00007f*1344
//! ```
//!
//! A region line is `NAME X Y W H RUN…`; a run is `RRGGBB` (one pixel) or `RRGGBB*N`,
//! row-major over the region. A flat patch is one run.

use super::case::{Case, Rect, Suite};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The captures' repository and the commit the expected values were read from.
pub const CAPTURES_REPO: &str = "github.com/abaire/nxdk_pgraph_tests_golden_results";
pub const CAPTURES_COMMIT: &str = "902343e26b3b91252214d21276fd2038b0032039";
/// The test programs' repository and the commit the cases were read from.
pub const TESTS_REPO: &str = "github.com/abaire/nxdk_pgraph_tests";
pub const TESTS_COMMIT: &str = "16c2782712d92136903d804576ceb091305bbd46";

/// One region's hardware pixels.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExpectedRegion {
    pub name: String,
    pub rect: Rect,
    /// Row-major, w · h entries.
    pub pixels: Vec<[u8; 3]>,
}

/// A suite's expected values: image file name → its regions.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Expected {
    pub images: BTreeMap<String, Vec<ExpectedRegion>>,
}

/// Where `conformance extract` writes a suite's expected values under `dir`
/// (`tables/conformance` in the repository by default).
pub fn table_path(dir: &Path, suite: &str) -> PathBuf {
    dir.join(format!("{suite}.txt"))
}

/// The capture `image` of `suite` in a checkout of the captures' repository (`dir` is
/// the checkout, or its `results/` folder, or the suite's folder itself).
pub fn capture_path(dir: &Path, suite: &str, image: &str) -> PathBuf {
    for cand in [
        dir.join("results").join(suite).join(image),
        dir.join(suite).join(image),
        dir.join(image),
    ] {
        if cand.is_file() {
            return cand;
        }
    }
    dir.join("results").join(suite).join(image)
}

/// An RGB capture, 8 bits per channel.
pub struct Capture {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Capture {
    pub fn load(path: &Path) -> Result<Capture, String> {
        let img = image::open(path)
            .map_err(|e| format!("{}: {e}", path.display()))?
            .to_rgb8();
        Ok(Capture {
            width: img.width(),
            height: img.height(),
            rgb: img.into_raw(),
        })
    }

    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// The pixels of `r`, row-major; an error names the region if it leaves the image.
    pub fn region(&self, r: Rect, name: &str) -> Result<Vec<[u8; 3]>, String> {
        if r.x + r.w > self.width || r.y + r.h > self.height || r.w == 0 || r.h == 0 {
            return Err(format!(
                "region {name} ({} {} {}x{}) is empty or outside the {}x{} capture",
                r.x, r.y, r.w, r.h, self.width, self.height
            ));
        }
        let mut v = Vec::with_capacity(r.pixels());
        for y in r.y..r.y + r.h {
            for x in r.x..r.x + r.w {
                v.push(self.pixel(x, y));
            }
        }
        Ok(v)
    }
}

fn encode_runs(pixels: &[[u8; 3]], out: &mut String) {
    let mut i = 0;
    while i < pixels.len() {
        let p = pixels[i];
        let mut n = 1;
        while i + n < pixels.len() && pixels[i + n] == p {
            n += 1;
        }
        let _ = write!(out, " {:02x}{:02x}{:02x}", p[0], p[1], p[2]);
        if n > 1 {
            let _ = write!(out, "*{n}");
        }
        i += n;
    }
}

fn decode_run(tok: &str) -> Result<([u8; 3], usize), String> {
    let (hex, n) = match tok.split_once('*') {
        Some((h, n)) => (
            h,
            n.parse::<usize>()
                .map_err(|_| format!("bad run count in {tok:?}"))?,
        ),
        None => (tok, 1),
    };
    if hex.len() != 6 {
        return Err(format!("bad colour in run {tok:?}"));
    }
    let byte = |k: usize| {
        u8::from_str_radix(&hex[k..k + 2], 16).map_err(|_| format!("bad colour in run {tok:?}"))
    };
    Ok(([byte(0)?, byte(2)?, byte(4)?], n))
}

/// The expected values of `cases` read from a checkout of the captures, as the text of
/// the suite's table (header with provenance, then one block per image).
pub fn extract(suite: &Suite, cases: &[Case], golden: &Path) -> Result<String, String> {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# Expected values of the `{}` hardware captures (NV2A, original Xbox), written by\n\
         # `glare-pipeline conformance extract`. Captures: {CAPTURES_REPO} commit\n\
         # {CAPTURES_COMMIT} (CC0), files results/{}/<image>. Test programs read for the\n\
         # regions: {TESTS_REPO} commit {TESTS_COMMIT} (MIT), {}.\n\
         # Per region: NAME X Y W H, then the pixels row-major as runs RRGGBB[*N].",
        suite.name, suite.name, suite.source
    );
    for case in cases {
        let path = capture_path(golden, suite.name, &case.image);
        let cap = Capture::load(&path)?;
        let _ = writeln!(out, "image {}", case.image);
        for r in &case.regions {
            let px = cap.region(r.rect, &format!("{}/{}", case.image, r.name))?;
            let _ = write!(
                out,
                "{} {} {} {} {}",
                r.name, r.rect.x, r.rect.y, r.rect.w, r.rect.h
            );
            encode_runs(&px, &mut out);
            out.push('\n');
        }
    }
    Ok(out)
}

/// Parses a suite's table (the text [`extract`] writes).
pub fn parse(text: &str) -> Result<Expected, String> {
    let mut exp = Expected::default();
    let mut current: Option<String> = None;
    for (ln, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let err = |m: String| format!("line {}: {m}", ln + 1);
        if let Some(img) = line.strip_prefix("image ") {
            current = Some(img.trim().to_string());
            exp.images.entry(img.trim().to_string()).or_default();
            continue;
        }
        let img = current
            .clone()
            .ok_or_else(|| err("region before any `image` line".into()))?;
        let mut toks = line.split_whitespace();
        let name = toks.next().unwrap_or_default().to_string();
        let mut num = || -> Result<u32, String> {
            toks.next()
                .and_then(|t| t.parse().ok())
                .ok_or_else(|| err(format!("region {name}: expected X Y W H")))
        };
        let rect = Rect::new(num()?, num()?, num()?, num()?);
        let mut pixels = Vec::with_capacity(rect.pixels());
        for tok in toks {
            let (c, n) = decode_run(tok).map_err(err)?;
            pixels.extend(std::iter::repeat_n(c, n));
        }
        if pixels.len() != rect.pixels() {
            return Err(err(format!(
                "region {name}: {} pixels for a {}x{} rectangle",
                pixels.len(),
                rect.w,
                rect.h
            )));
        }
        exp.images
            .get_mut(&img)
            .expect("inserted above")
            .push(ExpectedRegion { name, rect, pixels });
    }
    Ok(exp)
}

/// The committed table of `suite`, built into the program (so `conformance run` works
/// from any directory).
pub fn committed_text(suite: &str) -> Option<&'static str> {
    Some(match suite {
        "Combiner" => include_str!("../../tables/conformance/Combiner.txt"),
        "Blend_tests" => include_str!("../../tables/conformance/Blend_tests.txt"),
        "Texture_shadow_comparator" => {
            include_str!("../../tables/conformance/Texture_shadow_comparator.txt")
        }
        "Specular" => include_str!("../../tables/conformance/Specular.txt"),
        _ => return None,
    })
}

/// A suite's committed expected values.
pub fn load(suite: &str) -> Result<Expected, String> {
    let text =
        committed_text(suite).ok_or_else(|| format!("no committed table for suite {suite}"))?;
    parse(text).map_err(|e| format!("tables/conformance/{suite}.txt: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_round_trip() {
        let px = vec![[1, 2, 3], [1, 2, 3], [255, 0, 16], [1, 2, 3]];
        let mut s = String::new();
        encode_runs(&px, &mut s);
        assert_eq!(s, " 010203*2 ff0010 010203");
        let text = format!("image a.png\nr 0 0 2 2{s}\n");
        let e = parse(&text).unwrap();
        assert_eq!(e.images["a.png"][0].pixels, px);
        assert!(parse("image a.png\nr 0 0 2 2 010203\n").is_err());
    }
}
