//! A hash that stays the same across Rust versions, platforms and runs.

/// FNV-1a offset basis, 64 bit.
const FNV_OFFSET: u64 = 0xCBF2_9CE4_8422_2325;
/// FNV prime, 64 bit.
const FNV_PRIME: u64 = 0x0000_0100_0000_01B3;

/// 64-bit FNV-1a of `bytes` (Fowler, Noll & Vo; IETF draft-eastlake-fnv): for each byte,
/// h ← (h ⊕ byte)·prime mod 2⁶⁴ from the offset basis. Fixed by its definition, so stable across
/// drillopt versions, Rust versions and platforms (unlike `std::hash`, whose `DefaultHasher` may
/// change and is randomly keyed in `HashMap`). Not collision resistant against an adversary; it
/// tells apart models, which is all the cache needs.
///
/// Hash a canonical serialisation of the model (e.g. its JSON with fields in a fixed order and
/// floats written exactly) so that equal models give equal bytes.
pub fn stable_hash(bytes: &[u8]) -> u64 {
    bytes.iter().fold(FNV_OFFSET, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(FNV_PRIME)
    })
}
