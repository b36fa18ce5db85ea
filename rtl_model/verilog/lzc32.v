// 32-bit leading-zero count, 6-bit result (32 for a = 0): the model's
// leading_zero_counter(32). A priority encoder as a for loop: the last set bit
// the loop meets (the most significant) wins.
module lzc32(input [31:0] a, output reg [5:0] n);
  integer i;
  always @* begin
    n = 6'd32;
    for (i = 0; i < 32; i = i + 1)
      if (a[i]) n = 31 - i;
  end
endmodule
