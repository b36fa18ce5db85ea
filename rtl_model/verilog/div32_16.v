// Restoring divider: 32-bit dividend a, 16-bit divisor b, 16 quotient bits and a
// 16-bit remainder (valid when a[31:16] < b). As div16_8.v at twice the width: 16 rows
// of a 17-bit trial subtract and a keep-or-take select, the model's divider(17, 16).
module div32_16(input [31:0] a, input [15:0] b, output reg [15:0] q, output reg [15:0] r);
  reg [16:0] t;  // shifted partial remainder {r, a[i]}
  reg [17:0] d;  // t − b with the borrow in d[17]
  integer i;
  always @* begin
    r = a[31:16];
    for (i = 15; i >= 0; i = i - 1) begin
      t = {r, a[i]};
      d = {1'b0, t} - {2'b0, b};
      q[i] = ~d[17];
      r = d[17] ? t[15:0] : d[15:0];
    end
  end
endmodule
