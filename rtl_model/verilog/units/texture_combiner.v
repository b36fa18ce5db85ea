// texture_combiner — one texture-environment stage in COMBINE mode
// (GL_ARB_texture_env_combine / _dot3; rtl_model/src/units/texture_combiner.rs), the
// model's GeforceInteger rounding. The texture-environment state is parameters (one
// configuration per synthesis), coded as the model's enums in declaration order:
//   COMBINE_RGB   0 REPLACE 1 MODULATE 2 ADD 3 ADD_SIGNED 4 INTERPOLATE 5 SUBTRACT
//                 6 DOT3_RGB 7 DOT3_RGBA;  COMBINE_ALPHA 0 ..= 5
//   SRC_RGB, SRC_ALPHA  argument i in bits [2i+1:2i]: 0 TEXTURE 1 CONSTANT
//                       2 PRIMARY_COLOR 3 PREVIOUS
//   OP_RGB        argument i in bits [2i+1:2i]: 0 SRC_COLOR 1 ONE_MINUS_SRC_COLOR
//                 2 SRC_ALPHA 3 ONE_MINUS_SRC_ALPHA
//   OP_ALPHA      argument i in bit i: 0 SRC_ALPHA 1 ONE_MINUS_SRC_ALPHA
//   RGB_SCALE, ALPHA_SCALE  1, 2 or 4
// Each channel's exact value is X / D (D = 1, 2 or N = 2^BITS - 1, fixed by the
// function); X < 0 clamps to 0, X > N*D to N, then one round half up:
// D = 2: (X + 1) >> 1; D = N: t = X + 2^(BITS-1), (t + (t >> BITS)) >> BITS.
// Latency 2, II 1: stage 1 registers X per channel, stage 2 the rounded codes.
module texture_combiner #(
    parameter       BITS          = 8,
    parameter       COMBINE_RGB   = 1,
    parameter       COMBINE_ALPHA = 1,
    parameter [5:0] SRC_RGB       = 6'b01_11_00,  // (CONSTANT, PREVIOUS, TEXTURE)
    parameter [5:0] OP_RGB        = 6'b10_00_00,  // (SRC_ALPHA, SRC_COLOR, SRC_COLOR)
    parameter [5:0] SRC_ALPHA     = 6'b01_11_00,
    parameter [2:0] OP_ALPHA      = 3'b000,
    parameter       RGB_SCALE     = 1,
    parameter       ALPHA_SCALE   = 1
) (
    input                 clk,
    input                 rst,
    input                 in_valid,
    input      [BITS-1:0] texture_r,
    input      [BITS-1:0] texture_g,
    input      [BITS-1:0] texture_b,
    input      [BITS-1:0] texture_a,
    input      [BITS-1:0] constant_r,
    input      [BITS-1:0] constant_g,
    input      [BITS-1:0] constant_b,
    input      [BITS-1:0] constant_a,
    input      [BITS-1:0] primary_r,
    input      [BITS-1:0] primary_g,
    input      [BITS-1:0] primary_b,
    input      [BITS-1:0] primary_a,
    input      [BITS-1:0] previous_r,
    input      [BITS-1:0] previous_g,
    input      [BITS-1:0] previous_b,
    input      [BITS-1:0] previous_a,
    output reg            out_valid,
    output     [BITS-1:0] r,
    output     [BITS-1:0] g,
    output     [BITS-1:0] b,
    output     [BITS-1:0] a
);
  // X is at most s(2n+6) (DOT3 at scale 4); two bits of headroom.
  localparam W = 2 * BITS + 8;
  localparam [BITS-1:0] N = {BITS{1'b1}};
  localparam F_REPLACE = 0, F_MODULATE = 1, F_ADD = 2, F_ADD_SIGNED = 3,
             F_INTERPOLATE = 4, F_SUBTRACT = 5, F_DOT3_RGB = 6, F_DOT3_RGBA = 7;

  // Written for Icarus's interpreter (docs/rtl.md): the sources are concatenated and the
  // arguments, X and the roundings computed in the clocked blocks (continuous
  // assigns and function calls in them were re-evaluated on every one of the 16 input
  // changes), the functions are macros (a function call runs as a thread), every
  // argument's part-select is a constant expression of the parameters.

  localparam signed [W-1:0] NW = $signed({{(W - BITS) {1'b0}}, N});

  // Source s, channel c (0 r .. 3 a) at [(15 - 4s - c)*BITS +: BITS]. Mapped
  // arguments: lane l (0..2 RGB, 3 alpha), argument i at [(3l + i)*BITS +: BITS].
  // RGB argument i of lane L: SRC_ALPHA reads the alpha channel; ONE_MINUS: N - c,
  // the bitwise NOT.
`define TC_RGB_ARG(L, I) \
    ac = sv[(15-4*((SRC_RGB >> (2 * (I))) & 3)-(((OP_RGB >> (2 * (I))) & 3) >= 2 ? 3 : (L)))*BITS+:BITS]; \
    arg[(3*(L)+(I))*BITS+:BITS] = (((OP_RGB >> (2 * (I))) & 3) == 1 || ((OP_RGB >> (2 * (I))) & 3) == 3) ? ~ac : ac;
`define TC_ALPHA_ARG(I) \
    ac = sv[(15-4*((SRC_ALPHA >> (2 * (I))) & 3)-3)*BITS+:BITS]; \
    arg[(9+(I))*BITS+:BITS] = OP_ALPHA[I] ? ~ac : ac;

  // One lane's X for a non-DOT3 function F at scale SC, arguments A0, A1, A2.
`define TC_EXACT(DST, F, SC, A0, A1, A2) \
    e0 = $signed({{(W - BITS) {1'b0}}, A0}); \
    e1 = $signed({{(W - BITS) {1'b0}}, A1}); \
    e2 = $signed({{(W - BITS) {1'b0}}, A2}); \
    case (F) \
      F_REPLACE: DST = (SC) * e0;  /* u(n) << 2 -> u(n+2) */ \
      F_MODULATE: DST = (SC) * (e0 * e1);  /* u(n) x u(n) -> u(2n), << 2 */ \
      F_ADD: DST = (SC) * (e0 + e1);  /* u(n+1) << 2 -> u(n+3) */ \
      F_ADD_SIGNED: DST = (SC) * (2 * (e0 + e1) - NW);  /* s(n+3), scaled s(n+5) */ \
      F_INTERPOLATE: DST = (SC) * (e0 * e2 + e1 * (NW - e2));  /* <= N^2, u(2n+2) */ \
      default: DST = (SC) * (e0 - e1);  /* SUBTRACT: s(n+1) << 2 -> s(n+3) */ \
    endcase

  // DOT3: sum over r, g, b of (2a0 - N)(2a1 - N) (each factor s(n+1), the sum s(2n+4)).
`define TC_DOT3_TERM(K) \
    e0 = 2 * $signed({{(W - BITS) {1'b0}}, arg[(3*(K))*BITS+:BITS]}) - NW; \
    e1 = 2 * $signed({{(W - BITS) {1'b0}}, arg[(3*(K)+1)*BITS+:BITS]}) - NW; \
    dot = dot + e0 * e1;

  // Clamp X / D to [0, N] and round half up once.
`define TC_CLAMP_ROUND(DST, X, D_) \
    cx = X; \
    if (cx < 0) DST = 0; \
    else if ((D_) == 0) DST = cx > NW ? N : cx[BITS-1:0]; \
    else if ((D_) == 1) DST = cx > 2 * NW ? N : ((cx + 1) >>> 1); \
    else if (cx > NW * NW) DST = N; \
    else begin \
      ct = cx + (1 << (BITS - 1));  /* u(2n) + half -> u(2n+1) */ \
      DST = (ct + (ct >>> BITS)) >>> BITS; \
    end

  localparam RGB_DOT3 = COMBINE_RGB == F_DOT3_RGB || COMBINE_RGB == F_DOT3_RGBA;
  // The divisor class of a lane: 0 D = 1, 1 D = 2, 2 D = N.
  localparam RGB_D = RGB_DOT3 ? 2 :
      (COMBINE_RGB == F_MODULATE || COMBINE_RGB == F_INTERPOLATE) ? 2 :
      COMBINE_RGB == F_ADD_SIGNED ? 1 : 0;
  localparam A_D = COMBINE_RGB == F_DOT3_RGBA ? 2 :
      (COMBINE_ALPHA == F_MODULATE || COMBINE_ALPHA == F_INTERPOLATE) ? 2 :
      COMBINE_ALPHA == F_ADD_SIGNED ? 1 : 0;

  // Stage 1: X per lane, lane l at [l*W +: W].
  reg [4*W-1:0] x1;
  reg v1;
  reg [16*BITS-1:0] sv;
  reg [12*BITS-1:0] arg;
  reg [BITS-1:0] ac;
  reg signed [W-1:0] e0, e1, e2, dot, xl;
  always @(posedge clk) begin
    if (rst) v1 <= 1'b0;
    else v1 <= in_valid;
    sv = {
      texture_r, texture_g, texture_b, texture_a,
      constant_r, constant_g, constant_b, constant_a,
      primary_r, primary_g, primary_b, primary_a,
      previous_r, previous_g, previous_b, previous_a
    };
    `TC_RGB_ARG(0, 0)
    `TC_RGB_ARG(0, 1)
    `TC_RGB_ARG(0, 2)
    `TC_RGB_ARG(1, 0)
    `TC_RGB_ARG(1, 1)
    `TC_RGB_ARG(1, 2)
    `TC_RGB_ARG(2, 0)
    `TC_RGB_ARG(2, 1)
    `TC_RGB_ARG(2, 2)
    `TC_ALPHA_ARG(0)
    `TC_ALPHA_ARG(1)
    `TC_ALPHA_ARG(2)
    if (RGB_DOT3 || COMBINE_RGB == F_DOT3_RGBA) begin
      dot = 0;
      `TC_DOT3_TERM(0)
      `TC_DOT3_TERM(1)
      `TC_DOT3_TERM(2)
    end
    if (RGB_DOT3) begin
      xl = RGB_SCALE * dot;
      x1[3*W-1:0] <= {xl, xl, xl};
    end else begin
      `TC_EXACT(xl, COMBINE_RGB, RGB_SCALE, arg[0+:BITS], arg[BITS+:BITS], arg[2*BITS+:BITS])
      x1[0+:W] <= xl;
      `TC_EXACT(xl, COMBINE_RGB, RGB_SCALE, arg[3*BITS+:BITS], arg[4*BITS+:BITS], arg[5*BITS+:BITS])
      x1[W+:W] <= xl;
      `TC_EXACT(xl, COMBINE_RGB, RGB_SCALE, arg[6*BITS+:BITS], arg[7*BITS+:BITS], arg[8*BITS+:BITS])
      x1[2*W+:W] <= xl;
    end
    if (COMBINE_RGB == F_DOT3_RGBA) xl = ALPHA_SCALE * dot;
    else begin
      `TC_EXACT(xl, COMBINE_ALPHA, ALPHA_SCALE, arg[9*BITS+:BITS], arg[10*BITS+:BITS], arg[11*BITS+:BITS])
    end
    x1[3*W+:W] <= xl;
  end

  // Stage 2: the codes.
  reg [4*BITS-1:0] y;
  reg signed [W-1:0] cx, ct;
  reg [BITS-1:0] y0, y1, y2, y3;
  always @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= v1;
    `TC_CLAMP_ROUND(y3, x1[3*W+:W], A_D)
    `TC_CLAMP_ROUND(y2, x1[2*W+:W], RGB_D)
    `TC_CLAMP_ROUND(y1, x1[W+:W], RGB_D)
    `TC_CLAMP_ROUND(y0, x1[0+:W], RGB_D)
    y <= {y3, y2, y1, y0};
  end
`undef TC_RGB_ARG
`undef TC_ALPHA_ARG
`undef TC_EXACT
`undef TC_DOT3_TERM
`undef TC_CLAMP_ROUND
  assign r = y[0+:BITS];
  assign g = y[BITS+:BITS];
  assign b = y[2*BITS+:BITS];
  assign a = y[3*BITS+:BITS];
endmodule
