//! The C ABI of the golden model: every function here is exported by the library
//! built with feature `dpi` (without it they are plain Rust functions, for tests).
//!
//! Port values are the bits of the Verilog port of the same name, zero-extended
//! (a signed coordinate is passed as its two's-complement wire bits). A handle holds
//! the unit's state from its reset state; calls on one handle must not overlap.
//! Pointers must be valid for the lengths given; output pointers may be NULL.
#![allow(clippy::missing_safety_doc, clippy::too_many_arguments)]

use crate::model::Model;
use rtl_model::units::bloom_flare_modulator::BloomFlareModulatorConfig;
use rtl_model::units::texture_sampler::{
    AddressMode, Filter, FilterRounding, TextureSamplerConfig, WeightRounding,
};
use std::cell::RefCell;
use std::ffi::{c_char, CStr, CString};

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(e: &str) {
    let c = CString::new(e.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|l| *l.borrow_mut() = c);
}

fn handle(r: Result<Model, String>) -> *mut Model {
    match r {
        Ok(m) => Box::into_raw(Box::new(m)),
        Err(e) => {
            set_error(&e);
            std::ptr::null_mut()
        }
    }
}

unsafe fn text<'a>(p: *const c_char, what: &str) -> Result<&'a str, String> {
    if p.is_null() {
        return Err(format!("{what}: NULL"));
    }
    CStr::from_ptr(p)
        .to_str()
        .map_err(|_| format!("{what}: not UTF-8"))
}

unsafe fn slice<'a, T>(p: *const T, len: u64, what: &str) -> Result<&'a [T], String> {
    if p.is_null() {
        return if len == 0 {
            Ok(&[])
        } else {
            Err(format!("{what}: NULL with {len} entries"))
        };
    }
    Ok(std::slice::from_raw_parts(p, len as usize))
}

/// A typed kernel: `unit`'s handle stepped on `ins`, outputs written where non-NULL.
unsafe fn kernel(h: *mut Model, unit: &str, ins: &[u64], outs: &[*mut u32]) -> i32 {
    let Some(m) = h.as_mut() else {
        set_error("handle: NULL");
        return -1;
    };
    if m.name() != unit {
        set_error(&format!(
            "handle: a {} handle passed to {unit}_kernel",
            m.name()
        ));
        return -2;
    }
    let o = m.step(ins);
    for (k, &p) in outs.iter().enumerate() {
        if let Some(p) = p.as_mut() {
            *p = o.get(k).copied().unwrap_or(0) as u32;
        }
    }
    0
}

/// The error of the last call on this thread that failed (a `*_new` or
/// `glare_dpi_open` that returned NULL, a kernel that returned < 0): it names the
/// config field or argument at fault. Valid until the next failing call.
#[cfg_attr(feature = "dpi", no_mangle)]
pub extern "C" fn glare_dpi_last_error() -> *const c_char {
    LAST_ERROR.with(|l| l.borrow().as_ptr())
}

/// A unit by name with a text config: `key=value` pairs separated by blanks, the
/// config fields of the unit's `*_new` (missing ones keep the GeForce default) and
/// `seed` (the unit's tables are drawn from it). NULL on error (glare_dpi_last_error).
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_open(unit: *const c_char, spec: *const c_char) -> *mut Model {
    handle(text(unit, "unit").and_then(|u| Model::open(u, text(spec, "spec")?)))
}

/// Release a handle of any unit (NULL is ignored).
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_free(h: *mut Model) {
    if !h.is_null() {
        drop(Box::from_raw(h));
    }
}

/// Clocks from accepting an input to presenting its output (the model's Timing);
/// 0 for NULL.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_latency(h: *const Model) -> u32 {
    h.as_ref().map_or(0, Model::latency)
}

/// Clocks between accepted inputs (initiation interval); 0 for NULL.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_ii(h: *const Model) -> u32 {
    h.as_ref().map_or(0, Model::ii)
}

/// Bits of the packed input word (the input ports concatenated); 0 for NULL.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_in_bits(h: *const Model) -> u32 {
    h.as_ref().map_or(0, Model::in_bits)
}

/// Bits of the packed output word; 0 for NULL.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_out_bits(h: *const Model) -> u32 {
    h.as_ref().map_or(0, Model::out_bits)
}

/// Transactions stepped on this handle so far; 0 for NULL.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_transactions(h: *const Model) -> u64 {
    h.as_ref().map_or(0, Model::transactions)
}

/// One transaction on the packed input word: the input ports concatenated in the
/// unit's port order, the first in the most significant bits, as 32-bit words least
/// significant first (a SystemVerilog `bit [N-1:0]` argument, svBitVecVal*);
/// in_word holds ceil(in_bits/32) words, out_word ceil(out_bits/32). 0, or -1 (NULL).
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_step(
    h: *mut Model,
    in_word: *const u32,
    out_word: *mut u32,
) -> i32 {
    let Some(m) = h.as_mut() else {
        set_error("handle: NULL");
        return -1;
    };
    if in_word.is_null() || out_word.is_null() {
        set_error("glare_dpi_step: NULL word");
        return -1;
    }
    let ni = m.in_bits().div_ceil(32) as usize;
    let no = m.out_bits().div_ceil(32) as usize;
    let ins = std::slice::from_raw_parts(in_word, ni);
    let outs = std::slice::from_raw_parts_mut(out_word, no);
    m.step_packed(ins, outs);
    0
}

/// Entry `index` of the table the unit reads through the ports named `table`
/// (`shape`, `falloff`, `texels`), as the model holds it (codes); -1 if there is none.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn glare_dpi_table(h: *const Model, table: *const c_char, index: u64) -> i64 {
    let (Some(m), Ok(t)) = (h.as_ref(), text(table, "table")) else {
        return -1;
    };
    m.table(t, index as usize).map_or(-1, |v| v as i64)
}

/// modulate (GL_MODULATE on `bits`-bit unorms, 1 ..= 16); `mode` 0 exact (the
/// GeForce default), 1 shift, 2 plus_one, 3 trunc_div. NULL on error.
#[cfg_attr(feature = "dpi", no_mangle)]
pub extern "C" fn modulate_new(bits: u32, mode: u32) -> *mut Model {
    handle(Model::modulate(bits, mode))
}

/// y = a · b rounded as the mode says. 0, -1 (NULL handle), -2 (another unit's handle).
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn modulate_kernel(h: *mut Model, a: u32, b: u32, y: *mut u32) -> i32 {
    kernel(h, "modulate", &[a as u64, b as u64], &[y])
}

/// Release a modulate handle.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn modulate_free(h: *mut Model) {
    glare_dpi_free(h)
}

/// bloom_flare_modulator, radial correction off (GeForce default: 14, 7, 16, 8, 16,
/// 8, 12, 4, 12). shape: (2^shape_log2+1)² entries in [0, 1], v index major;
/// falloff: 2^falloff_log2+1 entries. NULL on error (the field is named).
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn bloom_flare_modulator_new(
    coord_frac_bits: u32,
    shape_log2: u32,
    shape_bits: u32,
    falloff_log2: u32,
    falloff_bits: u32,
    weight_bits: u32,
    gain_int_bits: u32,
    gain_frac_bits: u32,
    out_bits: u32,
    shape: *const f64,
    shape_len: u64,
    falloff: *const f64,
    falloff_len: u64,
) -> *mut Model {
    let cfg = BloomFlareModulatorConfig {
        coord_frac_bits,
        shape_log2,
        shape_bits,
        falloff_log2,
        falloff_bits,
        weight_bits,
        gain_int_bits,
        gain_frac_bits,
        out_bits,
        ..BloomFlareModulatorConfig::default()
    };
    handle((|| {
        let s = slice(shape, shape_len, "bloom_flare_modulator.shape")?;
        let f = slice(falloff, falloff_len, "bloom_flare_modulator.falloff")?;
        Model::bloom_flare_modulator(cfg, s, f)
    })())
}

/// One pixel: u, v are s2.F wire bits (coord_frac_bits + 2), the gains
/// u(gain_int).(gain_frac); d and lum_* as the ports. 0, -1 or -2 as modulate_kernel.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn bloom_flare_modulator_kernel(
    h: *mut Model,
    u: u32,
    v: u32,
    gain_r: u32,
    gain_g: u32,
    gain_b: u32,
    d: *mut u32,
    lum_r: *mut u32,
    lum_g: *mut u32,
    lum_b: *mut u32,
) -> i32 {
    let ins = [u, v, gain_r, gain_g, gain_b].map(u64::from);
    kernel(h, "bloom_flare_modulator", &ins, &[d, lum_r, lum_g, lum_b])
}

/// Release a bloom_flare_modulator handle.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn bloom_flare_modulator_free(h: *mut Model) {
    glare_dpi_free(h)
}

/// texture_sampler. weight_rounding 0 round, 1 truncate, 2 round_half_even;
/// filter_rounding 0 product_weights, 1 successive_lerps; filter 0 nearest,
/// 1 linear; address_* 0 clamp, 1 wrap. texels: w·h·d·channels codes, texel
/// (x, y, z) channel c at ((z·h + y)·w + x)·channels + c. NULL on error.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn texture_sampler_new(
    dims: u32,
    size_w: u32,
    size_h: u32,
    size_d: u32,
    channels: u32,
    texel_bits: u32,
    coord_int_bits: u32,
    coord_frac_bits: u32,
    weight_bits: u32,
    weight_rounding: u32,
    filter_rounding: u32,
    filter: u32,
    address_s: u32,
    address_t: u32,
    address_r: u32,
    texels_per_clock: u32,
    texels: *const u32,
    texels_len: u64,
) -> *mut Model {
    let pick = |v: u32, n: u32, field: &str| {
        if v < n {
            Ok(v as usize)
        } else {
            Err(format!(
                "texture_sampler.{field}: {v} is out of range (0 ..= {})",
                n - 1
            ))
        }
    };
    handle((|| {
        let am = [AddressMode::Clamp, AddressMode::Wrap];
        let cfg = TextureSamplerConfig {
            dims,
            size: [size_w, size_h, size_d],
            channels,
            texel_bits,
            coord_int_bits,
            coord_frac_bits,
            weight_bits,
            weight_rounding: [
                WeightRounding::Round,
                WeightRounding::Truncate,
                WeightRounding::RoundHalfEven,
            ][pick(weight_rounding, 3, "weight_rounding")?],
            filter_rounding: [
                FilterRounding::ProductWeights,
                FilterRounding::SuccessiveLerps,
            ][pick(filter_rounding, 2, "filter_rounding")?],
            filter: [Filter::Nearest, Filter::Linear][pick(filter, 2, "filter")?],
            address: [
                am[pick(address_s, 2, "address_s")?],
                am[pick(address_t, 2, "address_t")?],
                am[pick(address_r, 2, "address_r")?],
            ],
            texels_per_clock,
        };
        let t = slice(texels, texels_len, "texture_sampler.texels")?;
        Model::texture_sampler(cfg, t)
    })())
}

/// One sample: coordinates as s(coord_int).(coord_frac) wire bits (axes beyond
/// dims ignored); ch0..ch3 the filtered channels (beyond channels: 0).
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn texture_sampler_kernel(
    h: *mut Model,
    coord_s: u32,
    coord_t: u32,
    coord_r: u32,
    ch0: *mut u32,
    ch1: *mut u32,
    ch2: *mut u32,
    ch3: *mut u32,
) -> i32 {
    let ins = [coord_s, coord_t, coord_r].map(u64::from);
    kernel(h, "texture_sampler", &ins, &[ch0, ch1, ch2, ch3])
}

/// Release a texture_sampler handle.
#[cfg_attr(feature = "dpi", no_mangle)]
pub unsafe extern "C" fn texture_sampler_free(h: *mut Model) {
    glare_dpi_free(h)
}
