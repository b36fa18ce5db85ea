// 32-bit logical left shift by 0..31 (a 5-stage barrel shifter, a normaliser's
// datapath): the model's shifter(32, 5).
module shl32_5(input [31:0] a, input [4:0] s, output [31:0] y);
  assign y = a << s;
endmodule
