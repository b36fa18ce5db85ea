// modulate_chain — OPERANDS - 1 GL_MODULATE stages in a row on BITS-bit unorms, the
// model's PerStage rounding with the Exact modulate (rtl_model/src/units/
// modulate_chain.rs): acc = op0; acc = round(acc * op_j / N) for j = 1 .. OPERANDS - 1,
// each stage the `modulate` datapath (t = p + 2^(BITS-1); (t + (t >> BITS)) >> BITS).
// Latency 2 per stage (the product register, the rounded register), 1 with one
// operand; II 1. Operand j waits 2(j - 1) clocks in a delay line for its stage.
// Ports op0 .. op7 exist always; only op0 .. op(OPERANDS-1) are read.
module modulate_chain #(
    parameter BITS     = 8,
    parameter OPERANDS = 3
) (
    input             clk,
    input             rst,
    input             in_valid,
    input  [BITS-1:0] op0,
    input  [BITS-1:0] op1,
    input  [BITS-1:0] op2,
    input  [BITS-1:0] op3,
    input  [BITS-1:0] op4,
    input  [BITS-1:0] op5,
    input  [BITS-1:0] op6,
    input  [BITS-1:0] op7,
    output            out_valid,
    output [BITS-1:0] y
);
  localparam STAGES = OPERANDS - 1;
  localparam LAT = STAGES == 0 ? 1 : 2 * STAGES;
  wire [8*BITS-1:0] ops = {op7, op6, op5, op4, op3, op2, op1, op0};

  // The valid chain: LAT clocks.
  reg [LAT-1:0] vc;
  always @(posedge clk) begin
    if (rst) vc <= 0;
    else vc <= {vc, in_valid};
  end
  assign out_valid = vc[LAT-1];

  // acc[s] is stage s's result (acc[0] = op0).
  wire [OPERANDS*BITS-1:0] acc;
  assign acc[0+:BITS] = op0;
  genvar s;
  generate
    if (STAGES == 0) begin : pass
      reg [BITS-1:0] y0;
      always @(posedge clk) y0 <= op0;
      assign y = y0;
    end else begin : chain
      for (s = 1; s <= STAGES; s = s + 1) begin : stage
        localparam D = 2 * (s - 1);  // clocks operand s waits
        wire [BITS-1:0] b;
        if (D == 0) begin : now
          assign b = ops[s*BITS+:BITS];
        end else begin : delayed
          reg [D*BITS-1:0] dl;
          always @(posedge clk) dl <= {dl, ops[s*BITS+:BITS]};
          assign b = dl[D*BITS-1-:BITS];
        end
        reg  [2*BITS-1:0] p;  // u(n) x u(n) -> u(2n)
        reg  [  BITS-1:0] q;
        wire [2*BITS:0] t = {1'b0, p} + (1 << (BITS - 1));  // u(2n) + half -> u(2n+1)
        wire [2*BITS+1:0] sum = {1'b0, t} + {{(BITS + 1) {1'b0}}, t[2*BITS:BITS]};
        always @(posedge clk) begin
          p <= acc[(s-1)*BITS+:BITS] * b;
          q <= sum[2*BITS-1:BITS];
        end
        assign acc[s*BITS+:BITS] = q;
      end
      assign y = acc[STAGES*BITS+:BITS];
    end
  endgenerate
endmodule
