//! Shared by the walk tests (tests/raycast.rs, tests/thin_walk.rs).

use floorscan_core::raycast::{CellIndex, CellWalk};

/// Runs `walk` split at the boundaries of `tile`-sized boxes, as tiled storage does, and
/// returns the cells it visits in order (checking each run's count and end cell).
pub fn collect_in_boxes(mut walk: impl CellWalk, tile: i32) -> Vec<CellIndex> {
    let mut out = Vec::new();
    loop {
        let c = walk.cell();
        let min = CellIndex::new(c.x.div_euclid(tile) * tile, c.y.div_euclid(tile) * tile);
        let max = CellIndex::new(min.x + tile, min.y + tile);
        let stop = walk.last_cell_inside(min, max);
        let w = tile as usize;
        let local = ((c.y - min.y) as usize) * w + (c.x - min.x) as usize;
        let before = out.len();
        let n = walk.run_to(stop, local, w, |i| {
            assert!(i < w * w, "index left the box");
            out.push(CellIndex::new(
                min.x + (i % w) as i32,
                min.y + (i / w) as i32,
            ));
        });
        assert_eq!(n as usize, out.len() - before, "visited count");
        assert_eq!(walk.cell(), stop);
        if walk.is_at_end() {
            return out;
        }
        walk.step();
    }
}
