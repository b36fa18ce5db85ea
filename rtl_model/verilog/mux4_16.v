// 16-bit 4:1 multiplexer: the model's mux_k(16, 4).
module mux4_16(input [15:0] a, input [15:0] b, input [15:0] c, input [15:0] d,
               input [1:0] sel, output reg [15:0] y);
  always @* begin
    case (sel)
      2'd0: y = a;
      2'd1: y = b;
      2'd2: y = c;
      default: y = d;
    endcase
  end
endmodule
