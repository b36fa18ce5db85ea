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

// A read/write RAM port pair for the co-simulation of a unit whose RAM sits outside
// it (shadow_compare's depth map): DEPTH words of W bits, every word CLEAR from the
// start; synchronous read-first (rdata is the word the clock after raddr, before any
// write on the same edge), one write port, and `clear`, a one-clock flash clear of
// every word to CLEAR. The clear is a generation tag per word (a word whose tag is
// not the current generation reads CLEAR), as a fast-clear tag per block does in a
// real part, so a clear costs one clock in simulation too.
module rtl_ram #(
    parameter         W     = 8,
    parameter         DEPTH = 2,
    parameter         AW    = 1,
    parameter [W-1:0] CLEAR = 0
) (
    input               clk,
    input      [AW-1:0] raddr,
    output reg [ W-1:0] rdata,
    input               we,
    input      [AW-1:0] waddr,
    input      [ W-1:0] wdata,
    input               clear
);
  reg [W-1:0] mem[0:DEPTH-1];
  reg [31:0] tag[0:DEPTH-1];
  reg [31:0] gen;
  integer i;
  initial begin
    gen = 1;
    for (i = 0; i < DEPTH; i = i + 1) begin
      mem[i] = CLEAR;
      tag[i] = 0;
    end
  end
  always @(posedge clk) begin
    rdata <= tag[raddr] == gen ? mem[raddr] : CLEAR;
    if (clear) gen <= gen + 1;
    if (we) begin
      mem[waddr] <= wdata;
      tag[waddr] <= gen;
    end
  end
endmodule
