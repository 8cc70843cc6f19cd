//! Which pixels the adaptive anti-aliasing samples again: those whose centre ray sees
//! something else than a neighbour's.

use crate::draw::picture::Picture;
use rayon::prelude::*;
use relief_shade::PixelMask;

/// Two neighbours' depths differ so much, relative to the nearer, that they see different
/// surfaces (a silhouette, a cliff's foot): 4 %.
const DEPTH_JUMP: f32 = 0.04;

/// Two neighbours' normals differ by more than this angle's cosine (about 45 degrees): a box
/// edge, a sharp ridge, a crease (the gentler turns of a terrain's facets alias little).
const NORMAL_COS: f32 = 0.7;

/// Two neighbours' colours differ by more than this many 8-bit steps in a channel: a shadow's
/// edge, a material boundary.
const COLOUR_STEP: i32 = 48;

/// The pixels of `picture` (which keeps its depth and normals) on an edge: each pixel of a
/// pair of horizontal or vertical neighbours that differ in what they see (one hits and the
/// other misses, or their depths, normals or colours differ past the thresholds above).
/// Without depth or normals, only colours are compared.
pub fn edge_mask(picture: &Picture) -> PixelMask {
    let (w, h) = (picture.width as usize, picture.height as usize);
    // Each pair once, row by row in parallel: whether a pixel differs from its right and its
    // lower neighbour; then a pixel is marked when it differs from one of its four.
    let mut pairs = vec![[false; 2]; w * h];
    pairs.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
        for (i, pair) in row.iter_mut().enumerate() {
            let k = i + j * w;
            *pair =
                [i + 1 < w && differ(picture, k, k + 1), j + 1 < h && differ(picture, k, k + w)];
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

/// Whether pixels `a` and `b` of `picture` see different things.
#[inline]
fn differ(picture: &Picture, a: usize, b: usize) -> bool {
    let (ca, cb) = (picture.rgb[a], picture.rgb[b]);
    if (0..3).any(|c| (ca[c] as i32 - cb[c] as i32).abs() > COLOUR_STEP) {
        return true;
    }
    if let Some(depth) = &picture.depth {
        let (da, db) = (depth[a], depth[b]);
        match (da.is_finite(), db.is_finite()) {
            (true, true) => {
                if (da - db).abs() > DEPTH_JUMP * da.min(db) {
                    return true;
                }
            }
            (false, false) => {}
            _ => return true,
        }
    }
    if let Some(normals) = &picture.normals {
        let (na, nb) = (normals[a], normals[b]);
        let dot = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2];
        let hit = |n: [f32; 3]| n != [0.0; 3];
        if hit(na) && hit(nb) && dot < NORMAL_COS {
            return true;
        }
    }
    false
}
