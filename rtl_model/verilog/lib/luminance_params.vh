// The parameters of bloom_flare_modulator.v and halo_modulator.v (their widths;
// the derived ones are not set), `include`d into both parameter lists.
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
