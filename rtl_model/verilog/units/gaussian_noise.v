// gaussian_noise — the N(0, 1) source of the flare lines, Box–Muller mode
// (rtl_model/src/units/gaussian_noise.rs). Two taus88 generators A and B (reset to the
// model's GaussState::from_seed(SEED): SplitMix64 words, computed here by a constant
// function), one step of each per accepted request; the top B bits are k1, k2; then
// ln / sqrt / sin ROMs (ports, synchronous read) with linear interpolation, and the
// outputs x, y in s(O+1).f. Latency 9, II 1:
//   1-2 request delay (the state steps later; the outputs depend only on the count of
//       requests, so this is the model's sequence two clocks later)
//   3   generator register: state step, k1, k2
//   4   U1 leading-one, mantissa align, phase align -> ln, sin address registers
//   5   ROM data (ln, sin, cos)
//   6   ln interpolate, Y = e*ln2 - L (rounded, >= 0), sin/cos interpolate, quadrant
//   7   sqrt normalise -> sqrt address registers
//   8   ROM data (sqrt)
//   9   sqrt interpolate, r*cos, r*sin, round, saturate, sign -> output registers
// The central-limit mode is not implemented (the vector writer builds Box–Muller).
`include "leading_one.vh"

module gaussian_noise #(
    parameter UNIFORM_BITS  = 32,
    parameter TABLE_LOG2    = 10,
    parameter TABLE_BITS    = 18,
    parameter OUT_FRAC_BITS = 12,
    parameter OUT_INT_BITS  = 3,
    parameter LN2           = 46516319,  // round(ln 2 * 2^(TABLE_BITS+8))
    parameter SEED          = 1,
    // derived (do not set)
    parameter OB            = 1 + OUT_INT_BITS + OUT_FRAC_BITS,
    parameter SQAW          = TABLE_LOG2
) (
    input                       clk,
    input                       rst,
    input                       in_valid,
    input                       req,
    output reg [TABLE_LOG2:0]   ln_addr0,
    output reg [TABLE_LOG2:0]   ln_addr1,
    input      [TABLE_BITS-1:0] ln_data0,
    input      [TABLE_BITS-1:0] ln_data1,
    output reg [SQAW-1:0]       sqrt_addr0,
    output reg [SQAW-1:0]       sqrt_addr1,
    input      [TABLE_BITS+1:0] sqrt_data0,
    input      [TABLE_BITS+1:0] sqrt_data1,
    output reg [TABLE_LOG2:0]   sin_addr0,
    output reg [TABLE_LOG2:0]   sin_addr1,
    output reg [TABLE_LOG2:0]   sin_addr2,
    output reg [TABLE_LOG2:0]   sin_addr3,
    input      [TABLE_BITS:0]   sin_data0,
    input      [TABLE_BITS:0]   sin_data1,
    input      [TABLE_BITS:0]   sin_data2,
    input      [TABLE_BITS:0]   sin_data3,
    output reg                  out_valid,
    output reg [OB-1:0]         x,
    output reg [OB-1:0]         y
);
  localparam B = UNIFORM_BITS;
  localparam T = TABLE_LOG2;
  localparam E = TABLE_BITS;
  localparam D = TABLE_BITS;
  localparam TD = T + D;
  localparam PB = B - 2;
  localparam F = OUT_FRAC_BITS;
  localparam [2*E+5:0] MAXC = (1 << (OUT_INT_BITS + F)) - 1;
  localparam [OB-1:0] SATC = 2 * MAXC + 1;

  // ---- reset state: GaussState::from_seed(SEED) ----
  function [31:0] seed_word;
    input [63:0] seed;
    input integer idx;
    reg [63:0] s, z;
    reg [31:0] r, mn;
    integer j;
    begin
      s = seed;
      r = 0;
      for (j = 0; j <= idx; j = j + 1) begin
        s = s + 64'h9E3779B97F4A7C15;
        z = s;
        z = (z ^ (z >> 30)) * 64'hBF58476D1CE4E5B9;
        z = (z ^ (z >> 27)) * 64'h94D049BB133111EB;
        z = z ^ (z >> 31);
        r = z[31:0];
      end
      mn = (idx % 3 == 0) ? 32'd2 : (idx % 3 == 1) ? 32'd8 : 32'd16;
      seed_word = (r < mn) ? r + mn : r;
    end
  endfunction
  localparam [31:0] SA0 = seed_word(SEED, 0);
  localparam [31:0] SA1 = seed_word(SEED, 1);
  localparam [31:0] SA2 = seed_word(SEED, 2);
  localparam [31:0] SB0 = seed_word(SEED, 3);
  localparam [31:0] SB1 = seed_word(SEED, 4);
  localparam [31:0] SB2 = seed_word(SEED, 5);

  // Written for Icarus's interpreter (docs/rtl.md): one clocked block, every
  // combinational step a blocking temporary evaluated once per clock (no continuous
  // assigns or `always @*` loops, which vvp re-evaluated on every input change), the
  // leading ones binary searches (unrolled), the taus88 step, the interpolators and the
  // output scaling macros (a function call runs as a thread).

  // ---- taus88 (L'Ecuyer 1996): DST = {s2, s1, s0} of S stepped ----
`define GN_TAUS(DST, S) \
    ts0 = S[31:0]; \
    ts1 = S[63:32]; \
    ts2 = S[95:64]; \
    tsb = ((ts0 << 13) ^ ts0) >> 19; \
    ts0 = ((ts0 & 32'hFFFFFFFE) << 12) ^ tsb; \
    tsb = ((ts1 << 2) ^ ts1) >> 25; \
    ts1 = ((ts1 & 32'hFFFFFFF8) << 4) ^ tsb; \
    tsb = ((ts2 << 3) ^ ts2) >> 11; \
    ts2 = ((ts2 & 32'hFFFFFFF0) << 17) ^ tsb; \
    DST = {ts2, ts1, ts0};

  // Linear interpolation DST = a + round((b - a) * t / 2^D), entries A, B_ up to E + 2
  // bits. The result lies between the two entries, so it is cut to the entries' width W:
  // left as the adder's carries, the bits above W are always 0 but only a proof through
  // the multiplier shows it, and ABC's SAT sweeping (&fraig) stalled on that proof
  // (docs/units.md, gaussian_noise).
`define GN_INTERP(DST, A, B_, T_, W) \
    ia = A; \
    ib = B_; \
    df = $signed({1'b0, ib}) - $signed({1'b0, ia}); \
    pr = df * $signed({1'b0, T_}) + IRND; \
    iw = ia + pr[E+D+2:D]; \
    DST = iw[W-1:0];

  // Leading-one searches: LEAD_ONE (lib/leading_one.vh).

  // Stage 9: DST <= round(S |c| 2^(k+f-2E)), saturated, signed (0 for a zero Y).
  // Saturation is decided on the product: with s = osh - 1,
  // ((p >> s) + 1) >> 1 > MAXC  <=>  p >= (2 MAXC + 1) << s  (and never for s > 2E + 5,
  // where p >> s <= 1). Decided on the shifter's output instead, the same function left
  // ABC's SAT sweeping stalled (docs/units.md, gaussian_noise).
`define GN_SCALE(DST, C) \
    if (z8) DST <= 0; \
    else begin \
      ca = C[E+3] ? -C : C; \
      spr = s9 * ca; \
      mg = ((spr >> (osh - 1)) + 1) >> 1; \
      lim = {{2 * E + 5{1'b0}}, SATC} << (osh - 1); \
      if (osh - 1 <= 2 * E + 5 && {{OB{1'b0}}, spr} >= lim) mg = MAXC; \
      DST <= C[E+3] ? -mg[OB-1:0] : mg[OB-1:0]; \
    end

  localparam UB = $clog2(B + 1);  // leading one of U1 (B + 1 bits)
  localparam YB = $clog2(E + 7);  // leading one of {Y, 0} (E + 7 bits)
  localparam signed [E+D+3:0] IRND = {{E + 4{1'b0}}, 1'b1, {D - 1{1'b0}}};
  localparam [E+7:0] LN2C = LN2;

  reg [1:0] rq;
  reg [95:0] sa, sb;
  reg [B-1:0] k1, k2;
  reg v3, v4, v5, v6, v7, v8;
  reg [D-1:0] t_ln4, t_s4, t_c4, t_ln5, t_s5, t_c5;
  reg [5:0] ee4, ee5;
  reg [1:0] q4, q5;
  reg [E+5:0] yv;
  reg [E+6:0] y2;
  reg signed [E+3:0] cos6, sin6;
  reg signed [7:0] k7, k8;
  reg z7, z8;
  reg [D-1:0] t_q7, t_q8;
  reg signed [E+3:0] cos7, sin7, cos8, sin8;
  // combinational temporaries
  reg [95:0] na, nb;
  reg [31:0] ts0, ts1, ts2, tsb;
  reg [B:0] u1;
  reg [5:0] p, bl;
  reg [B+TD:0] u1w;
  reg [PB+TD-1:0] phw;
  reg [TD:0] pc;
  reg [T:0] pci1;
  reg [E+1:0] ia, ib;
  reg signed [E+2:0] df;
  reg signed [E+D+3:0] pr;
  reg [E+2:0] l6, s6, c6, s9, iw;
  reg [E+14:0] eln;  // u6 x u(E+8)
  reg signed [E+16:0] yr;
  reg signed [7:0] qq, kk;
  reg [7:0] rsh, osh;
  reg [2*E+T+7:0] mw;
  reg [E+2:0] ca;
  reg [2*E+5:0] spr, mg;
  reg [2*E+OB+5:0] lim;

  always @(posedge clk) begin
    `GN_TAUS(na, sa)
    `GN_TAUS(nb, sb)
    if (rst) begin
      rq <= 0;
      sa <= {SA2, SA1, SA0};
      sb <= {SB2, SB1, SB0};
      {v3, v4, v5, v6, v7, v8, out_valid} <= 0;
    end else begin
      rq <= {rq[0], in_valid & req};
      {v3, v4, v5, v6, v7, v8, out_valid} <= {rq[1], v3, v4, v5, v6, v7, v8};
      if (rq[1]) begin
        sa <= na;
        sb <= nb;
      end
    end
    // 3
    k1 <= (na[31:0] ^ na[63:32] ^ na[95:64]) >> (32 - B);
    k2 <= (nb[31:0] ^ nb[63:32] ^ nb[95:64]) >> (32 - B);
    // 4: leading one of U1 = 2 k1 + 1, alignments
    u1 = {k1, 1'b1};
    p = 0;
    `LEAD_ONE(p, u1, UB)
    u1w = {k1, 1'b1, {TD{1'b0}}} >> p;
    phw = {k2[PB-1:0], {TD{1'b0}}} >> PB;
    pc = {1'b1, {TD{1'b0}}} - phw[TD-1:0];
    pci1 = pc[TD:D] + 1;
    ln_addr0 <= {1'b0, u1w[TD-1:D]};
    ln_addr1 <= {1'b0, u1w[TD-1:D]} + 1;
    sin_addr0 <= {1'b0, phw[TD-1:D]};
    sin_addr1 <= {1'b0, phw[TD-1:D]} + 1;
    sin_addr2 <= pc[TD:D];
    sin_addr3 <= pci1 > (1 << T) ? (1 << T) : pci1;
    t_ln4 <= u1w[D-1:0];
    t_s4 <= phw[D-1:0];
    t_c4 <= pc[D-1:0];
    ee4 <= B + 1 - p;
    q4 <= k2[B-1:B-2];
    // 5
    {t_ln5, t_s5, t_c5, ee5, q5} <= {t_ln4, t_s4, t_c4, ee4, q4};
    // 6: ln, sin, cos interpolation; Y = e ln2 - L rounded, >= 0
    `GN_INTERP(l6, {2'b0, ln_data0}, {2'b0, ln_data1}, t_ln5, E)
    `GN_INTERP(s6, {1'b0, sin_data0}, {1'b0, sin_data1}, t_s5, E + 1)
    `GN_INTERP(c6, {1'b0, sin_data2}, {1'b0, sin_data3}, t_c5, E + 1)
    eln = ee5 * LN2C;
    yr = ($signed({2'b0, eln}) - $signed({6'b0, l6, 8'b0}) + 128) >>> 8;
    yv <= yr[E+16] ? 0 : yr[E+5:0];
    case (q5)
      2'd0: begin
        cos6 <= c6;
        sin6 <= s6;
      end
      2'd1: begin
        cos6 <= -s6;
        sin6 <= c6;
      end
      2'd2: begin
        cos6 <= -c6;
        sin6 <= -s6;
      end
      default: begin
        cos6 <= s6;
        sin6 <= -c6;
      end
    endcase
    // 7: sqrt normalise; m = Y * 2^(T-1-2k), as (Y << (T+E+2)) >> (E + 3 + 2k)
    bl = 0;  // the leading one of {Y, 0}: Y's leading one + 1, 0 for Y = 0
    y2 = {yv, 1'b0};
    `LEAD_ONE(bl, y2, YB)
    qq = $signed({2'b0, bl}) - E;
    kk = qq >>> 1;
    rsh = E + 3 + 2 * kk;
    mw = {yv, {T + E + 2{1'b0}}} >> rsh;
    sqrt_addr0 <= (yv == 0) ? 0 : mw[TD-1:D] - (1 << (T - 2));
    sqrt_addr1 <= (yv == 0) ? 1 : mw[TD-1:D] - (1 << (T - 2)) + 1;
    t_q7 <= mw[D-1:0];
    k7 <= kk;
    z7 <= (yv == 0);
    cos7 <= cos6;
    sin7 <= sin6;
    // 8
    {t_q8, k8, z8, cos8, sin8} <= {t_q7, k7, z7, cos7, sin7};
    // 9: r = S 2^k; x = round(S |c| 2^(k+f-2E)), saturate, sign
    `GN_INTERP(s9, sqrt_data0, sqrt_data1, t_q8, E + 2)
    osh = 2 * E - F - k8;  // >= 1 in the configurations built
    `GN_SCALE(x, cos8)
    `GN_SCALE(y, sin8)
  end
`undef GN_TAUS
`undef GN_INTERP
`undef GN_SCALE
endmodule
