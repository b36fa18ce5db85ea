// texture_sampler — 2D bilinear texture lookup, one channel
// (rtl_model/src/units/texture_sampler.rs at dims = 2, channels = 1, filter = linear,
// texels_per_clock = 4, so II = 1). The texel memory is outside the module: four
// synchronous read ports `texels_addr<i>` / `texels_data<i>` (data the clock after the
// address), corner i = (x_{i&1}, y_{i>>1}), address y*SIZE_W + x.
// Per axis, from the s(I).F texel-space coordinate c:
//   p = c - 1/2 in s(I+1).FP, FP = max(F, 1); i0 = floor(p), i1 = i0 + 1;
//   the fraction reduced to WEIGHT_BITS by WEIGHT_ROUNDING (0 round half up,
//   1 truncate, 2 round half to even) -> fx in [0, W], W = 2^WB; weights W - fx, fx;
//   ADDR_S / ADDR_T: 0 clamp to edge, 1 repeat (floored remainder).
// FILTER_ROUNDING 0 (product weights, the default): the four texel x (wx*wy) products
// summed exactly and rounded once, half up: latency 4 = address/weights | RAM read
// and lane weights | texel x weight | adder tree and round.
// FILTER_ROUNDING 1 (successive lerps, llvmpipe): v0 + ((w*(v1 - v0) + W/2) >>> WB)
// along s, then t: latency 4 = address/weights | RAM read | s lerps | t lerp.
module texture_sampler #(
    parameter SIZE_W          = 256,
    parameter SIZE_H          = 256,
    parameter TEXEL_BITS      = 8,
    parameter COORD_INT_BITS  = 16,
    parameter COORD_FRAC_BITS = 8,
    parameter WEIGHT_BITS     = 8,
    parameter WEIGHT_ROUNDING = 0,
    parameter FILTER_ROUNDING = 0,
    parameter ADDR_S          = 0,
    parameter ADDR_T          = 0,
    parameter ADDR_BITS       = 16
) (
    input                                          clk,
    input                                          rst,
    input                                          in_valid,
    input      [COORD_INT_BITS+COORD_FRAC_BITS-1:0] coord_s,
    input      [COORD_INT_BITS+COORD_FRAC_BITS-1:0] coord_t,
    output reg                                     out_valid,
    output reg [                   TEXEL_BITS-1:0] ch0,
    output     [                    ADDR_BITS-1:0] texels_addr0,
    output     [                    ADDR_BITS-1:0] texels_addr1,
    output     [                    ADDR_BITS-1:0] texels_addr2,
    output     [                    ADDR_BITS-1:0] texels_addr3,
    input      [                   TEXEL_BITS-1:0] texels_data0,
    input      [                   TEXEL_BITS-1:0] texels_data1,
    input      [                   TEXEL_BITS-1:0] texels_data2,
    input      [                   TEXEL_BITS-1:0] texels_data3
);
  localparam TB = TEXEL_BITS;
  localparam WB = WEIGHT_BITS;
  localparam [WB:0] W = 1 << WB;

  // ---- clock 1: per-axis set-up, corner addresses ----
  wire [WB:0] fx_s, fx_t;
  wire [31:0] is0, is1, it0, it1;  // axis indices after the address mode
  texture_sampler_axis #(
      .SIZE(SIZE_W),
      .I(COORD_INT_BITS),
      .F(COORD_FRAC_BITS),
      .WB(WB),
      .ROUNDING(WEIGHT_ROUNDING),
      .MODE(ADDR_S)
  ) ax_s (
      .c (coord_s),
      .fx(fx_s),
      .i0(is0),
      .i1(is1)
  );
  texture_sampler_axis #(
      .SIZE(SIZE_H),
      .I(COORD_INT_BITS),
      .F(COORD_FRAC_BITS),
      .WB(WB),
      .ROUNDING(WEIGHT_ROUNDING),
      .MODE(ADDR_T)
  ) ax_t (
      .c (coord_t),
      .fx(fx_t),
      .i0(it0),
      .i1(it1)
  );
  // y*w + x: a concatenation when SIZE_W is a power of two.
  wire [ADDR_BITS-1:0] a0 = it0 * SIZE_W + is0;
  wire [ADDR_BITS-1:0] a1 = it0 * SIZE_W + is1;
  wire [ADDR_BITS-1:0] a2 = it1 * SIZE_W + is0;
  wire [ADDR_BITS-1:0] a3 = it1 * SIZE_W + is1;

  reg v1, v2, v3;
  reg [ADDR_BITS-1:0] ra0, ra1, ra2, ra3;
  reg [WB:0] fs1, ft1;
  always @(posedge clk) begin
    if (rst) begin
      v1 <= 1'b0;
      v2 <= 1'b0;
      v3 <= 1'b0;
      out_valid <= 1'b0;
    end else begin
      v1 <= in_valid;
      v2 <= v1;
      v3 <= v2;
      out_valid <= v3;
    end
    ra0 <= a0;
    ra1 <= a1;
    ra2 <= a2;
    ra3 <= a3;
    fs1 <= fx_s;
    ft1 <= fx_t;
  end
  assign texels_addr0 = ra0;
  assign texels_addr1 = ra1;
  assign texels_addr2 = ra2;
  assign texels_addr3 = ra3;

  generate
    if (FILTER_ROUNDING == 0) begin : g_product
      // ---- clock 2: lane weights u(WB+1)^2 -> u(2WB+1) while the RAM reads ----
      localparam PW = 2 * WB + 1;
      localparam ACC = TB + 2 * WB;
      // Axis weights W - fx, fx: u(WB+1) each (fx <= W).
      wire [WB:0] ws0 = W - fs1, wt0 = W - ft1;
      reg [PW-1:0] pw0, pw1, pw2, pw3;
      always @(posedge clk) begin
        pw0 <= ws0 * wt0;
        pw1 <= fs1 * wt0;
        pw2 <= ws0 * ft1;
        pw3 <= fs1 * ft1;
      end
      // ---- clock 3: texel x weight, u(TB) x u(2WB+1) -> < 2^(TB+2WB) ----
      reg [ACC-1:0] p0, p1, p2, p3;
      always @(posedge clk) begin
        p0 <= texels_data0 * pw0;
        p1 <= texels_data1 * pw1;
        p2 <= texels_data2 * pw2;
        p3 <= texels_data3 * pw3;
      end
      // ---- clock 4: adder tree, round half up, >> 2WB ----
      wire [ACC:0] sum = p0 + p1 + p2 + p3 + (1 << (2 * WB - 1));
      always @(posedge clk) ch0 <= sum[ACC-1:2*WB];
    end else begin : g_lerps
      reg [WB:0] fs2, ft2, ft3;
      always @(posedge clk) begin
        fs2 <= fs1;
        ft2 <= ft1;
        ft3 <= ft2;
      end
      // ---- clock 3: lerp along s, rows y0 and y1 ----
      wire [TB-1:0] l0, l1, l2;
      texture_sampler_lerp #(
          .TB(TB),
          .WB(WB)
      ) lerp_s0 (
          .w (fs2),
          .v0(texels_data0),
          .v1(texels_data1),
          .o (l0)
      );
      texture_sampler_lerp #(
          .TB(TB),
          .WB(WB)
      ) lerp_s1 (
          .w (fs2),
          .v0(texels_data2),
          .v1(texels_data3),
          .o (l1)
      );
      reg [TB-1:0] r0, r1;
      always @(posedge clk) begin
        r0 <= l0;
        r1 <= l1;
      end
      // ---- clock 4: lerp along t ----
      texture_sampler_lerp #(
          .TB(TB),
          .WB(WB)
      ) lerp_t (
          .w (ft3),
          .v0(r0),
          .v1(r1),
          .o (l2)
      );
      always @(posedge clk) ch0 <= l2;
    end
  endgenerate
endmodule

// One axis: the two texel indices (address mode applied) and the upper weight fx.
module texture_sampler_axis #(
    parameter SIZE     = 256,
    parameter I        = 16,
    parameter F        = 8,
    parameter WB       = 8,
    parameter ROUNDING = 0,
    parameter MODE     = 0
) (
    input  [I+F-1:0] c,
    output [   WB:0] fx,
    output [   31:0] i0,
    output [   31:0] i1
);
  localparam FP = F > 0 ? F : 1;
  // p = c - 1/2: s(I).F -> s(I+1).FP, exact.
  wire signed [I+FP:0] cw = $signed(c);
  wire signed [I+FP:0] p = (cw <<< (FP - F)) - (1 <<< (FP - 1));
  wire signed [I+FP:0] j0 = p >>> FP;  // floor(p): s(I+1)
  wire signed [I+FP:0] j1 = j0 + 1;
  wire [FP-1:0] fr = p[FP-1:0];  // u(FP)
  generate
    if (FP <= WB) begin : g_exact
      assign fx = {1'b0, fr} << (WB - FP);
    end else begin : g_reduce
      localparam S = FP - WB;
      wire [WB-1:0] q = fr >> S;
      wire [S-1:0] rem = fr[S-1:0];
      wire [S-1:0] half = 1 << (S - 1);
      if (ROUNDING == 0) begin : g_round
        assign fx = ({1'b0, fr} + (1 << (S - 1))) >> S;
      end else if (ROUNDING == 1) begin : g_trunc
        assign fx = {1'b0, q};
      end else begin : g_even
        assign fx = q + (rem > half || (rem == half && q[0]));
      end
    end
  endgenerate
  texture_sampler_wrap #(
      .SIZE(SIZE),
      .N(I + FP + 1),
      .MODE(MODE)
  ) w0 (
      .i(j0),
      .o(i0)
  );
  texture_sampler_wrap #(
      .SIZE(SIZE),
      .N(I + FP + 1),
      .MODE(MODE)
  ) w1 (
      .i(j1),
      .o(i1)
  );
endmodule

// Address mode of one index: clamp to [0, SIZE - 1], or floored i mod SIZE.
module texture_sampler_wrap #(
    parameter SIZE = 256,
    parameter N    = 25,
    parameter MODE = 0
) (
    input  signed [N-1:0] i,
    output        [ 31:0] o
);
  generate
    if (MODE == 0) begin : g_clamp
      assign o = i < 0 ? 0 : i > SIZE - 1 ? SIZE - 1 : i;
    end else if ((SIZE & (SIZE - 1)) == 0) begin : g_mask
      assign o = i & (SIZE - 1);
    end else begin : g_rem
      wire signed [N:0] r = i % SIZE;
      assign o = r < 0 ? r + SIZE : r;
    end
  endgenerate
endmodule

// One successive lerp: v0 + ((w*(v1 - v0) + W/2) >>> WB), w in [0, 2^WB].
module texture_sampler_lerp #(
    parameter TB = 8,
    parameter WB = 8
) (
    input  [   WB:0] w,
    input  [ TB-1:0] v0,
    input  [ TB-1:0] v1,
    output [ TB-1:0] o
);
  wire signed [TB:0] d = $signed({1'b0, v1}) - $signed({1'b0, v0});  // s(TB+1)
  wire signed [WB+1:0] ws = $signed({1'b0, w});  // s(WB+2)
  wire signed [TB+WB+2:0] prod = ws * d;  // s(TB+WB+3)
  wire signed [TB+WB+2:0] sh = (prod + (1 <<< (WB - 1))) >>> WB;
  wire signed [TB+WB+2:0] sum = $signed({1'b0, v0}) + sh;
  assign o = sum[TB-1:0];
endmodule
