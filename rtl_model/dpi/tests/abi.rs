//! The C ABI against the model it wraps: typed kernels, the packed step of the
//! generic testbench, and errors naming the field.

use glare_dpi::abi::*;
use rtl_model::units::modulate::Modulate;
use std::ffi::{CStr, CString};

fn last_error() -> String {
    unsafe { CStr::from_ptr(glare_dpi_last_error()) }
        .to_string_lossy()
        .into_owned()
}

#[test]
fn modulate_matches_the_model_exhaustively() {
    let h = modulate_new(8, 0);
    assert!(!h.is_null());
    let m = Modulate::geforce();
    unsafe {
        assert_eq!((glare_dpi_latency(h), glare_dpi_ii(h)), (2, 1));
        assert_eq!((glare_dpi_in_bits(h), glare_dpi_out_bits(h)), (16, 8));
        for a in 0..256 {
            for b in 0..256 {
                let mut y = u32::MAX;
                assert_eq!(modulate_kernel(h, a, b, &mut y), 0);
                assert_eq!(y, m.apply(a, b), "a={a} b={b}");
            }
        }
        assert_eq!(glare_dpi_transactions(h), 65536);
        // Another unit's kernel on this handle is refused.
        let mut o = 0;
        let n = std::ptr::null_mut();
        assert_eq!(texture_sampler_kernel(h, 0, 0, 0, &mut o, n, n, n), -2);
        assert!(last_error().contains("modulate handle"), "{}", last_error());
        modulate_free(h);
        assert_eq!(modulate_kernel(std::ptr::null_mut(), 1, 1, &mut o), -1);
    }
}

#[test]
fn bad_configs_name_the_field() {
    assert!(modulate_new(0, 0).is_null());
    assert!(
        last_error().starts_with("modulate.bits"),
        "{}",
        last_error()
    );
    assert!(modulate_new(8, 9).is_null());
    assert!(
        last_error().starts_with("modulate.mode"),
        "{}",
        last_error()
    );
    let shape = [0.5; 4];
    let fall = vec![0.5; 257];
    let h = unsafe {
        bloom_flare_modulator_new(
            14,
            7,
            16,
            8,
            16,
            8,
            12,
            4,
            12,
            shape.as_ptr(),
            4,
            fall.as_ptr(),
            257,
        )
    };
    assert!(h.is_null());
    assert!(
        last_error().contains("bloom_flare_modulator.shape"),
        "{}",
        last_error()
    );
    let tex = [0u32; 16];
    let h = unsafe {
        texture_sampler_new(
            4,
            4,
            4,
            1,
            1,
            8,
            16,
            8,
            8,
            0,
            0,
            1,
            0,
            0,
            0,
            4,
            tex.as_ptr(),
            16,
        )
    };
    assert!(h.is_null());
    assert!(
        last_error().starts_with("texture_sampler.dims"),
        "{}",
        last_error()
    );
    let h = unsafe {
        texture_sampler_new(
            2,
            4,
            4,
            1,
            1,
            8,
            16,
            8,
            8,
            0,
            0,
            1,
            7,
            0,
            0,
            4,
            tex.as_ptr(),
            16,
        )
    };
    assert!(h.is_null());
    assert!(
        last_error().starts_with("texture_sampler.address_s"),
        "{}",
        last_error()
    );
    let (u, s) = (
        CString::new("modulate").unwrap(),
        CString::new("bits=8 colour=3").unwrap(),
    );
    assert!(unsafe { glare_dpi_open(u.as_ptr(), s.as_ptr()) }.is_null());
    assert!(
        last_error().starts_with("modulate.colour"),
        "{}",
        last_error()
    );
    let (u, s) = (CString::new("chaos").unwrap(), CString::new("").unwrap());
    assert!(unsafe { glare_dpi_open(u.as_ptr(), s.as_ptr()) }.is_null());
    assert!(last_error().starts_with("unit:"), "{}", last_error());
}

/// xorshift64 for port values.
fn next(s: &mut u64) -> u64 {
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    *s
}

/// The packed word of the generic testbench (first port most significant, 32-bit
/// words least significant first) gives the typed kernel's outputs.
#[test]
fn packed_step_matches_typed_kernels() {
    let spec = CString::new("seed=5").unwrap();
    let unit = CString::new("bloom_flare_modulator").unwrap();
    let mut rng = 0x1234_5678_9abc_def0u64;
    unsafe {
        let g = glare_dpi_open(unit.as_ptr(), spec.as_ptr());
        let t = glare_dpi_open(unit.as_ptr(), spec.as_ptr());
        assert!(!g.is_null() && !t.is_null());
        // 2·16 + 3·16 in, 16 + 3·12 out.
        assert_eq!((glare_dpi_in_bits(g), glare_dpi_out_bits(g)), (80, 52));
        let shape = CString::new("shape").unwrap();
        assert!(glare_dpi_table(g, shape.as_ptr(), 129 * 129 - 1) >= 0);
        assert_eq!(glare_dpi_table(g, shape.as_ptr(), 129 * 129), -1);
        for _ in 0..20_000 {
            let p: Vec<u32> = (0..5).map(|_| (next(&mut rng) & 0xffff) as u32).collect();
            // 80 bits: u in 79:64, v 63:48, gain_r 47:32, gain_g 31:16, gain_b 15:0.
            let w = [p[4] | p[3] << 16, p[2] | p[1] << 16, p[0]];
            let mut o = [0u32; 2];
            assert_eq!(glare_dpi_step(g, w.as_ptr(), o.as_mut_ptr()), 0);
            let (mut d, mut r, mut gg, mut b) = (0, 0, 0, 0);
            assert_eq!(
                bloom_flare_modulator_kernel(
                    t, p[0], p[1], p[2], p[3], p[4], &mut d, &mut r, &mut gg, &mut b
                ),
                0
            );
            let want = (d as u64) << 36 | (r as u64) << 24 | (gg as u64) << 12 | b as u64;
            assert_eq!(o[0] as u64 | (o[1] as u64) << 32, want, "ports {p:?}");
        }
        glare_dpi_free(g);
        glare_dpi_free(t);
    }
}

#[test]
fn texture_sampler_typed_and_opened_agree() {
    // A 4×4 two-channel texture, linear, wrap on s.
    let texels: Vec<u32> = (0..32).map(|i| (i * 37 % 256) as u32).collect();
    let unit = CString::new("texture_sampler").unwrap();
    let spec = CString::new("size_w=4 size_h=4 channels=2 address_s=wrap seed=3").unwrap();
    unsafe {
        let h = texture_sampler_new(
            2,
            4,
            4,
            1,
            2,
            8,
            16,
            8,
            8,
            0,
            0,
            1,
            1,
            0,
            0,
            4,
            texels.as_ptr(),
            32,
        );
        assert!(!h.is_null(), "{}", last_error());
        let o = glare_dpi_open(unit.as_ptr(), spec.as_ptr());
        assert!(!o.is_null(), "{}", last_error());
        assert_eq!(glare_dpi_latency(h), glare_dpi_latency(o));
        let name = CString::new("texels").unwrap();
        let codes: Vec<u32> = (0..32)
            .map(|i| glare_dpi_table(o, name.as_ptr(), i) as u32)
            .collect();
        assert_eq!(glare_dpi_table(h, name.as_ptr(), 5), texels[5] as i64);
        let h2 = texture_sampler_new(
            2,
            4,
            4,
            1,
            2,
            8,
            16,
            8,
            8,
            0,
            0,
            1,
            1,
            0,
            0,
            4,
            codes.as_ptr(),
            32,
        );
        let mut rng = 99u64;
        let n = std::ptr::null_mut();
        for _ in 0..5000 {
            let (s, t) = (
                (next(&mut rng) & 0xff_ffff) as u32,
                (next(&mut rng) & 0xff_ffff) as u32,
            );
            let (mut a, mut b, mut c, mut d) = (0, 0, 0, 7);
            let (mut a2, mut b2) = (0, 0);
            assert_eq!(
                texture_sampler_kernel(h2, s, t, 0, &mut a, &mut b, &mut c, &mut d),
                0
            );
            // 24-bit coordinates: the packed word is {s, t}.
            let w = [(t & 0xff_ffff) | (s << 24), s >> 8];
            let mut out = [0u32; 1];
            assert_eq!(glare_dpi_step(o, w.as_ptr(), out.as_mut_ptr()), 0);
            assert_eq!(out[0], a << 8 | b, "s={s:x} t={t:x}");
            assert_eq!((c, d), (0, 0));
            assert_eq!(
                texture_sampler_kernel(h, s, t, 0, &mut a2, &mut b2, n, n),
                0
            );
        }
        texture_sampler_free(h);
        texture_sampler_free(h2);
        glare_dpi_free(o);
    }
}
