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
//
// BARY = 1: the barycentric mode (the model's `barycentric: Some({weight_bits: W,
// strict: STRICT})`, the NV2A's triangle colours read from its captures, see
// docs/units.md). A triangle's attributes come from its two barycentric weights
// instead of the accumulators: in stage 2 the weights of its first and third vertices
// are the walker's edge functions of the opposite edges (ef[1], and ef[0] or ef[2] by
// the winding; the top-left bias added back) divided by the doubled area, quantised
// DOWN to W fraction bits, q = floor((E * 2^W - STRICT) / den) clamped to 0 ..= 2^W
// (two restoring dividers of W + 1 quotient bits: the top bit is the clamp), and each
// attribute is base * 2^W + q0 * d0 + q2 * d2 (two (W+1) x (attr+1) multipliers, two
// adders), rounded once (RND) from its ATTR_FRAC + W fraction bits to the output,
// saturating. The triangle's registers come from the setup through more read ports,
// one entry per primitive (bary_ctl: {en, sel2, bias2, bias0}; bary_den: the doubled
// area in edge units; bary_base, bary_d0, bary_d2: per attribute A1, A0 - A1, A2 - A1).
// en = 0 (a parallelogram) keeps the accumulators' output. BARY = 0 (the default):
// the ports are unused and the module is the planes' walker above.
module polygon_interpolator #(
    parameter COORD_INT_BITS = 13,
    parameter EDGE_BITS      = 38,
    parameter ACC_INT_BITS   = 20,
    parameter ACC_FRAC_BITS  = 24,
    parameter OUT_INT_BITS   = 16,
    parameter OUT_FRAC_BITS  = 8,
    parameter OUT_SIGNED     = 1,
    parameter PRIM_BITS      = 8,
    parameter BARY           = 0,
    parameter W              = 8,
    parameter STRICT         = 1,
    parameter ATTR_INT_BITS  = 16,
    parameter ATTR_FRAC_BITS = 16,
    // derived (do not set)
    parameter C              = COORD_INT_BITS,
    parameter EW             = EDGE_BITS,
    parameter AW             = ACC_INT_BITS + ACC_FRAC_BITS,
    parameter OW             = OUT_INT_BITS + OUT_FRAC_BITS,
    parameter PB             = PRIM_BITS,
    parameter AT             = ATTR_INT_BITS + ATTR_FRAC_BITS
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
    output     [PB-1:0] bary_ctl_addr0,
    input      [3:0]    bary_ctl_data0,
    output     [PB-1:0] bary_den_addr0,
    input      [EW-1:0] bary_den_data0,
    output     [PB+2-1:0] bary_base_addr0,
    output     [PB+2-1:0] bary_base_addr1,
    output     [PB+2-1:0] bary_base_addr2,
    output     [PB+2-1:0] bary_base_addr3,
    input      [AT-1:0] bary_base_data0,
    input      [AT-1:0] bary_base_data1,
    input      [AT-1:0] bary_base_data2,
    input      [AT-1:0] bary_base_data3,
    output     [PB+2-1:0] bary_d0_addr0,
    output     [PB+2-1:0] bary_d0_addr1,
    output     [PB+2-1:0] bary_d0_addr2,
    output     [PB+2-1:0] bary_d0_addr3,
    input      [AT:0]   bary_d0_data0,
    input      [AT:0]   bary_d0_data1,
    input      [AT:0]   bary_d0_data2,
    input      [AT:0]   bary_d0_data3,
    output     [PB+2-1:0] bary_d2_addr0,
    output     [PB+2-1:0] bary_d2_addr1,
    output     [PB+2-1:0] bary_d2_addr2,
    output     [PB+2-1:0] bary_d2_addr3,
    input      [AT:0]   bary_d2_data0,
    input      [AT:0]   bary_d2_data1,
    input      [AT:0]   bary_d2_data2,
    input      [AT:0]   bary_d2_data3,
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
  assign bary_ctl_addr0 = pa;
  assign bary_den_addr0 = pa;
  assign bary_base_addr0 = {pa, 2'd0};
  assign bary_base_addr1 = {pa, 2'd1};
  assign bary_base_addr2 = {pa, 2'd2};
  assign bary_base_addr3 = {pa, 2'd3};
  assign bary_d0_addr0 = {pa, 2'd0};
  assign bary_d0_addr1 = {pa, 2'd1};
  assign bary_d0_addr2 = {pa, 2'd2};
  assign bary_d0_addr3 = {pa, 2'd3};
  assign bary_d2_addr0 = {pa, 2'd0};
  assign bary_d2_addr1 = {pa, 2'd1};
  assign bary_d2_addr2 = {pa, 2'd2};
  assign bary_d2_addr3 = {pa, 2'd3};

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

  // Barycentric mode (BARY = 1). A weight: floor((e * 2^W - STRICT) / den) clamped to
  // 0 ..= 2^W; e is an edge function with its bias added back (EW + 1 bits), den > 0.
  localparam NW = EW + W + 2;  // the numerator, signed
  localparam RW = AT + W + 3;  // base * 2^W + two products
  localparam SB = ATTR_FRAC_BITS + W - OUT_FRAC_BITS;  // right shift of the rounding
  localparam SBR = SB > 0 ? SB : 0;
  localparam SBL = SB < 0 ? -SB : 0;
  localparam WB = (RW + SBL > OW ? RW + SBL : OW) + 2;  // rounding carrier
  localparam [WB-1:0] ONEB = 1;
  localparam signed [WB-1:0] HALFB = SBR > 0 ? ONEB << (SBR > 0 ? SBR - 1 : 0) : 0;
  localparam signed [WB-1:0] OMAXB = OUT_SIGNED ? (ONEB << (OW - 1)) - ONEB : (ONEB << OW) - ONEB;
  localparam signed [WB-1:0] OMINB = OUT_SIGNED ? -(ONEB << (OW - 1)) : 0;
  localparam [NW-1:0] TSTRICT = STRICT ? 1 : 0;
  function [W:0] weight;
    input signed [EW:0] e;
    input [EW-1:0] den;
    reg signed [NW-1:0] n;
    reg [NW-1:0] dw, r;
    integer i;
    begin
      n = ($signed({{(NW-EW-1){e[EW]}}, e}) <<< W) - $signed(TSTRICT);
      dw = {{(NW-EW){1'b0}}, den};
      weight = 0;
      if (n[NW-1]) weight = 0;  // a negative weight: 0
      else if (n >= (dw << W)) weight = 1 << W;  // the top quotient bit: the clamp
      else begin
        // W restoring rows: the remainder starts below den.
        r = n >> W;
        for (i = W - 1; i >= 0; i = i - 1) begin
          r = (r << 1) | n[i];
          if (r >= dw) begin
            r = r - dw;
            weight[i] = 1'b1;
          end
        end
      end
    end
  endfunction
  // base * 2^W + q0 * d0 + q2 * d2, rounded once (RND) to the output, saturating.
  function [OW-1:0] outb;
    input [AT-1:0] base;
    input signed [AT:0] d0, d2;
    input [W:0] q0, q2;
    reg signed [RW-1:0] b, p0, p2, raw;
    reg signed [WB-1:0] w;
    begin
      b = OUT_SIGNED ? {{(RW-AT){base[AT-1]}}, base} : {{(RW-AT){1'b0}}, base};
      b = b <<< W;
      p0 = $signed({1'b0, q0}) * d0;
      p2 = $signed({1'b0, q2}) * d2;
      raw = b + p0 + p2;
      w = (($signed({{(WB-RW){raw[RW-1]}}, raw}) <<< SBL) + HALFB) >>> SBR;
      if (w > OMAXB) w = OMAXB;
      if (w < OMINB) w = OMINB;
      outb = w[OW-1:0];
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

  // The barycentric registers (loaded with the primitive) and outputs.
  wire b_on;
  wire [OW-1:0] bo0, bo1, bo2, bo3;
  generate
    if (BARY != 0) begin : g_bary
      reg en, sel2;
      reg signed [EW:0] bias0, bias2;
      reg [EW-1:0] den;
      reg [AT-1:0] base[0:3];
      reg signed [AT:0] d0[0:3], d2[0:3];
      always @(posedge clk)
        if (ld) begin
          {en, sel2} <= bary_ctl_data0[3:2];
          bias2 <= bary_ctl_data0[1];
          bias0 <= bary_ctl_data0[0];
          den <= bary_den_data0;
          base[0] <= bary_base_data0;
          base[1] <= bary_base_data1;
          base[2] <= bary_base_data2;
          base[3] <= bary_base_data3;
          d0[0] <= bary_d0_data0;
          d0[1] <= bary_d0_data1;
          d0[2] <= bary_d0_data2;
          d0[3] <= bary_d0_data3;
          d2[0] <= bary_d2_data0;
          d2[1] <= bary_d2_data1;
          d2[2] <= bary_d2_data2;
          d2[3] <= bary_d2_data3;
        end
      // Stage 2: the weights from the stepped edge functions.
      wire signed [EW:0] e0 = $signed({ef[1][EW-1], ef[1]}) + bias0;
      wire signed [EW-1:0] e2r = sel2 ? ef[2] : ef[0];
      wire signed [EW:0] e2 = $signed({e2r[EW-1], e2r}) + bias2;
      wire [W:0] q0 = weight(e0, den);
      wire [W:0] q2 = weight(e2, den);
      assign b_on = en;
      assign bo0 = outb(base[0], d0[0], d2[0], q0, q2);
      assign bo1 = outb(base[1], d0[1], d2[1], q0, q2);
      assign bo2 = outb(base[2], d0[2], d2[2], q0, q2);
      assign bo3 = outb(base[3], d0[3], d2[3], q0, q2);
    end else begin : g_plane
      assign b_on = 1'b0;
      assign bo0 = 0;
      assign bo1 = 0;
      assign bo2 = 0;
      assign bo3 = 0;
    end
  endgenerate

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
    attr0 <= b_on ? bo0 : outq(acc[0]);
    attr1 <= b_on ? bo1 : outq(acc[1]);
    attr2 <= b_on ? bo2 : outq(acc[2]);
    attr3 <= b_on ? bo3 : outq(acc[3]);
  end
endmodule
