// blend — the GL / NV2A framebuffer blend on one RGBA pixel of BITS-bit unorms
// (rtl_model/src/units/blend.rs): y_c = clamp(eq(src_c * f_s, dst_c * f_d), 0, M),
// M = 2^BITS - 1. The blend state is parameters (the state registers of the chip):
// EQUATION 0..6 = ADD, SUBTRACT, REVERSE_SUBTRACT, MIN, MAX, ADD_SIGNED,
// REVERSE_SUBTRACT_SIGNED; SRC_FACTOR / DST_FACTOR 0..14 = ZERO, ONE, SRC_COLOR,
// ONE_MINUS_SRC_COLOR, SRC_ALPHA, ONE_MINUS_SRC_ALPHA, DST_ALPHA, ONE_MINUS_DST_ALPHA,
// DST_COLOR, ONE_MINUS_DST_COLOR, SRC_ALPHA_SATURATE, CONSTANT_COLOR,
// ONE_MINUS_CONSTANT_COLOR, CONSTANT_ALPHA, ONE_MINUS_CONSTANT_ALPHA; CONST_R..A the
// constant colour; ROUNDING 0 = once (round((s*fs +- d*fd)/M)), 1 = per term.
// Signed arithmetic is done as magnitude and sign in unsigned wires.
// SRC_BITS: the source ports' width; the source is aligned to BITS first (bit
// replication when widening, round to nearest when narrowing).
// DATAPATH 0 = programmable (every factor and equation; CONST_BITS = BITS), latency 4,
// II 1: stage 1 factor select (framebuffer read), stage 2 multiply, stage 3 add /
// divide by M / clamp, stage 4 write-back register.
// DATAPATH 1 = additive (ADD; SRC_FACTOR 1 = ONE or 13 = CONSTANT_ALPHA, a weight of
// CONST_BITS bits; DST_FACTOR 1 = ONE): y_c = min(dst_c + q_c, M) with
// q_c = align(src_c), or round(align(src_c) * CONST_A / (2^CONST_BITS - 1)). Latency 3,
// II 1: stage 1 aligns and weights the source while the framebuffer is read, stage 2
// adds and saturates, stage 3 is the write-back register.
module blend #(
    parameter BITS       = 8,
    parameter EQUATION   = 0,
    parameter SRC_FACTOR = 1,
    parameter DST_FACTOR = 0,
    parameter CONST_R    = 0,
    parameter CONST_G    = 0,
    parameter CONST_B    = 0,
    parameter CONST_A    = 0,
    parameter ROUNDING   = 0,
    parameter DATAPATH   = 0,
    parameter SRC_BITS   = BITS,
    parameter CONST_BITS = BITS
) (
    input                 clk,
    input                 rst,
    input                 in_valid,
    input  [SRC_BITS-1:0] src_r,
    input  [SRC_BITS-1:0] src_g,
    input  [SRC_BITS-1:0] src_b,
    input  [SRC_BITS-1:0] src_a,
    input      [BITS-1:0] dst_r,
    input      [BITS-1:0] dst_g,
    input      [BITS-1:0] dst_b,
    input      [BITS-1:0] dst_a,
    output reg            out_valid,
    output     [BITS-1:0] y_r,
    output     [BITS-1:0] y_g,
    output     [BITS-1:0] y_b,
    output     [BITS-1:0] y_a
);
  localparam [BITS-1:0] M = {BITS{1'b1}};
  localparam [4*BITS-1:0] K = {CONST_R[BITS-1:0], CONST_G[BITS-1:0], CONST_B[BITS-1:0],
                               CONST_A[BITS-1:0]};
  localparam [CONST_BITS-1:0] WEIGHT = CONST_A[CONST_BITS-1:0];
  localparam REP = (BITS + SRC_BITS - 1) / SRC_BITS;  // copies for bit replication

  // round(x / (2^k - 1)) for x <= (2^q - 1)(2^k - 1): with t = x + 2^(k-1) and
  // J = ceil(q / k), (t * sum_{j=0..J} 2^(jk)) >> (J+1)k (round_div_mersenne; 2^k - 1
  // is odd: no ties). The sum is at most q + k + Jk + 1 <= 64 bits.
  function [BITS-1:0] rdm;
    input [63:0] x;
    input integer k;
    input integer q;
    reg [79:0] t, acc;
    integer j, terms;
    begin
      terms = (q + k - 1) / k + 1;
      t = {16'd0, x} + (80'd1 << (k - 1));
      acc = 0;
      for (j = 0; j < 17; j = j + 1)  // terms <= 17 (k >= 1, q <= 16)
        if (j < terms) acc = acc + (t << (j * k));
      acc = acc >> (terms * k);
      rdm = acc[BITS-1:0];
    end
  endfunction

  // A source channel aligned to BITS: bit replication (wiring) when widening,
  // round(v * M / (2^SRC_BITS - 1)) when narrowing.
  function [BITS-1:0] align;
    input [SRC_BITS-1:0] v;
    reg [REP*SRC_BITS-1:0] r;
    begin
      if (BITS >= SRC_BITS) begin
        r = {REP{v}};
        align = r[REP*SRC_BITS-1-:BITS];
      end else begin
        align = rdm({32'd0, v} * {32'd0, M}, SRC_BITS, BITS);
      end
    end
  endfunction

  // The additive datapath's contribution of an aligned source channel.
  function [BITS-1:0] contribution;
    input [BITS-1:0] a;
    begin
      if (SRC_FACTOR == 13) contribution = rdm({32'd0, a} * {32'd0, WEIGHT}, CONST_BITS, BITS);
      else contribution = a;
    end
  endfunction
  localparam W = 4 * BITS + 4;  // the shift-add accumulator

  // Channel c of a packed RGBA word (c = 0 red .. 3 alpha; red in the top bits).
  function [BITS-1:0] ch;
    input [4*BITS-1:0] p;
    input integer c;
    ch = p[(3-c)*BITS+:BITS];
  endfunction

  // The factor `sel` for channel c.
  function [BITS-1:0] factor;
    input integer sel;
    input integer c;
    input [4*BITS-1:0] s;
    input [4*BITS-1:0] d;
    reg [BITS-1:0] sa, da;
    begin
      sa = ch(s, 3);
      da = ch(d, 3);
      case (sel)
        0: factor = 0;
        1: factor = M;
        2: factor = ch(s, c);
        3: factor = M - ch(s, c);
        4: factor = sa;
        5: factor = M - sa;
        6: factor = da;
        7: factor = M - da;
        8: factor = ch(d, c);
        9: factor = M - ch(d, c);
        10: factor = (c == 3) ? M : ((sa < M - da) ? sa : M - da);
        11: factor = ch(K, c);
        12: factor = M - ch(K, c);
        13: factor = ch(K, 3);
        default: factor = M - ch(K, 3);
      endcase
    end
  endfunction

  // round(x / M) for x <= 2*M*M: ((x + 2^(BITS-1)) * (1 + 2^BITS + 2^(2 BITS))) >> 3 BITS
  // (the shift-add series of round_div_mersenne with J = 2).
  function [BITS+1:0] rdiv;
    input [2*BITS+1:0] x;
    reg [W-1:0] t;
    reg [W-1:0] acc;
    begin
      t = {{(W - 2 * BITS - 2) {1'b0}}, x} + (1 << (BITS - 1));
      acc = t + (t << BITS) + (t << (2 * BITS));
      rdiv = acc[3*BITS+:BITS+2];
    end
  endfunction

  // Clamp an unsigned magnitude of BITS+2 bits to M.
  function [BITS-1:0] sat;
    input [BITS+1:0] v;
    sat = (v > {2'b00, M}) ? M : v[BITS-1:0];
  endfunction

  // a - b clamped at 0 (both BITS+2 bits).
  function [BITS-1:0] sub0;
    input [BITS+1:0] a;
    input [BITS+1:0] b;
    sub0 = (a > b) ? sat(a - b) : {BITS{1'b0}};
  endfunction

  wire [4*BITS-1:0] src = {align(src_r), align(src_g), align(src_b), align(src_a)};
  wire [4*BITS-1:0] dst = {dst_r, dst_g, dst_b, dst_a};

  reg [4*BITS-1:0] s1, d1, fs1, fd1, s2, d2, y3, y4;
  reg [8*BITS-1:0] ps2, pd2;  // four u(2n) products each
  reg v1, v2, v3;
  reg [4*BITS-1:0] q1, a2, a3;  // additive: contribution, saturated sum, write data
  reg [BITS:0] sum;  // u(n) + u(n) -> u(n+1)
  integer c;
  reg [2*BITS-1:0] ps, pd;
  reg [BITS-1:0] sc, dc, r;
  reg [BITS+1:0] qa, qb, sneg;

  always @(posedge clk) begin
    if (rst) begin
      v1 <= 1'b0;
      v2 <= 1'b0;
      v3 <= 1'b0;
      out_valid <= 1'b0;
    end else begin
      v1 <= in_valid;
      v2 <= v1;
      v3 <= v2;
      out_valid <= (DATAPATH == 1) ? v2 : v3;
    end
    // Stage 1: operands and factors.
    s1 <= src;
    d1 <= dst;
    for (c = 0; c < 4; c = c + 1) begin
      fs1[(3-c)*BITS+:BITS] <= factor(SRC_FACTOR, c, src, dst);
      fd1[(3-c)*BITS+:BITS] <= factor(DST_FACTOR, c, src, dst);
    end
    // Stage 2: products (u(n) x u(n) -> u(2n)).
    s2 <= s1;
    d2 <= d1;
    for (c = 0; c < 4; c = c + 1) begin
      ps2[(3-c)*2*BITS+:2*BITS] <= ch(s1, c) * ch(fs1, c);
      pd2[(3-c)*2*BITS+:2*BITS] <= ch(d1, c) * ch(fd1, c);
    end
    // Stage 3: the equation, the divide by M and the clamp.
    for (c = 0; c < 4; c = c + 1) begin
      ps = ps2[(3-c)*2*BITS+:2*BITS];
      pd = pd2[(3-c)*2*BITS+:2*BITS];
      sc = ch(s2, c);
      dc = ch(d2, c);
      sneg = (1 << BITS) - sc;  // |sx(src)| when src is negative
      if (ROUNDING == 0) begin
        // One rounding of the signed sum, as magnitude and sign.
        case (EQUATION)
          0: begin
            qa = rdiv({1'b0, ps} + {1'b0, pd});
            qb = 0;
          end
          1: begin
            qa = (ps > pd) ? rdiv(ps - pd) : 0;
            qb = 0;
          end
          default: begin
            qa = (pd > ps) ? rdiv(pd - ps) : 0;
            qb = 0;
          end
        endcase
      end else begin
        qa = rdiv(ps);
        qb = rdiv(pd);
      end
      case (EQUATION)
        0: r = (ROUNDING == 0) ? sat(qa) : sat(qa + qb);
        1: r = (ROUNDING == 0) ? sat(qa) : sub0(qa, qb);
        2: r = (ROUNDING == 0) ? sat(qa) : sub0(qb, qa);
        3: r = (sc < dc) ? sc : dc;
        4: r = (sc > dc) ? sc : dc;
        5: r = sc[BITS-1] ? sub0({2'b00, dc}, sneg) : sat({2'b00, dc} + {2'b00, sc});
        default: r = sc[BITS-1] ? sat({2'b00, dc} + sneg) : sub0({2'b00, dc}, {2'b00, sc});
      endcase
      y3[(3-c)*BITS+:BITS] <= r;
    end
    // Stage 4: write-back register.
    y4 <= y3;
    // The additive datapath: stage 1 contribution (d1 holds the framebuffer read),
    // stage 2 saturating add, stage 3 write-back register.
    for (c = 0; c < 4; c = c + 1) begin
      q1[(3-c)*BITS+:BITS] <= contribution(ch(src, c));
      sum = {1'b0, ch(q1, c)} + {1'b0, ch(d1, c)};
      a2[(3-c)*BITS+:BITS] <= sum[BITS] ? M : sum[BITS-1:0];
    end
    a3 <= a2;
  end
  assign {y_r, y_g, y_b, y_a} = (DATAPATH == 1) ? a3 : y4;
endmodule
