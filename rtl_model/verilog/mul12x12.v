// 12 x 12 unsigned multiplier, 24-bit product: the model's multiplier(12, 12).
module mul12x12(input [11:0] a, input [11:0] b, output [23:0] p);
  assign p = a * b;
endmodule
