//! glare_combiner against its f64 twin: the combiner is exact (bound 0: integer sum
//! and clamp), exhaustive for one channel at the defaults (2⁸·2¹² = 2²⁰ pairs) and for
//! all narrow widths, property tests at random widths; saturation and memory counters;
//! drivers agree; config errors name the field.

mod common;

use glare_pipeline::reference::glare_combiner::glare_combiner as twin;
use proptest::prelude::*;
use rtl_model::units::glare_combiner::{CombineIn, GlareCombiner, GlareCombinerConfig};
use rtl_model::{Counters, Unit};

fn check(m: &GlareCombiner, fb: [u32; 3], lum: [u32; 3]) {
    let c = m.config();
    let fmax = (1u32 << c.fb_bits) - 1;
    let mut ctr = Counters::default();
    let out = m.kernel(&mut (), &CombineIn { fb, lum }, &mut ctr);
    let want = twin(fb.map(f64::from), lum.map(f64::from), fmax as f64);
    assert_eq!(out.map(f64::from), want, "{c:?} {fb:?} + {lum:?}");
    let sats = (0..3).filter(|&i| fb[i] + lum[i] > fmax).count() as u64;
    assert_eq!(ctr.saturations, sats);
    let bytes = (3 * c.fb_bits as u64).div_ceil(8);
    assert_eq!((ctr.mem_read_bytes, ctr.mem_write_bytes), (bytes, bytes));
}

#[test]
fn exhaustive_at_defaults_one_channel_sweep() {
    let m = GlareCombiner::geforce();
    for f in 0..256u32 {
        for l in 0..4096u32 {
            check(&m, [f, 255 - f, f / 2], [l, 4095 - l, l / 3]);
        }
    }
}

#[test]
fn exhaustive_narrow_widths() {
    for fb_bits in 1..=6 {
        for lum_bits in 1..=6 {
            let m = GlareCombinerConfig { fb_bits, lum_bits }.build().unwrap();
            for f in 0..(1u32 << fb_bits) {
                for l in 0..(1u32 << lum_bits) {
                    check(&m, [f, f, 0], [l, 0, l]);
                }
            }
        }
    }
}

/// The defaults' timing and cost (`-- --nocapture` prints them), asserted to be what
/// docs/units.md quotes.
#[test]
fn defaults_cost() {
    let m = GlareCombiner::geforce();
    let (t, c) = (m.timing(), m.cost());
    println!(
        "glare_combiner defaults: latency {} II {} gates {:.0} NAND2, RAM bits {}",
        t.latency,
        t.ii,
        c.gates_nand2(),
        c.ram_bits
    );
    let doc = common::docs::section("units.md", "## glare_combiner");
    let at = "docs/units.md, section glare_combiner,";
    common::docs::assert_quotes(
        &doc,
        &format!("Latency **{}**, II **{}**", t.latency, t.ii),
        at,
    );
    common::docs::assert_quotes(
        &doc,
        &format!("**{} NAND2**", common::docs::grouped(c.gates_nand2())),
        at,
    );
    common::docs::assert_quotes(&doc, &format!("RAM {}.", c.ram_bits), at);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn exact_at_random_widths(fb_bits in 1u32..=16, lum_bits in 1u32..=16, fb in any::<[u32; 3]>(), lum in any::<[u32; 3]>()) {
        let m = GlareCombinerConfig { fb_bits, lum_bits }.build().unwrap();
        let fb = fb.map(|x| x & ((1 << fb_bits) - 1));
        let lum = lum.map(|x| x & ((1 << lum_bits) - 1));
        check(&m, fb, lum);
        // Wire masking: junk above the widths is ignored.
        let mut c = Counters::default();
        let junk = CombineIn { fb: fb.map(|x| x | (u32::MAX << fb_bits)), lum: lum.map(|x| x | (u32::MAX << lum_bits)) };
        prop_assert_eq!(m.kernel(&mut (), &junk, &mut c), m.kernel(&mut (), &CombineIn { fb, lum }, &mut c));
    }

    #[test]
    fn tick_and_span_drivers_agree(fb_bits in 1u32..=16, lum_bits in 1u32..=16, px in prop::collection::vec((any::<[u32; 3]>(), any::<[u32; 3]>()), 0..40)) {
        let m = GlareCombinerConfig { fb_bits, lum_bits }.build().unwrap();
        let inputs: Vec<CombineIn> = px.into_iter().map(|(fb, lum)| CombineIn { fb, lum }).collect();
        common::assert_drivers_agree(&m, (), &inputs);
    }

    #[test]
    fn random_configs_errors_name_the_field(fb_bits in 0u32..40, lum_bits in 0u32..40) {
        match (GlareCombinerConfig { fb_bits, lum_bits }).build() {
            Ok(_) => prop_assert!((1..=16).contains(&fb_bits) && (1..=16).contains(&lum_bits)),
            Err(e) => {
                let want = if !(1..=16).contains(&fb_bits) { "glare_combiner.fb_bits" } else { "glare_combiner.lum_bits" };
                prop_assert_eq!(e.field(), want);
            }
        }
    }
}
