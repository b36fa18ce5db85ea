// Restoring divider: 16-bit dividend a, 8-bit divisor b, 8 quotient bits and an
// 8-bit remainder (valid when a[15:8] < b, the usual 2n/n precondition). Each of the
// 8 rows shifts the next dividend bit into the remainder, subtracts b over 9 bits and
// keeps the difference or the old value: the model's divider(9, 8).
module div16_8(input [15:0] a, input [7:0] b, output reg [7:0] q, output reg [7:0] r);
  reg [8:0] t;   // shifted partial remainder {r, a[i]}
  reg [9:0] d;   // t − b with the borrow in d[9]
  integer i;
  always @* begin
    r = a[15:8];
    for (i = 7; i >= 0; i = i - 1) begin
      t = {r, a[i]};
      d = {1'b0, t} - {2'b0, b};
      q[i] = ~d[9];
      r = d[9] ? t[7:0] : d[7:0];
    end
  end
endmodule
