// projective_texcoord — u = s/q, v = t/q (rtl_model/src/units/projective_texcoord.rs).
// s, t, q are s(IN_BITS) words (the input fraction cancels); u, v are s(OUT_BITS) with
// OUT_FRAC_BITS fraction bits. The reciprocal ROM (2^RECIP_INDEX_BITS entries of
// RECIP_ENTRY_BITS, u0.E) is outside the module: one synchronous read port
// `recip_addr0` / `recip_data0` (data the clock after the address).
//   clock 1: q <= 0 -> behind; leading one p of Q = q (u(W-1)), m = Q << (W-2-p) in
//            u1.(W-2), the ROM index = the I bits of m below its leading one;
//   clock 2: ROM read, r = u0.E;
//   2 clocks per Newton step r' = r*(2 - m*r) in u1.N: (m*r, 2 - m*r rounded to
//            u1.N, clamped to [0, 2^(N+1)-1]) then (r*d rounded to u1.N, clamped);
//   then s*r and t*r (s(W) x u1.F_r, exact);
//   then >> (F_r + p - OUT_FRAC_BITS), round to nearest (ties up), saturate.
// Latency 4 + 2*NEWTON_STEPS, II 1.
module projective_texcoord #(
    parameter IN_BITS          = 32,
    parameter OUT_BITS         = 16,
    parameter OUT_FRAC_BITS    = 12,
    parameter RECIP_INDEX_BITS = 8,
    parameter RECIP_ENTRY_BITS = 16,
    parameter NEWTON_STEPS     = 1,
    parameter NEWTON_FRAC_BITS = 20
) (
    input                             clk,
    input                             rst,
    input                             in_valid,
    input      [         IN_BITS-1:0] s,
    input      [         IN_BITS-1:0] t,
    input      [         IN_BITS-1:0] q,
    output reg                        out_valid,
    output reg [        OUT_BITS-1:0] u,
    output reg [        OUT_BITS-1:0] v,
    output reg                        behind,
    output     [RECIP_INDEX_BITS-1:0] recip_addr0,
    input      [RECIP_ENTRY_BITS-1:0] recip_data0
);
  localparam W = IN_BITS;
  localparam FM = W - 2;  // fraction bits of the normalised m, u1.FM
  localparam IB = RECIP_INDEX_BITS;
  localparam E = RECIP_ENTRY_BITS;
  localparam N = NEWTON_FRAC_BITS;
  localparam FR = NEWTON_STEPS > 0 ? N : E;  // fraction bits of the final r
  localparam LAT = 4 + 2 * NEWTON_STEPS;

  // valid chain
  reg [LAT-1:0] vc;
  always @(posedge clk) begin
    if (rst) begin
      vc <= 0;
      out_valid <= 1'b0;
    end else begin
      vc <= {vc[LAT-2:0], in_valid};
      out_valid <= vc[LAT-2];
    end
  end

  // ---- clock 1: behind, leading one, normalise, ROM index ----
  wire signed [W-1:0] qs = q;
  wire bh = qs <= 0;
  wire [W-2:0] qmag = q[W-2:0];
  reg [7:0] p;
  integer j;
  always @* begin
    p = 0;
    for (j = 0; j < W - 1; j = j + 1) if (qmag[j]) p = j;
  end
  wire [FM:0] m = qmag << (FM - p);  // u1.FM
  wire [IB-1:0] idx;
  generate
    if (FM >= IB) begin : g_idx_down
      assign idx = m[FM-1:FM-IB];
    end else begin : g_idx_up
      assign idx = m[FM-1:0] << (IB - FM);
    end
  endgenerate

  reg [FM:0] m1;
  reg [IB-1:0] idx1;
  reg [7:0] p1;
  reg [W-1:0] s1, t1;
  reg b1;
  always @(posedge clk) begin
    m1   <= m;
    idx1 <= idx;
    p1   <= p;
    s1   <= s;
    t1   <= t;
    b1   <= bh;
  end

  // ---- clock 2: ROM read ----
  assign recip_addr0 = idx1;
  reg [FM:0] m2;
  reg [7:0] p2;
  reg [W-1:0] s2, t2;
  reg b2;
  always @(posedge clk) begin
    m2 <= m1;
    p2 <= p1;
    s2 <= s1;
    t2 <= t1;
    b2 <= b1;
  end

  // ---- Newton steps: step k takes r with FRk fraction bits to u1.N ----
  // Stage k holds r (up to max(E, N) + 1 bits), m, and the carry (s, t, p, behind).
  localparam RW = (E > N ? E : N) + 1;
  wire [RW-1:0] r_st[0:NEWTON_STEPS];
  wire [FM:0] m_st[0:NEWTON_STEPS];
  wire [2*W+8:0] c_st[0:NEWTON_STEPS];
  assign r_st[0] = recip_data0;
  assign m_st[0] = m2;
  assign c_st[0] = {s2, t2, p2, b2};
  genvar k;
  generate
    for (k = 0; k < NEWTON_STEPS; k = k + 1) begin : g_newton
      localparam FRK = k == 0 ? E : N;
      wire [RW-1:0] r_out;
      wire [FM:0] m_out;
      wire [2*W+8:0] c_out;
      projective_texcoord_newton #(
          .N (N),
          .FR(FRK),
          .FM(FM),
          .RW(RW),
          .CW(2 * W + 9)
      ) step (
          .clk  (clk),
          .r    (r_st[k]),
          .m    (m_st[k]),
          .c    (c_st[k]),
          .r_out(r_out),
          .m_out(m_out),
          .c_out(c_out)
      );
      assign r_st[k+1] = r_out;
      assign m_st[k+1] = m_out;
      assign c_st[k+1] = c_out;
    end
  endgenerate

  // ---- s*r, t*r: s(W) x u1.FR -> s(W+FR+2) ----
  wire [FR:0] r = r_st[NEWTON_STEPS][FR:0];
  wire [W-1:0] sf, tf;
  wire [7:0] pf;
  wire bf;
  assign {sf, tf, pf, bf} = c_st[NEWTON_STEPS];
  localparam PW = W + FR + 2;
  reg signed [PW-1:0] su, tv;
  reg [7:0] p5;
  reg b5;
  always @(posedge clk) begin
    su <= $signed(sf) * $signed({1'b0, r});
    tv <= $signed(tf) * $signed({1'b0, r});
    p5 <= pf;
    b5 <= bf;
  end

  // ---- shift by FR + p - OUT_FRAC_BITS, round half up, saturate ----
  wire [OUT_BITS-1:0] uo, vo;
  projective_texcoord_scale #(
      .PW(PW),
      .FR(FR),
      .OF(OUT_FRAC_BITS),
      .O (OUT_BITS)
  ) sc_u (
      .x(su),
      .p(p5),
      .y(uo)
  );
  projective_texcoord_scale #(
      .PW(PW),
      .FR(FR),
      .OF(OUT_FRAC_BITS),
      .O (OUT_BITS)
  ) sc_v (
      .x(tv),
      .p(p5),
      .y(vo)
  );
  always @(posedge clk) begin
    u <= b5 ? 0 : uo;
    v <= b5 ? 0 : vo;
    behind <= b5;
  end
endmodule

// One Newton-Raphson step, two clocks: r' = r*(2 - m*r), in u1.N.
module projective_texcoord_newton #(
    parameter N  = 20,
    parameter FR = 16,
    parameter FM = 30,
    parameter RW = 21,
    parameter CW = 73
) (
    input               clk,
    input      [RW-1:0] r,
    input      [  FM:0] m,
    input      [CW-1:0] c,
    output reg [RW-1:0] r_out,
    output reg [  FM:0] m_out,
    output reg [CW-1:0] c_out
);
  localparam [N+1:0] RMAX = (1 << (N + 1)) - 1;
  wire [N:0] mn;  // m truncated (or extended) to u1.N
  generate
    if (FM >= N) begin : g_down
      assign mn = m >> (FM - N);
    end else begin : g_up
      assign mn = m << (N - FM);
    end
  endgenerate
  wire [FR:0] ri = r[FR:0];
  // 2 - m*r: u1.N x u1.FR -> u2.(N+FR); the difference s3.(N+FR); round to u1.N.
  wire signed [N+FR+3:0] two = 2 <<< (N + FR);
  wire signed [N+FR+3:0] prod = mn * ri;
  wire signed [N+FR+3:0] dr = (two - prod + (1 <<< (FR - 1))) >>> FR;
  wire [N:0] d = dr < 0 ? 0 : dr > RMAX ? RMAX : dr[N:0];
  reg [N:0] d1;
  reg [FR:0] r1;
  reg [FM:0] m1;
  reg [CW-1:0] c1;
  always @(posedge clk) begin
    d1 <= d;
    r1 <= ri;
    m1 <= m;
    c1 <= c;
  end
  // r*d: u1.FR x u1.N -> u2.(FR+N), rounded to u1.N, clamped.
  wire [N+FR+2:0] rd = r1 * d1 + (1 << (FR - 1));
  wire [N+FR+2:0] rn = rd >> FR;
  always @(posedge clk) begin
    r_out <= rn > RMAX ? RMAX : rn;
    m_out <= m1;
    c_out <= c1;
  end
endmodule

// x * 2^-(FR + p - OF), rounded to nearest (ties up), saturated to s(O).
module projective_texcoord_scale #(
    parameter PW = 50,
    parameter FR = 20,
    parameter OF = 12,
    parameter O  = 16
) (
    input  signed [PW-1:0] x,
    input         [   7:0] p,
    output        [ O-1:0] y
);
  // A left shift by L = max(0, OF - FR) first, so the remaining shift is >= 0.
  localparam L = OF > FR ? OF - FR : 0;
  localparam XW = PW + L + 1;
  wire signed [XW-1:0] x2 = x <<< L;
  wire [7:0] sh = p + FR + L - OF;
  wire signed [XW-1:0] rnd = sh == 0 ? x2 : (x2 + (1 <<< (sh - 1))) >>> sh;
  localparam signed [XW-1:0] HI = {1'b0, {(O - 1) {1'b1}}};  // 2^(O-1) - 1
  localparam signed [XW-1:0] LO = ~HI;  // -2^(O-1)
  assign y = rnd > HI ? HI[O-1:0] : rnd < LO ? LO[O-1:0] : rnd[O-1:0];
endmodule
