//! A fast, stable 128-bit hash for the bind cache's key and checksum.
//!
//! Not cryptographic: it tells apart the rigs, meshes and files a user has, it does not
//! stand up to someone forging a collision (a forged cache could at worst give a wrong face,
//! never a panic: the parts are checked on load). Two lanes of 64 bits, each a bijection of
//! its state per word, so inputs of one length that differ in one word always differ in
//! both lanes; the same on every machine and every build (no `std` hasher, whose output may
//! change between Rust versions).

/// The streaming hasher: feed bytes or 32-bit words, then [`Hasher::finish`].
#[derive(Debug, Clone)]
pub struct Hasher {
    a: u64,
    b: u64,
    /// Bytes fed so far.
    len: u64,
    /// Bytes not yet making a whole word, low byte first.
    tail: u64,
    tail_len: u32,
}

const K1: u64 = 0x9E37_79B9_7F4A_7C15;
const K2: u64 = 0xC2B2_AE3D_27D4_EB4F;

impl Default for Hasher {
    fn default() -> Hasher {
        Hasher {
            a: 0x243F_6A88_85A3_08D3,
            b: 0x1319_8A2E_0370_7344,
            len: 0,
            tail: 0,
            tail_len: 0,
        }
    }
}

impl Hasher {
    /// Mixes in one whole word.
    #[inline(always)]
    fn word(&mut self, w: u64) {
        self.a = (self.a ^ w).wrapping_mul(K1).rotate_left(31);
        self.b = (self.b ^ w.rotate_left(29))
            .wrapping_mul(K2)
            .rotate_left(27);
    }

    /// Feeds bytes (any split of a byte stream gives the same hash).
    pub fn bytes(&mut self, mut data: &[u8]) {
        self.len += data.len() as u64;
        while self.tail_len != 0 && !data.is_empty() {
            self.tail |= u64::from(data[0]) << (8 * self.tail_len);
            self.tail_len = (self.tail_len + 1) % 8;
            data = &data[1..];
            if self.tail_len == 0 {
                let w = std::mem::take(&mut self.tail);
                self.word(w);
            }
        }
        let mut chunks = data.chunks_exact(8);
        for chunk in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(chunk);
            self.word(u64::from_le_bytes(w));
        }
        for &byte in chunks.remainder() {
            self.tail |= u64::from(byte) << (8 * self.tail_len);
            self.tail_len += 1;
        }
    }

    /// Feeds 32-bit words as their little-endian bytes.
    pub fn u32s(&mut self, words: impl IntoIterator<Item = u32>) {
        let mut words = words.into_iter();
        if self.tail_len != 0 {
            // Not word-aligned: the slow path keeps the byte stream's meaning.
            for w in words {
                self.bytes(&w.to_le_bytes());
            }
            return;
        }
        loop {
            match (words.next(), words.next()) {
                (Some(lo), Some(hi)) => {
                    self.len += 8;
                    self.word(u64::from(lo) | (u64::from(hi) << 32));
                }
                (Some(lo), None) => return self.bytes(&lo.to_le_bytes()),
                _ => return,
            }
        }
    }

    /// Feeds a length-prefixed string, so that two strings never run into each other.
    pub fn text(&mut self, text: &str) {
        self.u32s([text.len() as u32]);
        self.bytes(text.as_bytes());
    }

    /// The 128-bit hash of everything fed.
    pub fn finish(mut self) -> [u8; 16] {
        if self.tail_len != 0 {
            let w = self.tail;
            self.word(w);
        }
        let a = mix(self.a ^ self.len);
        let b = mix(self.b ^ a);
        let mut out = [0u8; 16];
        out[..8].copy_from_slice(&a.to_le_bytes());
        out[8..].copy_from_slice(&b.to_le_bytes());
        out
    }
}

/// The finaliser of SplitMix64: every input bit moves about half of the output bits.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn of(parts: &[&[u8]]) -> [u8; 16] {
        let mut h = Hasher::default();
        for p in parts {
            h.bytes(p);
        }
        h.finish()
    }

    #[test]
    fn any_split_of_the_bytes_gives_the_same_hash_and_words_are_their_bytes() {
        let data: Vec<u8> = (0..100u32).map(|i| (i * 37 % 251) as u8).collect();
        let whole = of(&[&data]);
        for cut in [1, 3, 7, 8, 9, 50, 99] {
            assert_eq!(of(&[&data[..cut], &data[cut..]]), whole, "cut at {cut}");
        }
        let words: Vec<u32> = data
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let mut h = Hasher::default();
        h.u32s(words.iter().copied());
        assert_eq!(h.finish(), whole);
        let mut h = Hasher::default();
        h.bytes(&data[..1]);
        h.u32s([u32::from_le_bytes([data[1], data[2], data[3], data[4]])]);
        h.bytes(&data[5..]);
        assert_eq!(h.finish(), whole);
    }

    #[test]
    fn one_changed_bit_or_byte_more_changes_the_hash() {
        let data = vec![7u8; 64];
        let whole = of(&[&data]);
        for i in 0..64 {
            let mut changed = data.clone();
            changed[i] ^= 1;
            assert_ne!(of(&[&changed]), whole);
        }
        assert_ne!(of(&[&data, &[0]]), whole);
        assert_ne!(of(&[&data[..63]]), whole);
    }
}
