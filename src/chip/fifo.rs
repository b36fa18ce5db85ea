//! A bounded FIFO between two stages of the clocked chip, with valid/ready
//! back-pressure.
//!
//! The handshake, as the engine evaluates a clock (producers before consumers):
//! - **ready is registered**: a producer may push only when the FIFO held fewer than
//!   `depth` entries at the start of the clock (the consumer's pop of the same clock
//!   is not yet seen), so a full FIFO costs its producer one clock after it drains;
//! - **valid falls through**: a consumer may pop an entry pushed in the same clock
//!   (a bypass register), so a chain of stages adds no clock per FIFO.
//!
//! With this handshake a FIFO of any depth ≥ 1 passes one entry per clock when both
//! sides can. The entries are small `Copy` indices (a quad's or a primitive's number);
//! the ring is allocated once per pass.

/// A ring buffer of at most `depth` entries, with its high-water mark.
#[derive(Clone, Debug)]
pub struct Fifo<T: Copy + Default> {
    ring: Vec<T>,
    head: usize,
    len: usize,
    high_water: usize,
}

impl<T: Copy + Default> Fifo<T> {
    /// An empty FIFO of `depth` entries (≥ 1).
    pub fn new(depth: usize) -> Self {
        Fifo {
            ring: vec![T::default(); depth.max(1)],
            head: 0,
            len: 0,
            high_water: 0,
        }
    }

    /// Entries it can hold.
    pub fn depth(&self) -> usize {
        self.ring.len()
    }

    /// Entries held now.
    #[inline]
    pub fn level(&self) -> usize {
        self.len
    }

    /// The deepest occupancy seen.
    pub fn high_water(&self) -> usize {
        self.high_water
    }

    /// valid: an entry is waiting.
    #[inline]
    pub fn valid(&self) -> bool {
        self.len > 0
    }

    /// ready: room for one more entry.
    #[inline]
    pub fn ready(&self) -> bool {
        self.len < self.ring.len()
    }

    /// The oldest entry, if any.
    #[inline]
    pub fn front(&self) -> Option<T> {
        (self.len > 0).then(|| self.ring[self.head])
    }

    /// Push; returns false (and leaves the FIFO as it was) when full.
    #[inline]
    pub fn push(&mut self, v: T) -> bool {
        if self.len == self.ring.len() {
            return false;
        }
        let mut i = self.head + self.len;
        if i >= self.ring.len() {
            i -= self.ring.len();
        }
        self.ring[i] = v;
        self.len += 1;
        self.high_water = self.high_water.max(self.len);
        true
    }

    /// Pop the oldest entry.
    #[inline]
    pub fn pop(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let v = self.ring[self.head];
        self.head += 1;
        if self.head == self.ring.len() {
            self.head = 0;
        }
        self.len -= 1;
        Some(v)
    }

    /// Empty it (the high-water mark is kept).
    pub fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }
}

/// An unbounded queue for the engine's inner loop (requests waiting for the memory
/// channel, reads in flight, quads inside a unit): a power-of-two ring that grows
/// when full. Unlike `VecDeque`, its push and pop are small enough to inline into the
/// per-clock loop (the growth is out of line), and an index wraps with a mask.
#[derive(Clone, Debug)]
pub struct Ring<T: Copy + Default> {
    buf: Vec<T>,
    head: usize,
    len: usize,
}

impl<T: Copy + Default> Default for Ring<T> {
    fn default() -> Self {
        Ring::with_capacity(8)
    }
}

impl<T: Copy + Default> Ring<T> {
    /// An empty ring with room for at least `cap` entries before it grows.
    pub fn with_capacity(cap: usize) -> Self {
        Ring {
            buf: vec![T::default(); cap.max(2).next_power_of_two()],
            head: 0,
            len: 0,
        }
    }

    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    #[inline]
    pub fn front(&self) -> Option<&T> {
        (self.len > 0).then(|| &self.buf[self.head])
    }

    #[inline]
    pub fn push_back(&mut self, v: T) {
        if self.len == self.buf.len() {
            self.grow();
        }
        let mask = self.buf.len() - 1;
        self.buf[(self.head + self.len) & mask] = v;
        self.len += 1;
    }

    #[inline]
    pub fn pop_front(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let v = self.buf[self.head];
        self.head = (self.head + 1) & (self.buf.len() - 1);
        self.len -= 1;
        Some(v)
    }

    pub fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }

    /// Double the ring, its entries moved to the front in order.
    #[cold]
    #[inline(never)]
    fn grow(&mut self) {
        let n = self.buf.len();
        let mut buf = Vec::with_capacity(2 * n);
        buf.extend((0..self.len).map(|k| self.buf[(self.head + k) & (n - 1)]));
        buf.resize(2 * n, T::default());
        self.buf = buf;
        self.head = 0;
    }
}

/// Clock a producer and a consumer joined by a FIFO of `depth`: the producer makes an
/// entry every `producer_ii` clocks, the consumer takes one every `consumer_ii` clocks,
/// `n` entries in all, with the handshake above. Returns (clocks until the consumer took
/// the last entry, the producer's stalled clocks: clocks it held a finished entry it
/// could not push). The engine's stages obey the same rules; this is the two-stage case
/// a test can work by hand.
pub fn producer_consumer(n: u64, producer_ii: u32, consumer_ii: u32, depth: usize) -> (u64, u64) {
    let (p, c) = (producer_ii.max(1) as u64, consumer_ii.max(1) as u64);
    let mut fifo: Fifo<u8> = Fifo::new(depth);
    let (mut made, mut taken) = (0u64, 0u64);
    // The producer's entry in hand is finished at `ready_at`; the consumer may take the
    // next entry at `next_take`.
    let mut ready_at = p - 1;
    let mut next_take = 0u64;
    let mut stalled = 0u64;
    let mut t = 0u64;
    loop {
        // Producer first (it sees the level at the start of the clock).
        if made < n && t >= ready_at {
            if fifo.push(0) {
                made += 1;
                ready_at = t + p;
            } else {
                stalled += 1;
            }
        }
        // Consumer (it may take an entry pushed this clock).
        if t >= next_take && fifo.pop().is_some() {
            taken += 1;
            next_take = t + c;
            if taken == n {
                return (t + 1, stalled);
            }
        }
        t += 1;
    }
}
