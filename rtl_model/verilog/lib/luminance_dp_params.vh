// Both units' parameters passed on to their luminance_datapath instance
// (`include`d in its parameter list before .NR).
      .COORD_FRAC_BITS(COORD_FRAC_BITS),
      .SHAPE_LOG2(SHAPE_LOG2),
      .SHAPE_BITS(SHAPE_BITS),
      .FALLOFF_LOG2(FALLOFF_LOG2),
      .FALLOFF_BITS(FALLOFF_BITS),
      .WEIGHT_BITS(WEIGHT_BITS),
      .GAIN_INT_BITS(GAIN_INT_BITS),
      .GAIN_FRAC_BITS(GAIN_FRAC_BITS),
      .OUT_BITS(OUT_BITS),
