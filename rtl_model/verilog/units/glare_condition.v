// glare_condition — does a specular highlight become a glare source
// (rtl_model/src/units/glare_condition.rs, SPEC B Table 2):
//   metallic I_ps = I * I_s * cos^2(a), water I_ps = I * cos(a); glare when
//   I_ps >= T * I_a, and for water also total internal reflection
//   eta^2 (1 - cos^2(theta)) > 1; i_ps = min(round(I_ps), 2^OUT_BITS - 1).
// The datapath is combinational into the first register, then two more registers
// (latency 3, II 1, as the model's Timing).
module glare_condition #(
    parameter INT_BITS      = 12,
    parameter FRAC_BITS     = 4,
    parameter COEF_BITS     = 8,
    parameter COS_FRAC_BITS = 14,
    parameter ETA_FRAC_BITS = 14,
    parameter ETA_CODE      = 21840,  // eta as u2.ETA_FRAC_BITS (1.333 -> 21840)
    parameter THRESHOLD     = 40,
    parameter OUT_BITS      = 8
) (
    input                                clk,
    input                                rst,
    input                                in_valid,
    input                                water,
    input      [INT_BITS+FRAC_BITS-1:0]  intensity,
    input      [COEF_BITS-1:0]           specular,
    input      [COS_FRAC_BITS:0]         cos_alpha,
    input      [COS_FRAC_BITS:0]         cos_theta,
    input      [INT_BITS+FRAC_BITS-1:0]  ambient,
    output reg                           out_valid,
    output reg                           glare,
    output reg                           tir,
    output reg [OUT_BITS-1:0]            i_ps,
    output reg                           contrast_ok
);
  localparam IW = INT_BITS + FRAC_BITS;
  localparam CF = COS_FRAC_BITS;
  localparam EF = ETA_FRAC_BITS;
  localparam W = (COEF_BITS > IW + 1) ? COEF_BITS : IW + 1;  // I_s replicated width
  localparam REP = (W + COEF_BITS - 1) / COEF_BITS;
  localparam SH = W + 2 * CF;
  localparam KW = W + 2 * CF + 1;  // k: u1.(W+2cf)
  localparam PW = IW + KW;  // I x k
  localparam TW = IW + 17;  // T * I_a
  localparam EW = 2 * EF + 4;
  localparam OW = 2 * EF + 2 * CF + 6;

  // a = max(cos a, 0): u(cf)
  wire [CF-1:0] a = cos_alpha[CF] ? {CF{1'b0}} : cos_alpha[CF-1:0];
  // I_s as u1.W: replicated code + its top bit (1.0 exact)
  wire [REP*COEF_BITS-1:0] rep = {REP{specular}};
  wire [W:0] srep = {1'b0, rep[REP*COEF_BITS-1-:W]} + specular[COEF_BITS-1];
  wire [2*CF-1:0] sq = a * a;  // u(cf)^2 -> u(2cf)
  wire [KW-1:0] k_met = srep * sq;  // u1.W x u.(2cf) -> u1.(W+2cf)
  wire [KW-1:0] k_wat = {{(KW - CF) {1'b0}}, a} << (W + CF);
  wire [KW-1:0] k = water ? k_wat : k_met;
  wire [PW-1:0] prod = intensity * k;  // u(ib+fb) x u1.(W+2cf)
  wire [PW-1:0] ips = (prod + ({{(PW - 1) {1'b0}}, 1'b1} << (SH - 1))) >> SH;
  wire [TW-1:0] t_ia = ambient * THRESHOLD;
  wire cok = {{(TW > PW ? TW - PW : 0) {1'b0}}, ips} >= t_ia;
  // TIR: eta^2 (2^(2cf) - cos^2 theta) > 2^(2cf+2ef)
  wire [CF:0] ct = cos_theta[CF] ? (0 - cos_theta) : cos_theta;  // |cos theta| <= 2^cf
  wire [2*CF+1:0] ct2 = ct * ct;
  wire [2*CF+1:0] one_minus = ({{(2 * CF + 1) {1'b0}}, 1'b1} << (2 * CF)) - ct2;
  wire [EW-1:0] ec = ETA_CODE;
  wire [EW-1:0] e2 = ec * ec;
  wire [OW-1:0] lhs = e2 * one_minus;
  wire tir_c = water & (lhs > ({{(OW - 1) {1'b0}}, 1'b1} << (2 * CF + 2 * EF)));
  // round to framebuffer codes and clamp
  wire [PW-1:0] r = (FRAC_BITS == 0) ? ips : ((ips + (1 << (FRAC_BITS - 1))) >> FRAC_BITS);
  wire [PW-1:0] omax = {OUT_BITS{1'b1}};
  wire [OUT_BITS-1:0] ips_c = (r > omax) ? omax[OUT_BITS-1:0] : r[OUT_BITS-1:0];
  wire glare_c = cok & (~water | tir_c);

  reg [OUT_BITS+2:0] s1, s2;
  reg v1, v2;
  always @(posedge clk) begin
    if (rst) begin
      v1 <= 1'b0;
      v2 <= 1'b0;
      out_valid <= 1'b0;
    end else begin
      v1 <= in_valid;
      v2 <= v1;
      out_valid <= v2;
    end
    s1 <= {glare_c, tir_c, ips_c, cok};
    s2 <= s1;
    {glare, tir, i_ps, contrast_ok} <= s2;
  end
endmodule
