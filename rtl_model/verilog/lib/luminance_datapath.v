// luminance_datapath — the luminance modulators' shared datapath (the model's
// rtl_model/src/units/luminance_ram.rs, radial correction off), instantiated by
// bloom_flare_modulator.v (NR = 1: one FALLOFF table for all three colours) and
// halo_modulator.v (NR = 3: one RING table per colour): (u, v) -> SHAPE RAM
// (bilinear) -> d -> falloff table(s) (linear) -> p -> x RGB gain, saturating. The
// tables are ports with synchronous read: 4 shape read ports (the four banks) and one
// address pair for the NR falloff tables (every table reads the same two entries;
// table i's data at [i*FALLOFF_BITS +: FALLOFF_BITS]).
// Latency 6, II 1:
//   1 address registers (clamp, split into index and weight)   -> shape RAM read
//   2 shape data                                                 (bilinear, round: d)
//   3 falloff address registers                                  -> falloff RAM read
//   4 falloff data                                               (lerp, gain multiply)
//   5 luminance registers
//   6 output registers
module luminance_datapath #(
    parameter NR              = 1,
    parameter COORD_FRAC_BITS = 14,
    parameter SHAPE_LOG2      = 7,
    parameter SHAPE_BITS      = 16,
    parameter FALLOFF_LOG2    = 8,
    parameter FALLOFF_BITS    = 16,
    parameter WEIGHT_BITS     = 8,
    parameter GAIN_INT_BITS   = 12,
    parameter GAIN_FRAC_BITS  = 4,
    parameter OUT_BITS        = 12,
    // derived (do not set)
    parameter SIDE            = (1 << SHAPE_LOG2) + 1,
    parameter SAW             = $clog2(SIDE * SIDE),
    parameter FAW             = FALLOFF_LOG2 + 1
) (
    input                                     clk,
    input                                     rst,
    input                                     in_valid,
    input      [COORD_FRAC_BITS+1:0]          u,
    input      [COORD_FRAC_BITS+1:0]          v,
    input      [GAIN_INT_BITS+GAIN_FRAC_BITS-1:0] gain_r,
    input      [GAIN_INT_BITS+GAIN_FRAC_BITS-1:0] gain_g,
    input      [GAIN_INT_BITS+GAIN_FRAC_BITS-1:0] gain_b,
    output reg [SAW-1:0]                      shape_addr0,
    output reg [SAW-1:0]                      shape_addr1,
    output reg [SAW-1:0]                      shape_addr2,
    output reg [SAW-1:0]                      shape_addr3,
    input      [SHAPE_BITS-1:0]               shape_data0,
    input      [SHAPE_BITS-1:0]               shape_data1,
    input      [SHAPE_BITS-1:0]               shape_data2,
    input      [SHAPE_BITS-1:0]               shape_data3,
    output reg [FAW-1:0]                      falloff_addr0,
    output reg [FAW-1:0]                      falloff_addr1,
    input      [NR*FALLOFF_BITS-1:0]          falloff_data0,
    input      [NR*FALLOFF_BITS-1:0]          falloff_data1,
    output reg                                out_valid,
    output reg [SHAPE_BITS-1:0]               d,
    output reg [OUT_BITS-1:0]                 lum_r,
    output reg [OUT_BITS-1:0]                 lum_g,
    output reg [OUT_BITS-1:0]                 lum_b
);
  localparam F = COORD_FRAC_BITS;
  localparam K = SHAPE_LOG2;
  localparam SB = SHAPE_BITS;
  localparam M = FALLOFF_LOG2;
  localparam FB = FALLOFF_BITS;
  localparam WB = WEIGHT_BITS;
  localparam GB = GAIN_INT_BITS + GAIN_FRAC_BITS;
  localparam GF = GAIN_FRAC_BITS;
  localparam S = F + 1 - K;  // fraction bits of the cell position
  localparam R = FB + GAIN_INT_BITS;  // p replicated width
  localparam SH = R + GF;
  localparam PW = R + 1 + GB;  // p x gain
  localparam REP_D = (M + WB + SB - 1) / SB;
  localparam REP_P = (R + FB - 1) / FB;

  // Written for Icarus's interpreter (docs/rtl.md): every combinational step is a
  // blocking temporary in the clocked block of the stage it feeds, evaluated once per
  // clock (the continuous bilinear and lerp nets were re-evaluated on each of the four
  // shape words' and the falloff words' changes), and the functions are macros (a
  // function call runs as a thread).

  // ---- stage 1: clamp to [-1, 1], split into (index u(K+1), weight u(WB)) ----
`define LD_SPLIT(I_, W_, C) \
    sa = $signed({C[F+1], C}) + $signed({3'b001, {F{1'b0}}});  /* u + 1 */ \
    if (sa < 0) sac = 0; \
    else if (sa > $signed({3'b010, {F{1'b0}}})) sac = {2'b10, {F{1'b0}}}; \
    else sac = sa[F+1:0]; \
    if (S <= 0) begin \
      I_ = sac << (-S); \
      W_ = 0; \
    end else begin \
      I_ = sac >> S; \
      sfr = sac & ((1 << S) - 1); \
      if (S >= WB) W_ = sfr >> (S - WB); \
      else W_ = sfr << (WB - S); \
    end

  // p x gain, rounded, saturated
`define LD_GMUL(DST, PR, G) \
    gprod = PR * G; \
    gl = (gprod + ({{(PW - 1) {1'b0}}, 1'b1} << (SH - 1))) >> SH; \
    DST <= (gl > {OUT_BITS{1'b1}}) ? {OUT_BITS{1'b1}} : gl[OUT_BITS-1:0];

  reg [WB-1:0] wx1, wy1, wx2, wy2;
  reg [3*GB-1:0] g1, g2, g3, g4;
  reg v1, v2, v3, v4, v5;
  reg signed [F+2:0] sa;
  reg [F+1:0] sac, sfr;
  reg [K:0] iu, jv, iu1, jv1;
  reg [WB-1:0] wu, wv;
  always @(posedge clk) begin
    `LD_SPLIT(iu, wu, u)
    `LD_SPLIT(jv, wv, v)
    iu1 = (iu == SIDE - 1) ? iu : iu + 1;
    jv1 = (jv == SIDE - 1) ? jv : jv + 1;
    shape_addr0 <= jv * SIDE + iu;  // s00
    shape_addr1 <= jv * SIDE + iu1;  // s10
    shape_addr2 <= jv1 * SIDE + iu;  // s01
    shape_addr3 <= jv1 * SIDE + iu1;  // s11
    wx1 <= wu;
    wy1 <= wv;
    g1 <= {gain_r, gain_g, gain_b};
    // stage 2: the RAM presents the samples; carry the weights along
    wx2 <= wx1;
    wy2 <= wy1;
    g2 <= g1;
  end

  // ---- stage 3: bilinear, round to d; the falloff address, d replicated to M + WB bits ----
  reg [SB-1:0] d3, d4, d5;
  reg [WB-1:0] fw3, fw4;
  reg signed [SB+1:0] s00, s10, s01, s11;
  reg signed [WB+1:0] wxs, wys;
  reg signed [SB+2*WB+3:0] r0, r1, t;
  reg [SB+2*WB+3:0] tr;
  reg [REP_D*SB-1:0] drep;
  always @(posedge clk) begin
    s00 = {2'b00, shape_data0};
    s10 = {2'b00, shape_data1};
    s01 = {2'b00, shape_data2};
    s11 = {2'b00, shape_data3};
    wxs = {2'b00, wx2};
    wys = {2'b00, wy2};
    r0 = (s00 <<< WB) + (s10 - s00) * wxs;
    r1 = (s01 <<< WB) + (s11 - s01) * wxs;
    t = (r0 <<< WB) + (r1 - r0) * wys;
    tr = t + (1 << (2 * WB - 1));
    drep = {REP_D{tr[2*WB+:SB]}};
    falloff_addr0 <= drep[REP_D*SB-1-:M];
    falloff_addr1 <= drep[REP_D*SB-1-:M] + 1;
    fw3 <= drep[REP_D*SB-1-M-:WB];
    d3 <= tr[2*WB+:SB];
    g3 <= g2;
    // stage 4: the falloff RAM presents its samples
    fw4 <= fw3;
    d4 <= d3;
    g4 <= g3;
  end

  // ---- stage 5: per table, lerp to p, replicate (u1.R operand); x gain ----
  // colour c reads table c (NR = 3) or the one table (NR = 1)
  localparam CR = NR == 1 ? 0 : 2;
  localparam CG = NR == 1 ? 0 : 1;
  reg [NR*(R+1)-1:0] prep;
  reg signed [FB+1:0] f0, f1;
  reg signed [FB+WB+3:0] ft;
  reg [FB+WB+3:0] ftr;
  reg [REP_P*FB-1:0] prep_w;
  reg [PW-1:0] gprod, gl;
  integer gi;
  reg [OUT_BITS-1:0] l5r, l5g, l5b;
  always @(posedge clk) begin
    for (gi = 0; gi < NR; gi = gi + 1) begin
      f0 = {2'b00, falloff_data0[gi*FB+:FB]};
      f1 = {2'b00, falloff_data1[gi*FB+:FB]};
      ft = (f0 <<< WB) + (f1 - f0) * $signed({2'b00, fw4});
      ftr = ft + (1 << (WB - 1));
      prep_w = {REP_P{ftr[WB+:FB]}};
      prep[gi*(R+1)+:R+1] = {1'b0, prep_w[REP_P*FB-1-:R]} + ftr[WB+FB-1];
    end
    `LD_GMUL(l5r, prep[CR*(R+1)+:R+1], g4[3*GB-1-:GB])
    `LD_GMUL(l5g, prep[CG*(R+1)+:R+1], g4[2*GB-1-:GB])
    `LD_GMUL(l5b, prep[0+:R+1], g4[GB-1:0])
    d5 <= d4;
    d <= d5;
    lum_r <= l5r;
    lum_g <= l5g;
    lum_b <= l5b;
  end
`undef LD_SPLIT
`undef LD_GMUL

  always @(posedge clk) begin
    if (rst) begin
      {v1, v2, v3, v4, v5, out_valid} <= 6'b0;
    end else begin
      {v1, v2, v3, v4, v5, out_valid} <= {in_valid, v1, v2, v3, v4, v5};
    end
  end
endmodule
