// The golden model as a scoreboard over DPI-C: drives seeded random transactions
// into a unit wrapped as IN_W/OUT_W words (the ports concatenated, the first in the
// most significant bits), calls the Rust model on the same input word through
// DPI-C when it is accepted, and checks on every clock that out_valid is high exactly
// on the clock the model's latency says (input k on clock k*II is presented on clock
// k*II + LAT) with the model's word. The model's latency, II and word widths are
// checked against the RTL's first. Plusargs: +tag=TAG selects the instance, +n=N
// transactions (default 10000), +seed=S (default 1). Prints one summary line:
//   DPI tag=<TAG> n=<N> checked=<C> mismatches=<M> valid_errors=<V> first_bad=<K|-1>
module tb_dpi #(
    parameter int IN_W = 8,
    parameter int OUT_W = 8,
    parameter int LAT = 1,
    parameter int II = 1,
    parameter string TAG = "unit",
    parameter string UNIT = "",
    parameter string SPEC = ""
) (
    output reg             clk,
    output reg             rst,
    output reg             in_valid,
    output reg [ IN_W-1:0] in_word,
    input                  out_valid,
    input      [OUT_W-1:0] out_word
);
  import glare_dpi_pkg::*;
  localparam int RING = 64;  // transactions in flight (LAT / II < RING)
  chandle h;
  string tag_arg;
  bit [255:0] iw, ow;
  reg [OUT_W-1:0] want[0:RING-1];
  longint unsigned rng;
  integer n, r, cyc, sent, got, mism, verr, first_bad, next_acc, last, seed;

  // xorshift64: the same stream under any simulator.
  function automatic longint unsigned xs(input longint unsigned s);
    s = s ^ (s << 13);
    s = s ^ (s >> 7);
    s = s ^ (s << 17);
    return s;
  endfunction

  initial begin
    clk = 0;
    rst = 1;
    in_valid = 0;
    in_word = 0;
    if ($value$plusargs("tag=%s", tag_arg) && tag_arg == TAG) begin
      n = 10000;
      seed = 1;
      r = $value$plusargs("n=%d", n);
      r = $value$plusargs("seed=%d", seed);
      rng = 64'h9e37_79b9_7f4a_7c15 ^ longint'(seed);
      h = glare_dpi_open(UNIT, SPEC);
      if (h == null) begin
        $display("DPI tag=%0s error=open %0s", TAG, glare_dpi_last_error());
        $finish;
      end
      if (glare_dpi_latency(h) != LAT || glare_dpi_ii(h) != II ||
          glare_dpi_in_bits(h) != IN_W || glare_dpi_out_bits(h) != OUT_W ||
          LAT / II >= RING) begin
        $display("DPI tag=%0s error=shape model lat=%0d ii=%0d in=%0d out=%0d rtl lat=%0d ii=%0d in=%0d out=%0d",
                 TAG, glare_dpi_latency(h), glare_dpi_ii(h), glare_dpi_in_bits(h),
                 glare_dpi_out_bits(h), LAT, II, IN_W, OUT_W);
        $finish;
      end
      // Two clocks of reset.
      #5 clk = 1;
      #5 clk = 0;
      #5 clk = 1;
      #5 clk = 0;
      rst = 0;
      cyc = 0;
      sent = 0;
      got = 0;
      mism = 0;
      verr = 0;
      first_bad = -1;
      next_acc = 0;
      last = (n - 1) * II + LAT;
      while (cyc <= last + 2) begin
        // Drive clock `cyc`'s input; the model computes its response now.
        if (sent < n && cyc == next_acc) begin
          iw = '0;
          for (int b = 0; b < IN_W; b += 32) begin
            rng = xs(rng);
            iw[b+:32] = rng[63:32];
          end
          in_word = iw[IN_W-1:0];
          iw = '0;
          iw[IN_W-1:0] = in_word;
          r = glare_dpi_step(h, iw, ow);
          want[sent%RING] = ow[OUT_W-1:0];
          in_valid = 1;
          sent = sent + 1;
          next_acc = cyc + II;
        end else begin
          in_valid = 0;
        end
        #1;
        // Check what the unit presents on clock `cyc`.
        if (got < n && cyc == got * II + LAT) begin
          if (out_valid !== 1'b1) begin
            verr = verr + 1;
            if (first_bad < 0) first_bad = got;
          end else if (out_word !== want[got%RING]) begin
            mism = mism + 1;
            if (first_bad < 0) first_bad = got;
            if (mism <= 5)
              $display("DPI tag=%0s mismatch k=%0d rtl=%h model=%h", TAG, got, out_word,
                       want[got%RING]);
          end
          got = got + 1;
        end else if (out_valid !== 1'b0) begin
          verr = verr + 1;
        end
        #4 clk = 1;
        #5 clk = 0;
        cyc = cyc + 1;
      end
      $display("DPI tag=%0s n=%0d checked=%0d mismatches=%0d valid_errors=%0d first_bad=%0d",
               TAG, n, got, mism, verr, first_bad);
      glare_dpi_free(h);
      $finish;
    end
  end
endmodule
