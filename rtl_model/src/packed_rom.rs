//! A ROM packed at its entry width in `bitvec`, so its bit count is the real one
//! (the Gaussian generator's ln/√/sin tables, the chaos map's log2/exp2 tables).

use bitvec::prelude::*;

/// The `width`-bit field (1 ..= 64) at bit `bit` of an LSB-first packed store, read
/// from its raw words: what `bits[bit..bit + width].load_le::<u64>()` reads from a
/// `BitVec<u64, Lsb0>`, in a shift and a mask (the field spans at most two words).
/// The bit must lie inside the store.
#[inline]
pub fn read_field(words: &[u64], bit: usize, width: u32) -> u64 {
    let (i, off) = (bit / 64, (bit % 64) as u32);
    let mask = u64::MAX >> (64 - width);
    let lo = words[i] >> off;
    if off + width <= 64 {
        lo & mask
    } else {
        (lo | (words[i + 1] << (64 - off))) & mask
    }
}

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
        read_field(self.bits.as_raw_slice(), i * self.width, self.width as u32) as i64
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `read_field` reads what bitvec's `load_le` reads, for every width and every
    /// offset across three words (both the one-word and the two-word case).
    #[test]
    fn read_field_matches_load_le() {
        let mut bits = bitvec![u64, Lsb0; 0; 256];
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for i in 0..256 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            bits.set(i, x & 1 == 1);
        }
        for width in 1..=64usize {
            for bit in 0..=(256 - width) {
                let want = bits[bit..bit + width].load_le::<u64>();
                assert_eq!(read_field(bits.as_raw_slice(), bit, width as u32), want);
            }
        }
    }
}
