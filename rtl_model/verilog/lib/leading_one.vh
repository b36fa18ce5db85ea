// Leading-one search, unrolled (gaussian_noise, chaos_map, reflection_vector): for
// K = 64 .. 1, POS |= K where V has a one at POS | K or above (V >> (POS | K) != 0), so
// POS ends as the leading one's position (0 when V = 0). POS must start at 0 and hold
// BITS <= 7 bits; a step with K >= 2^BITS is constant-false. V is not shifted: a mux
// per step on V's bits would cost Yosys more than the priority loop (pinned script,
// the search alone: 32 bits 76 cells, the loop 79, shifting V 81; 38 bits 90, 98, 108).
// Unrolled because Icarus pays per statement executed and a loop variable is a load.
`ifndef LEADING_ONE_VH
`define LEADING_ONE_VH
`define LEAD_ONE_STEP(POS, V, BITS, K) \
    if ((K) < (1 << (BITS)) && (V >> (POS | (K))) != 0) POS = POS | (K);
`define LEAD_ONE(POS, V, BITS) \
    `LEAD_ONE_STEP(POS, V, BITS, 64) \
    `LEAD_ONE_STEP(POS, V, BITS, 32) \
    `LEAD_ONE_STEP(POS, V, BITS, 16) \
    `LEAD_ONE_STEP(POS, V, BITS, 8) \
    `LEAD_ONE_STEP(POS, V, BITS, 4) \
    `LEAD_ONE_STEP(POS, V, BITS, 2) \
    `LEAD_ONE_STEP(POS, V, BITS, 1)
`endif
