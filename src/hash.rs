//! A hash that stays the same across Rust versions, platforms and runs: 64-bit FNV-1a
//! (Fowler, Noll & Vo; IETF draft-eastlake-fnv), the one hash function of drillopt.
//!
//! Used for the evaluation cache's keys and the problem hash in reports ([`stable_hash`] of
//! bytes), and in the simulator's time-step loop for the set of nodes touching the wall
//! ([`Fnv1a::word`], allocation-free). Fixed by its definition, so stable across drillopt versions,
//! Rust versions and platforms (unlike `std::hash`, whose `DefaultHasher` may change and is
//! randomly keyed in `HashMap`). Not collision resistant against an adversary; it tells apart
//! models, which is all drillopt needs.

/// FNV-1a offset basis, 64 bit.
const FNV_OFFSET: u64 = 0xCBF2_9CE4_8422_2325;
/// FNV prime, 64 bit.
const FNV_PRIME: u64 = 0x0000_0100_0000_01B3;

/// A running FNV-1a hash.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Self::new()
    }
}

impl Fnv1a {
    /// The offset basis.
    pub const fn new() -> Self {
        Fnv1a(FNV_OFFSET)
    }

    /// One FNV-1a round on a whole word: h ← (h ⊕ w)·prime mod 2⁶⁴.
    #[inline]
    pub fn word(&mut self, w: u64) {
        self.0 = (self.0 ^ w).wrapping_mul(FNV_PRIME);
    }

    /// The standard byte-wise FNV-1a over `bytes`.
    pub fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.word(u64::from(b));
        }
    }

    /// The hash value.
    pub fn finish(self) -> u64 {
        self.0
    }
}

/// 64-bit FNV-1a of `bytes`: for each byte, h ← (h ⊕ byte)·prime mod 2⁶⁴ from the offset basis.
///
/// Hash a canonical serialisation (fields in a fixed order, floats written exactly) so that equal
/// inputs give equal bytes.
pub fn stable_hash(bytes: &[u8]) -> u64 {
    let mut h = Fnv1a::new();
    h.bytes(bytes);
    h.finish()
}
