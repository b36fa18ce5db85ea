// The ports bloom_flare_modulator.v and halo_modulator.v share (clock, the
// coordinates and gains, the four shape-table read ports), `include`d first in
// both port lists; their falloff or ring ports and outputs follow.
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
