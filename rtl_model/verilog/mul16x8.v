// 16 x 8 unsigned multiplier, 24-bit product: the model's multiplier(16, 8).
module mul16x8(input [15:0] a, input [7:0] b, output [23:0] p);
  assign p = a * b;
endmodule
