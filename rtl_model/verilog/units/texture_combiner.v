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

  // Source s, channel c (0 r .. 3 a) at [(15 - 4s - c)*BITS +: BITS].
  wire [16*BITS-1:0] src = {
    texture_r, texture_g, texture_b, texture_a,
    constant_r, constant_g, constant_b, constant_a,
    primary_r, primary_g, primary_b, primary_a,
    previous_r, previous_g, previous_b, previous_a
  };

  // Mapped arguments: lane l (0..2 RGB, 3 alpha), argument i at [(3l + i)*BITS +: BITS].
  wire [12*BITS-1:0] arg;
  genvar l, i;
  generate
    for (l = 0; l < 3; l = l + 1) begin : rgb_lane
      for (i = 0; i < 3; i = i + 1) begin : rgb_arg
        localparam S = (SRC_RGB >> (2 * i)) & 3;
        localparam O = (OP_RGB >> (2 * i)) & 3;
        localparam C = O >= 2 ? 3 : l;  // SRC_ALPHA reads the alpha channel
        wire [BITS-1:0] code = src[(15-4*S-C)*BITS+:BITS];
        // ONE_MINUS: N - c, the bitwise NOT.
        assign arg[(3*l+i)*BITS+:BITS] = (O == 1 || O == 3) ? ~code : code;
      end
    end
    for (i = 0; i < 3; i = i + 1) begin : alpha_arg
      localparam S = (SRC_ALPHA >> (2 * i)) & 3;
      wire [BITS-1:0] code = src[(15-4*S-3)*BITS+:BITS];
      assign arg[(9+i)*BITS+:BITS] = OP_ALPHA[i] ? ~code : code;
    end
  endgenerate

  // One lane's X for a non-DOT3 function F at scale SC.
  function signed [W-1:0] exact;
    input integer f;
    input integer sc;
    input [BITS-1:0] a0, a1, a2;
    reg signed [W-1:0] x0, x1, x2, n;
    begin
      x0 = $signed({{(W - BITS) {1'b0}}, a0});
      x1 = $signed({{(W - BITS) {1'b0}}, a1});
      x2 = $signed({{(W - BITS) {1'b0}}, a2});
      n  = $signed({{(W - BITS) {1'b0}}, N});
      case (f)
        F_REPLACE: exact = sc * x0;  // u(n) << 2 -> u(n+2)
        F_MODULATE: exact = sc * (x0 * x1);  // u(n) x u(n) -> u(2n), << 2
        F_ADD: exact = sc * (x0 + x1);  // u(n+1) << 2 -> u(n+3)
        F_ADD_SIGNED: exact = sc * (2 * (x0 + x1) - n);  // s(n+3), scaled s(n+5)
        F_INTERPOLATE: exact = sc * (x0 * x2 + x1 * (n - x2));  // <= N^2, u(2n+2)
        default: exact = sc * (x0 - x1);  // SUBTRACT: s(n+1) << 2 -> s(n+3)
      endcase
    end
  endfunction

  // DOT3: sum over r, g, b of (2a0 - N)(2a1 - N) (each factor s(n+1), the sum s(2n+4)).
  function signed [W-1:0] dot3;
    input [12*BITS-1:0] args;
    integer k;
    reg signed [W-1:0] p, q;
    begin
      dot3 = 0;
      for (k = 0; k < 3; k = k + 1) begin
        p = 2 * $signed({{(W - BITS) {1'b0}}, args[(3*k)*BITS+:BITS]})
            - $signed({{(W - BITS) {1'b0}}, N});
        q = 2 * $signed({{(W - BITS) {1'b0}}, args[(3*k+1)*BITS+:BITS]})
            - $signed({{(W - BITS) {1'b0}}, N});
        dot3 = dot3 + p * q;
      end
    end
  endfunction

  localparam RGB_DOT3 = COMBINE_RGB == F_DOT3_RGB || COMBINE_RGB == F_DOT3_RGBA;
  // The divisor class of a lane: 0 D = 1, 1 D = 2, 2 D = N.
  localparam RGB_D = RGB_DOT3 ? 2 :
      (COMBINE_RGB == F_MODULATE || COMBINE_RGB == F_INTERPOLATE) ? 2 :
      COMBINE_RGB == F_ADD_SIGNED ? 1 : 0;
  localparam A_D = COMBINE_RGB == F_DOT3_RGBA ? 2 :
      (COMBINE_ALPHA == F_MODULATE || COMBINE_ALPHA == F_INTERPOLATE) ? 2 :
      COMBINE_ALPHA == F_ADD_SIGNED ? 1 : 0;

  wire signed [W-1:0] dot = dot3(arg);
  // X of lane l at [l*W +: W].
  wire [4*W-1:0] xr;
  generate
    for (l = 0; l < 3; l = l + 1) begin : rgb_x
      assign xr[l*W+:W] = RGB_DOT3 ? RGB_SCALE * dot :
          exact(COMBINE_RGB, RGB_SCALE, arg[(3*l)*BITS+:BITS], arg[(3*l+1)*BITS+:BITS],
                arg[(3*l+2)*BITS+:BITS]);
    end
  endgenerate
  assign xr[3*W+:W] = COMBINE_RGB == F_DOT3_RGBA ? ALPHA_SCALE * dot :
      exact(COMBINE_ALPHA, ALPHA_SCALE, arg[9*BITS+:BITS], arg[10*BITS+:BITS],
            arg[11*BITS+:BITS]);

  // Stage 1: X per lane.
  reg [4*W-1:0] x1;
  reg v1;
  always @(posedge clk) begin
    if (rst) v1 <= 1'b0;
    else v1 <= in_valid;
    x1 <= xr;
  end

  // Clamp X / D to [0, N] and round half up once.
  function [BITS-1:0] clamp_round;
    input signed [W-1:0] x;
    input integer d;
    reg signed [W-1:0] n, t;
    begin
      n = $signed({{(W - BITS) {1'b0}}, N});
      if (x < 0) clamp_round = 0;
      else if (d == 0) clamp_round = x > n ? N : x[BITS-1:0];
      else if (d == 1) clamp_round = x > 2 * n ? N : ((x + 1) >>> 1);
      else if (x > n * n) clamp_round = N;
      else begin
        t = x + (1 << (BITS - 1));  // u(2n) + half -> u(2n+1)
        clamp_round = (t + (t >>> BITS)) >>> BITS;
      end
    end
  endfunction

  // Stage 2: the codes.
  reg [4*BITS-1:0] y;
  always @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= v1;
    y <= {clamp_round(x1[3*W+:W], A_D), clamp_round(x1[2*W+:W], RGB_D),
          clamp_round(x1[W+:W], RGB_D), clamp_round(x1[0+:W], RGB_D)};
  end
  assign r = y[0+:BITS];
  assign g = y[BITS+:BITS];
  assign b = y[2*BITS+:BITS];
  assign a = y[3*BITS+:BITS];
endmodule
