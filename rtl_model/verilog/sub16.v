// 16-bit unsigned subtractor with borrow out: d[16] = (a < b). The model's subtractor(16).
module sub16(input [15:0] a, input [15:0] b, output [16:0] d);
  assign d = a - b;
endmodule
