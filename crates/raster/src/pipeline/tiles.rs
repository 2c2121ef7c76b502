//! Screen tiles and safe, disjoint per-tile views of row-major output buffers.

/// Tile edge in pixels.
pub(crate) const TILE: usize = 64;

/// One tile's rectangle in pixels.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TileRect {
    pub x0: usize,
    pub y0: usize,
    pub w: usize,
    pub h: usize,
}

/// Number of tiles across and down.
pub(crate) fn tile_counts(width: usize, height: usize) -> (usize, usize) {
    (width.div_ceil(TILE), height.div_ceil(TILE))
}

/// The tiles in row-major order.
pub(crate) fn tile_rects(width: usize, height: usize) -> Vec<TileRect> {
    let (tx, ty) = tile_counts(width, height);
    (0..tx * ty)
        .map(|i| {
            let (x0, y0) = ((i % tx) * TILE, (i / tx) * TILE);
            TileRect {
                x0,
                y0,
                w: TILE.min(width - x0),
                h: TILE.min(height - y0),
            }
        })
        .collect()
}

/// Splits a row-major `(height, width, channels)` buffer into per-tile lists of row slices,
/// so each tile can be written by a different thread without `unsafe`.
pub(crate) fn split_rows<T>(
    buf: &mut [T],
    width: usize,
    height: usize,
    channels: usize,
) -> Vec<Vec<&mut [T]>> {
    let (tiles_x, tiles_y) = tile_counts(width, height);
    let mut out: Vec<Vec<&mut [T]>> = (0..tiles_x * tiles_y)
        .map(|_| Vec::with_capacity(TILE))
        .collect();
    for (y, row) in buf.chunks_mut(width * channels).enumerate() {
        let ty = y / TILE;
        for (tx, seg) in row.chunks_mut(TILE * channels).enumerate() {
            out[ty * tiles_x + tx].push(seg);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_cover_the_buffer_once() {
        let (w, h) = (130, 70);
        let mut buf = vec![0u32; w * h * 2];
        let tiles = tile_rects(w, h);
        let mut rows = split_rows(&mut buf, w, h, 2);
        assert_eq!(tiles.len(), rows.len());
        for (t, r) in tiles.iter().zip(rows.iter_mut()) {
            assert_eq!(r.len(), t.h);
            for row in r.iter_mut() {
                assert_eq!(row.len(), t.w * 2);
                row.iter_mut().for_each(|v| *v += 1);
            }
        }
        assert!(buf.iter().all(|&v| v == 1));
    }
}
