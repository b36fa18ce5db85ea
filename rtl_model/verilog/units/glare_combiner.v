// glare_combiner — adds a modulator's RGB luminance into the framebuffer with
// saturation (rtl_model/src/units/glare_combiner.rs):
// out_c = min(fb_c + lum_c, 2^FB_BITS - 1). Latency 1, II 1 (the output register).
module glare_combiner #(
    parameter FB_BITS  = 8,
    parameter LUM_BITS = 12
) (
    input                     clk,
    input                     rst,
    input                     in_valid,
    input      [ FB_BITS-1:0] fb_r,
    input      [ FB_BITS-1:0] fb_g,
    input      [ FB_BITS-1:0] fb_b,
    input      [LUM_BITS-1:0] lum_r,
    input      [LUM_BITS-1:0] lum_g,
    input      [LUM_BITS-1:0] lum_b,
    output reg                out_valid,
    output reg [ FB_BITS-1:0] r,
    output reg [ FB_BITS-1:0] g,
    output reg [ FB_BITS-1:0] b
);
  localparam W = (FB_BITS > LUM_BITS ? FB_BITS : LUM_BITS) + 1;
  localparam [W-1:0] MAX = {FB_BITS{1'b1}};
  // u(fb) + u(lum) -> u(max(fb, lum) + 1)
  wire [W-1:0] sr = fb_r + lum_r;
  wire [W-1:0] sg = fb_g + lum_g;
  wire [W-1:0] sb = fb_b + lum_b;
  always @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= in_valid;
    r <= sr > MAX ? MAX[FB_BITS-1:0] : sr[FB_BITS-1:0];
    g <= sg > MAX ? MAX[FB_BITS-1:0] : sg[FB_BITS-1:0];
    b <= sb > MAX ? MAX[FB_BITS-1:0] : sb[FB_BITS-1:0];
  end
endmodule
