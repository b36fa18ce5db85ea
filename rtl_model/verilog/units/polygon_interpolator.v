// polygon_interpolator — the incremental (Pineda) walker (rtl_model/src/units/
// polygon_interpolator.rs, `kernel`): per move, the pixel counters, the 4 edge
// accumulators and the attribute accumulators add their x or y increment (adds only),
// then is_inside (the model's `inside`) = no edge negative and every attribute is rounded (RND) from the
// accumulator s(ACC_INT).(ACC_FRAC) to the output s(OUT_INT).(OUT_FRAC) (unsigned when
// OUT_SIGNED = 0), saturating. Latency 2, II 1:
//   1 the accumulators (the stage register)
//   2 sign test, round, saturate -> output registers
// The per-primitive setup (plane equations, one division per gradient) is not in
// this module: its results (the walker's start state) are read ports, one entry per
// primitive, in primitive order (pos: x, y; ef, ef_dx, ef_dy (edge functions): 4 each; acc,
// grad_x, grad_y: one per attribute; entry = primitive * {2|4} + index). A transaction
// with `load` set loads the next primitive's start state, then applies its move (the
// first move of a walk is Hold). Implemented: 4 attributes (ports attr0..attr3), the
// WRAP accumulator overflow and RND output rounding (the default configuration's).
module polygon_interpolator #(
    parameter COORD_INT_BITS = 13,
    parameter EDGE_BITS      = 38,
    parameter ACC_INT_BITS   = 20,
    parameter ACC_FRAC_BITS  = 24,
    parameter OUT_INT_BITS   = 16,
    parameter OUT_FRAC_BITS  = 8,
    parameter OUT_SIGNED     = 1,
    parameter PRIM_BITS      = 8,
    // derived (do not set)
    parameter C              = COORD_INT_BITS,
    parameter EW             = EDGE_BITS,
    parameter AW             = ACC_INT_BITS + ACC_FRAC_BITS,
    parameter OW             = OUT_INT_BITS + OUT_FRAC_BITS,
    parameter PB             = PRIM_BITS
) (
    input               clk,
    input               rst,
    input               in_valid,
    input               load,
    input      [1:0]    move,
    output     [PB+1-1:0] pos_addr0,
    output     [PB+1-1:0] pos_addr1,
    input      [C-1:0] pos_data0,
    input      [C-1:0] pos_data1,
    output     [PB+2-1:0] ef_addr0,
    output     [PB+2-1:0] ef_addr1,
    output     [PB+2-1:0] ef_addr2,
    output     [PB+2-1:0] ef_addr3,
    input      [EW-1:0] ef_data0,
    input      [EW-1:0] ef_data1,
    input      [EW-1:0] ef_data2,
    input      [EW-1:0] ef_data3,
    output     [PB+2-1:0] ef_dx_addr0,
    output     [PB+2-1:0] ef_dx_addr1,
    output     [PB+2-1:0] ef_dx_addr2,
    output     [PB+2-1:0] ef_dx_addr3,
    input      [EW-1:0] ef_dx_data0,
    input      [EW-1:0] ef_dx_data1,
    input      [EW-1:0] ef_dx_data2,
    input      [EW-1:0] ef_dx_data3,
    output     [PB+2-1:0] ef_dy_addr0,
    output     [PB+2-1:0] ef_dy_addr1,
    output     [PB+2-1:0] ef_dy_addr2,
    output     [PB+2-1:0] ef_dy_addr3,
    input      [EW-1:0] ef_dy_data0,
    input      [EW-1:0] ef_dy_data1,
    input      [EW-1:0] ef_dy_data2,
    input      [EW-1:0] ef_dy_data3,
    output     [PB+2-1:0] acc_addr0,
    output     [PB+2-1:0] acc_addr1,
    output     [PB+2-1:0] acc_addr2,
    output     [PB+2-1:0] acc_addr3,
    input      [AW-1:0] acc_data0,
    input      [AW-1:0] acc_data1,
    input      [AW-1:0] acc_data2,
    input      [AW-1:0] acc_data3,
    output     [PB+2-1:0] grad_x_addr0,
    output     [PB+2-1:0] grad_x_addr1,
    output     [PB+2-1:0] grad_x_addr2,
    output     [PB+2-1:0] grad_x_addr3,
    input      [AW-1:0] grad_x_data0,
    input      [AW-1:0] grad_x_data1,
    input      [AW-1:0] grad_x_data2,
    input      [AW-1:0] grad_x_data3,
    output     [PB+2-1:0] grad_y_addr0,
    output     [PB+2-1:0] grad_y_addr1,
    output     [PB+2-1:0] grad_y_addr2,
    output     [PB+2-1:0] grad_y_addr3,
    input      [AW-1:0] grad_y_data0,
    input      [AW-1:0] grad_y_data1,
    input      [AW-1:0] grad_y_data2,
    input      [AW-1:0] grad_y_data3,
    output reg          out_valid,
    output reg [C-1:0]  x,
    output reg [C-1:0]  y,
    output reg          is_inside,
    output reg [OW-1:0] attr0,
    output reg [OW-1:0] attr1,
    output reg [OW-1:0] attr2,
    output reg [OW-1:0] attr3
);
  localparam SH = ACC_FRAC_BITS - OUT_FRAC_BITS;  // right shift of the rounding
  localparam SHR = SH > 0 ? SH : 0;
  localparam SHL = SH < 0 ? -SH : 0;
  localparam WW = (AW + SHL > OW ? AW + SHL : OW) + 2;  // rounding carrier
  localparam [WW-1:0] ONE = 1;
  localparam signed [WW-1:0] HALF = SHR > 0 ? ONE << (SHR > 0 ? SHR - 1 : 0) : 0;
  localparam signed [WW-1:0] OMAX = OUT_SIGNED ? (ONE << (OW - 1)) - ONE : (ONE << OW) - ONE;
  localparam signed [WW-1:0] OMIN = OUT_SIGNED ? -(ONE << (OW - 1)) : 0;

  // Next primitive to load: its entries are on the read ports (the address moves
  // to the following one on the load's clock, so back-to-back loads work).
  reg [PB-1:0] prim;
  reg stage1;
  wire ld = in_valid & load;
  wire [PB-1:0] pa = ld ? prim + 1'b1 : prim;
  assign pos_addr0 = {pa, 1'b0};
  assign pos_addr1 = {pa, 1'b1};
  assign ef_addr0 = {pa, 2'd0};
  assign ef_addr1 = {pa, 2'd1};
  assign ef_addr2 = {pa, 2'd2};
  assign ef_addr3 = {pa, 2'd3};
  assign ef_dx_addr0 = {pa, 2'd0};
  assign ef_dx_addr1 = {pa, 2'd1};
  assign ef_dx_addr2 = {pa, 2'd2};
  assign ef_dx_addr3 = {pa, 2'd3};
  assign ef_dy_addr0 = {pa, 2'd0};
  assign ef_dy_addr1 = {pa, 2'd1};
  assign ef_dy_addr2 = {pa, 2'd2};
  assign ef_dy_addr3 = {pa, 2'd3};
  assign acc_addr0 = {pa, 2'd0};
  assign acc_addr1 = {pa, 2'd1};
  assign acc_addr2 = {pa, 2'd2};
  assign acc_addr3 = {pa, 2'd3};
  assign grad_x_addr0 = {pa, 2'd0};
  assign grad_x_addr1 = {pa, 2'd1};
  assign grad_x_addr2 = {pa, 2'd2};
  assign grad_x_addr3 = {pa, 2'd3};
  assign grad_y_addr0 = {pa, 2'd0};
  assign grad_y_addr1 = {pa, 2'd1};
  assign grad_y_addr2 = {pa, 2'd2};
  assign grad_y_addr3 = {pa, 2'd3};

  reg signed [C-1:0] px, py;
  reg signed [EW-1:0] ef[0:3], edx[0:3], edy[0:3];
  reg signed [AW-1:0] acc[0:3], gx[0:3], gy[0:3];
  wire hold = move == 2'd0;
  wire dn = move == 2'd3;
  wire lf = move == 2'd2;

  // One accumulator step by the move: +dx, -dx, +dy (wrapping), or hold.
  function signed [EW-1:0] step;
    input signed [EW-1:0] a, dx, dy;
    begin
      step = hold ? a : dn ? a + dy : lf ? a - dx : a + dx;
    end
  endfunction
  function signed [AW-1:0] stepa;
    input signed [AW-1:0] a, dx, dy;
    begin
      stepa = hold ? a : dn ? a + dy : lf ? a - dx : a + dx;
    end
  endfunction
  // RND (+ half, floor) to the output format, saturating.
  function [OW-1:0] outq;
    input signed [AW-1:0] a;
    reg signed [WW-1:0] w;
    begin
      w = (($signed({{(WW-AW){a[AW-1]}}, a}) <<< SHL) + HALF) >>> SHR;
      if (w > OMAX) w = OMAX;
      if (w < OMIN) w = OMIN;
      outq = w[OW-1:0];
    end
  endfunction

  wire signed [EW-1:0] e_b0 = load ? ef_data0 : ef[0];
  wire signed [EW-1:0] edx_b0 = load ? ef_dx_data0 : edx[0];
  wire signed [EW-1:0] edy_b0 = load ? ef_dy_data0 : edy[0];
  wire signed [EW-1:0] e_b1 = load ? ef_data1 : ef[1];
  wire signed [EW-1:0] edx_b1 = load ? ef_dx_data1 : edx[1];
  wire signed [EW-1:0] edy_b1 = load ? ef_dy_data1 : edy[1];
  wire signed [EW-1:0] e_b2 = load ? ef_data2 : ef[2];
  wire signed [EW-1:0] edx_b2 = load ? ef_dx_data2 : edx[2];
  wire signed [EW-1:0] edy_b2 = load ? ef_dy_data2 : edy[2];
  wire signed [EW-1:0] e_b3 = load ? ef_data3 : ef[3];
  wire signed [EW-1:0] edx_b3 = load ? ef_dx_data3 : edx[3];
  wire signed [EW-1:0] edy_b3 = load ? ef_dy_data3 : edy[3];
  wire signed [AW-1:0] a_b0 = load ? acc_data0 : acc[0];
  wire signed [AW-1:0] gx_b0 = load ? grad_x_data0 : gx[0];
  wire signed [AW-1:0] gy_b0 = load ? grad_y_data0 : gy[0];
  wire signed [AW-1:0] a_b1 = load ? acc_data1 : acc[1];
  wire signed [AW-1:0] gx_b1 = load ? grad_x_data1 : gx[1];
  wire signed [AW-1:0] gy_b1 = load ? grad_y_data1 : gy[1];
  wire signed [AW-1:0] a_b2 = load ? acc_data2 : acc[2];
  wire signed [AW-1:0] gx_b2 = load ? grad_x_data2 : gx[2];
  wire signed [AW-1:0] gy_b2 = load ? grad_y_data2 : gy[2];
  wire signed [AW-1:0] a_b3 = load ? acc_data3 : acc[3];
  wire signed [AW-1:0] gx_b3 = load ? grad_x_data3 : gx[3];
  wire signed [AW-1:0] gy_b3 = load ? grad_y_data3 : gy[3];
  wire signed [C-1:0] x_b = load ? pos_data0 : px;
  wire signed [C-1:0] y_b = load ? pos_data1 : py;
  wire [3:0] neg = {ef[3][EW-1], ef[2][EW-1], ef[1][EW-1], ef[0][EW-1]};

  always @(posedge clk) begin
    if (rst) begin
      prim <= 0;
      out_valid <= 0;
      stage1 <= 0;
    end else begin
      stage1 <= in_valid;
      out_valid <= stage1;
      if (ld) prim <= prim + 1'b1;
    end
    if (in_valid) begin
      px <= hold | dn ? x_b : lf ? x_b - 1'b1 : x_b + 1'b1;
      py <= dn ? y_b + 1'b1 : y_b;
      ef[0] <= step(e_b0, edx_b0, edy_b0);
      edx[0] <= edx_b0;
      edy[0] <= edy_b0;
      ef[1] <= step(e_b1, edx_b1, edy_b1);
      edx[1] <= edx_b1;
      edy[1] <= edy_b1;
      ef[2] <= step(e_b2, edx_b2, edy_b2);
      edx[2] <= edx_b2;
      edy[2] <= edy_b2;
      ef[3] <= step(e_b3, edx_b3, edy_b3);
      edx[3] <= edx_b3;
      edy[3] <= edy_b3;
      acc[0] <= stepa(a_b0, gx_b0, gy_b0);
      gx[0] <= gx_b0;
      gy[0] <= gy_b0;
      acc[1] <= stepa(a_b1, gx_b1, gy_b1);
      gx[1] <= gx_b1;
      gy[1] <= gy_b1;
      acc[2] <= stepa(a_b2, gx_b2, gy_b2);
      gx[2] <= gx_b2;
      gy[2] <= gy_b2;
      acc[3] <= stepa(a_b3, gx_b3, gy_b3);
      gx[3] <= gx_b3;
      gy[3] <= gy_b3;
    end
    // 2
    x <= px;
    y <= py;
    is_inside <= neg == 0;
      attr0 <= outq(acc[0]);
      attr1 <= outq(acc[1]);
      attr2 <= outq(acc[2]);
      attr3 <= outq(acc[3]);
  end
endmodule
