// 16 x 16 unsigned multiplier, 32-bit product: the model's multiplier(16, 16).
module mul16x16(input [15:0] a, input [15:0] b, output [31:0] p);
  assign p = a * b;
endmodule
