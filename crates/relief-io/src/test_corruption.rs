//! Deterministic byte corruption for the readers' robustness tests.

/// `copies` copies of `good`, each with `bytes_each` bytes overwritten at pseudo-random places
/// with pseudo-random values (xorshift64, fixed seed: the same copies every run).
pub(crate) fn corrupted_copies(good: &[u8], copies: usize, bytes_each: usize) -> Vec<Vec<u8>> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    (0..copies)
        .map(|_| {
            let mut bad = good.to_vec();
            for _ in 0..bytes_each {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let at = (state % bad.len() as u64) as usize;
                bad[at] = (state >> 32) as u8;
            }
            bad
        })
        .collect()
}
