//! The sampled mode's passes by kind ([`crate::chip::work::PassSample`]): of each
//! kind's passes some are recorded and clocked, and the others' clocks are estimated
//! from them in proportion to their roofline time (a ratio estimator over the kind's
//! passes), their timing scaled from the recorded pass of their kind before them.

use crate::chip::clock::{scale_timing, NamedPassTiming};
use crate::chip::{PassKind, PassStats};
use std::collections::BTreeMap;

/// A kind of pass (a stratum): the same pass kind, light and textures per fragment,
/// or a pass without statistics alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stratum {
    Kind {
        kind: PassKind,
        light: usize,
        textures: u32,
    },
    Alone(usize),
}

impl Stratum {
    pub fn of(s: &PassStats) -> Self {
        Stratum::Kind {
            kind: s.kind,
            light: s.light,
            textures: s.textures_per_fragment,
        }
    }
}

/// One kind's passes as the clock saw them.
#[derive(Default)]
struct Kind {
    /// The recorded passes: (clocked cycles, proxy, variance of the cycles from their
    /// own sampling in cycles²).
    recorded: Vec<(f64, f64, f64)>,
    /// The frame index of the last recorded pass.
    last: Option<usize>,
    /// The unrecorded passes: (frame index, proxy, frame index of the recorded pass
    /// before it, whose timing it is scaled from).
    scaled: Vec<(usize, f64, usize)>,
}

/// What one kind's estimate gives: the clocks per unit of proxy R, and the variance of
/// the kind's total cycles R·X in cycles².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KindEstimate {
    pub clocks_per_proxy: f64,
    pub variance: f64,
}

/// The ratio estimate over one kind: recorded passes `(cycles c_i, proxy x_i, their
/// own variance v_i)` and the unrecorded passes' proxies `unrecorded`.
///
/// R = Σc_i / Σx_i over the n recorded passes; the kind's N = n + u passes total
/// R·X, X the proxy over all of them. Its variance is the ratio estimator's,
/// N²(1 − n/N)/n · Σ(c_i − R·x_i)²/(n − 1) (systematic sampling read as simple random
/// sampling), plus the recorded passes' own variances scaled up to the kind,
/// (X / Σx_i) Σv_i (the two-stage estimator's second term: the spread between the
/// recorded passes already holds their own sampling noise once). With unrecorded
/// passes and fewer than two recorded ones the spread is unknown: the unrecorded part
/// is given a relative error of 1.
pub fn kind_estimate(recorded: &[(f64, f64, f64)], unrecorded: &[f64]) -> KindEstimate {
    let n = recorded.len() as f64;
    let c_sum: f64 = recorded.iter().map(|r| r.0).sum();
    let x_rec: f64 = recorded.iter().map(|r| r.1).sum();
    let x_unrec: f64 = unrecorded.iter().sum();
    let r = if x_rec > 0.0 { c_sum / x_rec } else { 0.0 };
    let x_all = x_rec + x_unrec;
    let carried = if x_rec > 0.0 {
        x_all / x_rec * recorded.iter().map(|r| r.2).sum::<f64>()
    } else {
        0.0
    };
    let spread = if unrecorded.is_empty() {
        0.0
    } else if recorded.len() < 2 {
        (r * x_unrec).powi(2)
    } else {
        let big_n = n + unrecorded.len() as f64;
        let s2 = recorded
            .iter()
            .map(|&(c, x, _)| (c - r * x).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        big_n * big_n * (1.0 - n / big_n) / n * s2
    };
    KindEstimate {
        clocks_per_proxy: r,
        variance: carried + spread,
    }
}

/// The frame's passes by kind, as the clock takes them in.
#[derive(Default)]
pub struct Strata {
    kinds: BTreeMap<Stratum, Kind>,
}

impl Strata {
    /// Frame pass `index` was recorded and clocked: `cycles`, its `proxy` (its
    /// roofline seconds) and the relative standard error of its cycles.
    pub fn recorded(&mut self, kind: Stratum, index: usize, cycles: u64, proxy: f64, rse: f64) {
        let k = self.kinds.entry(kind).or_default();
        let c = cycles as f64;
        k.recorded.push((c, proxy, (rse * c).powi(2)));
        k.last = Some(index);
    }

    /// Frame pass `index` was not recorded: it is scaled from the recorded pass of its
    /// kind before it at [`Strata::finish`]. `Err` when its kind has none (the
    /// recorder records each kind's first pass, so this is an internal error).
    pub fn unrecorded(&mut self, kind: Stratum, index: usize, proxy: f64) -> Result<(), String> {
        let k = self.kinds.entry(kind).or_default();
        let Some(from) = k.last else {
            return Err(format!(
                "internal: pass {index} was not recorded and no pass of its kind was"
            ));
        };
        k.scaled.push((index, proxy, from));
        Ok(())
    }

    /// Give every unrecorded pass its estimated cycles R·x and the timing of the pass
    /// it is scaled from, stretched to them (stage clocks in proportion, counts and
    /// bytes by the ratio of the proxies, the same FIFO high water). Returns the
    /// variance of the frame's cycles in cycles² (every kind's, summed: the kinds are
    /// sampled independently).
    pub fn finish(self, passes: &mut [NamedPassTiming]) -> f64 {
        let mut variance = 0.0;
        for k in self.kinds.values() {
            let proxies: Vec<f64> = k.scaled.iter().map(|s| s.1).collect();
            let est = kind_estimate(&k.recorded, &proxies);
            variance += est.variance;
            for &(index, proxy, from) in &k.scaled {
                let template = &passes[from];
                let cycles = (est.clocks_per_proxy * proxy).round() as u64;
                let f = if template.roofline_seconds > 0.0 {
                    proxy / template.roofline_seconds
                } else {
                    1.0
                };
                let mut t = scale_timing(template.timing.clone(), cycles, f);
                t.timeline.stretch(cycles);
                t.window = None;
                passes[index].timing = t;
                passes[index].scaled_from = Some(from);
            }
        }
        variance
    }
}
