// 8-bit 3:1 multiplexer (the texture sampler's clamp select): the model's mux_k(8, 3).
module mux3_8(input [7:0] a, input [7:0] b, input [7:0] c, input [1:0] sel,
              output reg [7:0] y);
  always @* begin
    case (sel)
      2'd0: y = a;
      2'd1: y = b;
      default: y = c;
    endcase
  end
endmodule
