//! Which pixels the adaptive anti-aliasing samples again: those whose centre ray sees
//! something else than a neighbour's, where that shows.

use crate::draw::picture::Picture;
use rayon::prelude::*;
use relief_shade::PixelMask;

/// Two neighbours' depths differ so much, relative to the nearer, that they see different
/// surfaces (a silhouette, a cliff's foot): 4 %.
const DEPTH_JUMP: f32 = 0.04;

/// Two neighbours' colours differ by more than this many 8-bit steps in a channel: a shadow's
/// edge, a material boundary.
const COLOUR_STEP: u8 = 64;

/// Two neighbours' normals differ by more than this angle's cosine (about 45 degrees) and
/// their colours by more than [`CREASE_COLOUR_STEP`]: a box edge, a sharp ridge, a crease that
/// shows (a crease the light does not show, as on the boxes of an MLHM scene whose shading
/// is filtered over the pixel, does not alias).
const CREASE_COS: f32 = 0.7;

/// The colour step a crease must show to count (see [`CREASE_COS`]).
const CREASE_COLOUR_STEP: u8 = 32;

/// The pixels of `picture` (which keeps its depth and normals) on an edge: each pixel of a
/// pair of horizontal or vertical neighbours that see different things (one hits and the
/// other misses, or their depths, their colours, or their normals and colours differ past
/// the thresholds above). Without depth or normals, only colours are compared.
pub fn edge_mask(picture: &Picture) -> PixelMask {
    let (w, h) = (picture.width as usize, picture.height as usize);
    let pixels = Pixels {
        rgb: &picture.rgb,
        depth: picture.depth.as_deref().unwrap_or(&[]),
        normals: picture.normals.as_deref().unwrap_or(&[]),
    };
    // Each pair once, row by row in parallel: whether a pixel differs from its right and its
    // lower neighbour; then a pixel is marked when it differs from one of its four.
    let mut pairs = vec![[false; 2]; w * h];
    pairs.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
        for (i, pair) in row.iter_mut().enumerate() {
            let k = i + j * w;
            *pair = [i + 1 < w && pixels.differ(k, k + 1), j + 1 < h && pixels.differ(k, k + w)];
        }
    });
    let mut marked = vec![false; w * h];
    marked.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
        for (i, mark) in row.iter_mut().enumerate() {
            let k = i + j * w;
            let [right, down] = pairs[k];
            *mark = right || down || (i > 0 && pairs[k - 1][0]) || (j > 0 && pairs[k - w][1]);
        }
    });
    PixelMask::new(w, h, marked)
}

/// What a picture's pixels see: their colours, and their depths and normals (empty where the
/// picture keeps none).
struct Pixels<'a> {
    rgb: &'a [[u8; 3]],
    depth: &'a [f32],
    normals: &'a [[f32; 3]],
}

impl Pixels<'_> {
    /// Whether pixels `a` and `b` see different things.
    #[inline]
    fn differ(&self, a: usize, b: usize) -> bool {
        let (ca, cb) = (self.rgb[a], self.rgb[b]);
        let step = ca[0].abs_diff(cb[0]).max(ca[1].abs_diff(cb[1])).max(ca[2].abs_diff(cb[2]));
        if step > COLOUR_STEP {
            return true;
        }
        if let (Some(&da), Some(&db)) = (self.depth.get(a), self.depth.get(b)) {
            // One hits and the other misses, or both hit far apart (NaN-free: misses are +inf).
            if da.is_finite() != db.is_finite()
                || (da.is_finite() && (da - db).abs() > DEPTH_JUMP * da.min(db))
            {
                return true;
            }
        }
        if step <= CREASE_COLOUR_STEP {
            return false;
        }
        let (Some(na), Some(nb)) = (self.normals.get(a), self.normals.get(b)) else {
            return false;
        };
        let dot = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2];
        let hit = |n: &[f32; 3]| *n != [0.0; 3];
        hit(na) && hit(nb) && dot < CREASE_COS
    }
}
