// shadow_compare — the shadow-map unit (rtl_model/src/units/shadow_compare.rs): a depth
// RAM of WIDTH x HEIGHT words of DEPTH_BITS (outside the module: the `ram_*` ports,
// synchronous read-first, one write port, a one-clock flash clear), written in the
// depth pass (z-buffer LESS: keep the minimum) and compared per fragment in the
// lookup pass (GL_ARB_shadow LEQUAL): lit <=> frag - BIAS*2^k <= stored*2^k.
// op: 0 clear, 1 write (depth = u(n) in the low bits), 2 test (depth = u(n).k).
// Coordinates x, y are s16 wires; outside the map a test is lit (border = far plane)
// and a write is dropped. Latency 2, II 1:
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
    parameter        ADDR_BITS      = 18
) (
    input                                      clk,
    input                                      rst,
    input                                      in_valid,
    input      [                          1:0] op,
    input      [                         15:0] x,
    input      [                         15:0] y,
    input      [DEPTH_BITS+FRAG_FRAC_BITS-1:0] depth,
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
  reg [FW-1:0] depth1;
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
  // Write: the depth word's low n bits, LESS against the stored word.
  wire [DEPTH_BITS-1:0] d = depth1[DEPTH_BITS-1:0];
  wire less = d < old;
  // Test: f - bias*2^k <= stored*2^k  <=>  f <= stored*2^k + bias*2^k (u(n+k+1), exact).
  wire [FW:0] old_k = {1'b0, old} << FRAG_FRAC_BITS;
  wire [FW:0] bias_k = BIAS << FRAG_FRAC_BITS;
  wire leq = {1'b0, depth1} <= old_k + bias_k;

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
      lit     <= !is_clear && !is_write;  // a test outside the map is lit
      written <= 1'b0;
      stored  <= FAR;
    end else if (is_write) begin
      lit     <= 1'b0;
      written <= less;
      stored  <= less ? d : old;
    end else begin
      lit     <= leq;
      written <= 1'b0;
      stored  <= old;
    end
  end
endmodule
