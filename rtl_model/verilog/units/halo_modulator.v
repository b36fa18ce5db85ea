// halo_modulator — the halo luminance circuit (rtl_model/src/units/halo_modulator.rs,
// datapath in luminance_ram.rs, radial correction off): (u, v) -> SHAPE RAM
// (bilinear) -> d -> one RING RAM per colour (linear) -> p_c -> x gain_c, saturating.
// The datapath is rtl_model/verilog/lib/luminance_datapath.v, shared with
// bloom_flare_modulator.v, with three falloff tables (NR = 3, the rings; every ring
// reads the same two addresses);
// tables are ports with synchronous read: 4 shape read ports, 2 per ring.
// Latency 6, II 1:
//   1 address registers (clamp, split into index and weight)   -> shape RAM read
//   2 shape data                                                 (bilinear, round: d)
//   3 falloff address registers                                  -> falloff RAM read
//   4 falloff data                                               (lerp, gain multiply)
//   5 luminance registers
//   6 output registers
module halo_modulator #(
`include "luminance_params.vh"
) (
`include "luminance_ports.vh"
    output     [FAW-1:0]                      ring_r_addr0,
    output     [FAW-1:0]                      ring_r_addr1,
    input      [FALLOFF_BITS-1:0]             ring_r_data0,
    input      [FALLOFF_BITS-1:0]             ring_r_data1,
    output     [FAW-1:0]                      ring_g_addr0,
    output     [FAW-1:0]                      ring_g_addr1,
    input      [FALLOFF_BITS-1:0]             ring_g_data0,
    input      [FALLOFF_BITS-1:0]             ring_g_data1,
    output     [FAW-1:0]                      ring_b_addr0,
    output     [FAW-1:0]                      ring_b_addr1,
    input      [FALLOFF_BITS-1:0]             ring_b_data0,
    input      [FALLOFF_BITS-1:0]             ring_b_data1,
    output                                    out_valid,
    output     [SHAPE_BITS-1:0]               d,
    output     [OUT_BITS-1:0]                 lum_r,
    output     [OUT_BITS-1:0]                 lum_g,
    output     [OUT_BITS-1:0]                 lum_b
);
  wire [FAW-1:0] a0, a1;
  assign {ring_r_addr0, ring_g_addr0, ring_b_addr0} = {3{a0}};
  assign {ring_r_addr1, ring_g_addr1, ring_b_addr1} = {3{a1}};
  luminance_datapath #(
`include "luminance_dp_params.vh"
      .NR(3)
  ) dp (
`include "luminance_dp_ports.vh"
      .falloff_addr0(a0),
      .falloff_addr1(a1),
      .falloff_data0({ring_r_data0, ring_g_data0, ring_b_data0}),
      .falloff_data1({ring_r_data1, ring_g_data1, ring_b_data1}),
      .out_valid(out_valid),
      .d(d),
      .lum_r(lum_r),
      .lum_g(lum_g),
      .lum_b(lum_b)
  );
endmodule
