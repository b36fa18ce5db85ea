// 16-bit unsigned magnitude comparator a < b: the model's comparator(16).
module cmp16(input [15:0] a, input [15:0] b, output lt);
  assign lt = a < b;
endmodule
