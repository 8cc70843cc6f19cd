//! The mesh of a height field's solid, exactly as the exact tracers intersect it, for a block
//! of the grid: the `triangles` surface here, the `boxes` surface in `box_mesh.rs`.
//!
//! The solid (see relief-trace's `CellGrid`) is the surface over the grid's footprint, closed
//! by vertical walls under the grid's outer border and around holes, down to the field's lowest
//! sample, where a flat bottom closes it. A block is meshed with the parts of all of these
//! inside it, and every vertex is computed from its grid coordinates and height alone, so
//! blocks meshed separately share their edges bit for bit: drawn together they leave no crack
//! and cover no pixel twice (the rasterizer's fill rule).

use crate::box_mesh::box_mesh;
use crate::mesh_builder::MeshBuilder;
use crate::{IndexedMesh, MeshError};
use relief_core::{DVec3, HeightField, SampleRegion, Surface};

/// The mesh of `field`'s solid for `surface` over `region` (in samples), in world coordinates.
///
/// - [`Surface::Triangles`]: vertices at the samples; the squares between the region's samples
///   are meshed (so regions that overlap by one sample, like the hybrid renderer's cells, tile
///   the grid), each split along the diagonal with the smaller height sum, none over a hole;
///   walls under the grid's border sample lines and around the squares over holes; the bottom
///   under every square.
/// - [`Surface::Boxes`]: the region's texels, each a flat top over its footprint, the vertical
///   faces between neighbouring texels of different heights (a face belongs to the higher
///   texel), walls under the grid's outer texel edges and around holes, and the bottom.
///
/// Walls and bottom reach the field's lowest sample, as the tracers have them. Adjacent
/// regions' meshes join without cracks. Every triangle is wound counter-clockwise seen from
/// outside the solid, so a camera outside it may draw with [`crate::Culling::BackFaces`].
/// Fails when the region reaches outside the grid.
///
/// ```
/// use relief_core::{GridGeometry, HeightField, SampleRegion, Surface};
/// use relief_mesh::height_field_mesh;
/// let field = HeightField::new(3, 3, vec![0.0, 1.0, 0.0, 1.0, 2.0, 1.0, 0.0, 1.0, 0.0],
///     GridGeometry::unit()).unwrap();
/// let mesh = height_field_mesh(&field, Surface::Triangles, SampleRegion::whole(3, 3)).unwrap();
/// // 8 surface triangles; 8 wall quads, each a triangle since one of its samples is the
/// // lowest (its foot is itself); a bottom fan of 8.
/// assert_eq!(mesh.triangle_count(), 8 + 8 + 8);
/// ```
pub fn height_field_mesh(
    field: &HeightField,
    surface: Surface,
    region: SampleRegion,
) -> Result<IndexedMesh, MeshError> {
    let (w, h) = (field.width(), field.height());
    if region.col1 > w || region.row1 > h {
        return Err(MeshError::Parameter {
            name: "sample region",
            reason: format!(
                "columns {}..{} and rows {}..{} reach outside the {w}x{h} grid",
                region.col0, region.col1, region.row0, region.row1
            ),
        });
    }
    if region.len() as u64 * 16 >= u32::MAX as u64 {
        return Err(MeshError::Limits(format!(
            "a region of {} samples is too large for one mesh's u32 ids",
            region.len()
        )));
    }
    match surface {
        Surface::Triangles => Ok(triangle_mesh(field, region)),
        Surface::Boxes => Ok(box_mesh(field, region)),
    }
}

/// The `triangles` solid over the squares between `region`'s samples.
fn triangle_mesh(field: &HeightField, region: SampleRegion) -> IndexedMesh {
    let mut mesh = MeshBuilder::default();
    if region.col1 < region.col0 + 2 || region.row1 < region.row0 + 2 {
        return mesh.finish();
    }
    let (w, h) = (field.width(), field.height());
    let (cells_x, cells_y) = (w - 1, h - 1);
    let geometry = field.geometry();
    let z_min = field.min_sample() as f64;
    let (rw, rh) = (region.col1 - region.col0, region.row1 - region.row0);
    let at = |col: usize, row: usize, z: f64| {
        geometry.point_to_world(DVec3::new(col as f64 + 0.5, row as f64 + 0.5, z))
    };
    // The region's samples on top; their feet at the lowest sample are made when a wall or
    // the bottom needs them (the sample itself when it is the lowest).
    let mut top = vec![0u32; rw * rh];
    let mut feet = vec![u32::MAX; rw * rh];
    for row in region.row0..region.row1 {
        for col in region.col0..region.col1 {
            let k = (col - region.col0) + (row - region.row0) * rw;
            top[k] = mesh.vertex(at(col, row, field.sample(col, row) as f64));
        }
    }
    let mut foot = |mesh: &mut MeshBuilder, k: usize| {
        if feet[k] == u32::MAX {
            let (col, row) = (region.col0 + k % rw, region.row0 + k / rw);
            let z = field.sample(col, row) as f64;
            feet[k] = if z == z_min { top[k] } else { mesh.vertex(at(col, row, z_min)) };
        }
        feet[k]
    };
    let local = |col: usize, row: usize| (col - region.col0) + (row - region.row0) * rw;
    let empty = |cx: usize, cy: usize| {
        field.is_hole(cx, cy)
            || field.is_hole(cx + 1, cy)
            || field.is_hole(cx, cy + 1)
            || field.is_hole(cx + 1, cy + 1)
    };
    let (cx0, cy0, cx1, cy1) = (region.col0, region.row0, region.col1 - 1, region.row1 - 1);
    let mut any_empty = false;
    for cy in cy0..cy1 {
        for cx in cx0..cx1 {
            if empty(cx, cy) {
                any_empty = true;
                continue;
            }
            let [v00, v10, v01, v11] =
                [local(cx, cy), local(cx + 1, cy), local(cx, cy + 1), local(cx + 1, cy + 1)];
            let (a, b) = (field.sample(cx, cy) as f64, field.sample(cx + 1, cy) as f64);
            let (c, d) = (field.sample(cx, cy + 1) as f64, field.sample(cx + 1, cy + 1) as f64);
            if relief_core::splits_along_ad(a, b, c, d) {
                mesh.triangle(top[v00], top[v10], top[v11]);
                mesh.triangle(top[v00], top[v11], top[v01]);
            } else {
                mesh.triangle(top[v00], top[v10], top[v01]);
                mesh.triangle(top[v10], top[v11], top[v01]);
            }
            // Walls on the sides facing the grid's border or an empty square, each from the
            // side's two samples down to their feet, seen from outside.
            let open = |dx: isize, dy: isize| {
                let (nx, ny) = (cx as isize + dx, cy as isize + dy);
                nx < 0
                    || ny < 0
                    || nx >= cells_x as isize
                    || ny >= cells_y as isize
                    || empty(nx as usize, ny as usize)
            };
            for (side, p, q) in
                [((0, -1), v00, v10), ((1, 0), v10, v11), ((0, 1), v11, v01), ((-1, 0), v01, v00)]
            {
                if open(side.0, side.1) {
                    let (fp, fq) = (foot(&mut mesh, p), foot(&mut mesh, q));
                    mesh.quad(top[q], top[p], fp, fq);
                }
            }
        }
    }
    // The bottom: without holes one fan from the block's centre to its border's feet (its
    // edges are the border's unit segments, as the walls' and the neighbours' are), else a
    // quad under every solid square.
    if any_empty {
        for cy in cy0..cy1 {
            for cx in cx0..cx1 {
                if !empty(cx, cy) {
                    let mut f = |col, row| foot(&mut mesh, local(col, row));
                    let (a, b) = (f(cx, cy), f(cx + 1, cy));
                    let (c, d) = (f(cx + 1, cy + 1), f(cx, cy + 1));
                    mesh.quad(d, c, b, a);
                }
            }
        }
    } else {
        let centre = geometry.point_to_world(DVec3::new(
            (cx0 + cx1) as f64 / 2.0 + 0.5,
            (cy0 + cy1) as f64 / 2.0 + 0.5,
            z_min,
        ));
        let centre = mesh.vertex(centre);
        let mut ring = Vec::with_capacity(2 * (rw + rh));
        ring.extend((cx0..cx1).map(|cx| (cx, cy0)));
        ring.extend((cy0..cy1).map(|cy| (cx1, cy)));
        ring.extend((cx0 + 1..=cx1).rev().map(|cx| (cx, cy1)));
        ring.extend((cy0 + 1..=cy1).rev().map(|cy| (cx0, cy)));
        let ring: Vec<u32> =
            ring.into_iter().map(|(cx, cy)| foot(&mut mesh, local(cx, cy))).collect();
        for k in 0..ring.len() {
            mesh.triangle(centre, ring[(k + 1) % ring.len()], ring[k]);
        }
    }
    mesh.finish()
}
