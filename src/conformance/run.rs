//! `conformance run`: every region's prediction against the hardware's pixels, tallied
//! per suite and per feature (the mismatch classes), with difference images when the
//! full captures are at hand.

use super::case::{Case, Chip, Region, Suite};
use super::store::{self, capture_path, Capture, ExpectedRegion};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Pixels of one class of regions, by how far the model is from the hardware
/// (largest channel difference, 8-bit levels).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Tally {
    pub regions: u64,
    pub compared: u64,
    pub exact: u64,
    pub off1: u64,
    pub worse: u64,
    /// Largest channel difference seen, levels.
    pub max_levels: u32,
}

impl Tally {
    fn add_pixel(&mut self, d: u32) {
        self.compared += 1;
        match d {
            0 => self.exact += 1,
            1 => self.off1 += 1,
            _ => self.worse += 1,
        }
        self.max_levels = self.max_levels.max(d);
    }

    fn merge(&mut self, o: &Tally) {
        self.regions += o.regions;
        self.compared += o.compared;
        self.exact += o.exact;
        self.off1 += o.off1;
        self.worse += o.worse;
        self.max_levels = self.max_levels.max(o.max_levels);
    }
}

/// One feature's tally (a mismatch class when it has pixels off).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct FeatureTally {
    pub feature: String,
    #[serde(flatten)]
    pub tally: Tally,
}

/// The region furthest from the hardware.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Worst {
    pub image: String,
    pub region: String,
    /// Pixels of the region not exact.
    pub off_pixels: u64,
    pub max_levels: u32,
    /// The model's colour and the hardware's most common colour in the region, RRGGBB.
    pub model: String,
    pub hardware: String,
}

/// A suite's result.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct SuiteReport {
    pub suite: String,
    pub chip: String,
    /// `committed` (tables/conformance) or `captures` (a checkout's PNGs).
    pub against: String,
    pub images: u64,
    #[serde(flatten)]
    pub tally: Tally,
    /// Features with pixels not exact, largest count of worse then off-by-one first.
    pub mismatch_classes: Vec<FeatureTally>,
    /// Every feature, in name order.
    pub features: Vec<FeatureTally>,
    pub worst: Option<Worst>,
    /// The images at even positions of the suite's file names sorted bytewise: the half
    /// any undocumented width or rounding is chosen on.
    pub calibration_half: Tally,
    /// The images at odd positions: the half that checks the choice.
    pub validation_half: Tally,
    /// Difference images written (with a checkout), paths.
    pub difference_images: Vec<String>,
}

fn hex(c: [u8; 3]) -> String {
    format!("{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

fn most_common(px: &[[u8; 3]]) -> [u8; 3] {
    let mut m: BTreeMap<[u8; 3], usize> = BTreeMap::new();
    for p in px {
        *m.entry(*p).or_default() += 1;
    }
    m.into_iter()
        .max_by_key(|(_, n)| *n)
        .map(|(c, _)| c)
        .unwrap_or([0; 3])
}

fn channel_diff(a: [u8; 3], b: [u8; 3]) -> u32 {
    (0..3)
        .map(|k| a[k].abs_diff(b[k]) as u32)
        .max()
        .unwrap_or(0)
}

/// Every region's pixels of one case, row-major, in the case's region order.
/// (Borrowed from the committed table, owned when read from a capture.)
type RegionPixels<'a> = Vec<std::borrow::Cow<'a, [[u8; 3]]>>;

/// Where the hardware pixels of a case come from.
enum Source<'a> {
    Committed(&'a BTreeMap<String, Vec<ExpectedRegion>>),
    Captures(&'a Path),
}

/// The hardware's pixels for every region of `case` (same order), or an error naming
/// the image and region the table lacks or holds with another rectangle.
fn hardware_pixels<'a>(
    suite: &Suite,
    case: &Case,
    source: &Source<'a>,
) -> Result<(RegionPixels<'a>, Option<Capture>), String> {
    match source {
        Source::Committed(images) => {
            let regions = images.get(&case.image).ok_or_else(|| {
                format!(
                    "{}: {} is not in tables/conformance/{}.txt (rerun `conformance extract`)",
                    suite.name, case.image, suite.name
                )
            })?;
            let mut out = Vec::with_capacity(case.regions.len());
            for r in &case.regions {
                let e = regions.iter().find(|e| e.name == r.name).ok_or_else(|| {
                    format!(
                        "{}: {} region {} is not in the committed table (rerun `conformance extract`)",
                        suite.name, case.image, r.name
                    )
                })?;
                if e.rect != r.rect {
                    return Err(format!(
                        "{}: {} region {}: the committed table has another rectangle (rerun `conformance extract`)",
                        suite.name, case.image, r.name
                    ));
                }
                out.push(std::borrow::Cow::Borrowed(e.pixels.as_slice()));
            }
            Ok((out, None))
        }
        Source::Captures(dir) => {
            let cap = Capture::load(&capture_path(dir, suite.name, &case.image))?;
            let mut out = Vec::with_capacity(case.regions.len());
            for r in &case.regions {
                out.push(std::borrow::Cow::Owned(
                    cap.region(r.rect, &format!("{}/{}", case.image, r.name))?,
                ));
            }
            Ok((out, Some(cap)))
        }
    }
}

/// One region's pixels against its prediction.
fn region_tally(r: &Region, hardware: &[[u8; 3]]) -> Tally {
    let mut t = Tally {
        regions: 1,
        ..Tally::default()
    };
    for (i, h) in hardware.iter().enumerate() {
        t.add_pixel(channel_diff(r.predicted.at(i), *h));
    }
    t
}

/// Replaces `worst` by region `r` of `image` when `r` is further from the hardware
/// (largest difference, then most pixels off).
fn keep_worst(worst: &mut Option<Worst>, image: &str, r: &Region, hardware: &[[u8; 3]], t: &Tally) {
    let off = t.off1 + t.worse;
    let further = match worst {
        None => off > 0,
        Some(w) => (t.max_levels, off) > (w.max_levels, w.off_pixels),
    };
    if further {
        *worst = Some(Worst {
            image: image.to_string(),
            region: r.name.clone(),
            off_pixels: off,
            max_levels: t.max_levels,
            model: hex(r.predicted.at(0)),
            hardware: hex(most_common(hardware)),
        });
    }
}

/// Runs `suite` in `chip`'s modes against the committed values, or against the
/// captures in `golden` (then difference images of every image with a pixel off, or
/// of every image with `all_images`, go to `diff_dir`, if given). With `only_case`, only
/// the case of that image (file name, `.png` optional); an unknown name is refused.
pub fn run_suite(
    suite: &Suite,
    chip: Chip,
    golden: Option<&Path>,
    diff_dir: Option<&Path>,
    all_images: bool,
    only_case: Option<&str>,
) -> Result<SuiteReport, String> {
    let mut cases = (suite.cases)(chip);
    // The halves are positions among all of the suite's images, with or without --case.
    let mut names: Vec<String> = cases.iter().map(|c| c.image.clone()).collect();
    names.sort_unstable();
    if let Some(name) = only_case {
        let want = format!("{}.png", name.trim_end_matches(".png"));
        cases.retain(|c| c.image == want);
        if cases.is_empty() {
            return Err(format!(
                "--case: {name} is not an image of suite {}",
                suite.name
            ));
        }
    }
    let committed;
    let source = match golden {
        Some(dir) => Source::Captures(dir),
        None => {
            committed = store::load(suite.name)?;
            Source::Committed(&committed.images)
        }
    };
    let mut total = Tally::default();
    let mut features: BTreeMap<String, Tally> = BTreeMap::new();
    let mut worst: Option<Worst> = None;
    let mut diffs = Vec::new();
    let mut halves = [Tally::default(), Tally::default()];
    for case in &cases {
        let half = names.binary_search(&case.image).unwrap_or(0) % 2;
        let (hw, capture) = hardware_pixels(suite, case, &source)?;
        let mut case_off = false;
        for (r, px) in case.regions.iter().zip(&hw) {
            let t = region_tally(r, px);
            case_off |= t.off1 + t.worse > 0;
            keep_worst(&mut worst, &case.image, r, px, &t);
            features.entry(r.feature.clone()).or_default().merge(&t);
            halves[half].merge(&t);
            total.merge(&t);
        }
        if let (Some(cap), Some(dir), true) = (&capture, diff_dir, case_off || all_images) {
            let path = dir
                .join(suite.name)
                .join(format!("{}.diff.png", case.image.trim_end_matches(".png")));
            write_difference(cap, &case.regions, &path)?;
            diffs.push(path.display().to_string());
        }
    }
    let features: Vec<FeatureTally> = features
        .into_iter()
        .map(|(feature, tally)| FeatureTally { feature, tally })
        .collect();
    let mut mismatch_classes: Vec<FeatureTally> = features
        .iter()
        .filter(|f| f.tally.off1 + f.tally.worse > 0)
        .cloned()
        .collect();
    mismatch_classes.sort_by(|a, b| {
        (b.tally.worse, b.tally.off1)
            .cmp(&(a.tally.worse, a.tally.off1))
            .then(a.feature.cmp(&b.feature))
    });
    Ok(SuiteReport {
        suite: suite.name.to_string(),
        chip: chip_name(chip).to_string(),
        against: if golden.is_some() {
            "captures"
        } else {
            "committed"
        }
        .to_string(),
        images: cases.len() as u64,
        tally: total,
        mismatch_classes,
        features,
        worst,
        calibration_half: halves[0].clone(),
        validation_half: halves[1].clone(),
        difference_images: diffs,
    })
}

/// The chip's name as `--chip` takes it.
pub fn chip_name(chip: Chip) -> &'static str {
    chip.name()
}

/// Hardware | model | difference, side by side (each 640 × 480 for the captures). The
/// model panel is the capture with every region painted with its prediction; the
/// difference panel shows |Δ| × 32 (largest channel) inside the regions, red where
/// worse than one level, and the capture dimmed to a quarter elsewhere.
pub fn write_difference(cap: &Capture, regions: &[Region], path: &Path) -> Result<(), String> {
    let (w, h) = (cap.width, cap.height);
    let mut img = image::RgbImage::new(3 * w, h);
    let mut model = cap.rgb.clone();
    let mut diff: Vec<u8> = cap.rgb.iter().map(|v| v / 4).collect();
    for r in regions {
        for y in 0..r.rect.h {
            for x in 0..r.rect.w {
                let (px, py) = (r.rect.x + x, r.rect.y + y);
                if px >= w || py >= h {
                    continue;
                }
                let i = 3 * (py as usize * w as usize + px as usize);
                let m = r.predicted.at((y * r.rect.w + x) as usize);
                let hw = cap.pixel(px, py);
                model[i..i + 3].copy_from_slice(&m);
                let d = channel_diff(m, hw);
                let v = (d * 32).min(255) as u8;
                let c = if d > 1 {
                    [255, v / 2, v / 2]
                } else {
                    [v, v, v]
                };
                diff[i..i + 3].copy_from_slice(&c);
            }
        }
    }
    for y in 0..h {
        for x in 0..w {
            let i = 3 * (y as usize * w as usize + x as usize);
            let at = |buf: &[u8]| image::Rgb([buf[i], buf[i + 1], buf[i + 2]]);
            img.put_pixel(x, y, at(&cap.rgb));
            img.put_pixel(w + x, y, at(&model));
            img.put_pixel(2 * w + x, y, at(&diff));
        }
    }
    // Through the one atomic writer (the temporary file keeps the `.png` the encoder is
    // picked by; the parent directory is made there).
    crate::report::atomic::write_atomically(path, |tmp| {
        img.save(tmp)
            .map_err(|e| format!("{}: {e}", path.display()))
    })
}
