//! Vectors of a unit whose input is a bare request (`In = ()`, one `req`-like bit):
//! the input space is one word, so the vectors are `count` requests in a row and the
//! expected words are the kernel's outputs in order from the unit's reset state (the
//! state carries from one transaction to the next, as in hardware).

use super::vector_set::{fields, pack_hex, time_batch_walks, RtlConfig, VectorSet, VerilogParams};
use rtl_model::{Counters, Unit};

/// `count` requests from reset state `state`.
pub(super) fn request_stream<U: Unit<In = ()>>(
    u: &U,
    mut state: U::State,
    config: RtlConfig,
    params: VerilogParams,
    count: usize,
) -> VectorSet {
    let mut ctr = Counters::default();
    let requests = vec![(); count];
    let model_batch_secs = time_batch_walks(u, &[(state.clone(), &requests[..])]);
    let in_f = fields(&u.in_signals(&()));
    let word = pack_hex(&u.in_signals(&()));
    let mut out_f = Vec::new();
    let mut expected = Vec::with_capacity(count);
    for _ in 0..count {
        let os = u.out_signals(&u.kernel(&mut state, &(), &mut ctr));
        if out_f.is_empty() {
            out_f = fields(&os);
        }
        expected.push(pack_hex(&os));
    }
    let t = u.timing();
    VectorSet {
        unit: u.name(),
        config,
        latency: t.latency,
        ii: t.ii,
        params,
        in_fields: in_f,
        out_fields: out_f,
        exhaustive: false,
        stateless: false,
        model_batch_secs,
        stimulus: vec![word; count],
        expected,
        gates_model: u.cost().gates_nand2(),
        roms: Vec::new(),
        rams: Vec::new(),
        variant: None,
    }
}
