// modulate — GL_MODULATE on BITS-bit unorms, the model's Exact mode
// (rtl_model/src/units/modulate.rs): t = a*b + 2^(BITS-1); y = (t + (t >> BITS)) >> BITS.
// Latency 2, II 1: stage 1 registers the product, stage 2 the rounded result.
module modulate #(
    parameter BITS = 8
) (
    input                 clk,
    input                 rst,
    input                 in_valid,
    input      [BITS-1:0] a,
    input      [BITS-1:0] b,
    output reg            out_valid,
    output reg [BITS-1:0] y
);
  reg  [2*BITS-1:0] p;  // u(n) x u(n) -> u(2n)
  reg               v1;
  wire [2*BITS:0]   t = {1'b0, p} + (1 << (BITS - 1));  // u(2n) + half -> u(2n+1)
  wire [2*BITS+1:0] s = {1'b0, t} + {{(BITS + 1) {1'b0}}, t[2*BITS:BITS]};
  always @(posedge clk) begin
    if (rst) begin
      v1 <= 1'b0;
      out_valid <= 1'b0;
    end else begin
      v1 <= in_valid;
      out_valid <= v1;
    end
    p <= a * b;
    y <= s[2*BITS-1:BITS];
  end
endmodule
