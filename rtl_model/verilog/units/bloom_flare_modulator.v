// bloom_flare_modulator — the bloom and flare luminance circuit (paper Fig. 2;
// rtl_model/src/units/bloom_flare_modulator.rs, datapath in luminance_ram.rs, radial
// correction off): (u, v) -> SHAPE RAM (bilinear) -> d -> FALLOFF RAM (linear) -> p
// -> x RGB gain, saturating. The tables are ports with synchronous read (the pipeline
// loads them per primitive): 4 shape read ports (the four banks) and 2 falloff ports.
// The datapath is rtl_model/verilog/lib/luminance_datapath.v with one falloff table
// (NR = 1), shared with halo_modulator.v.
// Latency 6, II 1:
//   1 address registers (clamp, split into index and weight)   -> shape RAM read
//   2 shape data                                                 (bilinear, round: d)
//   3 falloff address registers                                  -> falloff RAM read
//   4 falloff data                                               (lerp, gain multiply)
//   5 luminance registers
//   6 output registers
module bloom_flare_modulator #(
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
    output     [SAW-1:0]                      shape_addr0,
    output     [SAW-1:0]                      shape_addr1,
    output     [SAW-1:0]                      shape_addr2,
    output     [SAW-1:0]                      shape_addr3,
    input      [SHAPE_BITS-1:0]               shape_data0,
    input      [SHAPE_BITS-1:0]               shape_data1,
    input      [SHAPE_BITS-1:0]               shape_data2,
    input      [SHAPE_BITS-1:0]               shape_data3,
    output     [FAW-1:0]                      falloff_addr0,
    output     [FAW-1:0]                      falloff_addr1,
    input      [FALLOFF_BITS-1:0]             falloff_data0,
    input      [FALLOFF_BITS-1:0]             falloff_data1,
    output                                    out_valid,
    output     [SHAPE_BITS-1:0]               d,
    output     [OUT_BITS-1:0]                 lum_r,
    output     [OUT_BITS-1:0]                 lum_g,
    output     [OUT_BITS-1:0]                 lum_b
);
  luminance_datapath #(
      .COORD_FRAC_BITS(COORD_FRAC_BITS),
      .SHAPE_LOG2(SHAPE_LOG2),
      .SHAPE_BITS(SHAPE_BITS),
      .FALLOFF_LOG2(FALLOFF_LOG2),
      .FALLOFF_BITS(FALLOFF_BITS),
      .WEIGHT_BITS(WEIGHT_BITS),
      .GAIN_INT_BITS(GAIN_INT_BITS),
      .GAIN_FRAC_BITS(GAIN_FRAC_BITS),
      .OUT_BITS(OUT_BITS),
      .NR(1)
  ) dp (
      .clk(clk),
      .rst(rst),
      .in_valid(in_valid),
      .u(u),
      .v(v),
      .gain_r(gain_r),
      .gain_g(gain_g),
      .gain_b(gain_b),
      .shape_addr0(shape_addr0),
      .shape_addr1(shape_addr1),
      .shape_addr2(shape_addr2),
      .shape_addr3(shape_addr3),
      .shape_data0(shape_data0),
      .shape_data1(shape_data1),
      .shape_data2(shape_data2),
      .shape_data3(shape_data3),
      .falloff_addr0(falloff_addr0),
      .falloff_addr1(falloff_addr1),
      .falloff_data0(falloff_data0),
      .falloff_data1(falloff_data1),
      .out_valid(out_valid),
      .d(d),
      .lum_r(lum_r),
      .lum_g(lum_g),
      .lum_b(lum_b)
  );
endmodule
