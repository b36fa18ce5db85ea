// 32 x 16 unsigned multiplier, 48-bit product: the model's multiplier(32, 16), the
// shape of the units' wide products (32×21, 32×29, 52×19, …).
module mul32x16(input [31:0] a, input [15:0] b, output [47:0] p);
  assign p = a * b;
endmodule
