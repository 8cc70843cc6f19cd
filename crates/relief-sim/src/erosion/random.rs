//! Counter-based random numbers: a value per (seed, step, cell) from a hash, independent of
//! the order and the threads that ask for them.

/// SplitMix64's finaliser: a bijective mix of 64 bits.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A number uniform in [0, 1) for `cell` at `step` of the run seeded by `seed`: three rounds
/// of SplitMix64's mix over the keys, the top 24 bits as the fraction.
#[inline]
pub fn uniform(seed: u64, step: u64, cell: u64) -> f32 {
    const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;
    let h = mix(seed.wrapping_add(GOLDEN));
    let h = mix(h ^ step.wrapping_mul(GOLDEN).wrapping_add(0x632b_e59b_d9b4_e019));
    let h = mix(h ^ cell.wrapping_mul(0xd1b5_4a32_d192_ed03));
    (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_is_in_range_keyed_and_unbiased() {
        let mut sum = 0.0f64;
        let n = 100_000u64;
        for c in 0..n {
            let u = uniform(7, 3, c);
            assert!((0.0..1.0).contains(&u));
            sum += f64::from(u);
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.01);
        assert_ne!(uniform(7, 3, 1), uniform(7, 4, 1));
        assert_ne!(uniform(7, 3, 1), uniform(8, 3, 1));
        assert_eq!(uniform(7, 3, 1), uniform(7, 3, 1));
    }
}
