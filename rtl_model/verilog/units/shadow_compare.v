// shadow_compare — the shadow-map unit (rtl_model/src/units/shadow_compare.rs): a depth
// RAM of WIDTH x HEIGHT words of DEPTH_BITS (outside the module: the `ram_*` ports,
// synchronous read-first, one write port, a one-clock flash clear), written in the
// depth pass (z-buffer LESS: keep the minimum) and compared per fragment in the
// lookup pass (GL_ARB_shadow; COMPARE = LEQUAL by default):
// lit <=> (frag - BIAS*2^k) OP stored*2^k, OP the 3-bit code COMPARE (GL's order,
// NEVER 0 .. ALWAYS 7: bit 0 lit when less, bit 1 when equal, bit 2 when greater).
// op: 0 clear, 1 write (depth = a texel word: the depth is (word >> TEXEL_SHIFT)'s
// low n bits; TEXEL_SHIFT 8 for a Z24S8 texel), 2 test (depth = u(n).k).
// Coordinates x, y are s16 wires; outside the map a test compares the fragment,
// clamped to the far plane, against the far plane (border; LEQUAL: always lit) and a
// write is dropped. Latency 2, II 1:
//   clock 1: address y*WIDTH + x to the RAM read port (the RAM registers the word),
//            op / in-map / address / depth registered;
//   clock 2: bias, LEQUAL / LESS compare, write-back, output register. A test or a
//            write right behind a write (or a clear) gets the new word through the
//            forwarding register (the RAM still returns the old word on that edge).
module shadow_compare #(
    parameter        WIDTH          = 512,
    parameter        HEIGHT         = 512,
    parameter        DEPTH_BITS     = 24,
    parameter [31:0] BIAS           = 2,
    parameter        FRAG_FRAC_BITS = 0,
    parameter        ADDR_BITS      = 18,
    parameter [ 2:0] COMPARE        = 3,
    parameter        TEXEL_SHIFT    = 0,
    parameter        IN_BITS        = DEPTH_BITS + FRAG_FRAC_BITS
) (
    input                                      clk,
    input                                      rst,
    input                                      in_valid,
    input      [                          1:0] op,
    input      [                         15:0] x,
    input      [                         15:0] y,
    input      [                  IN_BITS-1:0] depth,
    output reg                                 out_valid,
    output reg                                 lit,
    output reg                                 written,
    output reg [               DEPTH_BITS-1:0] stored,
    output     [                ADDR_BITS-1:0] ram_raddr,
    input      [               DEPTH_BITS-1:0] ram_rdata,
    output                                     ram_we,
    output     [                ADDR_BITS-1:0] ram_waddr,
    output     [               DEPTH_BITS-1:0] ram_wdata,
    output                                     ram_clear
);
  localparam FW = DEPTH_BITS + FRAG_FRAC_BITS;  // fragment depth u(n).k
  localparam [DEPTH_BITS-1:0] FAR = {DEPTH_BITS{1'b1}};

  // ---- clock 1: map test and address ----
  // A negative s16 coordinate is >= 2^15 > any side as an unsigned word.
  wire in_map = (x < WIDTH) && (y < HEIGHT);
  // u(log2 h) x const w + u(log2 w) -> u(ADDR_BITS): wires when WIDTH is a power of 2.
  wire [ADDR_BITS-1:0] addr = y * WIDTH + x;
  assign ram_raddr = addr;

  reg          v1;
  reg [   1:0] op1;
  reg          map1;
  reg [ADDR_BITS-1:0] addr1;
  reg [IN_BITS-1:0] depth1;
  always @(posedge clk) begin
    if (rst) v1 <= 1'b0;
    else v1 <= in_valid;
    op1    <= op;
    map1   <= in_map;
    addr1  <= addr;
    depth1 <= depth;
  end

  // ---- clock 2: forwarding, compare, write-back ----
  reg                  fwd_clear;  // the op one clock ahead was a clear
  reg                  fwd_we;  // ... or wrote fwd_data at fwd_addr
  reg [ ADDR_BITS-1:0] fwd_addr;
  reg [DEPTH_BITS-1:0] fwd_data;
  wire [DEPTH_BITS-1:0] old = fwd_clear ? FAR
                            : (fwd_we && fwd_addr == addr1) ? fwd_data : ram_rdata;

  wire is_clear = op1 == 2'd0;
  wire is_write = op1 == 2'd1;
  // Write: the texel word's depth, LESS against the stored word.
  wire [IN_BITS-1:0] word_sh = depth1 >> TEXEL_SHIFT;
  wire [DEPTH_BITS-1:0] d = word_sh[DEPTH_BITS-1:0];
  wire less = d < old;
  // Test: (f - bias*2^k) OP stored*2^k  <=>  f OP stored*2^k + bias*2^k
  // (u(n+k+1), exact). Off the map (COMPARE other than LEQUAL): the operands are the
  // fragment clamped to the far plane and the far plane, through the same comparator.
  localparam [FW:0] FAR_K = {1'b0, FAR} << FRAG_FRAC_BITS;
  wire [FW-1:0] f = depth1[FW-1:0];
  wire border = (COMPARE != 3'd3) && !map1;
  wire [DEPTH_BITS-1:0] s_op = border ? FAR : old;
  wire [FW:0] f_op = (border && {1'b0, f} > FAR_K) ? FAR_K : {1'b0, f};
  wire [FW:0] old_k = {1'b0, s_op} << FRAG_FRAC_BITS;
  wire [FW:0] bias_k = BIAS << FRAG_FRAC_BITS;
  wire [FW+1:0] rhs = {1'b0, old_k} + {1'b0, bias_k};
  wire leq = {1'b0, f_op} <= rhs;
  wire eq = {1'b0, f_op} == rhs;
  // The function's truth table at the comparator's outcome (LEQUAL: leq itself).
  wire cmp_lit = (COMPARE == 3'd3) ? leq : (!leq ? COMPARE[2] : eq ? COMPARE[1] : COMPARE[0]);

  assign ram_clear = v1 && is_clear;
  assign ram_we    = v1 && is_write && map1 && less;
  assign ram_waddr = addr1;
  assign ram_wdata = d;

  always @(posedge clk) begin
    if (rst) out_valid <= 1'b0;
    else out_valid <= v1;
    fwd_clear <= ram_clear;
    fwd_we    <= ram_we;
    fwd_addr  <= addr1;
    fwd_data  <= d;
    if (is_clear || !map1) begin
      // A test outside the map: the border compare (LEQUAL: lit).
      lit     <= !is_clear && !is_write && ((COMPARE == 3'd3) || cmp_lit);
      written <= 1'b0;
      stored  <= FAR;
    end else if (is_write) begin
      lit     <= 1'b0;
      written <= less;
      stored  <= less ? d : old;
    end else begin
      lit     <= cmp_lit;
      written <= 1'b0;
      stored  <= old;
    end
  end
endmodule
