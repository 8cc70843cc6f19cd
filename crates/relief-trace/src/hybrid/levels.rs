//! The levels of precision of the hybrid renderer's approximate ray casting (Ammann et al.
//! 2010, section 5.1): how many linear and binary search steps [`super::lop_cast`] takes at
//! each level.

/// The linear and binary search steps of one level of precision of the ray casting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LopSteps {
    /// Fixed number of steps of the linear search from the box's entry to its exit.
    pub linear: u32,
    /// Fixed number of halvings of the binary search that follows.
    pub binary: u32,
}

/// The paper's four levels (section 5.1), most precise first.
pub const PAPER_LEVELS: [LopSteps; 4] = [
    LopSteps { linear: 55, binary: 25 },
    LopSteps { linear: 32, binary: 15 },
    LopSteps { linear: 16, binary: 10 },
    LopSteps { linear: 8, binary: 5 },
];

/// The steps of `count` levels of precision, most precise first.
///
/// Four levels are the paper's (55/25, 32/15, 16/10, 8/5; section 5.1). Other counts
/// interpolate geometrically between the ends of the paper's Table 2, 64/50 and 6/5: level
/// `i` of `m` has `round(64 (6/64)^(i/(m-1)))` linear and `round(50 (5/50)^(i/(m-1)))` binary
/// steps (two levels: 64/50 and 6/5; three: 64/50, 20/16, 6/5). An empty list for a count of
/// 0; one level is the most precise, 64/50.
pub fn lop_steps(count: usize) -> Vec<LopSteps> {
    if count == PAPER_LEVELS.len() {
        return PAPER_LEVELS.to_vec();
    }
    let ends = |hi: f64, lo: f64, i: usize| -> u32 {
        let f = if count > 1 { i as f64 / (count - 1) as f64 } else { 0.0 };
        (hi * (lo / hi).powf(f)).round() as u32
    };
    (0..count)
        .map(|i| LopSteps { linear: ends(64.0, 6.0, i), binary: ends(50.0, 5.0, i) })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_are_the_papers_or_interpolated_geometrically() {
        assert_eq!(lop_steps(4), PAPER_LEVELS.to_vec());
        let two = [LopSteps { linear: 64, binary: 50 }, LopSteps { linear: 6, binary: 5 }];
        assert_eq!(lop_steps(2), two.to_vec());
        assert_eq!(lop_steps(3)[1], LopSteps { linear: 20, binary: 16 });
        let ten = lop_steps(10);
        assert_eq!((ten[0], ten[9]), (two[0], two[1]));
        assert!(ten.windows(2).all(|w| w[0].linear > w[1].linear && w[0].binary >= w[1].binary));
    }
}
