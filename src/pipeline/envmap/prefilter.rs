//! Building the s³ voxel map of the multi-scale environment map (Okumura's thesis, eqs. (8)(9),
//! (13), (14)): the exact prefilter of every voxel, and the thesis' accelerated build
//! (pyramid → geodesic domes → weight table with threshold th).
//!
//! Conventions are those of [`crate::reference::envmap_prefilter`] and
//! [`crate::scene::envmap`] (equirectangular, φ = 0 along −z increasing towards +x,
//! θ from +y, d = (sin θ sin φ, cos θ, −sin θ cos φ); `tests/envmap_build.rs` checks the
//! two modules agree texel by texel). Voxel centres are [`VoxelMap::voxel_t`]. The input
//! is the thesis' 256-level map scaled to [0, 1]: [`env_to_levels`] =
//! `EnvMap::to_level_map(exposure) / 255`, and voxels store round(255·F) (8-bit codes).
//!
//! # Exact build ([`build_exact`])
//!
//! Every voxel t gets F(t) of eqs. (8)(9) with Λ = g(|t|) for the map's own side s
//! (`params.levels()` and `params.weighting()` are kept, `params.s()` is replaced by the
//! map's side), identical to
//! [`prefilter_voxel_exact`](crate::reference::envmap_prefilter::prefilter_voxel_exact)
//! except for the pruning below. It is not a brute-force loop over all W·H texels:
//!
//! * **Pruning.** With m = max ln(t̂·ω) over the samples, a sample whose log lobe
//!   Λ(ln(t̂·ω) − m) is below −60 is dropped. Each dropped term is ≤ ΔΩ_k·e⁻⁶⁰ while the
//!   normaliser is ≥ ΔΩ of the maximum sample, so the dropped share of the weight is
//!   ≤ e⁻⁶⁰ · 4π / ΔΩ_min (SolidAngle weighting; N·e⁻⁶⁰ for Uniform) — at 512 × 256,
//!   ΔΩ_min = 9.2·10⁻⁷ sr (the polar rows), so ≤ 1.2·10⁻¹⁹ of the weight, ≤ 3·10⁻¹⁷
//!   levels: far below one code ([`prune_bound`] computes it).
//! * **Candidate cap.** Only the samples within angle ψ of t̂ are visited, with
//!   cos ψ = e^(−60/Λ)·cos δ, δ the covering radius of the sample set (every direction
//!   has a sample within δ, so m ≥ ln cos δ, and every unpruned sample has
//!   ln(t̂·ω) ≥ m − 60/Λ ≥ ln(e^(−60/Λ) cos δ)). For the equirectangular texels
//!   hav δ = hav(π/2H) + hav(π/W) (haversine bound of the distance to the nearest texel
//!   centre); for a dome of frequency n, δ = atan 2 / n (the icosahedron's edge angle
//!   over n: the sub-triangles' edges are ≤ 1.33/n, their circumradii ≤ 0.77/n). The
//!   assumption is checked at run time: if the visited maximum is below cos δ, the voxel
//!   falls back to every sample. The samples are binned on a (θ, φ) grid
//!   ([`SphereIndex`]); the bins visited are those meeting the cap's bounding box
//!   θ ∈ [θ_t − ψ, θ_t + ψ], |φ − φ_t| ≤ asin(sin ψ / sin θ_t), with full rows when the
//!   cap holds a pole and every sample when ψ ≥ π/2 (Λ small).
//! * Voxels with |t| > 1 (the cube's corners, up to √3 (1 − 1/s)) are computed like the
//!   others: g is defined and finite there (Λ up to ≈ 1.36·10⁵ at s = 128); the lobe is
//!   then narrower than a texel and F is essentially the nearest texels' value.
//! * t = 0 never occurs at a voxel centre; the per-voxel kernel still follows the
//!   prefilter module's definition (the ΔΩ-weighted whole-sphere mean).
//!
//! Voxels are independent; z-slices run in parallel with rayon, each voxel's sum in a
//! fixed order, so the result is the same bytes for any thread count.
//!
//! # Accelerated build ([`build_accelerated`])
//!
//! The thesis' §3.4: a 4-level pyramid ([`build_pyramid`], 512×256 → 64×32), each level
//! resampled (bilinear) onto a geodesic dome of frequency 72 / 36 / 18 / 9 (51 842 /
//! 12 962 / 3 242 / 812 vertices), and for each voxel the weight table of eq. (14) over
//! one dome: entries ω with (t̂·ω)^Λ > th, weights the full-hemisphere normalised w of
//! (9) (the normaliser with the same −60 pruning as above), *not* renormalised over the
//! kept entries — as [`select_weight_entries`] and [`WeightEntries::apply`]. A voxel
//! with no entry gets F = 0 (the thesis' Fig. 19 "voxels not computed") in the study
//! build [`build_accelerated_both`]; [`build_accelerated`] refuses such a map.
//!
//! **Side.** The domes above are the thesis' for its s = 128. Λ = g(|t|) grows like
//! ln I·(|t|s)²/2, so the cap where (t̂·ω)^Λ > th shrinks like 1/(|t|s): with the n = 72
//! dome, a 256³ map left 2 481 840 voxels (15 %) with no vertex in their cap. The
//! frequencies are therefore [`dome_frequencies`]`(s)`: the thesis' up to s = 128,
//! ⌈n·s/128⌉ above, which keeps each voxel's cap-to-spacing ratio that of the s = 128
//! map (0 empty voxels at th = 0.001 at 64, 128 and 256: docs/envmap.md, "Map side").
//! A finished map with an empty voxel is an error ([`check_coverage`]).
//!
//! **Level choice.** ψ_½ = acos(2^(−1/Λ)) is the lobe's half-weight angle (cos^Λ ψ_½ = ½).
//! Level k's dome has vertex spacing ≈ a_k = atan 2 / n_k (0.0154 rad at n = 72, 0.123
//! at n = 9). A voxel uses the coarsest level with a_k ≤ [`LEVEL_FRACTION`]·ψ_½ (½: at
//! least ~4 vertices across the lobe's half-weight diameter, so the dome quadrature of
//! the lobe is well sampled, and the pyramid's 2^k box blur, about one vertex spacing
//! wide, is narrower than the lobe), else level 0. At s = 128 only the voxels with
//! Λ ≲ 370 (|t| ≲ 0.09, ≈ 0.04 % of them) leave level 0: rough voxels are few, the
//! table and the error are dominated by level 0, so this rule matters little for
//! Table 3 (it matters for time only near the centre, where the n = 72 dome's
//! hemisphere would be visited).
//!
//! The thesis states no rule: §3.4.1 says only that the rough voxels near the centre are
//! *stored* at a low resolution, so computing them from the full-resolution map is
//! wasted work, and they are computed from the reduced images. Read literally, a voxel
//! is computed at the resolution it is stored at: [`DomePick::VoxelSpacing`] takes the
//! coarsest dome with a_k ≤ ψ_voxel, the angle between neighbouring voxels of the shell
//! at |t| (eq. (12)); by eq. (13) that is where the lobe has fallen to 1/I,
//! ψ_voxel = acos(I^(−1/Λ)) ≈ √8·ψ_½ at I = 256, so that reading picks a dome about 5.7×
//! coarser than the model's [`DomePick::HalfWeight`] (`environment.dome_pick`;
//! docs/assumptions.md, envmap.dome_pick, has its effect on the maps and the renders).
//!
//! **Renormalised or not.** `reproduce envmap-table3` measures both (s = 128, pattern,
//! mean |Δ| at th = 0.001 / 0.01 / 0.1): not renormalised 0.26 / 2.85 / 30.7 levels,
//! renormalised 0.14 / 0.48 / 12.8; the thesis 0.1–0.3 / 3.8 / 38. The thesis' growth,
//! linear in th, is the lost-weight shape: the non-renormalised reading fits it.
//!
//! The table is built and applied voxel by voxel (never stored): [`TableStats`] reports
//! the entries it would hold and its size at [`BYTES_PER_ENTRY`] bytes per entry (a
//! 4-byte vertex index and a 4-byte f32 weight).

// `!(x > 0.0)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::voxmap::VoxelMap;
use crate::reference::envmap_prefilter::{
    build_pyramid, direction_to_angles, texel_direction, texel_solid_angle, Dome, Equirect,
    PrefilterParams, Weighting, THESIS_DOME_FREQUENCIES, THESIS_PYRAMID_LEVELS,
};
#[allow(unused_imports)] // doc links
use crate::reference::envmap_prefilter::{select_weight_entries, WeightEntries};
use crate::scene::envmap::EnvMap;
use rayon::prelude::*;
use rtl_model::error::ConfigError;
use std::f64::consts::PI;
use std::time::Instant;

/// Log-weight margin of the pruning: samples below the maximum lobe by more than
/// e^PRUNE_LOG are dropped.
pub const PRUNE_LOG: f64 = 60.0;
/// Level choice: the coarsest dome whose spacing is ≤ this × the lobe's half-weight angle.
pub const LEVEL_FRACTION: f64 = 0.5;

/// Which pyramid level's dome a voxel's lobe is filtered on in the accelerated build
/// (module notes, "Level choice"; the scene's `environment.dome_pick`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DomePick {
    /// The model's: the coarsest dome whose vertex spacing is ≤ [`LEVEL_FRACTION`] × the
    /// lobe's half-weight angle acos(2^(−1/Λ)) (the lobe well sampled).
    #[default]
    HalfWeight,
    /// The thesis' §3.4.1 read literally: the coarsest dome whose spacing is ≤ the
    /// voxel spacing ψ_voxel of eq. (12) at the voxel's |t|, i.e. acos(I^(−1/Λ)) by
    /// eq. (13) (a voxel computed at the resolution it is stored at).
    VoxelSpacing,
}
/// Bytes per weight-table entry: a 4-byte vertex index and a 4-byte f32 weight.
pub const BYTES_PER_ENTRY: u64 = 8;
/// Voxel bits of the thesis' map (256 levels).
pub const VOXEL_BITS: u32 = 8;

/// The thesis' 256-level input in [0, 1]: `env.to_level_map(exposure) / 255`.
pub fn env_to_levels(env: &EnvMap, exposure: f64) -> Result<Equirect, ConfigError> {
    let lv = env.to_level_map(exposure)?;
    let texels = lv.texels().iter().map(|t| t.map(|c| c / 255.0)).collect();
    Equirect::new(lv.width(), lv.height(), texels)
}

/// Upper bound of the weight share dropped by the −60 pruning on `map`'s texels
/// (module notes): e⁻⁶⁰·4π/ΔΩ_min (SolidAngle) or W·H·e⁻⁶⁰ (Uniform).
pub fn prune_bound(map: &Equirect, weighting: Weighting) -> f64 {
    let (w, h) = (map.width(), map.height());
    match weighting {
        Weighting::SolidAngle => {
            let min = (0..h)
                .map(|j| texel_solid_angle(j, w, h))
                .fold(f64::INFINITY, f64::min);
            (-PRUNE_LOG).exp() * 4.0 * PI / min
        }
        Weighting::Uniform => (w * h) as f64 * (-PRUNE_LOG).exp(),
    }
}

/// Samples on the sphere binned on a regular (θ, φ) grid, stored in bin order.
#[derive(Clone, Debug)]
pub struct SphereIndex {
    rows: usize,
    cols: usize,
    /// Bin b holds samples start[b] .. start[b + 1].
    start: Vec<u32>,
    dirs: Vec<[f64; 3]>,
    /// ΔΩ (SolidAngle) or 1 (Uniform).
    area: Vec<f64>,
    radiance: Vec<[f64; 3]>,
    /// Covering radius bound δ (rad).
    cover: f64,
}

impl SphereIndex {
    /// Bin the samples (`dirs`, `solid_angles`, `radiance`, equal lengths) on a
    /// `rows` × `cols` grid; `cover` is the covering radius bound of the set.
    fn new(
        rows: usize,
        cols: usize,
        dirs: &[[f64; 3]],
        solid_angles: &[f64],
        radiance: &[[f64; 3]],
        weighting: Weighting,
        cover: f64,
    ) -> Self {
        let rows = rows.max(1);
        let cols = cols.max(1);
        let bin_of = |d: [f64; 3]| {
            let (phi, theta) = direction_to_angles(d);
            let r = ((theta * rows as f64 / PI) as usize).min(rows - 1);
            let c = ((phi * cols as f64 / (2.0 * PI)) as usize).min(cols - 1);
            r * cols + c
        };
        let bins: Vec<usize> = dirs.iter().map(|&d| bin_of(d)).collect();
        let mut count = vec![0u32; rows * cols + 1];
        for &b in &bins {
            count[b + 1] += 1;
        }
        for b in 0..rows * cols {
            count[b + 1] += count[b];
        }
        let start = count.clone();
        let mut fill = count;
        let n = dirs.len();
        let mut order = vec![0usize; n];
        for (k, &b) in bins.iter().enumerate() {
            order[fill[b] as usize] = k;
            fill[b] += 1;
        }
        let area = |k: usize| match weighting {
            Weighting::SolidAngle => solid_angles.get(k).copied().unwrap_or(0.0).max(0.0),
            Weighting::Uniform => 1.0,
        };
        SphereIndex {
            rows,
            cols,
            start,
            dirs: order.iter().map(|&k| dirs[k]).collect(),
            area: order.iter().map(|&k| area(k)).collect(),
            radiance: order.iter().map(|&k| radiance[k]).collect(),
            cover,
        }
    }

    /// Every texel of an equirectangular map, one bin per texel.
    pub fn from_equirect(map: &Equirect, weighting: Weighting) -> Self {
        let (w, h) = (map.width(), map.height());
        let mut dirs = Vec::with_capacity(w * h);
        let mut sa = Vec::with_capacity(w * h);
        for j in 0..h {
            let a = texel_solid_angle(j, w, h);
            for i in 0..w {
                dirs.push(texel_direction(i, j, w, h));
                sa.push(a);
            }
        }
        let hav = |x: f64| (x / 2.0).sin().powi(2);
        let hv = (hav(PI / (2.0 * h as f64)) + hav(PI / w as f64)).min(1.0);
        let cover = 2.0 * hv.sqrt().asin();
        SphereIndex::new(h, w, &dirs, &sa, map.texels(), weighting, cover)
    }

    /// A dome's vertices with `radiance` (one per vertex), bins ≈ the vertex spacing.
    pub fn from_dome(dome: &Dome, radiance: &[[f64; 3]], weighting: Weighting) -> Self {
        let n = dome.frequency().max(1) as usize;
        let cover = 2f64.atan() / n as f64;
        SphereIndex::new(
            2 * n,
            4 * n,
            dome.dirs(),
            dome.solid_angles(),
            radiance,
            weighting,
            cover,
        )
    }

    pub fn len(&self) -> usize {
        self.dirs.len()
    }
    pub fn is_empty(&self) -> bool {
        self.dirs.is_empty()
    }
    /// The covering radius bound δ.
    pub fn cover(&self) -> f64 {
        self.cover
    }

    /// Call `f(k)` for every sample in the bins meeting the cap of angle `psi` around
    /// the unit direction `t_hat` (a superset of the samples within `psi`).
    fn visit(&self, t_hat: [f64; 3], psi: f64, mut f: impl FnMut(usize)) {
        let all = |f: &mut dyn FnMut(usize)| (0..self.dirs.len()).for_each(f);
        if !(psi < 0.5 * PI) {
            return all(&mut f);
        }
        let psi = psi + 1e-9;
        let (phi_t, theta_t) = direction_to_angles(t_hat);
        let rh = self.rows as f64 / PI;
        let r0 = ((theta_t - psi) * rh).floor().max(0.0) as usize;
        let r1 = (((theta_t + psi) * rh).floor().max(0.0) as usize).min(self.rows - 1);
        let pole = theta_t - psi <= 0.0 || theta_t + psi >= PI;
        let ratio = psi.sin() / theta_t.sin();
        let full = pole || !(ratio < 1.0);
        let (c0, c1) = if full {
            (0i64, self.cols as i64 - 1)
        } else {
            let dphi = ratio.asin();
            let cw = self.cols as f64 / (2.0 * PI);
            let c0 = ((phi_t - dphi) * cw).floor() as i64;
            let c1 = ((phi_t + dphi) * cw).floor() as i64;
            if c1 - c0 + 1 >= self.cols as i64 {
                (0, self.cols as i64 - 1)
            } else {
                (c0, c1)
            }
        };
        for r in r0..=r1 {
            let row = r * self.cols;
            for c in c0..=c1 {
                let b = row + c.rem_euclid(self.cols as i64) as usize;
                for k in self.start[b] as usize..self.start[b + 1] as usize {
                    f(k);
                }
            }
        }
    }
}

/// One voxel's result: F, the kept weight share and the table entries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelResult {
    /// Σ w·L over the kept samples (all unpruned ones when no th).
    pub f: [f64; 3],
    /// Σ w over the kept samples (1 without th, up to the pruning).
    pub kept_weight: f64,
    /// Samples kept (table entries with th; unpruned samples without).
    pub entries: u64,
}

/// F(t) over `index` at lobe exponent `lambda` (eqs. (8)(9); module notes), with the
/// −60 pruning; with `th`, only the samples with (t̂·ω)^Λ > th contribute (eq. (14),
/// weights not renormalised; equal to [`select_weight_entries`] + apply for
/// th ≥ e⁻⁶⁰ — below that the pruned samples are not entries). `scratch` is reused storage. Never NaN for finite
/// radiance; t = 0 or non-finite t is the whole-sphere mean, NaN or negative Λ is 0.
pub fn prefilter_voxel_indexed(
    index: &SphereIndex,
    t: [f64; 3],
    lambda: f64,
    th: Option<f64>,
    scratch: &mut Vec<(u32, f64)>,
) -> VoxelResult {
    let lambda = if lambda.is_nan() {
        0.0
    } else {
        lambda.max(0.0)
    };
    let ln_th = th.map(|x| if x > 0.0 { x.ln() } else { f64::NEG_INFINITY });
    let len = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
    if !(len > 0.0 && len.is_finite()) {
        // The centre: every sample, lobe 1 (0⁰), kept iff 1 > th.
        let keep = ln_th.is_none_or(|l| 0.0 > l);
        return finish(index, (0..index.len()).map(|k| (k, 1.0, keep)));
    }
    let t_hat = [t[0] / len, t[1] / len, t[2] / len];
    let dot = |d: [f64; 3]| t_hat[0] * d[0] + t_hat[1] * d[1] + t_hat[2] * d[2];
    if lambda == 0.0 {
        // Λ = 0: the hemisphere c ≥ 0, every lobe 1.
        let keep = ln_th.is_none_or(|l| 0.0 > l);
        let hemi = (0..index.len()).filter(|&k| dot(index.dirs[k]) >= 0.0);
        return finish(index, hemi.map(|k| (k, 1.0, keep)));
    }
    let kappa = (-PRUNE_LOG / lambda).exp() * index.cover.cos();
    let psi = kappa.clamp(-1.0, 1.0).acos();
    scratch.clear();
    let mut c_max = 0.0f64;
    index.visit(t_hat, psi, |k| {
        let c = dot(index.dirs[k]);
        if c > 0.0 {
            c_max = c_max.max(c);
            scratch.push((k as u32, c));
        }
    });
    if c_max < index.cover.cos() {
        // The covering assumption failed (never expected): every sample.
        scratch.clear();
        c_max = 0.0;
        for k in 0..index.len() {
            let c = dot(index.dirs[k]);
            if c > 0.0 {
                c_max = c_max.max(c);
                scratch.push((k as u32, c));
            }
        }
        if scratch.is_empty() {
            // No sample with c > 0: the c = 0 samples count 1 (as the prefilter module).
            let keep = ln_th.is_none_or(|l| 0.0 > l);
            let hemi = (0..index.len()).filter(|&k| dot(index.dirs[k]) >= 0.0);
            return finish(index, hemi.map(|k| (k, 1.0, keep)));
        }
    }
    let m = c_max.ln();
    let items = scratch.iter().filter_map(|&(k, c)| {
        let lnc = c.ln();
        let e = if c >= c_max { 0.0 } else { lambda * (lnc - m) };
        if e < -PRUNE_LOG {
            return None;
        }
        let keep = ln_th.is_none_or(|l| if c >= 1.0 { 0.0 > l } else { lambda * lnc > l });
        Some((k as usize, e.exp(), keep))
    });
    finish(index, items)
}

/// Σ over (sample, relative lobe, kept): normaliser over all, F and kept share over
/// the kept ones.
fn finish(index: &SphereIndex, items: impl Iterator<Item = (usize, f64, bool)>) -> VoxelResult {
    let mut z = 0.0;
    let mut acc = [0.0; 3];
    let mut kept = 0.0;
    let mut entries = 0u64;
    for (k, rel, keep) in items {
        let u = index.area[k] * rel;
        z += u;
        if keep {
            entries += 1;
            kept += u;
            let l = index.radiance[k];
            for c in 0..3 {
                acc[c] += u * l[c];
            }
        }
    }
    if z > 0.0 && z.is_finite() {
        let inv = 1.0 / z;
        VoxelResult {
            f: acc.map(|v| v * inv),
            kept_weight: kept * inv,
            entries,
        }
    } else {
        VoxelResult {
            f: [0.0; 3],
            kept_weight: 0.0,
            entries: 0,
        }
    }
}

/// The parameters with s replaced by the map side (Λ = g(|t|) for this resolution).
fn params_for(s: u32, params: &PrefilterParams) -> Result<PrefilterParams, ConfigError> {
    PrefilterParams::new(s as f64, params.levels(), params.weighting())
}

/// Value(s) and stats of one voxel.
type VoxelFn<'a> =
    dyn Fn(u32, u32, u32, &mut Vec<(u32, f64)>) -> ([f64; 3], [f64; 3], [u64; 2]) + Sync + 'a;

/// Run `f(x, y, z, scratch) -> (value, second value, stats)` over every voxel,
/// z-slices in parallel, with a progress bar; values go to `map` (and `second` if
/// given) as codes; returns the summed stats.
fn fill_voxels(
    map: &mut VoxelMap,
    second: Option<&mut VoxelMap>,
    what: &str,
    f: &VoxelFn<'_>,
) -> [u64; 2] {
    let s = map.side();
    let m = map.max_code() as f64;
    let bar = crate::report::progress::progress_bar(s as u64, what);
    let slice = ((s as usize) * (s as usize)).max(1);
    let seconds: Vec<Option<&mut [[u32; 3]]>> = match second {
        Some(sm) => sm.data_mut().chunks_mut(slice).map(Some).collect(),
        None => (0..s).map(|_| None).collect(),
    };
    let stats = map
        .data_mut()
        .par_chunks_mut(slice)
        .zip(seconds.into_par_iter())
        .enumerate()
        .map(|(z, (out, mut out2))| {
            let mut scratch = Vec::new();
            let mut st = [0u64; 2];
            for y in 0..s {
                for x in 0..s {
                    let (v, v2, a) = f(x, y, z as u32, &mut scratch);
                    let i = (y * s + x) as usize;
                    out[i] = v.map(|c| code(c, m));
                    if let Some(o2) = out2.as_deref_mut() {
                        o2[i] = v2.map(|c| code(c, m));
                    }
                    st[0] += a[0];
                    st[1] += a[1];
                }
            }
            bar.inc(1);
            st
        })
        .reduce(|| [0, 0], |a, b| [a[0] + b[0], a[1] + b[1]]);
    bar.finish_and_clear();
    stats
}

/// A value in [0, 1] (clamped, NaN → 0) as a code of full scale `m`.
fn code(v: f64, m: f64) -> u32 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    (v * m).round() as u32
}

/// The exact voxel map (module notes): s³ voxels (s in 1 ..= 512, `envmap.voxels`),
/// 8-bit codes of F ∈ [0, 1] (`env_levels` is the [0, 1] level map).
pub fn build_exact(
    env_levels: &Equirect,
    s: u32,
    params: &PrefilterParams,
) -> Result<VoxelMap, ConfigError> {
    build_exact_bits(env_levels, s, params, VOXEL_BITS)
}

/// [`build_exact`] with `bits`-wide unorm voxels (1 ..= 16, `envmap.voxel_bits`): the
/// entry-width knob. F is rounded to the nearest of 2^bits − 1 steps.
pub fn build_exact_bits(
    env_levels: &Equirect,
    s: u32,
    params: &PrefilterParams,
    bits: u32,
) -> Result<VoxelMap, ConfigError> {
    let mut map = VoxelMap::new(s, bits)?;
    let exact = Exact::new(env_levels, s, params)?;
    let probe = map.clone();
    fill_voxels(&mut map, None, "exact", &|x, y, z, scratch| {
        let r = exact.voxel(probe.voxel_t(x, y, z), scratch);
        (r.f, r.f, [0, 0])
    });
    Ok(map)
}

/// Size and time of an accelerated build's weight table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableStats {
    /// Table entries (Σ over voxels of the kept samples).
    pub entries: u64,
    /// entries × [`BYTES_PER_ENTRY`].
    pub bytes: u64,
    /// Wall time of the whole build (pyramid, domes, table, filter).
    pub build_seconds: f64,
    /// Voxels with no entry (F = 0; the thesis' Fig. 19).
    pub empty_voxels: u64,
}

impl TableStats {
    /// bytes / 10⁶.
    pub fn mbytes(&self) -> f64 {
        self.bytes as f64 / 1e6
    }
}

/// The accelerated pieces for one input map: per pyramid level a dome index.
#[derive(Clone, Debug)]
pub struct DomeLevels {
    levels: Vec<SphereIndex>,
    spacing: Vec<f64>,
}

impl DomeLevels {
    /// The thesis' pyramid (4 levels; W and H must halve 3 times) on the domes of
    /// frequency 72, 36, 18, 9 (the s = 128 domes of [`DomeLevels::for_side`]).
    pub fn thesis(env_levels: &Equirect, weighting: Weighting) -> Result<Self, ConfigError> {
        Self::with_frequencies(env_levels, weighting, THESIS_DOME_FREQUENCIES)
    }

    /// The pyramid on the domes of [`dome_frequencies`]`(s)`: the thesis' four for
    /// s ≤ 128, scaled by s / 128 above (module notes, "Side").
    pub fn for_side(
        env_levels: &Equirect,
        s: u32,
        weighting: Weighting,
    ) -> Result<Self, ConfigError> {
        Self::with_frequencies(env_levels, weighting, dome_frequencies(s))
    }

    fn with_frequencies(
        env_levels: &Equirect,
        weighting: Weighting,
        frequencies: [u32; 4],
    ) -> Result<Self, ConfigError> {
        let pyr = build_pyramid(env_levels, THESIS_PYRAMID_LEVELS)?;
        let mut levels = Vec::with_capacity(pyr.len());
        let mut spacing = Vec::with_capacity(pyr.len());
        for (lvl, n) in pyr.iter().zip(frequencies) {
            let dome = Dome::new(n)?;
            let radiance = dome.resample(lvl);
            levels.push(SphereIndex::from_dome(&dome, &radiance, weighting));
            spacing.push(2f64.atan() / n as f64);
        }
        Ok(DomeLevels { levels, spacing })
    }

    /// The level used at lobe exponent Λ (module notes): the coarsest k with
    /// spacing_k ≤ LEVEL_FRACTION · acos(2^(−1/Λ)), else 0.
    pub fn level_for(&self, lambda: f64) -> usize {
        self.level_within(LEVEL_FRACTION * half_weight_angle(lambda))
    }

    /// The level `pick` chooses at lobe exponent Λ with `levels` intensity levels I
    /// (eq. (13)'s I; only [`DomePick::VoxelSpacing`] reads it).
    pub fn level_picked(&self, pick: DomePick, lambda: f64, levels: f64) -> usize {
        match pick {
            DomePick::HalfWeight => self.level_for(lambda),
            DomePick::VoxelSpacing => self.level_within(lobe_angle(lambda, levels.ln())),
        }
    }

    /// The coarsest level whose dome spacing is ≤ `angle` (radians), else 0.
    pub fn level_within(&self, angle: f64) -> usize {
        (0..self.spacing.len())
            .rev()
            .find(|&k| self.spacing[k] <= angle)
            .unwrap_or(0)
    }

    pub fn index(&self, level: usize) -> Option<&SphereIndex> {
        self.levels.get(level)
    }
}

/// The dome frequencies of the four pyramid levels at voxel side `s`: the thesis'
/// 72 / 36 / 18 / 9 (its s = 128) for s ≤ 128, × s / 128 above (144 / 72 / 36 / 18 at
/// s = 256). The narrowest lobe's width scales as 1 / s (Λ ≈ ln I·(|t|s)²/2), so the
/// finest dome's spacing must too for the lobe-to-spacing ratio of every |t| — and so
/// the coverage measured at s = 128 — to hold at every side (module notes, "Side").
pub fn dome_frequencies(s: u32) -> [u32; 4] {
    let s = u64::from(s.max(REFERENCE_SIDE));
    let r = u64::from(REFERENCE_SIDE);
    // ⌈n·s / 128⌉: never coarser than the ratio asks (sides need not be powers of two).
    THESIS_DOME_FREQUENCIES.map(|n| (u64::from(n) * s).div_ceil(r) as u32)
}

/// The side the thesis' dome frequencies were chosen for (its 128³ map).
pub const REFERENCE_SIDE: u32 = 128;

/// ψ_½ with cos^Λ ψ_½ = ½ (π/2 for Λ ≤ 0 or NaN).
pub fn half_weight_angle(lambda: f64) -> f64 {
    lobe_angle(lambda, std::f64::consts::LN_2)
}

/// ψ with cos^Λ ψ = e^(−`ln_ratio`), i.e. acos(exp(−ln_ratio/Λ)) (π/2 for Λ ≤ 0 or
/// NaN): ln 2 gives the half-weight angle, ln I the voxel spacing of eq. (13).
pub fn lobe_angle(lambda: f64, ln_ratio: f64) -> f64 {
    if !(lambda > 0.0) {
        return 0.5 * PI;
    }
    // exp(−r/Λ); acos near 1 via 2·asin(√((1 − c)/2)).
    let one_minus = -(-ln_ratio / lambda).exp_m1();
    2.0 * (0.5 * one_minus).sqrt().min(1.0).asin()
}

fn check_th(th: f64) -> Result<f64, ConfigError> {
    let th = rtl_model::error::check_finite("envmap.th", th)?;
    if !(0.0..1.0).contains(&th) {
        return Err(ConfigError::out_of_range("envmap.th", th, 0.0, 1.0));
    }
    Ok(th)
}

/// The accelerated voxel map at threshold th ∈ [0, 1) (`envmap.th`) and its table's
/// stats (module notes). Weights not renormalised (as the thesis' eq. (14) reading).
pub fn build_accelerated(
    env_levels: &Equirect,
    s: u32,
    params: &PrefilterParams,
    th: f64,
) -> Result<(VoxelMap, TableStats), ConfigError> {
    build_accelerated_picked(env_levels, s, params, th, DomePick::default())
}

/// [`build_accelerated`] with the dome of each voxel chosen by `pick`.
pub fn build_accelerated_picked(
    env_levels: &Equirect,
    s: u32,
    params: &PrefilterParams,
    th: f64,
    pick: DomePick,
) -> Result<(VoxelMap, TableStats), ConfigError> {
    let (m, _, st) = build_both(env_levels, s, params, th, VOXEL_BITS, pick)?;
    check_coverage(&st, s, th)?;
    Ok((m, st))
}

/// A finished map has no empty voxel: one would be a black texel that no lobe put
/// there. The error names the threshold `envmap.th` and the finest dome frequency
/// (`envmap_prefilter.dome_frequency`, [`dome_frequencies`] of the side), the two
/// parameters that decide whether a voxel's lobe above th holds a dome vertex.
/// The study builds ([`build_accelerated_both`]: Table 3 at large th, the thesis'
/// Fig. 19 "voxels not computed") count empty voxels instead.
pub fn check_coverage(st: &TableStats, s: u32, th: f64) -> Result<(), ConfigError> {
    if st.empty_voxels == 0 {
        return Ok(());
    }
    Err(ConfigError::invalid(
        "envmap.th",
        &format!(
            "{th} leaves {} of the {s}³ voxels with no weight-table entry (no vertex of the \
             finest dome, envmap_prefilter.dome_frequency = {}, has a lobe weight above th): \
             lower th or use the exact prefilter",
            st.empty_voxels,
            dome_frequencies(s)[0]
        ),
    ))
}

/// As [`build_accelerated`], also returning the map with each voxel's kept weights
/// renormalised to 1 (F / kept share; 0 for an empty voxel), for comparison.
pub fn build_accelerated_both(
    env_levels: &Equirect,
    s: u32,
    params: &PrefilterParams,
    th: f64,
) -> Result<(VoxelMap, VoxelMap, TableStats), ConfigError> {
    build_accelerated_both_bits(env_levels, s, params, th, VOXEL_BITS)
}

/// [`build_accelerated_both`] with `bits`-wide unorm voxels (1 ..= 16,
/// `envmap.voxel_bits`).
pub fn build_accelerated_both_bits(
    env_levels: &Equirect,
    s: u32,
    params: &PrefilterParams,
    th: f64,
    bits: u32,
) -> Result<(VoxelMap, VoxelMap, TableStats), ConfigError> {
    build_both(env_levels, s, params, th, bits, DomePick::default())
}

fn build_both(
    env_levels: &Equirect,
    s: u32,
    params: &PrefilterParams,
    th: f64,
    bits: u32,
    pick: DomePick,
) -> Result<(VoxelMap, VoxelMap, TableStats), ConfigError> {
    check_th(th)?;
    let t0 = Instant::now();
    let mut map = VoxelMap::new(s, bits)?;
    let acc = Accelerated::new(env_levels, s, params, th)?.with_dome_pick(pick);
    let probe = map.clone();
    let mut renorm = map.clone();
    let stats = fill_voxels(
        &mut map,
        Some(&mut renorm),
        "accelerated",
        &|x, y, z, scratch| {
            let r = acc.voxel(probe.voxel_t(x, y, z), scratch);
            let rn = if r.kept_weight > 0.0 {
                r.f.map(|c| c / r.kept_weight)
            } else {
                [0.0; 3]
            };
            (r.f, rn, [r.entries, (r.entries == 0) as u64])
        },
    );
    let stats = TableStats {
        entries: stats[0],
        bytes: stats[0] * BYTES_PER_ENTRY,
        build_seconds: t0.elapsed().as_secs_f64(),
        empty_voxels: stats[1],
    };
    Ok((map, renorm, stats))
}

/// The accelerated build's per-voxel filter at one side: the side's Λ = g(|t|), its
/// domes ([`DomeLevels::for_side`]) and th. [`build_accelerated`] runs it on every
/// voxel; [`Accelerated::voxel`] runs it on one (tests check chosen voxels of a map
/// too large to build whole in a test).
#[derive(Clone, Debug)]
pub struct Accelerated {
    params: PrefilterParams,
    domes: DomeLevels,
    th: f64,
    pick: DomePick,
}

impl Accelerated {
    /// th ∈ [0, 1) (`envmap.th`), `params` with s replaced by the side `s`.
    pub fn new(
        env_levels: &Equirect,
        s: u32,
        params: &PrefilterParams,
        th: f64,
    ) -> Result<Self, ConfigError> {
        let th = check_th(th)?;
        let params = params_for(s, params)?;
        let domes = DomeLevels::for_side(env_levels, s, params.weighting())?;
        Ok(Accelerated {
            params,
            domes,
            th,
            pick: DomePick::default(),
        })
    }

    /// The same filter with each voxel's dome chosen by `pick`.
    pub fn with_dome_pick(mut self, pick: DomePick) -> Self {
        self.pick = pick;
        self
    }

    /// The pyramid level (0 = finest) of the voxel at `t`.
    pub fn level(&self, t: [f64; 3]) -> usize {
        self.domes
            .level_picked(self.pick, self.params.lambda(t), self.params.levels())
    }

    /// F of the voxel at `t` (codes not rounded), its kept weight and entries.
    pub fn voxel(&self, t: [f64; 3], scratch: &mut Vec<(u32, f64)>) -> VoxelResult {
        let lambda = self.params.lambda(t);
        let idx =
            &self.domes.levels[self
                .domes
                .level_picked(self.pick, lambda, self.params.levels())];
        prefilter_voxel_indexed(idx, t, lambda, Some(self.th), scratch)
    }
}

/// The exact build's per-voxel filter at one side (as [`build_exact`]).
#[derive(Clone, Debug)]
pub struct Exact {
    params: PrefilterParams,
    index: SphereIndex,
}

impl Exact {
    pub fn new(
        env_levels: &Equirect,
        s: u32,
        params: &PrefilterParams,
    ) -> Result<Self, ConfigError> {
        let params = params_for(s, params)?;
        let index = SphereIndex::from_equirect(env_levels, params.weighting());
        Ok(Exact { params, index })
    }

    /// F of the voxel at `t`.
    pub fn voxel(&self, t: [f64; 3], scratch: &mut Vec<(u32, f64)>) -> VoxelResult {
        prefilter_voxel_indexed(&self.index, t, self.params.lambda(t), None, scratch)
    }
}

/// Per-channel mean |Δ| and variance of Δ (Δ = a − b in codes) over all voxels;
/// `None` if the sides differ.
pub fn voxel_error(a: &VoxelMap, b: &VoxelMap) -> Option<([f64; 3], [f64; 3])> {
    if a.side() != b.side() || a.data().len() != b.data().len() {
        return None;
    }
    let n = a.data().len().max(1) as f64;
    let mut abs = [0.0; 3];
    let mut sum = [0.0; 3];
    let mut sq = [0.0; 3];
    for (p, q) in a.data().iter().zip(b.data()) {
        for c in 0..3 {
            let d = p[c] as f64 - q[c] as f64;
            abs[c] += d.abs();
            sum[c] += d;
            sq[c] += d * d;
        }
    }
    let mean_abs = abs.map(|v| v / n);
    let mut var = [0.0; 3];
    for c in 0..3 {
        let mu = sum[c] / n;
        var[c] = (sq[c] / n - mu * mu).max(0.0);
    }
    Some((mean_abs, var))
}
