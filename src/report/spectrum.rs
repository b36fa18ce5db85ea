//! Power spectra of real series (rustfft) and log-log slopes, for the 1/f check of
//! `chaos_map`.

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

/// Welch power spectrum: Hann-windowed segments of 2^`seg_log2` samples with 50 %
/// overlap, the mean removed per segment, |FFT|² averaged over segments. Returns
/// (frequency in cycles/step, power) for bins 1 ..= L/2 (DC left out). Empty if the
/// series is shorter than one segment.
pub fn welch_psd(x: &[f64], seg_log2: u32) -> (Vec<f64>, Vec<f64>) {
    let l = 1usize << seg_log2.min(30);
    if x.len() < l || l < 4 {
        return (Vec::new(), Vec::new());
    }
    let fft = FftPlanner::<f64>::new().plan_fft_forward(l);
    let win: Vec<f64> = (0..l)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / l as f64).cos())
        .collect();
    let wsum2: f64 = win.iter().map(|w| w * w).sum();
    let mut acc = vec![0.0; l / 2 + 1];
    let mut segs = 0usize;
    let mut buf = vec![Complex::new(0.0, 0.0); l];
    let mut start = 0;
    while start + l <= x.len() {
        let seg = &x[start..start + l];
        let mean = seg.iter().sum::<f64>() / l as f64;
        for (b, (v, w)) in buf.iter_mut().zip(seg.iter().zip(&win)) {
            *b = Complex::new((v - mean) * w, 0.0);
        }
        fft.process(&mut buf);
        for (a, c) in acc.iter_mut().zip(&buf) {
            *a += c.norm_sqr();
        }
        segs += 1;
        start += l / 2;
    }
    let scale = 1.0 / (segs as f64 * wsum2);
    let freq = (1..=l / 2).map(|j| j as f64 / l as f64).collect();
    let power = acc[1..=l / 2].iter().map(|p| p * scale).collect();
    (freq, power)
}

/// Least-squares slope of log10 power against log10 frequency over [f_lo, f_hi],
/// after averaging the power in `bins_per_decade` log-spaced bins (so the many
/// high-frequency points do not dominate). Returns (slope, bins used); `None` with
/// fewer than 3 non-empty bins.
pub fn loglog_slope(
    freq: &[f64],
    power: &[f64],
    f_lo: f64,
    f_hi: f64,
    bins_per_decade: u32,
) -> Option<(f64, usize)> {
    if !(f_lo > 0.0 && f_hi > f_lo) || bins_per_decade == 0 {
        return None;
    }
    let nb = ((f_hi / f_lo).log10() * bins_per_decade as f64).ceil() as usize;
    let mut sum_p = vec![0.0; nb];
    let mut sum_lf = vec![0.0; nb];
    let mut cnt = vec![0usize; nb];
    for (&f, &p) in freq.iter().zip(power) {
        if f < f_lo || f > f_hi || p <= 0.0 || !p.is_finite() {
            continue;
        }
        let b = (((f / f_lo).log10() * bins_per_decade as f64) as usize).min(nb - 1);
        sum_p[b] += p;
        sum_lf[b] += f.log10();
        cnt[b] += 1;
    }
    let pts: Vec<(f64, f64)> = (0..nb)
        .filter(|&b| cnt[b] > 0)
        .map(|b| {
            (
                sum_lf[b] / cnt[b] as f64,
                (sum_p[b] / cnt[b] as f64).log10(),
            )
        })
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    if sxx <= 0.0 {
        return None;
    }
    Some((sxy / sxx, pts.len()))
}
