// reflection_vector — per-pixel reflection vector, lambda scale and 3D texel
// coordinates (rtl_model/src/units/reflection_vector.rs): n^ = n/|n|, v^ = e/|e|,
// d = n^.v^, r = 2 d n^ - v^, t = r lambda, coord = (t + 1)/2 s, all in the model's
// integer words. Each vector: block normalisation to P-bit mantissas, the squared
// length S, 1/sqrt(S) by a ROM (one read port per vector, synchronous) and an optional
// Newton step y' = y (3 - m y^2)/2, then n^_i = x'_i y 2^-k rounded into s2.B.
// Latency 12 with NEWTON, 9 without; II 1:
//   1 block normalise, lambda clamp   7 (NEWTON) y' = y0 d / 2
//   2 squares, S                      8 (5) n^, v^ and the zero-vector muxes
//   3 LZC, k, ROM address, m_N        9 (6) d = n^.v^
//   4 ROM data                       10 (7) r = 2 d n^ - v^
//   5 (NEWTON) q = y0^2              11 (8) t = r lambda
//   6 (NEWTON) d = 3 - m q           12 (9) coord = (t + 1) scaled, saturated
module reflection_vector #(
    parameter IN_INT_BITS      = 16,
    parameter IN_FRAC_BITS     = 16,
    parameter LAMBDA_BITS      = 12,
    parameter RSQRT_ADDR_BITS  = 8,
    parameter RSQRT_BITS       = 11,
    parameter NEWTON           = 1,
    parameter NEWTON_FRAC_BITS = 18,
    parameter NORM_BITS        = 14,
    parameter MANT_BITS        = 19,
    parameter SIDE_LOG2        = 7,
    parameter COORD_INT_BITS   = 16,
    parameter COORD_FRAC_BITS  = 8,
    // derived (do not set)
    parameter W                = IN_INT_BITS + IN_FRAC_BITS,
    parameter OW               = COORD_INT_BITS + COORD_FRAC_BITS
) (
    input                            clk,
    input                            rst,
    input                            in_valid,
    input      [W-1:0]               nx,
    input      [W-1:0]               ny,
    input      [W-1:0]               nz,
    input      [W-1:0]               ex,
    input      [W-1:0]               ey,
    input      [W-1:0]               ez,
    input      [LAMBDA_BITS:0]       lambda,
    output     [RSQRT_ADDR_BITS-1:0] rsqrt_addr0,
    output     [RSQRT_ADDR_BITS-1:0] rsqrt_addr1,
    input      [RSQRT_BITS-1:0]      rsqrt_data0,
    input      [RSQRT_BITS-1:0]      rsqrt_data1,
    output                           out_valid,
    output reg [OW-1:0]              s,
    output reg [OW-1:0]              t,
    output reg [OW-1:0]              r,
    output reg                       back_facing,
    output reg                       zero_n,
    output reg                       zero_e
);
  localparam P = MANT_BITS;
  localparam XW = W > P ? W : P;  // a component before the block shift
  localparam QB = $clog2(XW);  // leading-one position of |x|, < XW
  localparam SW = 2 * P;  // S
  localparam PB = $clog2(SW);  // leading-one position of S
  localparam KB = PB;  // k = p / 2
  localparam A = RSQRT_ADDR_BITS;
  localparam A1 = A - 1;
  localparam R = RSQRT_BITS;
  localparam N = NEWTON_FRAC_BITS;
  localparam FY = NEWTON ? N : R;
  localparam YW = FY + 1;  // y: u1.FY
  localparam B = NORM_BITS;
  localparam L = LAMBDA_BITS;
  localparam F = COORD_FRAC_BITS;
  localparam LB = B > FY ? B - FY : 0;  // pre-shift: k + FY + LB - B >= 0
  localparam NW = P + YW + 1 + LB + 2;  // x' y, shifted and rounded
  localparam HW = B + 2;  // n^, v^: s2.B
  localparam DW = B + 3;  // d, r: s3.B
  localparam TW = B + L + 5;  // t: s4.(B+L), signed
  localparam integer OS = B + L + 1 - SIDE_LOG2 - F;  // coord shift (right if > 0)
  localparam CW = (TW + 1 + (OS < 0 ? -OS : 0)) > OW ? (TW + 1 + (OS < 0 ? -OS : 0)) : OW + 1;
  localparam LAT = NEWTON ? 12 : 9;

  // ---- stage 1: lambda clamp ----
  localparam [L:0] ONE = {1'b1, {L{1'b0}}};
  // lam_sr[(k-1)(L+1) +: L+1] is lambda at stage k
  reg [(LAT-1)*(L+1)-1:0] lam_sr;
  always @(posedge clk) lam_sr <= {lam_sr, lambda > ONE ? ONE : lambda};

  // ---- per vector (0: n, 1: e): stages 1-4 (7), and the comb n^_i ----
  wire [2*A-1:0] addr_w;
  wire [2*R-1:0] data_w = {rsqrt_data1, rsqrt_data0};
  wire [6*HW-1:0] hat_w;  // {v^ (e), n^ (n)}, component 0 lowest
  wire [1:0] zero_w;
  genvar g;
  generate
    for (g = 0; g < 2; g = g + 1) begin : g_vec
      wire signed [W-1:0] x0 = g == 0 ? nx : ex;
      wire signed [W-1:0] x1 = g == 0 ? ny : ey;
      wire signed [W-1:0] x2 = g == 0 ? nz : ez;
      wire [W-1:0] a0 = x0[W-1] ? -x0 : x0;
      wire [W-1:0] a1 = x1[W-1] ? -x1 : x1;
      wire [W-1:0] a2 = x2[W-1] ? -x2 : x2;
      wire [W-1:0] orv = a0 | a1 | a2;
      reg [QB-1:0] q;
      integer i;
      always @* begin
        q = 0;
        for (i = 0; i < W; i = i + 1) if (orv[i]) q = i;
      end
      wire [QB-1:0] sh = q > P - 2 ? q - (P - 2) : 0;
      wire signed [XW-1:0] xs0 = x0;
      wire signed [XW-1:0] xs1 = x1;
      wire signed [XW-1:0] xs2 = x2;
      wire signed [XW-1:0] t0 = xs0 >>> sh;
      wire signed [XW-1:0] t1 = xs1 >>> sh;
      wire signed [XW-1:0] t2 = xs2 >>> sh;
      // stage 1: mantissas s(P)
      reg signed [P-1:0] m1_0, m1_1, m1_2;
      reg z1;
      always @(posedge clk) begin
        m1_0 <= t0[P-1:0];
        m1_1 <= t1[P-1:0];
        m1_2 <= t2[P-1:0];
        z1 <= orv == 0;
      end
      // stage 2: S = sum of squares, u(2P)
      wire [SW-1:0] sq = m1_0 * m1_0 + m1_1 * m1_1 + m1_2 * m1_2;
      reg [SW-1:0] s2;
      reg signed [P-1:0] m2_0, m2_1, m2_2;
      reg z2;
      always @(posedge clk) begin
        s2 <= sq;
        {m2_0, m2_1, m2_2, z2} <= {m1_0, m1_1, m1_2, z1};
      end
      // stage 3: leading one p, k = p/2, address {parity, A-1 bits below}, m_N
      reg [PB-1:0] p;
      integer j;
      always @* begin
        p = 0;
        for (j = 0; j < SW; j = j + 1) if (s2[j]) p = j;
      end
      wire [SW-1:0] below = s2 & ~({{(SW - 1) {1'b0}}, 1'b1} << p);
      wire [SW+A-1:0] idx_w = ({{A{1'b0}}, below} << A1) >> p;  // < 2^(A-1)
      wire [A-1:0] addr = ({{(SW + A - 1) {1'b0}}, p[0]} << A1) | idx_w;
      wire [PB-1:0] k = p >> 1;
      wire [SW+N-1:0] mn_w = ({{N{1'b0}}, s2} << N) >> (2 * k);
      reg [A-1:0] addr3;
      reg [N+1:0] mn3, mn4;
      reg [KB-1:0] k3, k4;
      reg signed [P-1:0] m3_0, m3_1, m3_2, m4_0, m4_1, m4_2;
      reg z3, z4;
      always @(posedge clk) begin
        addr3 <= addr;
        mn3 <= mn_w[N+1:0];
        k3 <= k;
        {m3_0, m3_1, m3_2, z3} <= {m2_0, m2_1, m2_2, z2};
        // stage 4: the ROM presents y0
        {mn4, k4, m4_0, m4_1, m4_2, z4} <= {mn3, k3, m3_0, m3_1, m3_2, z3};
      end
      assign addr_w[g*A+:A] = addr3;
      wire [R-1:0] y0 = data_w[g*R+:R];
      wire [YW-1:0] yf;
      wire [KB-1:0] kf;
      wire signed [P-1:0] mf0, mf1, mf2;
      wire zf;
      if (NEWTON) begin : g_newton
        // stage 5: q = y0^2 in u1.N (rounded, ties up)
        wire [2*R:0] yy = y0 * y0;
        wire [2*R+N:0] qw = 2 * R > N ? (yy + ({{(2 * R + N) {1'b0}}, 1'b1} << (2 * R - N - 1))) >> (2 * R - N)
            : {{N{1'b0}}, yy} << (N - 2 * R);
        reg [N:0] q5;
        reg [R-1:0] y05, y06;
        reg [N+1:0] mn5;
        reg [KB-1:0] k5, k6, k7;
        reg signed [P-1:0] m5_0, m5_1, m5_2, m6_0, m6_1, m6_2, m7_0, m7_1, m7_2;
        reg z5, z6, z7;
        // stage 6: d = 3 - m_N q, rounded to u2.N, clamped
        wire [2*N+2:0] mq = mn5 * q5;
        wire signed [2*N+4:0] dm = $signed({3'b011, {(2 * N) {1'b0}}}) - $signed({2'b00, mq});
        wire signed [2*N+4:0] dr = (dm + $signed({{(2 * N + 4) {1'b0}}, 1'b1} << (N - 1))) >>> N;
        reg [N+1:0] d6;
        // stage 7: y' = y0 d / 2 in u1.N, clamped
        wire [R+N+2:0] ydw = y06 * d6 + ({{(R + N + 2) {1'b0}}, 1'b1} << R);
        wire [N+2:0] y1 = ydw >> (R + 1);
        reg [N:0] y7;
        always @(posedge clk) begin
          q5 <= qw[N:0];
          y05 <= y0;
          {mn5, k5, m5_0, m5_1, m5_2, z5} <= {mn4, k4, m4_0, m4_1, m4_2, z4};
          d6 <= dr < 0 ? {(N + 2) {1'b0}} : dr > $signed({{(N + 2) {1'b0}}, {(N + 2) {1'b1}}}) ?
              {(N + 2) {1'b1}} : dr[N+1:0];
          y06 <= y05;
          {k6, m6_0, m6_1, m6_2, z6} <= {k5, m5_0, m5_1, m5_2, z5};
          y7 <= y1 > {1'b0, {(N + 1) {1'b1}}} ? {(N + 1) {1'b1}} : y1[N:0];
          {k7, m7_0, m7_1, m7_2, z7} <= {k6, m6_0, m6_1, m6_2, z6};
        end
        assign yf = y7;
        assign {kf, mf0, mf1, mf2, zf} = {k7, m7_0, m7_1, m7_2, z7};
      end else begin : g_rom
        assign yf = {1'b0, y0};
        assign {kf, mf0, mf1, mf2, zf} = {k4, m4_0, m4_1, m4_2, z4};
      end
      // n^_i = x'_i y >> (k + FY - B), rounded (ties up), saturated to s2.B
      wire [7:0] rs = kf + (FY + LB - B);
      wire signed [NW-1:0] one = 1;
      wire signed [NW-1:0] h0 = (((mf0 * $signed({1'b0, yf})) <<< (LB + 1)) + (one <<< rs)) >>> (rs + 1);
      wire signed [NW-1:0] h1 = (((mf1 * $signed({1'b0, yf})) <<< (LB + 1)) + (one <<< rs)) >>> (rs + 1);
      wire signed [NW-1:0] h2 = (((mf2 * $signed({1'b0, yf})) <<< (LB + 1)) + (one <<< rs)) >>> (rs + 1);
      localparam signed [NW-1:0] HMAX = ({{(NW - 1) {1'b0}}, 1'b1} << (HW - 1)) - 1;
      localparam signed [NW-1:0] HMIN = -({{(NW - 1) {1'b0}}, 1'b1} << (HW - 1));
      assign hat_w[g*3*HW+:HW] = h0 > HMAX ? HMAX[HW-1:0] : h0 < HMIN ? HMIN[HW-1:0] : h0[HW-1:0];
      assign hat_w[g*3*HW+HW+:HW] = h1 > HMAX ? HMAX[HW-1:0] : h1 < HMIN ? HMIN[HW-1:0] : h1[HW-1:0];
      assign hat_w[g*3*HW+2*HW+:HW] = h2 > HMAX ? HMAX[HW-1:0] : h2 < HMIN ? HMIN[HW-1:0] : h2[HW-1:0];
      assign zero_w[g] = zf;
    end
  endgenerate
  assign rsqrt_addr0 = addr_w[A-1:0];
  assign rsqrt_addr1 = addr_w[2*A-1:A];

  localparam S5 = NEWTON ? 8 : 5;  // the n^, v^ stage
  // ---- n^, v^ with the zero-vector muxes ----
  reg [3*HW-1:0] nh5, vh5, nh6, vh6;
  reg zn5, ze5, zn6, ze6, zn7, ze7, zn8, ze8;
  wire [3*HW-1:0] nraw = hat_w[3*HW-1:0];
  wire [3*HW-1:0] vraw = hat_w[6*HW-1:3*HW];
  always @(posedge clk) begin
    nh5 <= zero_w[0] ? (zero_w[1] ? 0 : vraw) : nraw;
    vh5 <= zero_w[1] ? (zero_w[0] ? 0 : nraw) : vraw;
    {zn5, ze5} <= {zero_w[0], zero_w[1]};
  end

  // ---- d = n^.v^ rounded to s3.B, saturated ----
  function signed [HW-1:0] cmp;
    input [3*HW-1:0] v;
    input integer i;
    cmp = v[i*HW+:HW];
  endfunction
  wire signed [2*HW+1:0] dot = cmp(nh5, 0) * cmp(vh5, 0) + cmp(nh5, 1) * cmp(vh5, 1) + cmp(nh5, 2) * cmp(vh5, 2);
  wire signed [2*HW+1:0] dotr = (dot + $signed({{(2 * HW + 1) {1'b0}}, 1'b1} << (B - 1))) >>> B;
  localparam signed [2*HW+1:0] DMAX = ({{(2 * HW + 1) {1'b0}}, 1'b1} << (DW - 1)) - 1;
  localparam signed [2*HW+1:0] DMIN = -({{(2 * HW + 1) {1'b0}}, 1'b1} << (DW - 1));
  reg signed [DW-1:0] d6;
  always @(posedge clk) begin
    d6 <= dotr > DMAX ? DMAX[DW-1:0] : dotr < DMIN ? DMIN[DW-1:0] : dotr[DW-1:0];
    {nh6, vh6, zn6, ze6} <= {nh5, vh5, zn5, ze5};
  end

  // ---- r = 2 d n^ - v^ (aligned), rounded to s3.B, saturated ----
  localparam RW = DW + HW + 2;
  localparam signed [RW-1:0] RMAX = ({{(RW - 1) {1'b0}}, 1'b1} << (DW - 1)) - 1;
  localparam signed [RW-1:0] RMIN = -({{(RW - 1) {1'b0}}, 1'b1} << (DW - 1));
  function signed [DW-1:0] refl;
    input signed [DW-1:0] dd;
    input signed [HW-1:0] nn;
    input signed [HW-1:0] vv;
    reg signed [RW-1:0] x;
    begin
      x = ((((dd * nn) <<< 1) - (vv <<< B)) + $signed({{(RW - 1) {1'b0}}, 1'b1} << (B - 1))) >>> B;
      refl = x > RMAX ? RMAX[DW-1:0] : x < RMIN ? RMIN[DW-1:0] : x[DW-1:0];
    end
  endfunction
  reg signed [DW-1:0] r7_0, r7_1, r7_2;
  reg bf7, bf8;
  always @(posedge clk) begin
    r7_0 <= refl(d6, cmp(nh6, 0), cmp(vh6, 0));
    r7_1 <= refl(d6, cmp(nh6, 1), cmp(vh6, 1));
    r7_2 <= refl(d6, cmp(nh6, 2), cmp(vh6, 2));
    bf7 <= d6 < 0;
    {zn7, ze7} <= {zn6, ze6};
  end

  // ---- t = r lambda, exact ----
  wire [L:0] lam7 = lam_sr[(S5+1)*(L+1)+:L+1];  // stage S5 + 2
  reg signed [TW-1:0] t8_0, t8_1, t8_2;
  always @(posedge clk) begin
    t8_0 <= r7_0 * $signed({1'b0, lam7});
    t8_1 <= r7_1 * $signed({1'b0, lam7});
    t8_2 <= r7_2 * $signed({1'b0, lam7});
    {bf8, zn8, ze8} <= {bf7, zn7, ze7};
  end

  // ---- coord = (t + 1) >> OS, rounded (ties up), saturated to s(OW) ----
  localparam signed [CW-1:0] CMAX = ({{(CW - 1) {1'b0}}, 1'b1} << (OW - 1)) - 1;
  localparam signed [CW-1:0] CMIN = -({{(CW - 1) {1'b0}}, 1'b1} << (OW - 1));
  function [OW-1:0] coord;
    input signed [TW-1:0] tt;
    reg signed [CW-1:0] x;
    begin
      x = tt;
      x = x + $signed({{(CW - 1) {1'b0}}, 1'b1} << (B + L));
      if (OS > 0) x = (x + $signed({{(CW - 1) {1'b0}}, 1'b1} << (OS > 0 ? OS - 1 : 0))) >>> (OS > 0 ? OS : 0);
      else x = x <<< (OS > 0 ? 0 : -OS);
      coord = x > CMAX ? CMAX[OW-1:0] : x < CMIN ? CMIN[OW-1:0] : x[OW-1:0];
    end
  endfunction
  always @(posedge clk) begin
    s <= coord(t8_0);
    t <= coord(t8_1);
    r <= coord(t8_2);
    {back_facing, zero_n, zero_e} <= {bf8, zn8, ze8};
  end

  reg [LAT-1:0] vld;
  always @(posedge clk) begin
    if (rst) vld <= 0;
    else vld <= {vld[LAT-2:0], in_valid};
  end
  assign out_valid = vld[LAT-1];
endmodule
