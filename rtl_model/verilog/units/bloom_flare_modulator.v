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
`include "luminance_params.vh"
) (
`include "luminance_ports.vh"
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
`include "luminance_dp_params.vh"
      .NR(1)
  ) dp (
`include "luminance_dp_ports.vh"
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
