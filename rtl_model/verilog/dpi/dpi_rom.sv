// A table read port for the DPI-C testbench: DEPTH words of W bits, filled from the
// golden model's own table (`glare_dpi_table`) of a model opened with the same UNIT
// and SPEC as the scoreboard's, so RTL and model read the same codes. Synchronous
// read (data the clock after the address), as rtl_rom.
module dpi_rom #(
    parameter int W = 8,
    parameter int DEPTH = 2,
    parameter int AW = 1,
    parameter string UNIT = "",
    parameter string SPEC = "",
    parameter string TABLE = ""
) (
    input               clk,
    input      [AW-1:0] addr,
    output reg [ W-1:0] data
);
  import glare_dpi_pkg::*;
  reg [W-1:0] mem[0:DEPTH-1];
  initial begin
    chandle h;
    longint v;
    h = glare_dpi_open(UNIT, SPEC);
    if (h == null) $display("DPI error=rom-open %s", glare_dpi_last_error());
    else begin
      for (int i = 0; i < DEPTH; i++) begin
        v = glare_dpi_table(h, TABLE, i);
        if (v < 0) $display("DPI error=no-table %s[%0d]", TABLE, i);
        mem[i] = v[W-1:0];
      end
      glare_dpi_free(h);
    end
  end
  always @(posedge clk) data <= mem[addr];
endmodule
