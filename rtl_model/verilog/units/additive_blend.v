// additive_blend — the (GL_ONE, GL_ONE) framebuffer blend with saturation, four
// channels (rtl_model/src/units/additive_blend.rs, unweighted, FB_BITS >= SRC_BITS):
// y_c = min(dst_c + widen(src_c), 2^FB_BITS - 1), the source widened to FB_BITS by
// bit replication. Latency 3, II 1: stage 1 aligns the source and holds the
// framebuffer read; stage 2 adds and saturates; stage 3 is the write-back register.
module additive_blend #(
    parameter SRC_BITS = 8,
    parameter FB_BITS  = 8
) (
    input                    clk,
    input                    rst,
    input                    in_valid,
    input     [SRC_BITS-1:0] src_r,
    input     [SRC_BITS-1:0] src_g,
    input     [SRC_BITS-1:0] src_b,
    input     [SRC_BITS-1:0] src_a,
    input     [ FB_BITS-1:0] dst_r,
    input     [ FB_BITS-1:0] dst_g,
    input     [ FB_BITS-1:0] dst_b,
    input     [ FB_BITS-1:0] dst_a,
    output reg               out_valid,
    output    [ FB_BITS-1:0] y_r,
    output    [ FB_BITS-1:0] y_g,
    output    [ FB_BITS-1:0] y_b,
    output    [ FB_BITS-1:0] y_a
);
  localparam REP = (FB_BITS + SRC_BITS - 1) / SRC_BITS;
  localparam [FB_BITS-1:0] MAX = {FB_BITS{1'b1}};
  wire [4*SRC_BITS-1:0] src = {src_r, src_g, src_b, src_a};
  wire [4*FB_BITS-1:0] dst = {dst_r, dst_g, dst_b, dst_a};
  reg [4*FB_BITS-1:0] q1, d1, s2, y3;
  reg v1, v2;
  integer c;
  reg [REP*SRC_BITS-1:0] rep;
  reg [FB_BITS:0] sum;  // u(f) + u(f) -> u(f+1)
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
    for (c = 0; c < 4; c = c + 1) begin
      rep = {REP{src[c*SRC_BITS+:SRC_BITS]}};
      q1[c*FB_BITS+:FB_BITS] <= rep[REP*SRC_BITS-1-:FB_BITS];  // widen: wiring only
      sum = {1'b0, q1[c*FB_BITS+:FB_BITS]} + {1'b0, d1[c*FB_BITS+:FB_BITS]};
      s2[c*FB_BITS+:FB_BITS] <= sum[FB_BITS] ? MAX : sum[FB_BITS-1:0];
    end
    d1 <= dst;
    y3 <= s2;
  end
  assign {y_r, y_g, y_b, y_a} = y3;
endmodule
