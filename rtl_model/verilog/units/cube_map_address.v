// cube_map_address — cube-map face selection and face texel coordinates
// (rtl_model/src/units/cube_map_address.rs): three s(WI) texel-space words c_i in,
// D_i = 2 c_i - s 2^FI, major axis (ties: x, then y, then z), face, sc, tc; 1/|ma| by a
// reciprocal ROM (read port, synchronous) and an optional Newton step; (s, t) =
// (sc, tc) y >> (p + FY - G), rounded (ties up), + 2^G; saturated (face_s, face_t),
// clamped to the texel-centre range and stacked in t by face F 2^FO (s, t).
// Latency 10 with NEWTON, 7 without; II 1:
//   1 D                      6 d = 2 - q            (NEWTON)
//   2 compare, select        7 y' = y0 d            (NEWTON)
//   3 LZC, normalise -> ROM  8 (5) sc y, tc y
//   4 ROM data               9 (6) shift, round, + 2^G
//   5 q = m y0 (NEWTON)     10 (7) clamp, stack, saturate, output
module cube_map_address #(
    parameter IN_INT_BITS      = 16,
    parameter IN_FRAC_BITS     = 8,
    parameter SIDE_LOG2        = 7,
    parameter RCP_ADDR_BITS    = 6,
    parameter RCP_BITS         = 8,
    parameter NEWTON           = 1,
    parameter NEWTON_FRAC_BITS = 16,
    parameter FACE_LOG2        = 8,
    parameter COORD_INT_BITS   = 16,
    parameter COORD_FRAC_BITS  = 8,
    // derived (do not set)
    parameter WI               = IN_INT_BITS + IN_FRAC_BITS,
    parameter OW               = COORD_INT_BITS + COORD_FRAC_BITS
) (
    input                          clk,
    input                          rst,
    input                          in_valid,
    input      [WI-1:0]            cs,
    input      [WI-1:0]            ct,
    input      [WI-1:0]            cr,
    output reg [RCP_ADDR_BITS-1:0] rcp_addr0,
    input      [RCP_BITS-1:0]      rcp_data0,
    output                         out_valid,
    output reg [2:0]               face,
    output reg [OW-1:0]            face_s,
    output reg [OW-1:0]            face_t,
    output reg [OW-1:0]            s,
    output reg [OW-1:0]            t,
    output reg                     zero
);
  localparam FI = IN_FRAC_BITS;
  localparam CW = SIDE_LOG2 + FI;  // s 2^FI = 2^CW
  localparam DW = (WI > CW ? WI : CW + 1) + 2;  // D: signed
  localparam MW = DW - 1;  // |D|: unsigned
  localparam PB = $clog2(MW);  // p < MW
  localparam A = RCP_ADDR_BITS;
  localparam R = RCP_BITS;
  localparam N = NEWTON_FRAC_BITS;
  localparam FY = NEWTON ? N : R;  // fraction bits of y
  localparam YW = FY + 1;  // y: u1.FY
  localparam FO = COORD_FRAC_BITS;
  localparam G = FACE_LOG2 - 1 + FO;  // the "+ 1" is 2^G
  localparam L = G > FY ? G - FY : 0;  // pre-shift: p + FY + L - G >= 0
  localparam PW = DW + YW + 1;  // sc y, signed
  localparam XW = PW + L + 2;  // shifted and rounded
  localparam UW = (G + 5 > OW + 1) ? G + 5 : OW + 1;  // |u| < 2^(G+3); t + 6 F 2^FO
  localparam LAT = NEWTON ? 10 : 7;

  // ---- stage 1: D = 2c - s 2^FI ----
  localparam signed [DW-1:0] SC = {{(DW - 1) {1'b0}}, 1'b1} << CW;
  reg signed [DW-1:0] d1x, d1y, d1z;
  always @(posedge clk) begin
    d1x <= ($signed(cs) <<< 1) - SC;
    d1y <= ($signed(ct) <<< 1) - SC;
    d1z <= ($signed(cr) <<< 1) - SC;
  end

  // ---- stage 2: |D|, major axis, face, sc, tc, |ma| ----
  wire [MW-1:0] mx = d1x[DW-1] ? -d1x : d1x;
  wire [MW-1:0] my = d1y[DW-1] ? -d1y : d1y;
  wire [MW-1:0] mz = d1z[DW-1] ? -d1z : d1z;
  wire ax = mx >= my && mx >= mz;
  wire ay = !ax && my >= mz;
  wire nz = (mx | my | mz) != 0;
  reg [MW-1:0] ma2;
  reg signed [DW-1:0] sc2, tc2;
  reg [2:0] face2;
  reg zero2;
  always @(posedge clk) begin
    zero2 <= !nz;
    if (ax) begin
      ma2 <= mx;
      face2 <= {2'd0, d1x[DW-1]};  // the zero direction: face 0
      sc2 <= d1x[DW-1] ? d1z : -d1z;
      tc2 <= -d1y;
    end else if (ay) begin
      ma2 <= my;
      face2 <= {2'd1, d1y[DW-1]};
      sc2 <= d1x;
      tc2 <= d1y[DW-1] ? -d1z : d1z;
    end else begin
      ma2 <= mz;
      face2 <= {2'd2, d1z[DW-1]};
      sc2 <= d1z[DW-1] ? -d1x : d1x;
      tc2 <= -d1y;
    end
  end

  // ---- stage 3: leading one p, ROM address, m truncated to u1.N ----
  reg [PB-1:0] lz;
  integer i;
  always @* begin
    lz = 0;
    for (i = 0; i < MW; i = i + 1) if (ma2[i]) lz = i;
  end
  wire [MW-1:0] below = ma2 & ~({{(MW - 1) {1'b0}}, 1'b1} << lz);
  wire [MW+A-1:0] below_a = {below, {A{1'b0}}} >> lz;
  wire [MW+N:0] m_n = {ma2, {N{1'b0}}} >> lz;
  reg [N:0] mn3, mn4;
  reg [PB-1:0] p3, p4;
  reg signed [DW-1:0] sc3, tc3, sc4, tc4;
  reg [2:0] face3, face4;
  reg zero3, zero4;
  always @(posedge clk) begin
    rcp_addr0 <= below_a[A-1:0];
    mn3 <= m_n[N:0];
    p3 <= lz;
    {sc3, tc3, face3, zero3} <= {sc2, tc2, face2, zero2};
    // stage 4: the ROM presents y0
    {mn4, p4, sc4, tc4, face4, zero4} <= {mn3, p3, sc3, tc3, face3, zero3};
  end

  // ---- stages 5-7 (NEWTON): y' = y0 (2 - m y0) ----
  wire [YW-1:0] y_f;
  wire [PB-1:0] p_f;
  wire signed [DW-1:0] sc_f, tc_f;
  wire [2:0] face_f;
  wire zero_f;
  generate
    if (NEWTON) begin : g_newton
      wire [N+R:0] qp = mn4 * rcp_data0 + ({{(N + R) {1'b0}}, 1'b1} << (R - 1));
      reg [N+1:0] q5;  // u1.N, < 2^(N+2)
      reg [R-1:0] y05, y06;
      reg [N:0] d6;
      reg [N:0] y7;
      reg [PB-1:0] p5, p6, p7;
      reg signed [DW-1:0] sc5, tc5, sc6, tc6, sc7, tc7;
      reg [2:0] face5, face6, face7;
      reg zero5, zero6, zero7;
      wire signed [N+3:0] dd = $signed({2'b01, {(N + 1) {1'b0}}}) - $signed({2'b00, q5});
      wire [N+R+1:0] yp = y06 * d6 + ({{(N + R + 1) {1'b0}}, 1'b1} << (R - 1));
      wire [N+1:0] y1 = yp[N+R+1:R];
      always @(posedge clk) begin
        q5 <= qp[N+R:R];
        y05 <= rcp_data0;
        {p5, sc5, tc5, face5, zero5} <= {p4, sc4, tc4, face4, zero4};
        d6 <= dd < 0 ? {(N + 1) {1'b0}} : dd > $signed({3'b001, {(N + 1) {1'b0}}}) - 1 ?
            {(N + 1) {1'b1}} : dd[N:0];
        y06 <= y05;
        {p6, sc6, tc6, face6, zero6} <= {p5, sc5, tc5, face5, zero5};
        y7 <= y1[N+1] ? {(N + 1) {1'b1}} : y1[N:0];
        {p7, sc7, tc7, face7, zero7} <= {p6, sc6, tc6, face6, zero6};
      end
      assign y_f = y7;
      assign {p_f, sc_f, tc_f, face_f, zero_f} = {p7, sc7, tc7, face7, zero7};
    end else begin : g_rom
      assign y_f = {1'b0, rcp_data0};
      assign {p_f, sc_f, tc_f, face_f, zero_f} = {p4, sc4, tc4, face4, zero4};
    end
  endgenerate

  // ---- sc y, tc y ----
  reg signed [PW-1:0] ps8, pt8;
  reg [PB-1:0] p8;
  reg [2:0] face8;
  reg zero8;
  always @(posedge clk) begin
    ps8 <= sc_f * $signed({1'b0, y_f});
    pt8 <= tc_f * $signed({1'b0, y_f});
    {p8, face8, zero8} <= {p_f, face_f, zero_f};
  end

  // ---- shift by p + FY - G, round (ties up), + 2^G; the zero direction: the centre ----
  wire [7:0] rs = p8 + (FY + L - G);
  wire signed [XW-1:0] xs = ($signed(ps8) <<< (L + 1)) + ($signed({{(XW - 1) {1'b0}}, 1'b1}) <<< rs);
  wire signed [XW-1:0] xt = ($signed(pt8) <<< (L + 1)) + ($signed({{(XW - 1) {1'b0}}, 1'b1}) <<< rs);
  wire signed [XW-1:0] vs = xs >>> (rs + 1);
  wire signed [XW-1:0] vt = xt >>> (rs + 1);
  wire signed [UW-1:0] vs_u = vs;  // |v| <= 4 2^G + 1: exact in UW bits
  wire signed [UW-1:0] vt_u = vt;
  localparam signed [UW-1:0] HALF = {{(UW - 1) {1'b0}}, 1'b1} << G;
  reg signed [UW-1:0] us9, ut9;
  reg [2:0] face9;
  reg zero9;
  always @(posedge clk) begin
    us9 <= zero8 ? HALF : vs_u + HALF;
    ut9 <= zero8 ? HALF : vt_u + HALF;
    {face9, zero9} <= {face8, zero8};
  end

  // ---- saturate; clamp to [1/2, F - 1/2] texels, stack t by face F ----
  localparam signed [UW-1:0] LO = {{(UW - 1) {1'b0}}, 1'b1} << (FO - 1);
  localparam signed [UW-1:0] HI = ({{(UW - 1) {1'b0}}, 1'b1} << (FACE_LOG2 + FO)) - LO;
  localparam signed [UW-1:0] OMAX = ({{(UW - 1) {1'b0}}, 1'b1} << (OW - 1)) - 1;
  localparam signed [UW-1:0] OMIN = -({{(UW - 1) {1'b0}}, 1'b1} << (OW - 1));
  function [OW-1:0] sat;
    input signed [UW-1:0] x;
    sat = x > OMAX ? OMAX[OW-1:0] : x < OMIN ? OMIN[OW-1:0] : x[OW-1:0];
  endfunction
  function signed [UW-1:0] clampc;
    input signed [UW-1:0] x;
    clampc = x < LO ? LO : x > HI ? HI : x;
  endfunction
  wire signed [UW-1:0] stack = clampc(ut9) + ($signed({{(UW - 3) {1'b0}}, face9}) <<< (FACE_LOG2 + FO));
  always @(posedge clk) begin
    face <= face9;
    zero <= zero9;
    face_s <= sat(us9);
    face_t <= sat(ut9);
    s <= sat(clampc(us9));
    t <= sat(stack);
  end

  reg [LAT-1:0] vld;
  always @(posedge clk) begin
    if (rst) vld <= 0;
    else vld <= {vld[LAT-2:0], in_valid};
  end
  assign out_valid = vld[LAT-1];
endmodule
