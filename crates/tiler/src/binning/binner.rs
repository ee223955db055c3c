//! The binner: adds each primitive to the polygon list of every tile where it may cover a
//! sample.
//!
//! The test is exact against each tile's sample hull, not just the bounding box: for every
//! tile the primitive's bounding box meets, the three edge functions are evaluated at the
//! extreme sample positions of the tile (∩ the primitive's box); a tile where any edge is
//! negative at its extreme is skipped. A triangle crossing a tile's corner therefore lands
//! only in the tiles it enters.
//!
//! Binning runs in parallel over bands of tile rows; each band walks the new primitives in
//! submission order and appends to its own tiles' lists, so every list stays in submission
//! order whatever the thread count.

use rayon::prelude::*;

use super::frame_data::{FrameData, POLYGON_LIST_ENTRY_BYTES, Primitive};
use crate::binning::grid::TileGrid;
use crate::raster::PixelRect;
use crate::raster::fixed::SubPixel;
use crate::raster::samples::SampleLocations;

/// Bins the primitives appended since the last call, over `bands` bands of tile rows;
/// returns the entries added.
pub fn bin(frame: &mut FrameData, samples: &SampleLocations, bands: usize) -> u64 {
    let grid = frame.grid;
    let from = frame.binned;
    frame.binned = frame.primitives.len();
    frame.unbinned_bound = 0;
    let primitives = &frame.primitives[from..];
    if primitives.is_empty() {
        return 0;
    }
    let rows_per_band = (grid.tiles_y as usize).div_ceil(bands.max(1)).max(1);
    let hull = samples.hull();
    let entries: u64 = frame
        .lists
        .par_chunks_mut(grid.tiles_x as usize * rows_per_band)
        .enumerate()
        .map(|(band, lists)| {
            let row0 = (band * rows_per_band) as u32;
            let row1 = row0 + (lists.len() / grid.tiles_x as usize) as u32;
            let mut added = 0u64;
            for (i, primitive) in primitives.iter().enumerate() {
                let index = (from + i) as u32;
                let (tx0, ty0, tx1, ty1) = grid.tiles_meeting(&primitive.bbox);
                if ty1 < row0 || ty0 >= row1 {
                    continue;
                }
                let single = tx0 == tx1 && ty0 == ty1;
                for ty in ty0.max(row0)..=ty1.min(row1 - 1) {
                    for tx in tx0..=tx1 {
                        if single || covers_tile(primitive, &grid, tx, ty, hull) {
                            lists[((ty - row0) * grid.tiles_x + tx) as usize].push(index);
                            added += 1;
                        }
                    }
                }
            }
            added
        })
        .sum();
    frame.bytes.polygon_list_entries += entries * POLYGON_LIST_ENTRY_BYTES;
    entries
}

/// Whether some sample position of tile `(tx, ty)` within the primitive's box is on the inner
/// side of all three edges, edge by edge.
fn covers_tile(p: &Primitive, grid: &TileGrid, tx: u32, ty: u32, hull: (i32, i32, i32, i32)) -> bool {
    let r: PixelRect = grid.tile_rect(tx, ty).intersect(&p.bbox);
    if r.is_empty() {
        return false;
    }
    let (hx0, hy0, hx1, hy1) = hull;
    let x0 = SubPixel::pixel_corner(r.x0) + hx0 as i64;
    let y0 = SubPixel::pixel_corner(r.y0) + hy0 as i64;
    let x1 = SubPixel::pixel_corner(r.x1 - 1) + hx1 as i64;
    let y1 = SubPixel::pixel_corner(r.y1 - 1) + hy1 as i64;
    p.edges().iter().all(|e| e.max_over(x0, y0, x1, y1) >= 0)
}
