// 8-bit unsigned saturating adder: min(a + b, 255), the additive blend's datapath.
module satadd8(input [7:0] a, input [7:0] b, output [7:0] s);
  wire [8:0] sum = a + b;
  assign s = sum[8] ? 8'hff : sum[7:0];
endmodule
