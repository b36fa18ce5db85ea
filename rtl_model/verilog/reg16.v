// 16-bit register, clocked, no reset or enable: the model's register(16).
module reg16(input clk, input [15:0] d, output reg [15:0] q);
  always @(posedge clk) q <= d;
endmodule
