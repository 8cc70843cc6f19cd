//! The terrains every tracer is checked on: seeded, of odd and tiny sizes (1x1, 2x2, 1xN),
//! flat, noisy, spiky, cliffs, integer heights, with and without holes, on unit and non-unit,
//! square and non-square spacing.

use super::seeded::Seeded;
use relief_core::{DVec2, GridGeometry, HeightField};

/// The character of a terrain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Relief {
    /// One height everywhere.
    Flat,
    /// Uniform noise over 10 units.
    Noisy,
    /// Nearly flat with a few tall spikes.
    Spiky,
    /// A straight cliff 10^4 units high across the grid.
    Cliff,
    /// Whole heights from 0 to 3: many exact ties between neighbours.
    Integer,
}

/// Every relief, in a fixed order.
pub const RELIEFS: [Relief; 5] =
    [Relief::Flat, Relief::Noisy, Relief::Spiky, Relief::Cliff, Relief::Integer];

/// The sizes every run covers first, before random ones: the smallest grids and odd shapes.
const FIXED_SIZES: [(usize, usize); 8] =
    [(1, 1), (2, 2), (1, 7), (9, 1), (3, 5), (2, 13), (17, 16), (33, 31)];

/// The `index`-th terrain of the suite drawn from `numbers`: the first ones have the fixed
/// small sizes, later ones random sizes up to 48 x 52. One in three has square cells with a
/// unit height scale (what a tracer of square cells, such as an MLHM's, can stand for), one
/// in five holes.
pub fn terrain(index: usize, numbers: &mut Seeded) -> HeightField {
    let (w, h) = FIXED_SIZES
        .get(index)
        .copied()
        .unwrap_or_else(|| (1 + numbers.index(48), 1 + numbers.index(52)));
    let relief = RELIEFS[index % RELIEFS.len()];
    let offset = numbers.range(-50.0, 50.0);
    let geometry = if index.is_multiple_of(3) {
        let spacing = [1.0, 0.5, 2.5][index / 3 % 3];
        GridGeometry { dx: spacing, dy: spacing, z_scale: 1.0, origin: DVec2::new(offset, -offset) }
    } else {
        GridGeometry {
            dx: numbers.range(0.25, 4.0),
            dy: numbers.range(0.25, 4.0),
            z_scale: numbers.range(0.1, 3.0),
            origin: DVec2::new(3.0 * offset, -offset),
        }
    };
    let samples = heights(w, h, relief, offset, numbers);
    let field = HeightField::new(w, h, samples, geometry).expect("a valid random terrain");
    if index % 5 == 4 {
        let holes: Vec<bool> = (0..w * h).map(|_| numbers.unit() < 0.15).collect();
        // A field of holes only is refused: it stays whole then.
        return field.clone().with_holes(holes).unwrap_or(field);
    }
    field
}

/// `w x h` samples of `relief`, raised by `offset`.
fn heights(w: usize, h: usize, relief: Relief, offset: f64, numbers: &mut Seeded) -> Vec<f32> {
    let (a, b, c) = (numbers.unit(), numbers.unit(), numbers.unit());
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            let v = match relief {
                Relief::Flat => 3.0,
                Relief::Noisy => 10.0 * numbers.unit(),
                Relief::Spiky if numbers.unit() < 0.08 => 50.0 * numbers.unit(),
                Relief::Spiky => 0.5 * numbers.unit(),
                Relief::Cliff => {
                    let side = (x - a * w as f64) * (b - 0.5) + (y - c * h as f64) * 0.7;
                    2.0 * numbers.unit() + if side > 0.0 { 1e4 } else { 0.0 }
                }
                Relief::Integer => (4.0 * numbers.unit()).floor(),
            };
            (v + offset) as f32
        })
        .collect()
}
