// The float format's derived widths and its rounding (fp_round, fp_pack) for
// vertex_lighting.v's operator modules, `include`d into each module body (after its
// EXP_BITS, MANT_BITS, ROUNDING parameters). Uses the VL_FZ / VL_FE macros that
// vertex_lighting.v defines.
  localparam W = 1 + EXP_BITS + MANT_BITS;
  localparam E = EXP_BITS;
  localparam M = MANT_BITS;
  localparam integer BIAS = (1 << (E - 1)) - 1;
  localparam integer EMIN = 1 - BIAS;
  localparam integer EMAX = BIAS;
  localparam [E-1:0] BIAS_E = BIAS;
  localparam K = M + 4;  // pow's fraction bits
  localparam VW = E + M + 8;  // fp_pack's operand width
  localparam [W-1:0] ONE = {2'b00, {(E - 1) {1'b1}}, {M{1'b0}}};
  localparam [W-2:0] MAXMAG = {{(E - 1) {1'b1}}, 1'b0, {M{1'b1}}};

  // (−1)^neg · sig · 2^(ex − M), sig = 1.f (M + 1 bits), with the round bit and the
  // sticky bit below it: round once, saturate or flush.
  function [W-1:0] fp_round(input neg, input integer ex, input [M:0] sig, input rbit,
                            input sticky);
    reg [M+1:0] q;
    integer e;
    begin
      // Rounding up a significand of all ones carries into bit M + 1 and leaves the
      // fraction bits zero: the exponent steps up and the fraction needs no shift.
      q = {1'b0, sig} + (ROUNDING == 0 && rbit && (sticky || sig[0]));
      e = ex + q[M+1];
      if (e > EMAX) fp_round = {neg, MAXMAG};
      else if (e < EMIN) fp_round = {neg, {(W - 1) {1'b0}}};
      else fp_round = {neg, e[E-1:0] + BIAS_E, q[M-1:0]};
    end
  endfunction

  // (−1)^neg · (val + frac) · 2^ex0, frac > 0 iff sticky: normalise and round (the
  // model's round_pack); val = 0 gives ±0.
  function [W-1:0] fp_pack(input neg, input integer ex0, input [VW-1:0] val,
                           input sticky);
    integer t;
    reg [63:0] v;
    begin
      if (val == 0) fp_pack = {neg, {(W - 1) {1'b0}}};
      else begin
        // The leading one to bit 63: a 6-level normalising shifter (VW ≤ 64), t its
        // position in val. Then sig = v[63:63−M], the round bit below it and the
        // sticky bit the OR of the rest (all zero when val has ≤ M + 1 bits).
        v = {{(64 - VW) {1'b0}}, val};
        t = 63;
        if (v[63:32] == 0) begin
          v = v << 32;
          t = t - 32;
        end
        if (v[63:48] == 0) begin
          v = v << 16;
          t = t - 16;
        end
        if (v[63:56] == 0) begin
          v = v << 8;
          t = t - 8;
        end
        if (v[63:60] == 0) begin
          v = v << 4;
          t = t - 4;
        end
        if (v[63:62] == 0) begin
          v = v << 2;
          t = t - 2;
        end
        if (!v[63]) begin
          v = v << 1;
          t = t - 1;
        end
        fp_pack = fp_round(neg, ex0 + t, v[63:63-M], v[62-M], sticky | (|v[61-M:0]));
      end
    end
  endfunction
