//! modulate_chain's vectors. The Verilog (rtl_model/verilog/units/modulate_chain.v)
//! implements the PerStage rounding with the Exact modulate; the Fused (Mesa binary32)
//! chain and the alternate modulate modes are not built.

use super::vector_set::{collect, RtlConfig, VectorSet};
use rtl_model::units::modulate::ModulateMode;
use rtl_model::units::modulate_chain::{ChainRounding, ModulateChain, ModulateChainIn};

pub(super) fn modulate_chain_vectors(
    config: RtlConfig,
    count: usize,
    seed: u64,
) -> Result<VectorSet, String> {
    let u = match config {
        // 8 bits, three operands (primary colour × texture 0 × texture 1).
        RtlConfig::Default => ModulateChain::geforce(),
        // 4 bits, four operands: 16 input bits, exhaustive.
        RtlConfig::Narrow => ModulateChain::new(4, ModulateMode::Exact, ChainRounding::PerStage)
            .and_then(|c| c.with_operands(4))
            .map_err(|e| e.to_string())?,
    };
    let make = |v: &[u64]| {
        let mut i = ModulateChainIn::default();
        for (o, &x) in i.ops.iter_mut().zip(v) {
            *o = x as u32;
        }
        i
    };
    let params = vec![
        ("BITS", u.modulate().bits() as u64),
        ("OPERANDS", u.operands() as u64),
    ];
    Ok(collect(
        &u,
        (),
        config,
        ModulateChainIn::default(),
        make,
        params,
        count,
        seed,
    ))
}
