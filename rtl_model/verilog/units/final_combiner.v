// final_combiner — GL_NV_register_combiners' final combiner
// (rtl_model/src/units/final_combiner.rs): per RGB lane
// out = round(U * clamp(A*B + (S - A)*C + S*D, S^2) / S^2), alpha = round(U * G / S),
// S = 2^(N-1) - 1 the code of 1.0 in an N-bit signed register, U = 2^OUT_BITS - 1.
// E_TIMES_F = round(E*F / S); SPARE0_PLUS_SECONDARY_COLOR = max(spare0, 0) +
// max(secondary, 0), clamped to S when COLOR_SUM_CLAMP. Every value divided is >= 0,
// so each rounding is floor + a carry chosen by ROUNDING (the model's Quant, in
// declaration order: 0 TRN 1 TRN_ZERO 2 RND 3 RND_ZERO 4 RND_INF 5 RND_MIN_INF
// 6 RND_CONV). The configuration is parameters; variable V = A .. G has
//   V_IN   0 .. 11 a register (Table NV_register_combiners.1 order: ZERO, CONSTANT_COLOR0,
//          CONSTANT_COLOR1, FOG, PRIMARY, SECONDARY, SPARE0, SPARE1, TEXTURE0 .. 3),
//          12 E_TIMES_F, 13 SPARE0_PLUS_SECONDARY_COLOR
//   V_MAP  0 UNSIGNED_IDENTITY (max(0, x)), 1 UNSIGNED_INVERT (S - min(max(0, x), S))
//   V_USE  0 RGB, 1 ALPHA, 2 BLUE
// NV2A modes (0 = the GeForce default): INVERT_R0 / INVERT_V1 put SPARE0 / SECONDARY
// under UNSIGNED_INVERT in the colour sum; FINAL_CONST 1 reads C0_R .. C1_A (codes) as
// CONSTANT_COLOR0/1 instead of the set's.
// Latency 3, II 1: stage 1 the variables, stage 2 the clamped sums, stage 3 the codes.
module final_combiner #(
    parameter N = 9,
    parameter OUT_BITS = 8,
    parameter ROUNDING = 2,
    parameter COLOR_SUM_CLAMP = 0,
    parameter A_IN = 3, parameter A_MAP = 0, parameter A_USE = 1,
    parameter B_IN = 13, parameter B_MAP = 0, parameter B_USE = 0,
    parameter C_IN = 3, parameter C_MAP = 0, parameter C_USE = 0,
    parameter D_IN = 0, parameter D_MAP = 0, parameter D_USE = 0,
    parameter E_IN = 0, parameter E_MAP = 0, parameter E_USE = 0,
    parameter F_IN = 0, parameter F_MAP = 0, parameter F_USE = 0,
    parameter G_IN = 6, parameter G_MAP = 0, parameter G_USE = 1,
    parameter INVERT_R0 = 0, parameter INVERT_V1 = 0, parameter FINAL_CONST = 0,
    parameter C0_R = 0, parameter C0_G = 0, parameter C0_B = 0, parameter C0_A = 0,
    parameter C1_R = 0, parameter C1_G = 0, parameter C1_B = 0, parameter C1_A = 0
) (
    input clk,
    input rst,
    input in_valid,
`include "combiner_register_file.vh"
    output reg out_valid,
    output [OUT_BITS-1:0] r,
    output [OUT_BITS-1:0] g,
    output [OUT_BITS-1:0] b,
    output [OUT_BITS-1:0] a
);
  localparam [63:0] S = (64'd1 << (N - 1)) - 1;
  localparam [63:0] U = (64'd1 << OUT_BITS) - 1;
  // Wide enough for U * S^2: 2(N-1) + OUT_BITS bits, plus headroom.
  localparam W = 2 * N + OUT_BITS + 2;
  // Written for Icarus's interpreter (docs/rtl.md): the register file is concatenated
  // in the clocked block (a continuous concatenation of the 48 ports is rebuilt on each
  // port's change), the roundings and variable reads are macros (a function call runs
  // as a thread, and copied the 48N-bit file on every call), and E_TIMES_F and the
  // colour sum are formed only when a variable reads them. The macros use the block's
  // temporaries below.

  // DST = floor(NUM / DEN) + the carry ROUNDING gives, NUM >= 0; NUM, DEN at W bits.
`define FC_RDIV(DST, NUM, DEN) \
    rn = NUM; \
    rd = DEN; \
    rq = rn / rd; \
    rr = rn % rd; \
    case (ROUNDING) \
      0, 1: rup = 1'b0; \
      2, 4: rup = 2 * rr >= rd && rr != 0; \
      3, 5: rup = 2 * rr > rd; \
      default: rup = 2 * rr > rd || (2 * rr == rd && rr != 0 && rq[0]); \
    endcase \
    DST = rq + rup;

  // DST = register REG's component C (register i, component c (0 r .. 3 a) at
  // [(47 - 4i - c)*N +: N]), sign-extended to W bits, then max(0, x).
`define FC_COMP(DST, REG, C) \
    cx = fl[(47-4*(REG)-(C))*N+:N]; \
    DST = ((REG) == 0 || cx[N-1]) ? 0 : {{(W - N) {1'b0}}, cx};

  // DST = the unsigned mapping M of X (a W-bit variable, already >= 0).
`define FC_UMAP(DST, X, M) \
    DST = (M) == 1 ? (X > S ? 0 : S - X) : X;

  // DST = a register variable on lane LANE (usage RGB reads the lane; ALPHA 3; BLUE 2).
`define FC_REGVAR(DST, IN, M, CU, LANE) \
    `FC_COMP(ct, IN, (CU) == 1 ? 3 : (CU) == 2 ? 2 : (LANE)) \
    `FC_UMAP(DST, ct, M)

  // DST = variable V (IN, MAP, USE) on lane l: a register, E_TIMES_F or the colour sum.
`define FC_VAR(DST, IN, M, CU) \
    if ((IN) == 12) begin \
      `FC_UMAP(DST, ef, M) \
    end else if ((IN) == 13) begin \
      `FC_UMAP(DST, sum, M) \
    end else begin \
      `FC_REGVAR(DST, IN, M, CU, l) \
    end

  localparam EF = A_IN == 12 || B_IN == 12 || C_IN == 12 || D_IN == 12;
  localparam CS = B_IN == 13 || C_IN == 13 || D_IN == 13;
  reg v1, v2;
  reg [W-1:0] va [0:3], vb [0:3], vc [0:3], vd [0:3];
  reg [W-1:0] x2 [0:3];
  reg [OUT_BITS-1:0] y [0:3];
  integer l;
  reg [48*N-1:0] fl;
  reg [W-1:0] ef, sum, t, te, tv;
  // the macros' temporaries
  reg [N-1:0] cx;
  reg [W-1:0] ct, rn, rd, rq, rr;
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
    fl = `COMBINER_REGISTER_FILE;
    if (FINAL_CONST) begin
      fl[43*N+:N] = C0_R;
      fl[42*N+:N] = C0_G;
      fl[41*N+:N] = C0_B;
      fl[40*N+:N] = C0_A;
      fl[39*N+:N] = C1_R;
      fl[38*N+:N] = C1_G;
      fl[37*N+:N] = C1_B;
      fl[36*N+:N] = C1_A;
    end
    // Stage 1: the variables A .. D of each RGB lane, G in lane 3's A.
    for (l = 0; l < 3; l = l + 1) begin
      if (EF) begin
        `FC_REGVAR(te, E_IN, E_MAP, E_USE, l)
        `FC_REGVAR(tv, F_IN, F_MAP, F_USE, l)
        `FC_RDIV(ef, te * tv, S)
      end
      if (CS) begin
        `FC_COMP(te, 6, l)
        `FC_COMP(tv, 5, l)
        if (INVERT_R0) te = te > S ? 0 : S - te;
        if (INVERT_V1) tv = tv > S ? 0 : S - tv;
        sum = te + tv;  // u(N)
        if (COLOR_SUM_CLAMP && sum > S) sum = S;
      end
      `FC_VAR(t, A_IN, A_MAP, A_USE)
      va[l] <= t;
      `FC_VAR(t, B_IN, B_MAP, B_USE)
      vb[l] <= t;
      `FC_VAR(t, C_IN, C_MAP, C_USE)
      vc[l] <= t;
      `FC_VAR(t, D_IN, D_MAP, D_USE)
      vd[l] <= t;
    end
    `FC_REGVAR(t, G_IN, G_MAP, G_USE, 3)
    va[3] <= t;
    // Stage 2: A*B + (S - A)*C + S*D clamped to S^2; G as it is.
    for (l = 0; l < 3; l = l + 1) begin
      t = va[l] * vb[l] + (S - va[l]) * vc[l] + S * vd[l];
      x2[l] <= t > S * S ? S * S : t;
    end
    x2[3] <= va[3];
    // Stage 3: the output codes.
    for (l = 0; l < 3; l = l + 1) begin
      `FC_RDIV(t, x2[l] * U, S * S)
      y[l] <= t;
    end
    `FC_RDIV(t, x2[3] * U, S)
    y[3] <= t;
  end
`undef FC_RDIV
`undef FC_COMP
`undef FC_UMAP
`undef FC_REGVAR
`undef FC_VAR
  assign r = y[0];
  assign g = y[1];
  assign b = y[2];
  assign a = y[3];
endmodule
