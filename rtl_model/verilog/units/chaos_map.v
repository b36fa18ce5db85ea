// chaos_map — the intermittent map of the 1/f fluctuation (rtl_model/src/units/
// chaos_map.rs): n patch states S_i (u0.F, reset to the model's seeded_state(SEED):
// SplitMix64 words, by a constant function), stepped one after another through one
// 7-stage datapath per request, then I_p = round(sum S_i * K) (u0.O, saturating).
// Left branch (S <= A): S + max?(round(u S^z), 1) with u S^z = 2^-V,
// V = z (-log2 S) - log2 u (log2 and exp2 ROMs as ports, synchronous read, linearly
// interpolated); right branch: floor((S - A) * RECIP / 2^(F+4)). Latency n + 7,
// II max(n, 7). Patch i enters on clock c + i (c: the request's clock):
//   1 state read, leading one, mantissa align -> log2 address registers
//   2 ROM data (log2)
//   3 L interpolate, delta = p 2^E - L, V = Zq delta - LU (>= 0) -> exp2 address regs
//   4 ROM data (exp2)
//   5 X interpolate
//   6 inc = round(X 2^(F-E-n)), escape, S + inc (saturating) | right branch, branch mux
//   7 state write-back and patch accumulator
// then the output register: round(sum * K / 2^(F+14)), saturating.
`include "leading_one.vh"

module chaos_map #(
    parameter PATCHES     = 4,
    parameter STATE_BITS  = 32,
    parameter TABLE_LOG2  = 10,
    parameter TABLE_BITS  = 24,
    parameter Z_FRAC_BITS = 16,
    parameter OUT_BITS    = 16,
    parameter A           = 32'd3435973837,  // a as u0.F
    parameter ZQ          = 127795,      // z as u1.Z
    parameter LU_MAG      = 0,           // |round(log2 u * 2^(E+Z))|
    parameter LU_NEG      = 0,           // log2 u < 0
    parameter K_OUT       = 268435456,   // round(I * 2^(O+14) / n)
    parameter ESCAPE      = 1,           // 0: none (sticks), 1: min step
    parameter SEED        = 1
) (
    input                     clk,
    input                     rst,
    input                     in_valid,
    input                     step,
    output reg [TABLE_LOG2:0] log2_addr0,
    output reg [TABLE_LOG2:0] log2_addr1,
    input      [TABLE_BITS:0] log2_data0,
    input      [TABLE_BITS:0] log2_data1,
    output reg [TABLE_LOG2:0] exp2_addr0,
    output reg [TABLE_LOG2:0] exp2_addr1,
    input      [TABLE_BITS:0] exp2_data0,
    input      [TABLE_BITS:0] exp2_data1,
    output reg                out_valid,
    output reg [OUT_BITS-1:0] ip
);
  localparam N = PATCHES;
  localparam F = STATE_BITS;
  localparam T = TABLE_LOG2;
  localparam E = TABLE_BITS;
  localparam D = TABLE_BITS;
  localparam Z = Z_FRAC_BITS;
  localparam O = OUT_BITS;
  localparam TD = T + D;
  localparam EZ = E + Z;
  localparam FR = F + 4;
  localparam II = N > 7 ? N : 7;
  localparam IW = 7;  // patch index
  localparam VW = EZ + 10;  // V: s(8).(E+Z) plus headroom
  localparam [F-1:0] SMAX = {F{1'b1}};
  localparam [F-1:0] AQ = A;

  function [2*F+3:0] recip_of;  // floor(2^(F+FR) / (2^F - A))
    input integer dummy;
    reg [2*F+4:0] num;
    reg [F:0] den;
    begin
      num = 1;
      num = num << (F + FR);
      den = {1'b1, {F{1'b0}}} - AQ;
      recip_of = num / den;
    end
  endfunction
  localparam [2*F+3:0] RECIP = recip_of(0);

  function [F-1:0] seed_state;  // top F bits of SplitMix64 word idx
    input [63:0] seed;
    input integer idx;
    reg [63:0] s, z;
    integer j;
    begin
      s = seed;
      z = 0;
      for (j = 0; j <= idx; j = j + 1) begin
        s = s + 64'h9E3779B97F4A7C15;
        z = s;
        z = (z ^ (z >> 30)) * 64'hBF58476D1CE4E5B9;
        z = (z ^ (z >> 27)) * 64'h94D049BB133111EB;
        z = z ^ (z >> 31);
      end
      seed_state = z >> (64 - F);
    end
  endfunction

  // Written for Icarus's interpreter (docs/rtl.md): one clocked block, every
  // combinational step a blocking temporary evaluated once per clock (no continuous
  // assigns, which vvp re-evaluates bit by bit on every input change), the leading one
  // a binary search (log2 steps, not a loop over bits), the interpolator inline (a
  // function call runs as a thread), and each branch's arithmetic only when taken.
  localparam FB = $clog2(F + 1);  // binary-search steps for the leading one of {s1, 0}
  localparam [Z:0] ZQW = ZQ;
  localparam [VW-1:0] LUW = LU_MAG;
  localparam signed [E+D+2:0] IRND = {{E + 3{1'b0}}, 1'b1, {D - 1{1'b0}}};

  reg [F-1:0] st[0:N-1];
  reg [IW-1:0] cnt;  // clocks since the request (0 .. II-1), issuing while < N
  reg busy;
  reg [F-1:0] s2, s3, s4, s5, s6;
  reg [6:0] p2, p3;
  reg [D-1:0] t2, t3, t4, t5;
  reg [IW-1:0] x2, x3, x4, x5, x6, x7;
  reg v2, v3, v4, v5, v6, v7;
  reg [8:0] n4, n5, n6;
  reg [E+1:0] xq;
  reg [F-1:0] ns;
  reg [F+6:0] acc;
  reg last;
  // combinational temporaries
  reg issue;
  reg [IW-1:0] idx1;
  reg [F-1:0] s1;
  reg [F:0] s10;
  reg [6:0] bl;
  reg [F+TD-1:0] sw;
  reg signed [E+1:0] df;  // interpolation: b - a
  reg signed [E+D+2:0] pr;  // (b - a) t + 2^(D-1)
  reg [E+1:0] l3;
  reg [E+1:0] iw;  // an interpolant before its cut to the entries' E + 1 bits
  reg [E+6:0] delta;  // u6.E
  reg [EZ+7:0] zdu;  // u1.Z x u6.E
  reg signed [VW-1:0] vr;
  reg [VW-1:0] v;
  reg [EZ+TD-1:0] phw;
  reg [E+F+1:0] inc;
  reg [9:0] rs;
  reg [E+F+2:0] sum_l;
  reg [F-1:0] sma;
  reg [3*F+3:0] rp;
  reg [F+O+21:0] rnd;
  integer i;

  // bl = the leading one of {s1, 0} (s1's leading one + 1, 0 for s1 = 0): LEAD_ONE
  // (lib/leading_one.vh; F < 128).

  always @(posedge clk) begin
    // ---- 1: state read, leading one, mantissa align ----
    issue = (in_valid & step) | (busy & cnt < N);
    idx1 = (in_valid & step) ? 0 : cnt;
    s1 = st[idx1];
    bl = 0;
    s10 = {s1, 1'b0};
    `LEAD_ONE(bl, s10, FB)
    sw = {s1, {TD{1'b0}}} >> (bl - 1);
    // ---- 3: L interpolate, delta = p 2^E - L, V = Zq delta - LU (>= 0) ----
    df = $signed({1'b0, log2_data1}) - $signed({1'b0, log2_data0});
    pr = df * $signed({1'b0, t3}) + IRND;
    // The interpolant lies between its two entries (E + 1 bits), so the carry above them
    // is cut: left in, it is 0 only through the product, which ABC's SAT sweep
    // (&fraig) stalled on proving (docs/units.md, gaussian_noise and chaos_map).
    iw = log2_data0 + pr[E+D+1:D];
    l3 = {1'b0, iw[E:0]};
    delta = {p3, {E{1'b0}}} - l3;
    zdu = ZQW * delta;
    if (LU_NEG) vr = $signed({2'b0, zdu}) + $signed(LUW);
    else vr = $signed({2'b0, zdu}) - $signed(LUW);
    v = vr < 0 ? 0 : vr;
    phw = {v[EZ-1:0], {TD{1'b0}}} >> EZ;
    if (rst) begin
      cnt <= 0;
      busy <= 0;
      {v2, v3, v4, v5, v6, v7, last, out_valid} <= 0;
      for (i = 0; i < N; i = i + 1) st[i] <= seed_state(SEED, i);
    end else begin
      if (in_valid & step) begin
        busy <= 1;
        cnt <= 1;
      end else if (busy) begin
        cnt <= cnt + 1;
        if (cnt == II - 1) busy <= 0;
      end
      {v2, v3, v4, v5, v6, v7} <= {issue, v2, v3, v4, v5, v6};
      if (v7) begin
        st[x7] <= ns;
        acc <= (x7 == 0 ? 0 : acc) + ns;
      end
      last <= v7 && x7 == N - 1;
      out_valid <= last;
    end
    // 1
    log2_addr0 <= {1'b0, sw[TD-1:D]};
    log2_addr1 <= {1'b0, sw[TD-1:D]} + 1;
    s2 <= s1;
    p2 <= F + 1 - bl;
    t2 <= sw[D-1:0];
    x2 <= idx1;
    // 2
    {s3, p3, t3, x3} <= {s2, p2, t2, x2};
    // 3
    exp2_addr0 <= {1'b0, phw[TD-1:D]};
    exp2_addr1 <= {1'b0, phw[TD-1:D]} + 1;
    t4 <= phw[D-1:0];
    n4 <= v[VW-1:EZ];
    s4 <= s3;
    x4 <= x3;
    // 4
    {s5, n5, x5, t5} <= {s4, n4, x4, t4};
    // 5: X interpolate
    df = $signed({1'b0, exp2_data1}) - $signed({1'b0, exp2_data0});
    pr = df * $signed({1'b0, t5}) + IRND;
    iw = exp2_data0 + pr[E+D+1:D];
    xq <= {1'b0, iw[E:0]};  // cut as l3
    n6 <= n5;
    s6 <= s5;
    x6 <= x5;
    // 6: inc = round(X * 2^(F-E-n)) = round((X << F) / 2^(E+n)), escape, S + inc
    // (saturating) | right branch floor((S - a) RECIP / 2^(F+4)); S - a at F bits (only
    // S > a uses the product, and then 0 < S - a < 2^F): at the product's width the
    // borrow would be copied into 2F + 4 more operand bits
    if (s6 <= AQ) begin
      rs = E + n6 - 1;
      inc = s6 == 0 ? 0 : (({xq, {F{1'b0}}} >> rs) + 1) >> 1;
      if (ESCAPE != 0 && inc == 0) inc = 1;
      sum_l = s6 + inc;
      ns <= sum_l > SMAX ? SMAX : sum_l[F-1:0];
    end else begin
      sma = s6 - AQ;
      rp = sma * RECIP;
      ns <= rp >> FR;
    end
    x7 <= x6;
    // output: round(sum * K / 2^(F+14)), saturating
    rnd = (acc * K_OUT + (1 << (F + 13))) >> (F + 14);
    ip <= rnd > {O{1'b1}} ? {O{1'b1}} : rnd[O-1:0];
  end
endmodule
