// 8 x 8 unsigned multiplier, 16-bit product: the model's multiplier(8, 8).
module mul8x8(input [7:0] a, input [7:0] b, output [15:0] p);
  assign p = a * b;
endmodule
