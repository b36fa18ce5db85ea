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
    parameter G_IN = 6, parameter G_MAP = 0, parameter G_USE = 1
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
  // Register i, component c (0 r .. 3 a) at [(47 - 4i - c)*N +: N].
  wire [48*N-1:0] file = `COMBINER_REGISTER_FILE;

  // floor(num / den) + the carry ROUNDING gives, num >= 0.
  function [W-1:0] rdiv;
    input [W-1:0] num;
    input [W-1:0] den;
    reg [W-1:0] q, rem;
    reg up;
    begin
      q = num / den;
      rem = num % den;
      case (ROUNDING)
        0, 1: up = 1'b0;
        2, 4: up = 2 * rem >= den && rem != 0;
        3, 5: up = 2 * rem > den;
        default: up = 2 * rem > den || (2 * rem == den && rem != 0 && q[0]);
      endcase
      rdiv = q + up;
    end
  endfunction

  // Register component, sign-extended to W bits, then max(0, x).
  function [W-1:0] comp;
    input [48*N-1:0] f;
    input integer reg_i;
    input integer c;
    reg [N-1:0] x;
    begin
      x = f[(47-4*reg_i-c)*N+:N];
      comp = (reg_i == 0 || x[N-1]) ? 0 : {{(W - N) {1'b0}}, x};
    end
  endfunction

  // The unsigned mapping of a value already >= 0.
  function [W-1:0] umap;
    input [W-1:0] x;
    input integer m;
    begin
      umap = m == 1 ? (x > S ? 0 : S - x) : x;
    end
  endfunction

  // A register variable on lane l (usage RGB reads the lane; ALPHA 3; BLUE 2).
  function [W-1:0] regvar;
    input [48*N-1:0] f;
    input integer in, m, cu, lane;
    begin
      regvar = umap(comp(f, in, cu == 1 ? 3 : cu == 2 ? 2 : lane), m);
    end
  endfunction

  reg v1, v2;
  reg [W-1:0] va [0:3], vb [0:3], vc [0:3], vd [0:3];
  reg [W-1:0] x2 [0:3];
  reg [OUT_BITS-1:0] y [0:3];
  integer l;
  reg [W-1:0] ef, sum, t;
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
    // Stage 1: the variables A .. D of each RGB lane, G in lane 3's A.
    for (l = 0; l < 3; l = l + 1) begin
      ef = rdiv(regvar(file, E_IN, E_MAP, E_USE, l) * regvar(file, F_IN, F_MAP, F_USE, l), S);
      sum = comp(file, 6, l) + comp(file, 5, l);  // u(N)
      if (COLOR_SUM_CLAMP && sum > S) sum = S;
      va[l] <= A_IN == 12 ? umap(ef, A_MAP) : regvar(file, A_IN, A_MAP, A_USE, l);
      vb[l] <= B_IN == 12 ? umap(ef, B_MAP) : B_IN == 13 ? umap(sum, B_MAP) :
               regvar(file, B_IN, B_MAP, B_USE, l);
      vc[l] <= C_IN == 12 ? umap(ef, C_MAP) : C_IN == 13 ? umap(sum, C_MAP) :
               regvar(file, C_IN, C_MAP, C_USE, l);
      vd[l] <= D_IN == 12 ? umap(ef, D_MAP) : D_IN == 13 ? umap(sum, D_MAP) :
               regvar(file, D_IN, D_MAP, D_USE, l);
    end
    va[3] <= regvar(file, G_IN, G_MAP, G_USE, 3);
    // Stage 2: A*B + (S - A)*C + S*D clamped to S^2; G as it is.
    for (l = 0; l < 3; l = l + 1) begin
      t = va[l] * vb[l] + (S - va[l]) * vc[l] + S * vd[l];
      x2[l] <= t > S * S ? S * S : t;
    end
    x2[3] <= va[3];
    // Stage 3: the output codes.
    for (l = 0; l < 3; l = l + 1) y[l] <= rdiv(x2[l] * U, S * S);
    y[3] <= rdiv(x2[3] * U, S);
  end
  assign r = y[0];
  assign g = y[1];
  assign b = y[2];
  assign a = y[3];
endmodule
