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

  // a + round((b - a) * t / 2^D), entries u1.E
  function [E+1:0] interp;
    input [E:0] a;
    input [E:0] b;
    input [D-1:0] t;
    reg signed [E+1:0] df;
    reg signed [E+D+2:0] pr, sh;
    begin
      df = $signed({1'b0, b}) - $signed({1'b0, a});
      pr = df * $signed({1'b0, t});
      pr = pr + $signed({{E + 3{1'b0}}, 1'b1, {D - 1{1'b0}}});
      sh = pr >>> D;
      interp = a + sh[E+1:0];
    end
  endfunction

  reg [F-1:0] st[0:N-1];
  reg [IW-1:0] cnt;  // clocks since the request (0 .. II-1), issuing while < N
  reg busy;
  wire issue = (in_valid & step) | (busy & cnt < N);
  wire [IW-1:0] idx1 = (in_valid & step) ? 0 : cnt;

  // ---- 1 ----
  wire [F-1:0] s1 = st[idx1];
  reg [6:0] bl;
  integer i;
  always @(*) begin
    bl = 0;
    for (i = 0; i < F; i = i + 1) if (s1[i]) bl = i + 1;
  end
  wire [F+TD-1:0] sw = {s1, {TD{1'b0}}} >> (bl - 1);
  wire [TD-1:0] fr = sw[TD-1:0];
  reg [F-1:0] s2, s3, s4, s5, s6;
  reg [6:0] p2, p3;
  reg [D-1:0] t2, t3;
  reg [IW-1:0] x2, x3, x4, x5, x6;
  reg v2, v3, v4, v5, v6;

  // ---- 3 ----
  wire [E+1:0] l3 = interp(log2_data0, log2_data1, t3);
  wire [E+6:0] delta = {p3, {E{1'b0}}} - l3;  // u6.E
  localparam [Z:0] ZQW = ZQ;
  wire [EZ+7:0] zdu = ZQW * delta;  // u1.Z x u6.E
  wire signed [VW-1:0] zd = $signed({2'b0, zdu});
  localparam [VW-1:0] LUW = LU_MAG;
  wire signed [VW-1:0] vr = LU_NEG ? zd + $signed(LUW) : zd - $signed(LUW);
  wire [VW-1:0] v = vr < 0 ? 0 : vr;
  wire [8:0] nn = v[VW-1:EZ];
  wire [EZ+TD-1:0] phw = {v[EZ-1:0], {TD{1'b0}}} >> EZ;
  wire [TD-1:0] ph = phw[TD-1:0];
  reg [8:0] n4, n5;
  reg [D-1:0] t4, t5;

  // ---- 5 ----
  wire [E+1:0] x5w = interp(exp2_data0, exp2_data1, t5);
  reg [E+1:0] xq;
  reg [8:0] n6;

  // ---- 6 ----
  // inc = round(X * 2^(F-E-n)) = round((X << F) / 2^(E+n))
  wire [E+F+1:0] xw = {xq, {F{1'b0}}};
  wire [9:0] rs = E + n6 - 1;
  wire [E+F+1:0] inc0 = s6 == 0 ? 0 : ((xw >> rs) + 1) >> 1;
  wire [E+F+1:0] inc = (ESCAPE != 0 && inc0 == 0) ? 1 : inc0;
  wire [E+F+2:0] sum_l = s6 + inc;
  wire [F-1:0] nl = sum_l > SMAX ? SMAX : sum_l[F-1:0];
  // S - a at F bits (only S > a uses the product, and then 0 < S - a < 2^F): at the
  // product's width the borrow would be copied into 2F + 4 more operand bits
  wire [F-1:0] sma = s6 - AQ;
  wire [3*F+3:0] rp = sma * RECIP;
  wire [F-1:0] nr = rp >> FR;
  wire [F-1:0] ns6 = s6 <= AQ ? nl : nr;
  reg [F-1:0] ns;
  reg v7;
  reg [IW-1:0] x7;

  // ---- 7 and output ----
  reg [F+6:0] acc;
  wire [F+6:0] acc_n = (x7 == 0 ? 0 : acc) + ns;
  reg last;
  wire [F+O+21:0] prod = acc * K_OUT;
  wire [F+O+21:0] rnd = (prod + (1 << (F + 13))) >> (F + 14);

  always @(posedge clk) begin
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
        acc <= acc_n;
      end
      last <= v7 && x7 == N - 1;
      out_valid <= last;
    end
    // 1
    log2_addr0 <= {1'b0, fr[TD-1:D]};
    log2_addr1 <= {1'b0, fr[TD-1:D]} + 1;
    s2 <= s1;
    p2 <= F + 1 - bl;
    t2 <= fr[D-1:0];
    x2 <= idx1;
    // 2
    {s3, p3, t3, x3} <= {s2, p2, t2, x2};
    // 3
    exp2_addr0 <= {1'b0, ph[TD-1:D]};
    exp2_addr1 <= {1'b0, ph[TD-1:D]} + 1;
    t4 <= ph[D-1:0];
    n4 <= nn;
    s4 <= s3;
    x4 <= x3;
    // 4
    {s5, n5, x5, t5} <= {s4, n4, x4, t4};
    // 5
    xq <= x5w;
    n6 <= n5;
    s6 <= s5;
    x6 <= x5;
    // 6
    ns <= ns6;
    x7 <= x6;
    // output
    ip <= rnd > {O{1'b1}} ? {O{1'b1}} : rnd[O-1:0];
  end
endmodule
