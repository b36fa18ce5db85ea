// Generic vector testbench: drives one transaction of the stimulus file every II
// clocks into a unit wrapped as `IN_W`/`OUT_W` words, and checks on every clock that
// out_valid is high exactly on the clock the model's latency says (input k accepted on
// clock k*II is presented on clock k*II + LAT) with the expected word.
// Files are read line by line ($fscanf, one hex word a line), so one build serves any
// vector file: +stim=FILE +expect=FILE +n=COUNT, and +tag=TAG selects the instance.
// Prints one summary line:
//   COSIM tag=<TAG> n=<N> checked=<C> mismatches=<M> valid_errors=<V> first_bad=<K|-1>
module tb_vectors #(
    parameter IN_W  = 8,
    parameter OUT_W = 8,
    parameter LAT   = 1,
    parameter II    = 1,
    parameter TAG   = "unit"
) (
    output reg             clk,
    output reg             rst,
    output reg             in_valid,
    output reg [ IN_W-1:0] in_word,
    input                  out_valid,
    input      [OUT_W-1:0] out_word
);
  reg [8*64-1:0]   tag_arg;
  reg [8*1024-1:0] stim_file;
  reg [8*1024-1:0] exp_file;
  reg [OUT_W-1:0]  want;
  integer n, fs, fe, r, cyc, sent, got, mism, verr, first_bad, next_acc, last;
  initial begin
    clk = 0;
    rst = 1;
    in_valid = 0;
    in_word = 0;
    if ($value$plusargs("tag=%s", tag_arg) && tag_arg == TAG) begin
      n = 0;
      r = $value$plusargs("n=%d", n);
      r = $value$plusargs("stim=%s", stim_file);
      r = $value$plusargs("expect=%s", exp_file);
      fs = $fopen(stim_file, "r");
      fe = $fopen(exp_file, "r");
      if (fs == 0 || fe == 0) begin
        $display("COSIM tag=%0s error=cannot-open-vectors", TAG);
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
        // Drive clock `cyc`'s input.
        if (sent < n && cyc == next_acc) begin
          r = $fscanf(fs, "%h\n", in_word);
          in_valid = 1;
          sent = sent + 1;
          next_acc = cyc + II;
        end else begin
          in_valid = 0;
        end
        #1;
        // Check what the unit presents on clock `cyc`.
        if (got < n && cyc == got * II + LAT) begin
          r = $fscanf(fe, "%h\n", want);
          if (out_valid !== 1'b1) begin
            verr = verr + 1;
            if (first_bad < 0) first_bad = got;
          end else if (out_word !== want) begin
            mism = mism + 1;
            if (first_bad < 0) first_bad = got;
            if (mism <= 5)
              $display("COSIM tag=%0s mismatch k=%0d got=%h want=%h", TAG, got, out_word, want);
          end
          got = got + 1;
        end else if (out_valid !== 1'b0) begin
          verr = verr + 1;
        end
        #4 clk = 1;
        #5 clk = 0;
        cyc = cyc + 1;
      end
      $display("COSIM tag=%0s n=%0d checked=%0d mismatches=%0d valid_errors=%0d first_bad=%0d",
               TAG, n, got, mism, verr, first_bad);
      $fclose(fs);
      $fclose(fe);
      $finish;
    end
  end
endmodule
