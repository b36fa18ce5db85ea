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
`include "leading_one.vh"

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

  // Written for Icarus's interpreter (docs/rtl.md): each vector's stages are one clocked
  // block and the shared stages another, every combinational step a blocking temporary
  // evaluated once per clock (no `always @*` or continuous-assign cascades), the
  // leading-one searches binary (log2 steps, not a loop over bits), no function calls.
  localparam [L:0] ONE = {1'b1, {L{1'b0}}};
  localparam QS = 2 * R > N ? 2 * R - N : 0;  // q = y0^2 in u1.N: right shift, rounded
  localparam QL = 2 * R > N ? 0 : N - 2 * R;  // or left shift
  localparam [2*R+N:0] QRND = 2 * R > N ? {{(2 * R + N) {1'b0}}, 1'b1} << (QS - 1) : 0;
  localparam signed [NW-1:0] ONE_NW = 1;
  localparam signed [NW-1:0] HMAX = ({{(NW - 1) {1'b0}}, 1'b1} << (HW - 1)) - 1;
  localparam signed [NW-1:0] HMIN = -({{(NW - 1) {1'b0}}, 1'b1} << (HW - 1));

  // Leading-one searches: LEAD_ONE (lib/leading_one.vh).

  // ---- per vector (0: n, 1: e): stages 1-4 (7), n^_i registered raw at stage S5 ----
  wire [2*A-1:0] addr_w;
  wire [6*HW-1:0] hat_w;  // {v^ (e), n^ (n)}, component 0 lowest, before the zero muxes
  wire [1:0] zero_w;
  genvar g;
  generate
    for (g = 0; g < 2; g = g + 1) begin : g_vec
      reg signed [P-1:0] m1_0, m1_1, m1_2, m2_0, m2_1, m2_2, m3_0, m3_1, m3_2;
      reg signed [P-1:0] m4_0, m4_1, m4_2, m5_0, m5_1, m5_2, m6_0, m6_1, m6_2;
      reg signed [P-1:0] m7_0, m7_1, m7_2;
      reg z1, z2, z3, z4, z5, z6, z7;
      reg [SW-1:0] s2;
      reg [A-1:0] addr3;
      reg [N+1:0] mn3, mn4, mn5;
      reg [KB-1:0] k3, k4, k5, k6, k7;
      reg [N:0] q5, y7;
      reg [R-1:0] y05, y06;
      reg [N+1:0] d6;
      reg [3*HW-1:0] h5;  // n^ (or v^), saturated, before the zero muxes
      reg zh5;
      // combinational temporaries
      reg signed [W-1:0] x0, x1, x2;
      reg [W-1:0] orv;
      reg [QB-1:0] q, sh;
      reg [PB-1:0] p;
      reg [SW+A-1:0] idx_w;
      reg [SW+N-1:0] mn_w;
      reg [R-1:0] y0;
      reg [2*R+N:0] qw;
      reg [2*N+2:0] mq;
      reg signed [2*N+4:0] dr;
      reg [R+N+2:0] ydw;
      reg [N+2:0] y1;
      reg [YW-1:0] yf;
      reg [KB-1:0] kf;
      reg signed [P-1:0] mf0, mf1, mf2;
      reg [7:0] rs;
      reg signed [NW-1:0] h0, h1, h2;
      always @(posedge clk) begin
        // stage 1: block normalise to s(P) mantissas
        x0 = g == 0 ? nx : ex;
        x1 = g == 0 ? ny : ey;
        x2 = g == 0 ? nz : ez;
        orv = (x0[W-1] ? -x0 : x0) | (x1[W-1] ? -x1 : x1) | (x2[W-1] ? -x2 : x2);
        q = 0;  // leading one of orv (0 when orv = 0)
        `LEAD_ONE(q, orv, QB)
        sh = q > P - 2 ? q - (P - 2) : 0;
        m1_0 <= x0 >>> sh;  // at XW = max(W, P) bits, then the low P
        m1_1 <= x1 >>> sh;
        m1_2 <= x2 >>> sh;
        z1 <= orv == 0;
        // stage 2: S = sum of squares, u(2P)
        s2 <= m1_0 * m1_0 + m1_1 * m1_1 + m1_2 * m1_2;
        {m2_0, m2_1, m2_2, z2} <= {m1_0, m1_1, m1_2, z1};
        // stage 3: leading one p, k = p/2, address {parity, A-1 bits below}, m_N
        p = 0;
        `LEAD_ONE(p, s2, PB)
        idx_w = ({{A{1'b0}}, s2 & ~({{(SW - 1) {1'b0}}, 1'b1} << p)} << A1) >> p;  // < 2^(A-1)
        addr3 <= ({{(SW + A - 1) {1'b0}}, p[0]} << A1) | idx_w;
        mn_w = ({{N{1'b0}}, s2} << N) >> {p[PB-1:1], 1'b0};
        mn3 <= mn_w[N+1:0];
        k3 <= p >> 1;
        {m3_0, m3_1, m3_2, z3} <= {m2_0, m2_1, m2_2, z2};
        // stage 4: the ROM presents y0
        {mn4, k4, m4_0, m4_1, m4_2, z4} <= {mn3, k3, m3_0, m3_1, m3_2, z3};
        y0 = g == 0 ? rsqrt_data0 : rsqrt_data1;
        if (NEWTON) begin
          // stage 5: q = y0^2 in u1.N (rounded, ties up)
          qw = ((y0 * y0 + QRND) >> QS) << QL;
          q5 <= qw[N:0];
          y05 <= y0;
          {mn5, k5, m5_0, m5_1, m5_2, z5} <= {mn4, k4, m4_0, m4_1, m4_2, z4};
          // stage 6: d = 3 - m_N q, rounded to u2.N, clamped
          mq = mn5 * q5;
          dr = ($signed({3'b011, {(2 * N) {1'b0}}}) - $signed({2'b00, mq})
                + $signed({{(2 * N + 4) {1'b0}}, 1'b1} << (N - 1))) >>> N;
          d6 <= dr < 0 ? {(N + 2) {1'b0}} : dr > $signed({{(N + 2) {1'b0}}, {(N + 2) {1'b1}}}) ?
              {(N + 2) {1'b1}} : dr[N+1:0];
          y06 <= y05;
          {k6, m6_0, m6_1, m6_2, z6} <= {k5, m5_0, m5_1, m5_2, z5};
          // stage 7: y' = y0 d / 2 in u1.N, clamped
          ydw = y06 * d6 + ({{(R + N + 2) {1'b0}}, 1'b1} << R);
          y1 = ydw >> (R + 1);
          y7 <= y1 > {1'b0, {(N + 1) {1'b1}}} ? {(N + 1) {1'b1}} : y1[N:0];
          {k7, m7_0, m7_1, m7_2, z7} <= {k6, m6_0, m6_1, m6_2, z6};
          yf = y7;
          {kf, mf0, mf1, mf2} = {k7, m7_0, m7_1, m7_2};
          zh5 <= z7;
        end else begin
          yf = {1'b0, y0};
          {kf, mf0, mf1, mf2} = {k4, m4_0, m4_1, m4_2};
          zh5 <= z4;
        end
        // n^_i = x'_i y >> (k + FY - B), rounded (ties up), saturated to s2.B
        rs = kf + (FY + LB - B);
        h0 = (((mf0 * $signed({1'b0, yf})) <<< (LB + 1)) + (ONE_NW <<< rs)) >>> (rs + 1);
        h1 = (((mf1 * $signed({1'b0, yf})) <<< (LB + 1)) + (ONE_NW <<< rs)) >>> (rs + 1);
        h2 = (((mf2 * $signed({1'b0, yf})) <<< (LB + 1)) + (ONE_NW <<< rs)) >>> (rs + 1);
        h5[HW-1:0] <= h0 > HMAX ? HMAX[HW-1:0] : h0 < HMIN ? HMIN[HW-1:0] : h0[HW-1:0];
        h5[2*HW-1:HW] <= h1 > HMAX ? HMAX[HW-1:0] : h1 < HMIN ? HMIN[HW-1:0] : h1[HW-1:0];
        h5[3*HW-1:2*HW] <= h2 > HMAX ? HMAX[HW-1:0] : h2 < HMIN ? HMIN[HW-1:0] : h2[HW-1:0];
      end
      assign addr_w[g*A+:A] = addr3;
      assign hat_w[g*3*HW+:3*HW] = h5;
      assign zero_w[g] = zh5;
    end
  endgenerate
  assign rsqrt_addr0 = addr_w[A-1:0];
  assign rsqrt_addr1 = addr_w[2*A-1:A];

  localparam S5 = NEWTON ? 8 : 5;  // the n^, v^ stage
  localparam RW = DW + HW + 2;
  localparam signed [2*HW+1:0] DMAX = ({{(2 * HW + 1) {1'b0}}, 1'b1} << (DW - 1)) - 1;
  localparam signed [2*HW+1:0] DMIN = -({{(2 * HW + 1) {1'b0}}, 1'b1} << (DW - 1));
  localparam signed [RW-1:0] RMAX = ({{(RW - 1) {1'b0}}, 1'b1} << (DW - 1)) - 1;
  localparam signed [RW-1:0] RMIN = -({{(RW - 1) {1'b0}}, 1'b1} << (DW - 1));
  localparam signed [RW-1:0] RRND = {{(RW - 1) {1'b0}}, 1'b1} << (B - 1);
  localparam signed [CW-1:0] CMAX = ({{(CW - 1) {1'b0}}, 1'b1} << (OW - 1)) - 1;
  localparam signed [CW-1:0] CMIN = -({{(CW - 1) {1'b0}}, 1'b1} << (OW - 1));
  // coord = (t + 1) >> OS rounded (ties up), or << -OS: one constant added, two shifts
  localparam integer COS = OS > 0 ? OS : 0;
  localparam integer CSL = OS > 0 ? 0 : -OS;
  localparam signed [CW-1:0] CADD = ({{(CW - 1) {1'b0}}, 1'b1} << (B + L))
      + ({{(CW - 1) {1'b0}}, OS > 0 ? 1'b1 : 1'b0} << (OS > 0 ? OS - 1 : 0));

  // lam_sr[(k-1)(L+1) +: L+1] is lambda at stage k
  reg [(LAT-1)*(L+1)-1:0] lam_sr;
  reg [3*HW-1:0] nh6, vh6;
  reg zn6, ze6, zn7, ze7, zn8, ze8;
  reg signed [DW-1:0] d6;
  reg signed [DW-1:0] r7_0, r7_1, r7_2;
  reg bf7, bf8;
  reg signed [TW-1:0] t8_0, t8_1, t8_2;
  // combinational temporaries
  reg [3*HW-1:0] nh, vh;
  reg signed [HW-1:0] n0, n1, n2, e0, e1, e2;
  reg signed [2*HW+1:0] dotr;
  reg signed [RW-1:0] xr0, xr1, xr2;
  reg signed [CW-1:0] c0, c1, c2;
  always @(posedge clk) begin
    // stage 1: lambda clamp
    lam_sr <= {lam_sr, lambda > ONE ? ONE : lambda};
    // ---- stage S5 + 1: the zero-vector muxes; d = n^.v^ rounded to s3.B, saturated ----
    nh = zero_w[0] ? (zero_w[1] ? {(3 * HW) {1'b0}} : hat_w[6*HW-1:3*HW]) : hat_w[3*HW-1:0];
    vh = zero_w[1] ? (zero_w[0] ? {(3 * HW) {1'b0}} : hat_w[3*HW-1:0]) : hat_w[6*HW-1:3*HW];
    {n2, n1, n0} = nh;
    {e2, e1, e0} = vh;
    dotr = (n0 * e0 + n1 * e1 + n2 * e2 + $signed({{(2 * HW + 1) {1'b0}}, 1'b1} << (B - 1))) >>> B;
    d6 <= dotr > DMAX ? DMAX[DW-1:0] : dotr < DMIN ? DMIN[DW-1:0] : dotr[DW-1:0];
    {nh6, vh6, zn6, ze6} <= {nh, vh, zero_w[0], zero_w[1]};
    // ---- r = 2 d n^ - v^ (aligned), rounded to s3.B, saturated ----
    {n2, n1, n0} = nh6;
    {e2, e1, e0} = vh6;
    xr0 = ((((d6 * n0) <<< 1) - (e0 <<< B)) + RRND) >>> B;
    xr1 = ((((d6 * n1) <<< 1) - (e1 <<< B)) + RRND) >>> B;
    xr2 = ((((d6 * n2) <<< 1) - (e2 <<< B)) + RRND) >>> B;
    r7_0 <= xr0 > RMAX ? RMAX[DW-1:0] : xr0 < RMIN ? RMIN[DW-1:0] : xr0[DW-1:0];
    r7_1 <= xr1 > RMAX ? RMAX[DW-1:0] : xr1 < RMIN ? RMIN[DW-1:0] : xr1[DW-1:0];
    r7_2 <= xr2 > RMAX ? RMAX[DW-1:0] : xr2 < RMIN ? RMIN[DW-1:0] : xr2[DW-1:0];
    bf7 <= d6 < 0;
    {zn7, ze7} <= {zn6, ze6};
    // ---- t = r lambda, exact (lambda at stage S5 + 2) ----
    t8_0 <= r7_0 * $signed({1'b0, lam_sr[(S5+1)*(L+1)+:L+1]});
    t8_1 <= r7_1 * $signed({1'b0, lam_sr[(S5+1)*(L+1)+:L+1]});
    t8_2 <= r7_2 * $signed({1'b0, lam_sr[(S5+1)*(L+1)+:L+1]});
    {bf8, zn8, ze8} <= {bf7, zn7, ze7};
    // ---- coord = (t + 1) >> OS, rounded (ties up), saturated to s(OW) ----
    c0 = ((t8_0 + CADD) >>> COS) <<< CSL;
    c1 = ((t8_1 + CADD) >>> COS) <<< CSL;
    c2 = ((t8_2 + CADD) >>> COS) <<< CSL;
    s <= c0 > CMAX ? CMAX[OW-1:0] : c0 < CMIN ? CMIN[OW-1:0] : c0[OW-1:0];
    t <= c1 > CMAX ? CMAX[OW-1:0] : c1 < CMIN ? CMIN[OW-1:0] : c1[OW-1:0];
    r <= c2 > CMAX ? CMAX[OW-1:0] : c2 < CMIN ? CMIN[OW-1:0] : c2[OW-1:0];
    {back_facing, zero_n, zero_e} <= {bf8, zn8, ze8};
  end

  reg [LAT-1:0] vld;
  always @(posedge clk) begin
    if (rst) vld <= 0;
    else vld <= {vld[LAT-2:0], in_valid};
  end
  assign out_valid = vld[LAT-1];
endmodule
