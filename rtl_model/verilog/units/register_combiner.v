// register_combiner — one GENERAL combiner stage of GL_NV_register_combiners, RGB and
// alpha portions (rtl_model/src/units/register_combiner.rs, steps 1-7 of its notes):
// select, map (Table 4, in half-LSB units), products (or dot products over R, G, B),
// one product rounding round(p * 2^G / (4S)), the sum or the SPARE0-alpha mux, bias,
// scale, one output rounding round(V / 2^(G+2)), clamp to [-S, S], write into the
// register set. S = 2^(N-1) - 1. The state is parameters, per portion P = RGB, ALPHA:
//   P_V_IN  register 0 .. 11 (Table NV_register_combiners.1 order)
//   P_V_MAP Table 4 in the model's order: 0 UNSIGNED_IDENTITY 1 UNSIGNED_INVERT
//           2 EXPAND_NORMAL 3 EXPAND_NEGATE 4 HALF_BIAS_NORMAL 5 HALF_BIAS_NEGATE
//           6 SIGNED_IDENTITY 7 SIGNED_NEGATE
//   P_V_USE 0 RGB 1 ALPHA 2 BLUE
//   P_AB_OUT, P_CD_OUT, P_SUM_OUT  a register 0 .. 11, 15 DISCARD
//   P_SCALE 0 NONE 1 x2 2 x4 3 x1/2; P_BIAS 1 BIAS_BY_NEGATIVE_ONE_HALF;
//   P_AB_DOT, P_CD_DOT (RGB only), P_MUX_SUM
// NV2A modes (0 = the GeForce default): BIAS_HALF_CODE 1 makes the -1/2 bias 2^(N-2)
// codes ((S+1)/2) instead of S/2; MUX_LSB 1 tests SPARE0 alpha's low bit instead of
// >= 0.5; AB_BLUE_TO_ALPHA / CD_BLUE_TO_ALPHA also write the RGB portion's out1 / out2
// blue to its register's alpha; STAGE_CONST 1 makes the stage read C0_R .. C1_A (codes)
// as CONSTANT_COLOR0/1 instead of the set's (which pass on).
// ROUNDING is the model's Quant in declaration order (0 TRN 1 TRN_ZERO 2 RND
// 3 RND_ZERO 4 RND_INF 5 RND_MIN_INF 6 RND_CONV), for both roundings.
// Latency 3, II 1: stage 1 the input set, stage 2 the rounded products, stage 3 the
// written set.
module register_combiner #(
    parameter N = 9,
    parameter G = 0,
    parameter ROUNDING = 2,
    parameter RGB_A_IN = 4, parameter RGB_A_MAP = 0, parameter RGB_A_USE = 0,
    parameter RGB_B_IN = 0, parameter RGB_B_MAP = 1, parameter RGB_B_USE = 0,
    parameter RGB_C_IN = 0, parameter RGB_C_MAP = 0, parameter RGB_C_USE = 0,
    parameter RGB_D_IN = 0, parameter RGB_D_MAP = 0, parameter RGB_D_USE = 0,
    parameter RGB_AB_OUT = 15, parameter RGB_CD_OUT = 15, parameter RGB_SUM_OUT = 6,
    parameter RGB_SCALE = 0, parameter RGB_BIAS = 0,
    parameter RGB_AB_DOT = 0, parameter RGB_CD_DOT = 0, parameter RGB_MUX_SUM = 0,
    parameter ALPHA_A_IN = 4, parameter ALPHA_A_MAP = 0, parameter ALPHA_A_USE = 1,
    parameter ALPHA_B_IN = 0, parameter ALPHA_B_MAP = 1, parameter ALPHA_B_USE = 1,
    parameter ALPHA_C_IN = 0, parameter ALPHA_C_MAP = 0, parameter ALPHA_C_USE = 1,
    parameter ALPHA_D_IN = 0, parameter ALPHA_D_MAP = 0, parameter ALPHA_D_USE = 1,
    parameter ALPHA_AB_OUT = 15, parameter ALPHA_CD_OUT = 15, parameter ALPHA_SUM_OUT = 6,
    parameter ALPHA_SCALE = 0, parameter ALPHA_BIAS = 0,
    parameter ALPHA_AB_DOT = 0, parameter ALPHA_CD_DOT = 0, parameter ALPHA_MUX_SUM = 0,
    parameter BIAS_HALF_CODE = 0, parameter MUX_LSB = 0,
    parameter AB_BLUE_TO_ALPHA = 0, parameter CD_BLUE_TO_ALPHA = 0,
    parameter STAGE_CONST = 0,
    parameter C0_R = 0, parameter C0_G = 0, parameter C0_B = 0, parameter C0_A = 0,
    parameter C1_R = 0, parameter C1_G = 0, parameter C1_B = 0, parameter C1_A = 0,
    parameter UNUSED = 0
) (
    input clk,
    input rst,
    input in_valid,
`include "combiner_register_file.vh"
    output reg out_valid,
    output [N-1:0] o_zero_r,
    output [N-1:0] o_zero_g,
    output [N-1:0] o_zero_b,
    output [N-1:0] o_zero_a,
    output [N-1:0] o_ccc0_r,
    output [N-1:0] o_ccc0_g,
    output [N-1:0] o_ccc0_b,
    output [N-1:0] o_ccc0_a,
    output [N-1:0] o_ccc1_r,
    output [N-1:0] o_ccc1_g,
    output [N-1:0] o_ccc1_b,
    output [N-1:0] o_ccc1_a,
    output [N-1:0] o_fog_r,
    output [N-1:0] o_fog_g,
    output [N-1:0] o_fog_b,
    output [N-1:0] o_fog_a,
    output [N-1:0] o_pri_r,
    output [N-1:0] o_pri_g,
    output [N-1:0] o_pri_b,
    output [N-1:0] o_pri_a,
    output [N-1:0] o_sec_r,
    output [N-1:0] o_sec_g,
    output [N-1:0] o_sec_b,
    output [N-1:0] o_sec_a,
    output [N-1:0] o_spare0_r,
    output [N-1:0] o_spare0_g,
    output [N-1:0] o_spare0_b,
    output [N-1:0] o_spare0_a,
    output [N-1:0] o_spare1_r,
    output [N-1:0] o_spare1_g,
    output [N-1:0] o_spare1_b,
    output [N-1:0] o_spare1_a,
    output [N-1:0] o_tex0_r,
    output [N-1:0] o_tex0_g,
    output [N-1:0] o_tex0_b,
    output [N-1:0] o_tex0_a,
    output [N-1:0] o_tex1_r,
    output [N-1:0] o_tex1_g,
    output [N-1:0] o_tex1_b,
    output [N-1:0] o_tex1_a,
    output [N-1:0] o_tex2_r,
    output [N-1:0] o_tex2_g,
    output [N-1:0] o_tex2_b,
    output [N-1:0] o_tex2_a,
    output [N-1:0] o_tex3_r,
    output [N-1:0] o_tex3_g,
    output [N-1:0] o_tex3_b,
    output [N-1:0] o_tex3_a
);
  localparam W = 2 * N + G + 16;
  localparam signed [W-1:0] S = (1 << (N - 1)) - 1;
  // Register i, component c (0 r .. 3 a) at [(47 - 4i - c)*N +: N].

  // Written for Icarus's interpreter (docs/rtl.md): the register file is concatenated
  // in the clocked block (a continuous concatenation of the 48 ports is rebuilt on each
  // port's change), and the roundings and mappings are macros (a function call runs as
  // a thread, and copied the 48N-bit file on every call). Each macro uses the block's
  // temporaries below.

  // DST = floor(NUM / DEN) plus the carry of ROUNDING; DEN > 0. NUM, DEN at W bits.
`define RC_RDIV(DST, NUM, DEN) \
    rn = NUM; \
    rd = DEN; \
    rq = rn / rd;  /* toward zero */ \
    rr = rn - rq * rd; \
    if (rr < 0) begin \
      rq = rq - 1; \
      rr = rr + rd; \
    end \
    rt = 2 * rr; \
    if (rr == 0) rup = 1'b0; \
    else \
      case (ROUNDING) \
        0: rup = 1'b0; \
        1: rup = rn < 0; \
        default: \
        if (rt > rd) rup = 1'b1; \
        else if (rt < rd) rup = 1'b0; \
        else \
          case (ROUNDING) \
            2: rup = 1'b1; \
            3: rup = rn < 0; \
            4: rup = !(rn < 0); \
            5: rup = 1'b0; \
            default: rup = rq[0]; \
          endcase \
      endcase \
    DST = rq + rup;

  // DST = variable (IN, M, CU) on LANE: the register component (ZERO reads 0),
  // sign-extended, then Table 4 in half-LSB units (s(N+2)).
`define RC_MAPPED(DST, IN, M, CU, LANE) \
    mx = fr[(47-4*(IN)-((CU) == 1 ? 3 : (CU) == 2 ? 2 : (LANE)))*N+:N]; \
    mr = (IN) == 0 ? 0 : $signed({{(W - N) {mx[N-1]}}, mx}); \
    mp = mr < 0 ? 0 : mr; \
    case (M) \
      0: DST = 2 * mp; \
      1: DST = 2 * (S - (mp > S ? S : mp)); \
      2: DST = 2 * (2 * mp - S); \
      3: DST = 2 * (S - 2 * mp); \
      4: DST = 2 * mp - S; \
      5: DST = S - 2 * mp; \
      6: DST = 2 * mr; \
      default: DST = -2 * mr; \
    endcase

  // Step 6: DST = clamp(round((2x - b) * k / 2^(G+2)), -S, S), x = X at W bits.
`define RC_OUTV(DST, X, SCALE, BIAS) \
    ox = X; \
    `RC_RDIV(ov, (2 * ox - ((BIAS) ? ((BIAS_HALF_CODE ? S + 1 : S) <<< G) : 0)) * ((SCALE) == 0 ? 2 : (SCALE) == 1 ? 4 : (SCALE) == 2 ? 8 : 1), 1 << (G + 2)) \
    DST = ov > S ? S : ov < -S ? -S : ov;

  reg v1, v2;
  reg [48*N-1:0] f1, f2, f3, fo, fr;
  // Stage 2's rounded products: lane l's q_ab at [l*W +: W] (lanes 0..2 RGB, 3 alpha).
  reg [4*W-1:0] qab, qcd;
  reg mux_cd;
  integer l;
  reg signed [W-1:0] ab [0:3], cd [0:3];
  reg signed [W-1:0] va, vb, q, x, sum;
  // the macros' temporaries
  reg [N-1:0] mx;
  reg signed [W-1:0] mr, mp, rn, rd, rq, rr, rt, ox, ov;
  reg rup;
  always @(posedge clk) begin
    if (rst) begin
      v1 <= 1'b0;
      v2 <= 1'b0;
      out_valid <= 1'b0;
    end else begin
      v1 <= in_valid;
      v2 <= v1;
      out_valid <= v2;
    end
    // Stage 1: the input set.
    f1 <= `COMBINER_REGISTER_FILE;
    // Stage 2: products (s(2N+2)), dot products (s(2N+3)), each rounded once:
    // round(p * 2^G / (4S)). The variables read fr: the input set with the stage's
    // own constants when STAGE_CONST.
    fr = f1;
    if (STAGE_CONST) begin
      fr[43*N+:N] = C0_R;
      fr[42*N+:N] = C0_G;
      fr[41*N+:N] = C0_B;
      fr[40*N+:N] = C0_A;
      fr[39*N+:N] = C1_R;
      fr[38*N+:N] = C1_G;
      fr[37*N+:N] = C1_B;
      fr[36*N+:N] = C1_A;
    end
    for (l = 0; l < 3; l = l + 1) begin
      `RC_MAPPED(va, RGB_A_IN, RGB_A_MAP, RGB_A_USE, l)
      `RC_MAPPED(vb, RGB_B_IN, RGB_B_MAP, RGB_B_USE, l)
      ab[l] = va * vb;
      `RC_MAPPED(va, RGB_C_IN, RGB_C_MAP, RGB_C_USE, l)
      `RC_MAPPED(vb, RGB_D_IN, RGB_D_MAP, RGB_D_USE, l)
      cd[l] = va * vb;
    end
    `RC_MAPPED(va, ALPHA_A_IN, ALPHA_A_MAP, ALPHA_A_USE, 3)
    `RC_MAPPED(vb, ALPHA_B_IN, ALPHA_B_MAP, ALPHA_B_USE, 3)
    ab[3] = va * vb;
    `RC_MAPPED(va, ALPHA_C_IN, ALPHA_C_MAP, ALPHA_C_USE, 3)
    `RC_MAPPED(vb, ALPHA_D_IN, ALPHA_D_MAP, ALPHA_D_USE, 3)
    cd[3] = va * vb;
    if (RGB_AB_DOT) begin
      `RC_RDIV(q, (ab[0] + ab[1] + ab[2]) <<< G, 4 * S)
      qab[3*W-1:0] <= {q, q, q};
    end else
      for (l = 0; l < 3; l = l + 1) begin
        `RC_RDIV(q, ab[l] <<< G, 4 * S)
        qab[l*W+:W] <= q;
      end
    if (RGB_CD_DOT) begin
      `RC_RDIV(q, (cd[0] + cd[1] + cd[2]) <<< G, 4 * S)
      qcd[3*W-1:0] <= {q, q, q};
    end else
      for (l = 0; l < 3; l = l + 1) begin
        `RC_RDIV(q, cd[l] <<< G, 4 * S)
        qcd[l*W+:W] <= q;
      end
    `RC_RDIV(q, ab[3] <<< G, 4 * S)
    qab[3*W+:W] <= q;
    `RC_RDIV(q, cd[3] <<< G, 4 * S)
    qcd[3*W+:W] <= q;
    // SPARE0 alpha of the input set >= 0.5: c >= 2^(N-2) (non-negative); or, MUX_LSB,
    // its low bit.
    mux_cd <= MUX_LSB ? f1[(47-4*6-3)*N] : !f1[(47-4*6-3)*N+N-1] && f1[(47-4*6-3)*N+N-2];
    f2 <= f1;
    // Stage 3: outputs written into the set (RGB lanes 0..2, alpha lane 3).
    f3 = f2;
    for (l = 0; l < 4; l = l + 1) begin
      sum = (l < 3 ? RGB_MUX_SUM : ALPHA_MUX_SUM) ?
          (mux_cd ? $signed(qcd[l*W+:W]) : $signed(qab[l*W+:W])) :
          $signed(qab[l*W+:W]) + $signed(qcd[l*W+:W]);
      if (l < 3) begin
        if (RGB_AB_OUT != 15) begin
          `RC_OUTV(x, qab[l*W+:W], RGB_SCALE, RGB_BIAS)
          f3[(47-4*RGB_AB_OUT-l)*N+:N] = x;
        end
        if (RGB_CD_OUT != 15) begin
          `RC_OUTV(x, qcd[l*W+:W], RGB_SCALE, RGB_BIAS)
          f3[(47-4*RGB_CD_OUT-l)*N+:N] = x;
        end
        if (RGB_SUM_OUT != 15) begin
          `RC_OUTV(x, sum, RGB_SCALE, RGB_BIAS)
          f3[(47-4*RGB_SUM_OUT-l)*N+:N] = x;
        end
      end else begin
        if (ALPHA_AB_OUT != 15) begin
          `RC_OUTV(x, qab[3*W+:W], ALPHA_SCALE, ALPHA_BIAS)
          f3[(47-4*ALPHA_AB_OUT-3)*N+:N] = x;
        end
        if (ALPHA_CD_OUT != 15) begin
          `RC_OUTV(x, qcd[3*W+:W], ALPHA_SCALE, ALPHA_BIAS)
          f3[(47-4*ALPHA_CD_OUT-3)*N+:N] = x;
        end
        if (ALPHA_SUM_OUT != 15) begin
          `RC_OUTV(x, sum, ALPHA_SCALE, ALPHA_BIAS)
          f3[(47-4*ALPHA_SUM_OUT-3)*N+:N] = x;
        end
      end
    end
    // NV2A blue-to-alpha: out1 / out2's blue lane to its register's alpha.
    if (AB_BLUE_TO_ALPHA && RGB_AB_OUT != 15) begin
      `RC_OUTV(x, qab[2*W+:W], RGB_SCALE, RGB_BIAS)
      f3[(47-4*RGB_AB_OUT-3)*N+:N] = x;
    end
    if (CD_BLUE_TO_ALPHA && RGB_CD_OUT != 15) begin
      `RC_OUTV(x, qcd[2*W+:W], RGB_SCALE, RGB_BIAS)
      f3[(47-4*RGB_CD_OUT-3)*N+:N] = x;
    end
    fo <= f3;
  end
`undef RC_RDIV
`undef RC_MAPPED
`undef RC_OUTV
  assign o_zero_r = fo[47*N+:N];
  assign o_zero_g = fo[46*N+:N];
  assign o_zero_b = fo[45*N+:N];
  assign o_zero_a = fo[44*N+:N];
  assign o_ccc0_r = fo[43*N+:N];
  assign o_ccc0_g = fo[42*N+:N];
  assign o_ccc0_b = fo[41*N+:N];
  assign o_ccc0_a = fo[40*N+:N];
  assign o_ccc1_r = fo[39*N+:N];
  assign o_ccc1_g = fo[38*N+:N];
  assign o_ccc1_b = fo[37*N+:N];
  assign o_ccc1_a = fo[36*N+:N];
  assign o_fog_r = fo[35*N+:N];
  assign o_fog_g = fo[34*N+:N];
  assign o_fog_b = fo[33*N+:N];
  assign o_fog_a = fo[32*N+:N];
  assign o_pri_r = fo[31*N+:N];
  assign o_pri_g = fo[30*N+:N];
  assign o_pri_b = fo[29*N+:N];
  assign o_pri_a = fo[28*N+:N];
  assign o_sec_r = fo[27*N+:N];
  assign o_sec_g = fo[26*N+:N];
  assign o_sec_b = fo[25*N+:N];
  assign o_sec_a = fo[24*N+:N];
  assign o_spare0_r = fo[23*N+:N];
  assign o_spare0_g = fo[22*N+:N];
  assign o_spare0_b = fo[21*N+:N];
  assign o_spare0_a = fo[20*N+:N];
  assign o_spare1_r = fo[19*N+:N];
  assign o_spare1_g = fo[18*N+:N];
  assign o_spare1_b = fo[17*N+:N];
  assign o_spare1_a = fo[16*N+:N];
  assign o_tex0_r = fo[15*N+:N];
  assign o_tex0_g = fo[14*N+:N];
  assign o_tex0_b = fo[13*N+:N];
  assign o_tex0_a = fo[12*N+:N];
  assign o_tex1_r = fo[11*N+:N];
  assign o_tex1_g = fo[10*N+:N];
  assign o_tex1_b = fo[9*N+:N];
  assign o_tex1_a = fo[8*N+:N];
  assign o_tex2_r = fo[7*N+:N];
  assign o_tex2_g = fo[6*N+:N];
  assign o_tex2_b = fo[5*N+:N];
  assign o_tex2_a = fo[4*N+:N];
  assign o_tex3_r = fo[3*N+:N];
  assign o_tex3_g = fo[2*N+:N];
  assign o_tex3_b = fo[1*N+:N];
  assign o_tex3_a = fo[0*N+:N];
endmodule
