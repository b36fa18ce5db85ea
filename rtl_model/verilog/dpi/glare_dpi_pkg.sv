// The golden model over DPI-C: the calls of rtl_model/dpi/include/glare_dpi.h a
// SystemVerilog testbench imports (link libglare_dpi.so, built by
// `cargo build -p glare_dpi --features dpi`). A handle is a chandle; a packed port
// word travels as bit [255:0] (svBitVecVal*, 32-bit words least significant first).
package glare_dpi_pkg;
  import "DPI-C" function chandle glare_dpi_open(input string unit, input string spec);
  import "DPI-C" function string glare_dpi_last_error();
  import "DPI-C" function void glare_dpi_free(input chandle h);
  import "DPI-C" function int unsigned glare_dpi_latency(input chandle h);
  import "DPI-C" function int unsigned glare_dpi_ii(input chandle h);
  import "DPI-C" function int unsigned glare_dpi_in_bits(input chandle h);
  import "DPI-C" function int unsigned glare_dpi_out_bits(input chandle h);
  import "DPI-C" function int glare_dpi_step(input chandle h, input bit [255:0] in_word,
                                             output bit [255:0] out_word);
  import "DPI-C" function longint glare_dpi_table(input chandle h, input string name,
                                                  input longint unsigned index);
endpackage
