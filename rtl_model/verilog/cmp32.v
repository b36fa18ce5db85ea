// 32-bit unsigned magnitude comparator a < b: the model's comparator(32).
module cmp32(input [31:0] a, input [31:0] b, output lt);
  assign lt = a < b;
endmodule
