//! A ROM packed at its entry width in `bitvec`, so its bit count is the real one
//! (the Gaussian generator's ln/√/sin tables, the chaos map's log2/exp2 tables).

use bitvec::prelude::*;

/// `depth` unsigned entries of `width` bits.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PackedRom {
    width: usize,
    depth: usize,
    bits: BitVec<u64, Lsb0>,
}

impl PackedRom {
    /// Pack `words`, each truncated to `width` (≤ 64) bits.
    pub fn new(width: u32, words: &[u64]) -> Self {
        let w = width as usize;
        let mut bits = bitvec![u64, Lsb0; 0; words.len() * w];
        for (i, &v) in words.iter().enumerate() {
            bits[i * w..(i + 1) * w].store_le::<u64>(v);
        }
        PackedRom {
            width: w,
            depth: words.len(),
            bits,
        }
    }

    /// Entry `i` (an index past the end reads the last entry: the address clamps).
    #[inline]
    pub fn read(&self, i: usize) -> i64 {
        let i = i.min(self.depth - 1);
        self.bits[i * self.width..(i + 1) * self.width].load_le::<u64>() as i64
    }

    /// Every entry, for `$readmemh` images.
    pub fn words(&self) -> Vec<u64> {
        (0..self.depth).map(|i| self.read(i) as u64).collect()
    }

    /// Bits stored: depth × width.
    pub fn ram_bits(&self) -> u64 {
        self.bits.len() as u64
    }
}
