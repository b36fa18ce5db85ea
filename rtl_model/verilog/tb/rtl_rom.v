// A table (RAM/ROM) read port for the co-simulation: DEPTH words of W bits loaded
// with $readmemh from FILE, synchronous read (data the clock after the address).
// The units take their tables as ports (the pipeline writes them per primitive);
// the generated cosim block attaches one of these per read port.
module rtl_rom #(
    parameter W     = 8,
    parameter DEPTH = 2,
    parameter AW    = 1,
    parameter FILE  = ""
) (
    input               clk,
    input      [AW-1:0] addr,
    output reg [ W-1:0] data
);
  reg [W-1:0] mem[0:DEPTH-1];
  initial $readmemh(FILE, mem);
  always @(posedge clk) data <= mem[addr];
endmodule
