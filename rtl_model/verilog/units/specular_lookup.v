// specular_lookup — (n·h)^s from a table (rtl_model/src/units/specular_lookup.rs).
// The DOT3 word `dot` (IN_BITS wires, unsigned, or signed two's complement when
// SIGNED = 1: a negative word reads as 0) is an m-bit magnitude code x (m = IN_BITS,
// or IN_BITS - 1 when signed); the table of 2^K entries of B bits is read at the
// position P = x·N/M in u(K).W, N = 2^K - 1, M = 2^m - 1:
//   P = (x·C + 2^(m-1)) >> m, C = POS_SCALE = round(N·2^(W+m)/M) (the writer computes
//   it as the model does), clamped to N·2^W (the guard; it cannot fire). When m = K,
//   C = 2^(W+m) and P = x << W (no multiplier, no clamp).
// The table is outside the module, in two banks of 2^(K-1) words, even entries
// (`even_addr0`/`even_data0`) and odd ones (`odd_addr0`/`odd_data0`), synchronous read
// (the data the clock after the address), so linear reads T_i0 and T_i0+1 on one clock.
//   LINEAR = 0 (nearest): i = (P + 2^(W-1)) >> W, one bank read (bank i[0], address
//     i >> 1), spec = T_i. Latency 2: position | ROM read.
//   LINEAR = 1: i0 = P >> W, f = P mod 2^W; odd bank at i0 >> 1, even bank at
//     (i0 + 1) >> 1 (wrapping at i0 = N, where f = 0 so T_i1 does not matter: the
//     model's min(i0 + 1, N)); T0, T1 swapped by i0[0]; d = T1 - T0 (s(B+1)),
//     d·f (s(B+W+1)); spec = T0 + ((d·f + 2^(W-1)) >>> W). Latency 4:
//     position | ROM reads | d·f | round, + T0.
// II 1. Counters (saturations, overflows, underflows, table reads) are the model's.
module specular_lookup #(
    parameter IN_BITS     = 8,
    parameter SIGNED      = 0,
    parameter TABLE_LOG2  = 8,
    parameter ENTRY_BITS  = 8,
    parameter WEIGHT_BITS = 8,
    parameter LINEAR      = 1,
    parameter POS_SCALE   = 65536
) (
    input                                                clk,
    input                                                rst,
    input                                                in_valid,
    input      [                            IN_BITS-1:0] dot,
    output reg                                           out_valid,
    output     [                         ENTRY_BITS-1:0] spec,
    output     [(TABLE_LOG2 > 1 ? TABLE_LOG2 - 1 : 1)-1:0] even_addr0,
    input      [                         ENTRY_BITS-1:0] even_data0,
    output     [(TABLE_LOG2 > 1 ? TABLE_LOG2 - 1 : 1)-1:0] odd_addr0,
    input      [                         ENTRY_BITS-1:0] odd_data0
);
  localparam M = IN_BITS - SIGNED;  // magnitude bits (= guard bits g)
  localparam K = TABLE_LOG2;
  localparam B = ENTRY_BITS;
  localparam W = WEIGHT_BITS;
  localparam PW = K + W;  // the position u(K).W
  localparam LAT = LINEAR ? 4 : 2;

  // valid chain
  reg [LAT-1:0] vc;
  always @(posedge clk) begin
    if (rst) begin
      vc <= 0;
      out_valid <= 1'b0;
    end else begin
      vc <= {vc[LAT-2:0], in_valid};
      out_valid <= vc[LAT-2];
    end
  end

  // ---- clock 1: magnitude, position ----
  wire [M-1:0] x;
  generate
    if (SIGNED) begin : g_signed
      assign x = dot[IN_BITS-1] ? {M{1'b0}} : dot[M-1:0];  // back-facing reads as 0
    end else begin : g_unsigned
      assign x = dot;
    end
  endgenerate
  wire [PW-1:0] pos;
  generate
    if (M == K) begin : g_exact
      assign pos = {x, {W{1'b0}}};  // C = 2^(W+m): wiring
    end else begin : g_scaled
      localparam CW = K + W + 1;
      localparam XW = M + CW + 1;  // the product, + 2^(m-1)
      localparam [CW-1:0] C = POS_SCALE;
      localparam [PW:0] TOP = ((1 << K) - 1) << W;  // N·2^W
      wire [XW-1:0] prod = x * C + (1 << (M - 1));
      wire [XW-M-1:0] p = prod[XW-1:M];
      assign pos = p > TOP ? TOP[PW-1:0] : p[PW-1:0];  // guard (cannot fire)
    end
  endgenerate
  reg [PW-1:0] pos1;
  always @(posedge clk) pos1 <= pos;

  // ---- clock 2: bank reads ----
  generate
    if (LINEAR) begin : g_linear
      wire [K-1:0] i0 = pos1[PW-1:W];
      if (K > 1) begin : g_banks
        assign odd_addr0  = i0[K-1:1];
        assign even_addr0 = i0[K-1:1] + i0[0];  // wraps at i0 = N (f = 0 there)
      end else begin : g_one
        assign odd_addr0  = 1'b0;
        assign even_addr0 = 1'b0;
      end
      reg [W-1:0] f2;
      reg sel2;
      always @(posedge clk) begin
        f2   <= pos1[W-1:0];
        sel2 <= i0[0];
      end
      // ---- clock 3: swap, d = T1 - T0, d·f ----
      wire [B-1:0] t0 = sel2 ? odd_data0 : even_data0;
      wire [B-1:0] t1 = sel2 ? even_data0 : odd_data0;
      wire signed [B:0] d = $signed({1'b0, t1}) - $signed({1'b0, t0});
      reg signed [B+W+1:0] df3;
      reg [B-1:0] t03;
      always @(posedge clk) begin
        df3 <= d * $signed({1'b0, f2});
        t03 <= t0;
      end
      // ---- clock 4: round (floor shift = half up), + T0 ----
      wire signed [B+W+1:0] r = (df3 + (1 <<< (W - 1))) >>> W;
      wire [B+1:0] sum = {2'b00, t03} + r[B+1:0];
      reg [B-1:0] out4;
      always @(posedge clk) out4 <= sum[B-1:0];
      assign spec = out4;
    end else begin : g_nearest
      wire [PW:0] pr = {1'b0, pos1} + (1 << (W - 1));
      wire [K-1:0] i = pr[PW-1:W];  // <= N: no carry out
      if (K > 1) begin : g_banks
        assign odd_addr0  = i[K-1:1];
        assign even_addr0 = i[K-1:1];
      end else begin : g_one
        assign odd_addr0  = 1'b0;
        assign even_addr0 = 1'b0;
      end
      reg sel2;
      always @(posedge clk) sel2 <= i[0];
      assign spec = sel2 ? odd_data0 : even_data0;
    end
  endgenerate
endmodule
