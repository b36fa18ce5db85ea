//! The memory controller: one channel of `bytes_per_clock` shared by four clients
//! (texture misses, depth, colour, copy), a request queue of `queue_depth` entries over
//! all clients, an arbiter (round robin or fixed priority) and optional DRAM pages.
//!
//! The model, clock by clock (the controller is evaluated first in every clock):
//! - a request enqueued in clock t may start in clock t + 1 (the queue is registered);
//! - the channel transfers one request at a time: a request of b bytes occupies it for
//!   b ÷ bytes_per_clock clocks (fractional; the next request starts where it ended),
//!   plus `page_miss_clocks` when DRAM pages are modelled and its bank has another
//!   page open (the bank of address a is ⌊a / page_bytes⌋ mod banks);
//! - a read's data arrives `latency_clocks` after its transfer ends (rounded up to a
//!   clock); a write is posted (nobody waits for it);
//! - in every clock the channel is free, the arbiter picks the next client with a
//!   request waiting: round robin from the client after the last one served, or the
//!   fixed order texture, depth, colour, copy.
//!
//! Reads of one client complete in the order they were issued (one channel, one
//! latency), so a client's reads are numbered and "read n has arrived" is a count.

use super::config::{Arbitration, MemoryConfig};
use super::fifo::Ring;

/// The memory clients, in fixed-priority order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Client {
    Texture = 0,
    Depth = 1,
    Colour = 2,
    Copy = 3,
}

/// The clients' names, as `PassTiming::bytes_by_client` keys them.
pub const CLIENT_NAMES: [&str; 4] = ["texture", "depth", "colour", "copy"];

#[derive(Clone, Copy, Debug, Default)]
struct Request {
    bytes: u32,
    addr: u64,
    read: bool,
}

/// The controller's state over one pass.
#[derive(Clone, Debug)]
pub struct Memory {
    cfg: MemoryConfig,
    queues: [Ring<Request>; 4],
    queued: usize,
    /// The channel is busy until this (fractional) clock.
    free_at: f64,
    /// Reads issued and arrived, per client.
    reads_issued: [u64; 4],
    reads_done: [u64; 4],
    /// Arrival clocks of reads transferred but not yet arrived, per client, in order.
    in_flight: [Ring<u64>; 4],
    open_page: Vec<u64>,
    next_rr: usize,
    /// The earliest arrival clock among the reads in flight (u64::MAX: none).
    earliest_arrival: u64,
    /// Bytes each client moved (counted when the request is queued).
    pub bytes: [u64; 4],
    /// Clocks the channel transferred (fractional sum of the requests' occupancy).
    pub transfer_clocks: f64,
}

impl Memory {
    pub fn new(cfg: &MemoryConfig) -> Self {
        let banks = cfg.pages.map_or(0, |p| p.banks as usize);
        Memory {
            cfg: *cfg,
            queues: Default::default(),
            queued: 0,
            free_at: 0.0,
            reads_issued: [0; 4],
            reads_done: [0; 4],
            in_flight: Default::default(),
            open_page: vec![u64::MAX; banks],
            next_rr: 0,
            earliest_arrival: u64::MAX,
            bytes: [0; 4],
            transfer_clocks: 0.0,
        }
    }

    /// Start a new hardware pass at clock 0 (queues are empty; counters are kept).
    pub fn restart(&mut self) {
        self.free_at = 0.0;
        self.reads_issued = [0; 4];
        self.reads_done = [0; 4];
        for q in &mut self.in_flight {
            q.clear();
        }
        self.earliest_arrival = u64::MAX;
        for q in &mut self.queues {
            q.clear();
        }
        self.queued = 0;
    }

    /// Room for another request in the queue.
    #[inline]
    pub fn has_room(&self) -> bool {
        self.queued < self.cfg.queue_depth as usize
    }

    /// Requests waiting (not yet started).
    pub fn queued(&self) -> usize {
        self.queued
    }

    /// The number the next read of `c` will get (reads are numbered from 1).
    #[inline]
    pub fn next_read(&self, c: Client) -> u64 {
        self.reads_issued[c as usize] + 1
    }

    /// Reads of `c` that have arrived (read n has arrived when this is ≥ n).
    #[inline]
    pub fn reads_done(&self, c: Client) -> u64 {
        self.reads_done[c as usize]
    }

    /// Reads of `c` issued and not yet arrived.
    #[inline]
    pub fn reads_outstanding(&self, c: Client) -> u64 {
        self.reads_issued[c as usize] - self.reads_done[c as usize]
    }

    /// Queue a request (the caller checked [`Memory::has_room`]; one quad's requests
    /// may enter together). Returns the read's number (0 for a write).
    #[inline]
    pub fn enqueue(&mut self, c: Client, bytes: u32, addr: u64, read: bool) -> u64 {
        let i = c as usize;
        self.queues[i].push_back(Request { bytes, addr, read });
        self.queued += 1;
        self.bytes[i] += bytes as u64;
        if read {
            self.reads_issued[i] += 1;
            self.reads_issued[i]
        } else {
            0
        }
    }

    fn pick(&mut self) -> Option<usize> {
        match self.cfg.arbitration {
            Arbitration::FixedPriority => (0..4).find(|&c| !self.queues[c].is_empty()),
            Arbitration::RoundRobin => {
                let c = (0..4)
                    .map(|k| (self.next_rr + k) % 4)
                    .find(|&c| !self.queues[c].is_empty())?;
                self.next_rr = (c + 1) % 4;
                Some(c)
            }
        }
    }

    /// Clock `now`: start every request the channel can begin in this clock, then count
    /// the reads whose data has arrived by this clock. Returns whether anything changed.
    #[inline]
    pub fn tick(&mut self, now: u64) -> bool {
        // Nothing queued and no read due: the common clock of a pass the memory does
        // not bound, answered without a call.
        if self.queued == 0 && self.earliest_arrival > now {
            return false;
        }
        self.tick_work(now)
    }

    /// [`Memory::tick`] when a request waits or a read arrives.
    fn tick_work(&mut self, now: u64) -> bool {
        let mut changed = false;
        let t = now as f64;
        while self.queued > 0 && self.free_at < t + 1.0 {
            let Some(c) = self.pick() else { break };
            let Some(r) = self.queues[c].pop_front() else {
                break;
            };
            self.queued -= 1;
            let start = self.free_at.max(t);
            let mut clocks = r.bytes as f64 / self.cfg.bytes_per_clock;
            if let Some(p) = self.cfg.pages {
                let page = r.addr / p.page_bytes as u64;
                let bank = (page % p.banks as u64) as usize;
                if self.open_page[bank] != page {
                    if self.open_page[bank] != u64::MAX {
                        clocks += p.page_miss_clocks as f64;
                    }
                    self.open_page[bank] = page;
                }
            }
            self.free_at = start + clocks;
            self.transfer_clocks += clocks;
            if r.read {
                let arrive = self.free_at.ceil() as u64 + self.cfg.latency_clocks as u64;
                self.in_flight[c].push_back(arrive);
                self.earliest_arrival = self.earliest_arrival.min(arrive);
            }
            changed = true;
        }
        if self.earliest_arrival > now {
            return changed;
        }
        self.earliest_arrival = u64::MAX;
        for c in 0..4 {
            while let Some(&a) = self.in_flight[c].front() {
                if a > now {
                    break;
                }
                self.in_flight[c].pop_front();
                self.reads_done[c] += 1;
                changed = true;
            }
            if let Some(&a) = self.in_flight[c].front() {
                self.earliest_arrival = self.earliest_arrival.min(a);
            }
        }
        changed
    }

    /// The channel transfers during clock `now` (after `tick(now)`).
    #[inline]
    pub fn busy(&self, now: u64) -> bool {
        self.free_at > now as f64
    }

    /// Nothing queued, nothing in flight, the channel idle at `now`.
    pub fn idle(&self, now: u64) -> bool {
        self.queued == 0 && self.in_flight.iter().all(|q| q.is_empty()) && !self.busy(now)
    }

    /// The next clock after `now` at which the controller's state or its busy signal
    /// changes by itself, if any.
    pub fn next_event(&self, now: u64) -> Option<u64> {
        let mut next = u64::MAX;
        for q in &self.in_flight {
            if let Some(&a) = q.front() {
                next = next.min(a.max(now + 1));
            }
        }
        if self.free_at > now as f64 {
            // The channel frees (or a queued request may start) at the end of the
            // current transfer.
            let f = self.free_at.floor() as u64;
            next = next.min(
                if self.queued > 0 {
                    f
                } else {
                    self.free_at.ceil() as u64
                }
                .max(now + 1),
            );
        } else if self.queued > 0 {
            next = next.min(now + 1);
        }
        (next != u64::MAX).then_some(next)
    }
}
