// vertex_lighting — GL 1.x fixed-function lighting of one vertex in a configurable
// float format (rtl_model/src/units/vertex_lighting.rs, arithmetic of
// rtl_model/src/float_format.rs), bit-exact with the model.
//
// Format: 1 + EXP_BITS + MANT_BITS, IEEE layout, the all-ones exponent reserved (it
// reads as the largest finite exponent, never produced), subnormals flushed (operands
// read as zero, results below the smallest normal become ±0), each operation
// exactly rounded once: ROUNDING 0 = nearest-even, 1 = toward zero. Overflow
// saturates to ±max finite.
//   mul: (M+1)×(M+1) significand product, 1-bit normalise, round.
//   add: operands ordered by magnitude, the smaller aligned with guard, round and a
//        jammed sticky bit (exactly rounded), LZC normalise, round; exact cancel → +0.
//   rcp: ⌊2^(2M+4)/sig⌋ by restoring division, remainder → sticky (the model's
//        exactly rounded reciprocal); rcp(±0) = ±max finite.
//   rsq: sig (doubled for an odd exponent) → ⌊√⌊2^(2P)/sig⌋⌋, 2P = 3M + 8 + M mod 2,
//        by restoring division then a restoring square root; inexact unless both
//        remainders are 0 (the model's exactly rounded 1/√|x|); rsq(0) = +max finite.
//   pow: the model's log2 → mul → exp2: K = M + 4 squaring steps of y in u1.K
//        (truncated each step), log rounded to the format, t = s·log2 x, then
//        2^t = 2^n · Π 2^(2^-k) over the set bits of t's K fraction bits, the
//        constants a ROM of K words in u1.K built by a constant function exactly as
//        the model builds it (K integer square roots from 2 at K + 16 bits), each
//        product truncated to u1.K; pow(x, 0) = 1, pow(x ≤ 0, s) = 0.
//
// Restriction (the vector writer refuses anything else): exactly ONE light, its
// loaded registers (position or direction, attenuation, spot, the colour products)
// and the material's (e_m + a_m·a_s, shininess or the specular curve's k0 … k2,
// alpha) as parameters, format words as the model loaded them. LOCAL selects a local
// light (attenuation by rcp) or a directional one; SPOT a spot cone (cutoff < 180°)
// or none; NORMALIZE (GL_NORMALIZE) and LOCAL_VIEWER as in the model. Subnormals
// flushed only.
//
// NV2A modes (the model's config fields; nxdk_pgraph_tests' Specular captures):
// * normalize_directional: a load-time choice, so no parameter of its own — a
//   directional light's LIGHT_X/Y/Z are the vector normalised at load or as the host
//   wrote it, and the datapath uses them as given either way (N·L scales with the
//   length, H = normalize(L + V) of that vector).
// * light_control: LIGHT_CONTROL = 1 gives two colours, primary (r, g, b, a) and
//   secondary (r2, g2, b2, a2), from the vertex's diffuse (dr … da) and specular
//   (sr … sa) colour ports, routed by LIGHTING, SPECULAR_ENABLE, SEPARATE_SPECULAR and
//   SPEC_ALPHA_FROM_VERTEX as the model's `light_nv2a`: lighting off, no datapath is
//   built and the primary is the vertex's diffuse; lighting on, the diffuse sum
//   e_m + a_m·a_s + k·(a + nl·d) and the specular sum k·(spec·s) are formed apart
//   (one more multiply per channel than GL's k·(t + spec·s), one add fewer), the
//   specular sum converted as the secondary RGB when specular is enabled and
//   separate, else added to the diffuse sum before its conversion (one more add);
//   the primary alpha is the material's. Secondary: (0, 0, 0, 1) with specular
//   disabled; else RGB the lit specular (separate) or the vertex's, alpha the
//   vertex's specular alpha (SPEC_ALPHA_FROM_VERTEX) or 1. II and latency follow the
//   model's issues (3 more multiplies and 3 more adds). LIGHT_CONTROL = 0 (the
//   default) is GL's single colour: the colour ports are unused, r2 … a2 are 0.
// * specular_curve: SPECULAR_CURVE = 1 replaces pow(x, SHININESS), x = max(N·h, 0),
//   by the NV2A's SET_SPECULAR_PARAMS curve f = (x + k0)·rcp(k1·x + k2), k0 … k2 the
//   loaded words CURVE_K0 … CURVE_K2, as the model's `specular_factor`: num = x + k0,
//   den = k1·x + k2, the RCP operator on den, num·rcp, and f = 0 unless num > 0 and
//   den > 0 (the sign gate). II and latency follow the model's issues (1 more
//   multiply, 2 more adds, one special fewer: RCP instead of LOG + EXP).
//   SPECULAR_CURVE = 0 (the default) is GL's pow, the datapath as before.
//
// Schedule: the model's Timing is a schedule over shared FP units (6 multipliers,
// 4 adders, one special-function unit): II = max(1, ⌈muls/6⌉, ⌈adds/4⌉, specials),
// latency II + 6. This Verilog computes the same function as one fixed datapath
// (every operation its own operator, in the model's order) into a register on the
// clock a vertex is accepted, then a delay line presents it on the model's cycle:
// one vertex every II clocks, output LATENCY clocks after its input.
//
// Hierarchy: the operators are modules (vertex_lighting_mul, _add, _rcp, _rsq,
// _log2 with its K squaring stages _log2_sq, _exp2, _unorm), instantiated where the
// datapath has them; dot3, normalise and pow are modules that group operators.
// The operators carry (* keep_hierarchy *): `units --synth` (synth -flatten) keeps
// them, synthesises each ONCE and counts it per instance (Yosys's design hierarchy
// total), so no logic is optimised across an operator's ports (a constant operand
// stays a port): a conservative count. The rounding helpers (fp_round, fp_pack) and
// the format's widths are lib/vertex_lighting_fp.vh, `include`d into each operator.

// Fields, as macros (a function call is a thread fork and join in Icarus, and these
// two were most of the calls; the same gates either way). x is an identifier.
// Zero (a zero exponent field: subnormals are flushed).
`define VL_FZ(x) (x[W-2:M] == 0)
// Effective biased exponent, E bits unsigned (the reserved all-ones field reads as
// 2^E − 2).
`define VL_FE(x) ((&x[W-2:M]) ? {{(E - 1) {1'b1}}, 1'b0} : x[W-2:M])
// An operator's parameter list.
`define VL_FP #(.EXP_BITS(EXP_BITS), .MANT_BITS(MANT_BITS), .ROUNDING(ROUNDING))
`define VL_FP3(lu, lv) #(.EXP_BITS(EXP_BITS), .MANT_BITS(MANT_BITS), .ROUNDING(ROUNDING), .LU(lu), .LV(lv))
`define VL_FPN(lin) #(.EXP_BITS(EXP_BITS), .MANT_BITS(MANT_BITS), .ROUNDING(ROUNDING), .LIN(lin))

// Icarus only, scheduling and no logic: an operator is a process woken by its first
// changed input; with WAIT rounds of #0 it runs once, when all its inputs have
// settled, instead of once per input event (a glitch re-running everything after it).
// WAIT is the operator's level minus its earliest input's (defparams below, from
// the levels L_* of the datapath; the inputs are level 0, a constant is −1). A wrong
// WAIT only costs time: an input that changes later wakes the process again.
// Yosys and Verilator see neither the parameter nor the waits.
`ifdef __ICARUS__
`define VL_WAIT_PARAM parameter WAIT = 1;
`define VL_SETTLE repeat (WAIT) #0;
`define VL_WAIT(inst, v) defparam inst.WAIT = v;
`else
`define VL_WAIT_PARAM
`define VL_SETTLE
`define VL_WAIT(inst, v)
`endif
// An operator's format parameters (every operator module takes the same three).
`define VL_FMT_PARAMS parameter EXP_BITS = 8, parameter MANT_BITS = 23, parameter ROUNDING = 0
`define VL_MAX(a, b) ((a) > (b) ? (a) : (b))
// Rounds (Icarus scheduling only, see VL_WAIT) from an operator's input change to its
// output's, for the operators made of kept pieces: RSQ's front, its NQ division pieces
// (each a round after the last) and the root with the pack; pow's LOG (its stages run
// in the round their input changes), the multiply, EXP's front, its NCH product pieces
// and the pack. Every other operator takes one.
// The piece sizes and counts are these macros' only, so the modules and the rounds
// cannot disagree: RSQ divides 2M + 9 + M mod 2 quotient bits in pieces of VL_RSQ_CH
// steps, EXP multiplies K = M + 4 times in pieces of VL_EXP_CH.
`define VL_RSQ_CH 8
`define VL_EXP_CH 9
`define VL_NQ(m) ((2 * (m) + 9 + (m) % 2 + `VL_RSQ_CH - 1) / `VL_RSQ_CH)
`define VL_D_RSQ(m) (`VL_NQ(m) + 2)
`define VL_NCH(m) (((m) + 4 + `VL_EXP_CH - 1) / `VL_EXP_CH)
`define VL_D_POW(m) (`VL_NCH(m) + 4)
`define VL_FMIN(a, b) ((a) < 0 ? (b) : (b) < 0 ? (a) : (a) < (b) ? (a) : (b))
`define VL_WT(f1, s1, f2, s2) (`VL_FMIN(f1, f2) < 0 ? 1 : `VL_MAX(s1, s2) + 1 - `VL_FMIN(f1, f2))
`define VL_NEXT(s) ((s) < 0 ? -1 : (s) + 1)

// x · y, exactly rounded.
(* keep_hierarchy *)
module vertex_lighting_mul #(
    `VL_FMT_PARAMS
) (
    input  [EXP_BITS+MANT_BITS:0] x,
    input  [EXP_BITS+MANT_BITS:0] y,
    output reg [EXP_BITS+MANT_BITS:0] o
);
`include "vertex_lighting_fp.vh"
  function [W-1:0] fp_mul(input [W-1:0] x, input [W-1:0] y);
    reg [2*M+1:0] p;
    integer ex;
    begin
      if (`VL_FZ(x) || `VL_FZ(y)) fp_mul = {x[W-1] ^ y[W-1], {(W - 1) {1'b0}}};
      else begin
        p  = {1'b1, x[M-1:0]} * {1'b1, y[M-1:0]};
        ex = `VL_FE(x) + `VL_FE(y) - 2 * BIAS;
        if (p[2*M+1])
          fp_mul = fp_round(x[W-1] ^ y[W-1], ex + 1, p[2*M+1:M+1], p[M], |p[M-1:0]);
        else fp_mul = fp_round(x[W-1] ^ y[W-1], ex, p[2*M:M], p[M-1], |p[M-2:0]);
      end
    end
  endfunction

  `VL_WAIT_PARAM
  always @(x, y) begin
    `VL_SETTLE
    o = fp_mul(x, y);
  end
endmodule

// x + y, exactly rounded.
(* keep_hierarchy *)
module vertex_lighting_add #(
    `VL_FMT_PARAMS
) (
    input  [EXP_BITS+MANT_BITS:0] x,
    input  [EXP_BITS+MANT_BITS:0] y,
    output reg [EXP_BITS+MANT_BITS:0] o
);
`include "vertex_lighting_fp.vh"
  function [W-1:0] fp_add(input [W-1:0] x, input [W-1:0] y);
    reg [W-1:0] big, sml;
    reg [E-1:0] eb, es, d;
    reg [M+3:0] bs, ss;
    reg [M+4:0] s;
    begin
      if (`VL_FZ(x) || `VL_FZ(y))
        fp_add = `VL_FZ(y) ? (`VL_FZ(x) ? {x[W-1] & y[W-1], {(W - 1) {1'b0}}} : x) : y;
      else begin
        eb = `VL_FE(x);
        es = `VL_FE(y);
        if ((es > eb) || (es == eb && y[M-1:0] > x[M-1:0])) begin
          big = y;
          sml = x;
          d   = es - eb;
          eb  = es;
        end else begin
          big = x;
          sml = y;
          d   = eb - es;
        end
        // The smaller aligned with guard and round bits, the bits shifted out jammed
        // into its lsb (sticky); shifted out entirely it is the sticky bit alone.
        ss = {1'b1, sml[M-1:0], 3'b000};
        if (d > M + 3) ss = 1;
        else ss = (ss >> d) | (|(ss & ~({(M + 4) {1'b1}} << d)));
        bs = {1'b1, big[M-1:0], 3'b000};
        if (big[W-1] == sml[W-1]) s = bs + ss;
        else s = bs - ss;
        if (s == 0) fp_add = {W{1'b0}};
        else
          fp_add = fp_pack(big[W-1], eb - BIAS - M - 3, {{(VW - M - 5) {1'b0}}, s}, 1'b0);
      end
    end
  endfunction

  `VL_WAIT_PARAM
  always @(x, y) begin
    `VL_SETTLE
    o = fp_add(x, y);
  end
endmodule

// 1 / x, exactly rounded.
(* keep_hierarchy *)
module vertex_lighting_rcp #(
    `VL_FMT_PARAMS
) (
    input  [EXP_BITS+MANT_BITS:0] x,
    output reg [EXP_BITS+MANT_BITS:0] o
);
`include "vertex_lighting_fp.vh"
  localparam RK = 2 * M + 4;  // ⌊2^RK / sig⌋

  function [W-1:0] fp_rcp(input [W-1:0] x);
    reg [M:0] sig;
    reg [M+2:0] rem;
    reg [M+4:0] q;
    integer j, lsb;
    begin
      if (`VL_FZ(x)) fp_rcp = {x[W-1], MAXMAG};
      else begin
        sig = {1'b1, x[M-1:0]};
        rem = {{(M + 2) {1'b0}}, 1'b1} << (M - 1);  // 2^RK >> (M + 5) < sig
        q   = 0;
        for (j = M + 4; j >= 0; j = j - 1) begin
          rem = rem << 1;
          if (rem >= {2'b00, sig}) begin
            rem  = rem - {2'b00, sig};
            q[j] = 1'b1;
          end
        end
        lsb = `VL_FE(x) - BIAS - M;
        fp_rcp = fp_pack(x[W-1], -RK - lsb, {{(VW - M - 5) {1'b0}}, q}, rem != 0);
      end
    end
  endfunction

  `VL_WAIT_PARAM
  always @(x) begin
    `VL_SETTLE
    o = fp_rcp(x);
  end
endmodule

// 1 / √|x|, exactly rounded. The division's steps are kept modules of up to CH steps
// each: as one module, ABC's SAT sweep (&fraig) stalled (more than 20 CPU-minutes,
// unfinished), while each piece alone is swept in seconds.
(* keep_hierarchy *)
module vertex_lighting_rsq #(
    `VL_FMT_PARAMS
) (
    input  [EXP_BITS+MANT_BITS:0] x,
    output reg [EXP_BITS+MANT_BITS:0] o
);
`include "vertex_lighting_fp.vh"
  localparam TWO_P = 3 * M + 8 + (M % 2);  // ⌊2^TWO_P / sig⌋
  localparam QB = TWO_P - M + 1;  // quotient bits
  localparam QB2 = QB + (QB % 2);
  localparam RB = QB2 / 2;  // root bits
  localparam CH = `VL_RSQ_CH;  // steps per kept module
  localparam NQ = `VL_NQ(M);  // division pieces, ⌈QB / CH⌉

  // sig (doubled for an odd exponent, so the exponent halves exactly) and the lsb.
  `VL_WAIT_PARAM
  reg [M+1:0] sig;
  integer lsb;
  reg zero_x;
  always @(x) begin
    `VL_SETTLE
    zero_x = `VL_FZ(x);
    lsb = `VL_FE(x) - BIAS - M;
    if (lsb % 2 != 0) begin
      sig = {1'b1, x[M-1:0], 1'b0};
      lsb = lsb - 1;
    end else sig = {1'b0, 1'b1, x[M-1:0]};
  end

  // ⌊2^TWO_P / sig⌋, restoring: the remainder before quotient bit QB − 1 is
  // 2^(M−1) < sig. quo's bits QB2 − 1 .. QB are 0 (QB odd).
  wire [QB2-1:0] quo;
  genvar gq;
  generate
    if (QB2 > QB) begin : g_pad
      assign quo[QB2-1:QB] = 0;
    end
    for (gq = 0; gq < NQ; gq = gq + 1) begin : g_div
      localparam N = (QB - gq * CH) < CH ? (QB - gq * CH) : CH;
      wire [M+3:0] rin, rout;
      if (gq == 0) begin : g_first
        assign rin = {{(M + 3) {1'b0}}, 1'b1} << (M - 1);
      end else begin : g_next
        assign rin = g_div[gq-1].rout;
      end
      vertex_lighting_div_steps #(.RW(M + 4), .SW(M + 2), .N(N)) st (
          .rem(rin), .sig(sig), .rem_o(rout), .q(quo[QB-1-gq*CH-:N]));
      `VL_WAIT(st, gq + 1)
    end
  endgenerate
  wire [M+3:0] rem_q = g_div[NQ-1].rout;

  // ⌊√quo⌋, restoring, and the pack. (x in the list: woken when x changes, it waits
  // for the last division piece, so o changes once, `VL_D_RSQ rounds after x.)
  always @(x, zero_x, lsb, quo, rem_q) begin : root_pack
    reg [RB+1:0] rem2;
    reg [RB-1:0] root;
    integer j;
`ifdef __ICARUS__
    repeat (NQ + 2) #0;  // scheduling only, as VL_SETTLE
`endif
    rem2 = 0;
    root = 0;
    for (j = RB - 1; j >= 0; j = j - 1) begin
      rem2 = {rem2[RB-1:0], quo[2*j+:2]};
      if (rem2 >= {root, 2'b01}) begin
        rem2 = rem2 - {root, 2'b01};
        root = {root[RB-2:0], 1'b1};
      end else root = root << 1;
    end
    if (zero_x) o = {1'b0, MAXMAG};
    else
      o = fp_pack(1'b0, -(TWO_P / 2) - lsb / 2, {{(VW - RB) {1'b0}}, root},
                  rem_q != 0 || rem2 != 0);
  end
endmodule

// N restoring-division steps: rem ← 2·rem, and where rem ≥ sig, rem ← rem − sig with
// quotient bit 1 (q's MSB first).
(* keep_hierarchy *)
module vertex_lighting_div_steps #(
    parameter RW = 27,
    parameter SW = 25,
    parameter N  = 8
) (
    input      [RW-1:0] rem,
    input      [SW-1:0] sig,
    output reg [RW-1:0] rem_o,
    output reg [N-1:0]  q
);
  `VL_WAIT_PARAM
  // The steps on local copies, the ports written once (Icarus propagates every write
  // to an output port).
  reg [RW-1:0] r;
  reg [N-1:0] qq;
  integer j;
  always @(rem, sig) begin
    `VL_SETTLE
    r = rem;
    for (j = N - 1; j >= 0; j = j - 1) begin
      r = r << 1;
      if (r >= {{(RW - SW) {1'b0}}, sig}) begin
        r = r - {{(RW - SW) {1'b0}}, sig};
        qq[j] = 1'b1;
      end else qq[j] = 1'b0;
    end
    rem_o = r;
    q = qq;
  end
endmodule

// pow's log2 x (x > 0), the model's K = M + 4 squarings.
(* keep_hierarchy *)
module vertex_lighting_log2 #(
    `VL_FMT_PARAMS
) (
    input  [EXP_BITS+MANT_BITS:0] x,
    output reg [EXP_BITS+MANT_BITS:0] l
);
`include "vertex_lighting_fp.vh"
  // K squaring stages of y = 1.f in u1.K, each stage's carry a fraction bit of log2.
  // (Each stage's own wires: one wide vector of all stages, part-selected, costs
  // Icarus the whole vector on every stage's change.)
  wire [K:0] y0 = {1'b1, x[M-1:0], 4'b0000};
  wire [K-1:0] f;
  genvar gi;
  generate
    for (gi = 0; gi < K; gi = gi + 1) begin : g_sq
      wire [K:0] yo;
      if (gi == 0) begin : g_first
        vertex_lighting_log2_sq #(.K(K)) sq (.y(y0), .yo(yo), .b(f[K-1-gi]));
      end else begin : g_next
        vertex_lighting_log2_sq #(.K(K)) sq (.y(g_sq[gi-1].yo), .yo(yo), .b(f[K-1-gi]));
      end
    end
  endgenerate

  // The log rounded to the format: (e − BIAS) + 0.f.
  function [W-1:0] log_pack(input [W-1:0] x, input [K-1:0] f);
    reg signed [VW-1:0] lfix;
    reg [VW-1:0] lmag;
    integer e;
    begin
      e = `VL_FE(x) - BIAS;
      lfix = e;
      lfix = (lfix <<< K) + $signed({1'b0, f});
      lmag = lfix < 0 ? -lfix : lfix;
      log_pack = fp_pack(lfix < 0, -K, lmag, 1'b0);
    end
  endfunction

  `VL_WAIT_PARAM
  // (The stages run in the round x changes, so one round settles f too.)
  always @(x, f) begin
    `VL_SETTLE
    l = log_pack(x, f);
  end
endmodule

// One squaring stage of log2: z = y², y in u1.K; the carry (z ≥ 2) is the next
// fraction bit and picks the truncated u1.K result.
(* keep_hierarchy *)
module vertex_lighting_log2_sq #(
    parameter K = 27
) (
    input          [K:0] y,
    output reg     [K:0] yo,
    output reg           b
);
  // A process, not continuous assignments: Icarus's net multiplier is bitwise.
  reg [2*K+1:0] z;
  always @(y) begin
    z  = y * y;
    b  = z[2*K+1];
    yo = b ? z[2*K+1:K+1] : z[2*K:K];
  end
endmodule

// pow's 2^t: 2^n · Π 2^(2^-k) over the set bits of t's K fraction bits.
// The product stays in [1, 2) (every ROM word is above 1.0, and the product of all K
// words, truncated at each step, is below 2: 1.99999984 at K = 27), so its leading
// one is not carried: each step holds the K fraction bits, p = 1.f. Carried, that bit
// is constant only by that argument, through the multipliers, and ABC's SAT sweep
// (&fraig) stalled on it; the steps are kept modules, so each is swept alone.
(* keep_hierarchy *)
module vertex_lighting_exp2 #(
    `VL_FMT_PARAMS
) (
    input  [EXP_BITS+MANT_BITS:0] t,
    output reg [EXP_BITS+MANT_BITS:0] o
);
`include "vertex_lighting_fp.vh"
  localparam TW = M + 21;  // the signed t·2^K

  // ---- the exp2 constants: 2^(2^-k) in u1.K, k = 1 ..= K (the model's ROM) --------
  function [127:0] isqrt128(input [127:0] v);
    reg [127:0] rem, root, trial;
    integer i;
    begin
      rem  = 0;
      root = 0;
      for (i = 63; i >= 0; i = i - 1) begin
        rem   = (rem << 2) | ((v >> (2 * i)) & 128'd3);
        trial = (root << 2) | 128'd1;
        if (rem >= trial) begin
          rem  = rem - trial;
          root = (root << 1) | 128'd1;
        end else root = root << 1;
      end
      isqrt128 = root;
    end
  endfunction

  function [K*(K+1)-1:0] exp2_rom_all(input integer dummy);
    reg [127:0] c, word;
    reg [K*(K+1)-1:0] acc;
    integer i, wide;
    begin
      wide = K + 16;
      c = 128'd2 << wide;
      acc = 0;
      for (i = 0; i < K; i = i + 1) begin
        c = isqrt128(c << wide);
        word = (c + 128'd32768) >> 16;
        acc = acc | ({{(K * (K + 1) - K - 1) {1'b0}}, word[K:0]} << (i * (K + 1)));
      end
      exp2_rom_all = acc;
    end
  endfunction

  localparam [K*(K+1)-1:0] EXP2_ROM = exp2_rom_all(0);

  // t as n + f/2^K (n integer, f the K fraction bits), and the cases that skip the
  // product: t = 0 gives 1; n above the format's range saturates, below it flushes.
  `VL_WAIT_PARAM
  reg [K-1:0] f;
  reg signed [TW-1:0] n;
  reg zero_t, sat, flush;
  always @(t) begin : front
    reg [M:0] sig;
    reg [TW-1:0] mag, mask;
    reg inexact;
    reg signed [TW-1:0] tfix;
    integer sh;
    `VL_SETTLE
    sig = {1'b1, t[M-1:0]};
    sh  = `VL_FE(t) - BIAS - M + K;
    inexact = 1'b0;
    if (sh >= 18) mag = {{(TW - 1) {1'b0}}, 1'b1} << (M + 18);
    else if (sh >= 0) mag = {{(TW - M - 1) {1'b0}}, sig} << sh;
    else if (-sh >= M + 1) begin
      mag = 0;
      inexact = 1'b1;
    end else begin
      mag = {{(TW - M - 1) {1'b0}}, sig} >> (-sh);
      mask = ~({TW{1'b1}} << (-sh));
      inexact = |({{(TW - M - 1) {1'b0}}, sig} & mask);
    end
    if (t[W-1]) tfix = -$signed(mag + {{(TW - 1) {1'b0}}, inexact});
    else tfix = $signed(mag);
    n = tfix >>> K;
    f = tfix[K-1:0];
    zero_t = `VL_FZ(t);
    sat = n > EMAX + 1;
    flush = n < EMIN - M - 2;
  end

  // The product over f's set bits, in kept modules of up to CH steps each (swept alone
  // by ABC: the whole chain in one module stalled its SAT sweep).
  localparam CH = `VL_EXP_CH;  // steps per kept module
  localparam NCH = `VL_NCH(M);  // ⌈K / CH⌉
  genvar gc;
  generate
    for (gc = 0; gc < NCH; gc = gc + 1) begin : g_ch
      localparam N = (K - gc * CH) < CH ? (K - gc * CH) : CH;
      wire [K-1:0] q;
      wire [K-1:0] pin;
      if (gc == 0) begin : g_first
        assign pin = {K{1'b0}};
      end else begin : g_next
        assign pin = g_ch[gc-1].q;
      end
      vertex_lighting_exp2_steps #(.K(K), .N(N),
          .ROM(EXP2_ROM[gc*CH*(K+1)+:N*(K+1)])) st (
          .p(pin), .f(f[K-1-gc*CH-:N]), .q(q));
      `VL_WAIT(st, gc + 1)
    end
  endgenerate
  wire [K-1:0] pf = g_ch[NCH-1].q;

  // (t in the list: woken when t changes, it waits for the last piece, a round after
  // the front's and each piece a round after the last.)
  always @(t, zero_t, sat, flush, n, pf) begin
`ifdef __ICARUS__
    repeat (WAIT + NCH + 1) #0;  // scheduling only, as VL_SETTLE
`endif
    if (zero_t) o = ONE;
    else if (sat) o = {1'b0, MAXMAG};
    else if (flush) o = {W{1'b0}};
    else o = fp_pack(1'b0, n - K, {{(VW - K - 1) {1'b0}}, 1'b1, pf}, 1'b0);
  end
endmodule

// N steps of exp2's product: for each set bit of f (MSB first) multiply 1.p by the
// next ROM word (2^(2^-k) in u1.K), truncated to u1.K; p and q are K fraction bits
// (the product is 1.p, in [1, 2)).
(* keep_hierarchy *)
module vertex_lighting_exp2_steps #(
    parameter K = 27,
    parameter N = 9,
    parameter [N*(K+1)-1:0] ROM = 0
) (
    input      [K-1:0] p,
    input      [N-1:0] f,
    output reg [K-1:0] q
);
  `VL_WAIT_PARAM
  // The ROM words as constant nets (read from the wide parameter, Icarus would
  // rebuild all its bits on every read); the product on a local copy, the port
  // written once.
  wire [K:0] rom[0:N-1];
  genvar gr;
  generate
    for (gr = 0; gr < N; gr = gr + 1) begin : g_rom
      assign rom[gr] = ROM[gr*(K+1)+:(K+1)];
    end
  endgenerate
  reg [2*K+1:0] wide;
  reg [K-1:0] a;
  integer i;
  always @(p, f) begin
    `VL_SETTLE
    a = p;
    for (i = 0; i < N; i = i + 1)
    if (f[N-1-i]) begin
      wide = {1'b1, a} * rom[i];
      a = wide[2*K-1:K];
    end
    q = a;
  end
endmodule

// x clamped to [0, 1] as a CB-bit unorm, round(x·(2^CB − 1)) half up.
(* keep_hierarchy *)
module vertex_lighting_unorm #(
    parameter EXP_BITS   = 8,
    parameter MANT_BITS  = 23,
    parameter ROUNDING   = 0,
    parameter COLOR_BITS = 8
) (
    input  [EXP_BITS+MANT_BITS:0] x,
    output reg [COLOR_BITS-1:0]   u
);
`include "vertex_lighting_fp.vh"
  localparam CB = COLOR_BITS;

  function [CB-1:0] fp_unorm(input [W-1:0] x);
    reg [M+CB:0] prod;
    reg [M+CB+1:0] sum;
    integer sh;
    begin
      if (`VL_FZ(x) || x[W-1]) fp_unorm = 0;
      else if (x[W-2:0] >= ONE[W-2:0]) fp_unorm = {CB{1'b1}};
      else begin
        prod = {1'b1, x[M-1:0]} * {CB{1'b1}};
        sh = BIAS + M - `VL_FE(x);
        if (sh >= M + CB + 2) fp_unorm = 0;
        else begin
          sum = {1'b0, prod} + ({{(M + CB + 1) {1'b0}}, 1'b1} << (sh - 1));
          fp_unorm = sum >> sh;
        end
      end
    end
  endfunction

  `VL_WAIT_PARAM
  always @(x) begin
    `VL_SETTLE
    u = fp_unorm(x);
  end
endmodule

// u · v = (u_x·v_x + u_y·v_y) + u_z·v_z, in the model's order.
module vertex_lighting_dot3 #(
    `VL_FMT_PARAMS,
    parameter LU        = 0,  // u's and v's levels (Icarus scheduling only)
    parameter LV        = 0
) (
    input  [3*(EXP_BITS+MANT_BITS+1)-1:0] u,
    input  [3*(EXP_BITS+MANT_BITS+1)-1:0] v,
    output [  EXP_BITS+MANT_BITS:0]       o
);
  localparam W = 1 + EXP_BITS + MANT_BITS;
  wire [W-1:0] t0, t1, t2, s;
  vertex_lighting_mul `VL_FP m0 (.x(u[3*W-1-:W]), .y(v[3*W-1-:W]), .o(t0));
  vertex_lighting_mul `VL_FP m1 (.x(u[2*W-1-:W]), .y(v[2*W-1-:W]), .o(t1));
  vertex_lighting_add `VL_FP a0 (.x(t0), .y(t1), .o(s));
  vertex_lighting_mul `VL_FP m2 (.x(u[W-1:0]), .y(v[W-1:0]), .o(t2));
  vertex_lighting_add `VL_FP a1 (.x(s), .y(t2), .o(o));
  `VL_WAIT(m0, `VL_WT(LU, LU, LV, LV))
  `VL_WAIT(m1, `VL_WT(LU, LU, LV, LV))
  `VL_WAIT(m2, `VL_WT(LU, LU, LV, LV))
  `VL_WAIT(a1, 2)
endmodule

// v · rsq(v · v).
module vertex_lighting_norm #(
    `VL_FMT_PARAMS,
    parameter LIN       = 0  // v's level (Icarus scheduling only)
) (
    input  [3*(EXP_BITS+MANT_BITS+1)-1:0] v,
    output [3*(EXP_BITS+MANT_BITS+1)-1:0] o
);
  localparam W = 1 + EXP_BITS + MANT_BITS;
  wire [W-1:0] d2, rr;
  vertex_lighting_dot3 `VL_FP3(LIN, LIN) dt (.u(v), .v(v), .o(d2));
  vertex_lighting_rsq `VL_FP rs (.x(d2), .o(rr));
  genvar gc;
  generate
    for (gc = 0; gc < 3; gc = gc + 1) begin : g_c
      vertex_lighting_mul `VL_FP m (.x(v[gc*W+:W]), .y(rr), .o(o[gc*W+:W]));
      `VL_WAIT(m, 4 + `VL_D_RSQ(MANT_BITS))
    end
  endgenerate
endmodule

// x^s as the model's log2 → mul → exp2; pow(x, 0) = 1, pow(x ≤ 0, s) = 0.
module vertex_lighting_pow #(
    `VL_FMT_PARAMS
) (
    input  [EXP_BITS+MANT_BITS:0] x,
    input  [EXP_BITS+MANT_BITS:0] s,
    output [EXP_BITS+MANT_BITS:0] o
);
  localparam W = 1 + EXP_BITS + MANT_BITS;
  localparam M = MANT_BITS;
  localparam [W-1:0] ONE = {2'b00, {(EXP_BITS - 1) {1'b1}}, {M{1'b0}}};
  wire [W-1:0] l, t, e;
  vertex_lighting_log2 `VL_FP lg (.x(x), .l(l));
  vertex_lighting_mul `VL_FP mu (.x(s), .y(l), .o(t));
  vertex_lighting_exp2 `VL_FP ex (.t(t), .o(e));
  assign o = (s[W-2:M] == 0) ? ONE : (x[W-1] || x[W-2:M] == 0) ? {W{1'b0}} : e;
endmodule

module vertex_lighting #(

    parameter EXP_BITS     = 8,
    parameter MANT_BITS    = 23,
    parameter ROUNDING     = 0,
    parameter COLOR_BITS   = 8,
    parameter NORMALIZE    = 1,
    parameter LOCAL_VIEWER = 0,
    parameter LOCAL        = 1,
    parameter SPOT         = 0,
    // The NV2A's light control (the model's `light_control`): 0 = GL's single colour
    // (the vertex colour ports unused, the secondary outputs 0); 1 = two colours,
    // routed by the four switches below (the model's `LightControl` fields).
    parameter LIGHT_CONTROL          = 0,
    parameter LIGHTING               = 1,
    parameter SPECULAR_ENABLE        = 1,
    parameter SEPARATE_SPECULAR      = 1,
    parameter SPEC_ALPHA_FROM_VERTEX = 1,
    // The NV2A's specular curve (the model's `specular_curve`): 0 = pow(N·h,
    // SHININESS) (GL); 1 = (x + k0)·rcp(k1·x + k2), x = max(N·h, 0), 0 unless the
    // numerator and the denominator are both positive, k0 … k2 the loaded
    // SET_SPECULAR_PARAMS words CURVE_K0 … CURVE_K2 below.
    parameter SPECULAR_CURVE         = 0,
    // The light's loaded registers (format words).
    parameter [63:0] LIGHT_X   = 0,
    parameter [63:0] LIGHT_Y   = 0,
    parameter [63:0] LIGHT_Z   = 0,
    parameter [63:0] ATT_C     = 0,
    parameter [63:0] ATT_L     = 0,
    parameter [63:0] ATT_Q     = 0,
    parameter [63:0] SPOT_X    = 0,
    parameter [63:0] SPOT_Y    = 0,
    parameter [63:0] SPOT_Z    = 0,
    parameter [63:0] SPOT_COS  = 0,
    parameter [63:0] SPOT_EXP  = 0,
    parameter [63:0] AMB_R     = 0,
    parameter [63:0] AMB_G     = 0,
    parameter [63:0] AMB_B     = 0,
    parameter [63:0] DIF_R     = 0,
    parameter [63:0] DIF_G     = 0,
    parameter [63:0] DIF_B     = 0,
    parameter [63:0] SPE_R     = 0,
    parameter [63:0] SPE_G     = 0,
    parameter [63:0] SPE_B     = 0,
    // The material's: e_m + a_m·a_s, shininess, and the alpha unorm.
    parameter [63:0] BASE_R    = 0,
    parameter [63:0] BASE_G    = 0,
    parameter [63:0] BASE_B    = 0,
    parameter [63:0] SHININESS = 0,
    parameter [63:0] ALPHA     = 0,
    // The specular curve's k0, k1, k2 (SPECULAR_CURVE only; format words as loaded).
    parameter [63:0] CURVE_K0  = 0,
    parameter [63:0] CURVE_K1  = 0,
    parameter [63:0] CURVE_K2  = 0
) (
    input                   clk,
    input                   rst,
    input                   in_valid,
    input  [EXP_BITS+MANT_BITS:0] px,
    input  [EXP_BITS+MANT_BITS:0] py,
    input  [EXP_BITS+MANT_BITS:0] pz,
    input  [EXP_BITS+MANT_BITS:0] nx,
    input  [EXP_BITS+MANT_BITS:0] ny,
    input  [EXP_BITS+MANT_BITS:0] nz,
    // The vertex's diffuse and specular colours (LIGHT_CONTROL only).
    input  [COLOR_BITS-1:0] dr,
    input  [COLOR_BITS-1:0] dg,
    input  [COLOR_BITS-1:0] db,
    input  [COLOR_BITS-1:0] da,
    input  [COLOR_BITS-1:0] sr,
    input  [COLOR_BITS-1:0] sg,
    input  [COLOR_BITS-1:0] sb,
    input  [COLOR_BITS-1:0] sa,
    output                  out_valid,
    output [COLOR_BITS-1:0] r,
    output [COLOR_BITS-1:0] g,
    output [COLOR_BITS-1:0] b,
    output [COLOR_BITS-1:0] a,
    // The secondary (specular) colour (LIGHT_CONTROL only; 0 without).
    output [COLOR_BITS-1:0] r2,
    output [COLOR_BITS-1:0] g2,
    output [COLOR_BITS-1:0] b2,
    output [COLOR_BITS-1:0] a2
);
  localparam W = 1 + EXP_BITS + MANT_BITS;
  localparam E = EXP_BITS;
  localparam M = MANT_BITS;
  localparam CB = COLOR_BITS;
  localparam [W-1:0] ONE = {2'b00, {(E - 1) {1'b1}}, {M{1'b0}}};

  // Light control: the lighting datapath is built unless lighting is off (then both
  // colours are the vertex's); the lit specular sum is its own colour when specular
  // is enabled and separate, else it joins the diffuse sum.
  localparam LC = LIGHT_CONTROL ? 1 : 0;
  localparam LIT = !LIGHT_CONTROL || LIGHTING;
  localparam SPLIT = SPECULAR_ENABLE && SEPARATE_SPECULAR;

  // The model's Timing: issues per light 36 / 28 / 7, per normalise 6 / 2 / 1; light
  // control 3 multiplies (k·spec·s per channel, one light) and 3 adds (the join); the
  // specular curve 1 more multiply (k1·x and num·rcp instead of s·log), 2 more adds
  // and one special fewer (RCP instead of LOG + EXP).
  localparam NK = NORMALIZE + LOCAL_VIEWER;
  localparam CV = SPECULAR_CURVE ? 1 : 0;
  localparam MULS = 36 + 6 * NK + 3 * LC + CV;
  localparam ADDS = 28 + 2 * NK + 3 * LC + 2 * CV;
  localparam SPECIALS = 7 + NK - CV;
  localparam II_MUL = (MULS + 5) / 6;
  localparam II_ADD = (ADDS + 3) / 4;
  localparam II_A = II_MUL > II_ADD ? II_MUL : II_ADD;
  localparam II = II_A > SPECIALS ? II_A : SPECIALS;
  localparam LATENCY = II + 6;

  // Signed comparison key (±0 and flushed subnormals are 0).
  function signed [W:0] fkey(input [W-1:0] x);
    begin
      if (`VL_FZ(x)) fkey = 0;
      else if (x[W-1]) fkey = -$signed({2'b00, x[W-2:0]});
      else fkey = $signed({2'b00, x[W-2:0]});
    end
  endfunction

  function flt(input [W-1:0] x, input [W-1:0] y);
    flt = fkey(x) < fkey(y);
  endfunction

  function [W-1:0] fmax0(input [W-1:0] x);
    fmax0 = (!x[W-1] && !`VL_FZ(x)) ? x : {W{1'b0}};
  endfunction

  localparam [3*W-1:0] LVEC = {LIGHT_X[W-1:0], LIGHT_Y[W-1:0], LIGHT_Z[W-1:0]};
  localparam [3*W-1:0] SDIR = {SPOT_X[W-1:0], SPOT_Y[W-1:0], SPOT_Z[W-1:0]};
  localparam [3*W-1:0] AMB = {AMB_R[W-1:0], AMB_G[W-1:0], AMB_B[W-1:0]};
  localparam [3*W-1:0] DIF = {DIF_R[W-1:0], DIF_G[W-1:0], DIF_B[W-1:0]};
  localparam [3*W-1:0] SPE = {SPE_R[W-1:0], SPE_G[W-1:0], SPE_B[W-1:0]};
  localparam [3*W-1:0] BASE = {BASE_R[W-1:0], BASE_G[W-1:0], BASE_B[W-1:0]};
  localparam [3*W-1:0] NEG3 = {3{1'b1, {(W - 1) {1'b0}}}};  // XOR: negate each

  // Levels (Icarus scheduling only, see VL_WAIT): the delta round in which a signal
  // settles, the inputs 0, a constant −1; F_/S_ a signal's first and last change.
  // RSQ and pow take D_RSQ and D_POW rounds (VL_D_RSQ, VL_D_POW).
  localparam integer D_RSQ = `VL_D_RSQ(M);
  localparam integer D_POW = `VL_D_POW(M);
  // The specular factor: pow, or the curve's add/mul → add → RCP → mul (4 rounds).
  localparam integer D_SPF = SPECULAR_CURVE ? 4 : D_POW;
  localparam integer L_N = NORMALIZE ? 4 + D_RSQ : 0;
  localparam integer L_V = LOCAL_VIEWER ? 4 + D_RSQ : -1;
  localparam integer L_LV = LOCAL ? 5 + D_RSQ : -1;
  localparam integer L_ATT = LOCAL ? 9 + D_RSQ : -1;
  localparam integer L_CD = L_LV < 0 ? -1 : L_LV + 3;
  localparam integer F_SPOT = SPOT ? L_CD : -1;
  localparam integer S_SPOT = (SPOT && L_CD >= 0) ? L_CD + D_POW : -1;
  localparam integer L_NL = `VL_MAX(L_N, L_LV) + 3;
  localparam integer L_HV = `VL_NEXT(`VL_MAX(L_LV, L_V));
  localparam integer L_H = L_HV < 0 ? -1 : L_HV + 4 + D_RSQ;
  localparam integer L_NHR = `VL_MAX(L_N, L_H) + 3;
  localparam integer F_SPEC = `VL_FMIN(L_NL, L_NHR);
  localparam integer S_SPEC = `VL_MAX(L_NL, L_NHR + D_SPF);
  localparam integer L_KK = `VL_NEXT(`VL_MAX(L_ATT, S_SPOT));
  localparam integer L_T1 = L_NL + 2;
  localparam integer L_MS = S_SPEC + 1;
  localparam integer L_T2 = `VL_MAX(L_T1, L_MS) + 1;
  // Light control: k·(a + nl·d), the diffuse sum, k·spec·s.
  localparam integer L_MK = `VL_MAX(L_KK, L_T1) + 1;
  localparam integer L_DACC = L_MK + 1;
  localparam integer L_MKS = `VL_MAX(L_KK, L_MS) + 1;

  // ---- the datapath, in the model's order (VertexLighting::light) --------------------
  // rgb: the lit colour (GL), or with light control the lit primary (the diffuse sum,
  // plus the specular sum unless split); rgb2: the lit secondary (the specular sum,
  // when split).
  wire [3*CB-1:0] rgb, rgb2;
  genvar gc;
  generate
    if (LIT) begin : g_lit
      wire [3*W-1:0] p = {px, py, pz};
      wire [3*W-1:0] nin = {nx, ny, nz};
      wire [3*W-1:0] n, v, lv, hv, h;
      wire [W-1:0] att, spot, nl_raw, nh_raw, sp, spec, kk;
      if (NORMALIZE) begin : g_norm
        vertex_lighting_norm `VL_FPN(0) nrm (.v(nin), .o(n));
      end else begin : g_nonorm
        assign n = nin;
      end
      if (LOCAL_VIEWER) begin : g_viewer
        vertex_lighting_norm `VL_FPN(0) nrm (.v(p ^ NEG3), .o(v));
      end else begin : g_noviewer
        assign v = {{W{1'b0}}, {W{1'b0}}, ONE};
      end
      if (LOCAL) begin : g_local
        wire [3*W-1:0] vp;
        wire [W-1:0] d2, rr, d, tl, den1, tq, den;
        for (gc = 0; gc < 3; gc = gc + 1) begin : g_c
          vertex_lighting_add `VL_FP ad (.x(LVEC[gc*W+:W]), .y(p[gc*W+:W] ^ NEG3[W-1:0]),
                                       .o(vp[gc*W+:W]));
          vertex_lighting_mul `VL_FP m (.x(vp[gc*W+:W]), .y(rr), .o(lv[gc*W+:W]));
          `VL_WAIT(m, 4 + D_RSQ)
        end
        vertex_lighting_dot3 `VL_FP3(1, 1) dt (.u(vp), .v(vp), .o(d2));
        vertex_lighting_rsq `VL_FP rs (.x(d2), .o(rr));
        vertex_lighting_mul `VL_FP md (.x(d2), .y(rr), .o(d));
        vertex_lighting_mul `VL_FP ml (.x(ATT_L[W-1:0]), .y(d), .o(tl));
        vertex_lighting_add `VL_FP a1 (.x(ATT_C[W-1:0]), .y(tl), .o(den1));
        vertex_lighting_mul `VL_FP mq (.x(ATT_Q[W-1:0]), .y(d2), .o(tq));
        vertex_lighting_add `VL_FP ad2 (.x(den1), .y(tq), .o(den));
        vertex_lighting_rcp `VL_FP rc (.x(den), .o(att));
        `VL_WAIT(md, 1 + D_RSQ)
        `VL_WAIT(ad2, 3 + D_RSQ)
      end else begin : g_dir
        // A directional light: its register as loaded (normalised at load, or as the
        // host wrote it: the model's `normalize_directional` acts on the parameter).
        assign lv  = LVEC;
        assign att = ONE;
      end
      if (SPOT) begin : g_spot
        wire [W-1:0] cd, c, pw;
        vertex_lighting_dot3 `VL_FP3(L_LV, -1) dt (.u(lv), .v(SDIR), .o(cd));
        assign c = cd ^ NEG3[W-1:0];
        vertex_lighting_pow `VL_FP pwr (.x(c), .s(SPOT_EXP[W-1:0]), .o(pw));
        reg c_lt;  // c < the cutoff's cosine
        always @(c) c_lt = flt(c, SPOT_COS[W-1:0]);
        assign spot = c_lt ? {W{1'b0}} : pw;
      end else begin : g_nospot
        assign spot = ONE;
      end
      vertex_lighting_dot3 `VL_FP3(L_N, L_LV) dnl (.u(n), .v(lv), .o(nl_raw));
      for (gc = 0; gc < 3; gc = gc + 1) begin : g_h
        vertex_lighting_add `VL_FP ad (.x(lv[gc*W+:W]), .y(v[gc*W+:W]), .o(hv[gc*W+:W]));
        `VL_WAIT(ad, `VL_WT(L_LV, L_LV, L_V, L_V))
      end
      vertex_lighting_norm `VL_FPN(L_HV) nrh (.v(hv), .o(h));
      vertex_lighting_dot3 `VL_FP3(L_N, L_H) dnh (.u(n), .v(h), .o(nh_raw));
      // max(0, ·) and the N·L > 0 test, as processes (a function in a continuous
      // assignment is re-run by Icarus on every input event).
      reg [W-1:0] nl, nh;
      reg nl_pos;
      always @(nl_raw) begin
        nl = fmax0(nl_raw);
        nl_pos = flt({W{1'b0}}, nl_raw);
      end
      always @(nh_raw) nh = fmax0(nh_raw);
      if (SPECULAR_CURVE) begin : g_curve
        // The NV2A curve, in the model's order (specular_factor): num = x + k0,
        // den = k1·x + k2, num·rcp(den), 0 unless num > 0 and den > 0.
        wire [W-1:0] num, tk, den, rd, q;
        vertex_lighting_add `VL_FP an (.x(nh), .y(CURVE_K0[W-1:0]), .o(num));
        vertex_lighting_mul `VL_FP mk (.x(CURVE_K1[W-1:0]), .y(nh), .o(tk));
        vertex_lighting_add `VL_FP ad (.x(tk), .y(CURVE_K2[W-1:0]), .o(den));
        vertex_lighting_rcp `VL_FP rc (.x(den), .o(rd));
        vertex_lighting_mul `VL_FP mq (.x(num), .y(rd), .o(q));
        `VL_WAIT(mq, 3)
        reg pos;  // the sign gate: numerator and denominator both positive
        always @(num, den) pos = flt({W{1'b0}}, num) && flt({W{1'b0}}, den);
        assign sp = pos ? q : {W{1'b0}};
      end else begin : g_pow
        vertex_lighting_pow `VL_FP psp (.x(nh), .s(SHININESS[W-1:0]), .o(sp));
      end
      assign spec = nl_pos ? sp : {W{1'b0}};
      vertex_lighting_mul `VL_FP mkk (.x(att), .y(spot), .o(kk));
      `VL_WAIT(mkk, `VL_WT(L_ATT, L_ATT, F_SPOT, S_SPOT))
      for (gc = 0; gc < 3; gc = gc + 1) begin : g_ch
        wire [W-1:0] md, t1, ms, acc;
        vertex_lighting_mul `VL_FP m1 (.x(nl), .y(DIF[gc*W+:W]), .o(md));
        vertex_lighting_add `VL_FP a1 (.x(AMB[gc*W+:W]), .y(md), .o(t1));
        vertex_lighting_mul `VL_FP m2 (.x(spec), .y(SPE[gc*W+:W]), .o(ms));
        `VL_WAIT(m2, `VL_WT(F_SPEC, S_SPEC, -1, -1))
        if (!LIGHT_CONTROL) begin : g_gl
          // acc = e_m + a_m·a_s + k·((a + nl·d) + spec·s).
          wire [W-1:0] t2, mk;
          vertex_lighting_add `VL_FP ad2 (.x(t1), .y(ms), .o(t2));
          vertex_lighting_mul `VL_FP m3 (.x(kk), .y(t2), .o(mk));
          vertex_lighting_add `VL_FP a3 (.x(BASE[gc*W+:W]), .y(mk), .o(acc));
          `VL_WAIT(ad2, `VL_WT(L_T1, L_T1, L_MS, L_MS))
          `VL_WAIT(m3, `VL_WT(L_KK, L_KK, L_T2, L_T2))
        end else begin : g_two
          // The model's two sums (light_nv2a): diffuse dacc = e_m + a_m·a_s +
          // k·(a + nl·d), specular sacc = 0 + k·(spec·s). One light, so sacc is the
          // product mks itself: 0 + x = x for every non-zero x (a product is never
          // the reserved exponent), and a zero x gives a zero either way, which the
          // join (x + ±0 = x for x ≠ 0) and the unorm (±0 → 0) do not tell apart.
          wire [W-1:0] mk, dacc, mks;
          vertex_lighting_mul `VL_FP m3 (.x(kk), .y(t1), .o(mk));
          vertex_lighting_add `VL_FP a3 (.x(BASE[gc*W+:W]), .y(mk), .o(dacc));
          vertex_lighting_mul `VL_FP m4 (.x(kk), .y(ms), .o(mks));
          `VL_WAIT(m3, `VL_WT(L_KK, L_KK, L_T1, L_T1))
          `VL_WAIT(m4, `VL_WT(L_KK, L_KK, L_MS, L_MS))
          if (SPLIT) begin : g_split
            // The specular sum is the secondary colour.
            assign acc = dacc;
            vertex_lighting_unorm #(
                .EXP_BITS(EXP_BITS),
                .MANT_BITS(MANT_BITS),
                .ROUNDING(ROUNDING),
                .COLOR_BITS(COLOR_BITS)
            ) un2 (
                .x(mks),
                .u(rgb2[gc*CB+:CB])
            );
          end else begin : g_join
            // The specular sum joins the diffuse before the conversion.
            vertex_lighting_add `VL_FP a4 (.x(dacc), .y(mks), .o(acc));
            `VL_WAIT(a4, `VL_WT(L_DACC, L_DACC, L_MKS, L_MKS))
            assign rgb2[gc*CB+:CB] = 0;
          end
        end
        vertex_lighting_unorm #(
            .EXP_BITS(EXP_BITS),
            .MANT_BITS(MANT_BITS),
            .ROUNDING(ROUNDING),
            .COLOR_BITS(COLOR_BITS)
        ) un (
            .x(acc),
            .u(rgb[gc*CB+:CB])
        );
      end
      if (!LIGHT_CONTROL) begin : g_nosec
        assign rgb2 = 0;
      end
    end else begin : g_unlit
      // Lighting off: no datapath, both colours are the vertex's.
      assign rgb  = 0;
      assign rgb2 = 0;
    end
  endgenerate

  // ---- the outputs: GL's lit RGB (alpha the material's), or with light control the
  // primary and secondary RGBA (the model's light_nv2a routing) ------------------------
  localparam OW = LIGHT_CONTROL ? 8 * CB : 3 * CB;
  localparam [CB-1:0] CMAX = {CB{1'b1}};
  wire [OW-1:0] res;
  generate
    if (LIGHT_CONTROL) begin : g_route
      // Primary: lit RGB and the material's alpha, or the vertex's diffuse.
      wire [4*CB-1:0] pri = LIGHTING ? {rgb, ALPHA[CB-1:0]} : {dr, dg, db, da};
      // Secondary: (0, 0, 0, 1) with specular disabled; else the lit specular sum
      // when lit and separate, the vertex's specular RGB otherwise; alpha the vertex's
      // specular alpha or 1.
      wire [3*CB-1:0] srgb = !SPECULAR_ENABLE ? {(3 * CB) {1'b0}} :
          (LIGHTING && SEPARATE_SPECULAR) ? rgb2 : {sr, sg, sb};
      wire [CB-1:0] salpha = (SPECULAR_ENABLE && SPEC_ALPHA_FROM_VERTEX) ? sa : CMAX;
      assign res = {pri, srgb, salpha};
    end else begin : g_gl_out
      assign res = rgb;
    end
  endgenerate

  // ---- pipeline: the result on the clock a vertex is accepted, then a delay line ----
  reg [OW-1:0] s0;
  reg [(LATENCY-1)*OW-1:0] dl;
  reg [LATENCY-1:0] vc;
  always @(posedge clk) begin
    if (rst) vc <= 0;
    else vc <= {vc[LATENCY-2:0], in_valid};
    if (in_valid) s0 <= res;
    dl <= {dl[(LATENCY-2)*OW-1:0], s0};
  end
  assign out_valid = vc[LATENCY-1];
  generate
    if (LIGHT_CONTROL) begin : g_out2
      assign {r, g, b, a, r2, g2, b2, a2} = dl[(LATENCY-1)*OW-1-:OW];
    end else begin : g_out1
      assign {r, g, b} = dl[(LATENCY-1)*OW-1-:OW];
      assign a = ALPHA[CB-1:0];
      assign {r2, g2, b2, a2} = 0;
    end
  endgenerate
endmodule

`undef VL_FZ
`undef VL_FE
`undef VL_FP
`undef VL_FP3
`undef VL_FPN
`undef VL_WAIT_PARAM
`undef VL_SETTLE
`undef VL_WAIT
`undef VL_MAX
`undef VL_FMT_PARAMS
`undef VL_FMIN
`undef VL_WT
`undef VL_NEXT
`undef VL_NQ
`undef VL_RSQ_CH
`undef VL_EXP_CH
`undef VL_D_RSQ
`undef VL_NCH
`undef VL_D_POW
