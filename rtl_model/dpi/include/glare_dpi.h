/* glare_dpi.h — GENERATED from rtl_model/dpi/src/abi.rs by
 *   cargo run -p glare_dpi --bin glare-dpi-header > rtl_model/dpi/include/glare_dpi.h
 * Do not edit: rtl_model/dpi/tests/header.rs fails when this file is stale.
 *
 * The C ABI of the golden model: every function here is exported by the library
 * built with feature `dpi` (without it they are plain Rust functions, for tests).
 *
 * Port values are the bits of the Verilog port of the same name, zero-extended
 * (a signed coordinate is passed as its two's-complement wire bits). A handle holds
 * the unit's state from its reset state; calls on one handle must not overlap.
 * Pointers must be valid for the lengths given; output pointers may be NULL.
 *
 * Library: cargo build -p glare_dpi --features dpi (target/<profile>/libglare_dpi.so).
 */
#ifndef GLARE_DPI_H
#define GLARE_DPI_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A unit with its config, tables and state (opaque). */
typedef struct glare_dpi_handle glare_dpi_handle;

/* The error of the last call on this thread that failed (a `*_new` or */
/* `glare_dpi_open` that returned NULL, a kernel that returned < 0): it names the */
/* config field or argument at fault. Valid until the next failing call. */
const char *glare_dpi_last_error(void);

/* A unit by name with a text config: `key=value` pairs separated by blanks, the */
/* config fields of the unit's `*_new` (missing ones keep the GeForce default) and */
/* `seed` (the unit's tables are drawn from it). NULL on error (glare_dpi_last_error). */
glare_dpi_handle *glare_dpi_open(const char *unit, const char *spec);

/* Release a handle of any unit (NULL is ignored). */
void glare_dpi_free(glare_dpi_handle *h);

/* Clocks from accepting an input to presenting its output (the model's Timing); */
/* 0 for NULL. */
uint32_t glare_dpi_latency(const glare_dpi_handle *h);

/* Clocks between accepted inputs (initiation interval); 0 for NULL. */
uint32_t glare_dpi_ii(const glare_dpi_handle *h);

/* Bits of the packed input word (the input ports concatenated); 0 for NULL. */
uint32_t glare_dpi_in_bits(const glare_dpi_handle *h);

/* Bits of the packed output word; 0 for NULL. */
uint32_t glare_dpi_out_bits(const glare_dpi_handle *h);

/* Transactions stepped on this handle so far; 0 for NULL. */
uint64_t glare_dpi_transactions(const glare_dpi_handle *h);

/* One transaction on the packed input word: the input ports concatenated in the */
/* unit's port order, the first in the most significant bits, as 32-bit words least */
/* significant first (a SystemVerilog `bit [N-1:0]` argument, svBitVecVal*); */
/* in_word holds ceil(in_bits/32) words, out_word ceil(out_bits/32). 0, or -1 (NULL). */
int32_t glare_dpi_step(glare_dpi_handle *h, const uint32_t *in_word, uint32_t *out_word);

/* Entry `index` of the table the unit reads through the ports named `table` */
/* (`shape`, `falloff`, `texels`), as the model holds it (codes); -1 if there is none. */
int64_t glare_dpi_table(const glare_dpi_handle *h, const char *table, uint64_t index);

/* modulate (GL_MODULATE on `bits`-bit unorms, 1 ..= 16); `mode` 0 exact (the */
/* GeForce default), 1 shift, 2 plus_one, 3 trunc_div. NULL on error. */
glare_dpi_handle *modulate_new(uint32_t bits, uint32_t mode);

/* y = a · b rounded as the mode says. 0, -1 (NULL handle), -2 (another unit's handle). */
int32_t modulate_kernel(glare_dpi_handle *h, uint32_t a, uint32_t b, uint32_t *y);

/* Release a modulate handle. */
void modulate_free(glare_dpi_handle *h);

/* bloom_flare_modulator, radial correction off (GeForce default: 14, 7, 16, 8, 16, */
/* 8, 12, 4, 12). shape: (2^shape_log2+1)² entries in [0, 1], v index major; */
/* falloff: 2^falloff_log2+1 entries. NULL on error (the field is named). */
glare_dpi_handle *bloom_flare_modulator_new(uint32_t coord_frac_bits, uint32_t shape_log2, uint32_t shape_bits, uint32_t falloff_log2, uint32_t falloff_bits, uint32_t weight_bits, uint32_t gain_int_bits, uint32_t gain_frac_bits, uint32_t out_bits, const double *shape, uint64_t shape_len, const double *falloff, uint64_t falloff_len);

/* One pixel: u, v are s2.F wire bits (coord_frac_bits + 2), the gains */
/* u(gain_int).(gain_frac); d and lum_* as the ports. 0, -1 or -2 as modulate_kernel. */
int32_t bloom_flare_modulator_kernel(glare_dpi_handle *h, uint32_t u, uint32_t v, uint32_t gain_r, uint32_t gain_g, uint32_t gain_b, uint32_t *d, uint32_t *lum_r, uint32_t *lum_g, uint32_t *lum_b);

/* Release a bloom_flare_modulator handle. */
void bloom_flare_modulator_free(glare_dpi_handle *h);

/* texture_sampler. weight_rounding 0 round, 1 truncate, 2 round_half_even; */
/* filter_rounding 0 product_weights, 1 successive_lerps; filter 0 nearest, */
/* 1 linear; address_* 0 clamp, 1 wrap. texels: w·h·d·channels codes, texel */
/* (x, y, z) channel c at ((z·h + y)·w + x)·channels + c. NULL on error. */
glare_dpi_handle *texture_sampler_new(uint32_t dims, uint32_t size_w, uint32_t size_h, uint32_t size_d, uint32_t channels, uint32_t texel_bits, uint32_t coord_int_bits, uint32_t coord_frac_bits, uint32_t weight_bits, uint32_t weight_rounding, uint32_t filter_rounding, uint32_t filter, uint32_t address_s, uint32_t address_t, uint32_t address_r, uint32_t texels_per_clock, const uint32_t *texels, uint64_t texels_len);

/* One sample: coordinates as s(coord_int).(coord_frac) wire bits (axes beyond */
/* dims ignored); ch0..ch3 the filtered channels (beyond channels: 0). */
int32_t texture_sampler_kernel(glare_dpi_handle *h, uint32_t coord_s, uint32_t coord_t, uint32_t coord_r, uint32_t *ch0, uint32_t *ch1, uint32_t *ch2, uint32_t *ch3);

/* Release a texture_sampler handle. */
void texture_sampler_free(glare_dpi_handle *h);

#ifdef __cplusplus
}
#endif

#endif /* GLARE_DPI_H */
