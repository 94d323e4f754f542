//! The last raster cell a lookup landed in, with what it found there: pixels next to each other
//! mostly land in the same cell of the scene's coverings or of the light map, and then skip the
//! range checks, the flooring and the loads. The answer is the same either way: a point is in
//! the remembered cell exactly when the floor of its raster coordinates is that cell.

/// What a lookup found in raster cell (`x0`, `y0`) (integers held as floats).
#[derive(Debug, Clone, Copy)]
pub struct CellMemo<T> {
    x0: f64,
    y0: f64,
    value: T,
}

impl<T: Copy + Default> Default for CellMemo<T> {
    fn default() -> Self {
        // NaN: no coordinate compares inside, so the first lookup always misses.
        CellMemo {
            x0: f64::NAN,
            y0: f64::NAN,
            value: T::default(),
        }
    }
}

impl<T: Copy> CellMemo<T> {
    /// The value remembered for the cell holding raster coordinates (gx, gy), if it is the
    /// remembered cell (floor(gx), floor(gy)) = (x0, y0): exact, since x0 + 1 is exact).
    #[inline(always)]
    pub fn get(&self, gx: f64, gy: f64) -> Option<T> {
        let inside = gx >= self.x0 && gx < self.x0 + 1.0 && gy >= self.y0 && gy < self.y0 + 1.0;
        inside.then_some(self.value)
    }

    /// Remembers `value` for cell (ix, iy) (|ix|, |iy| < 2^52).
    #[inline(always)]
    pub fn set(&mut self, ix: i64, iy: i64, value: T) {
        (self.x0, self.y0, self.value) = (ix as f64, iy as f64, value);
    }

    /// The remembered cell's corner (x0, y0).
    #[inline(always)]
    pub fn corner(&self) -> (f64, f64) {
        (self.x0, self.y0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{fast_floor, Rng};

    /// The float just below `x`.
    fn below(x: f64) -> f64 {
        if x > 0.0 {
            f64::from_bits(x.to_bits() - 1)
        } else if x < 0.0 {
            f64::from_bits(x.to_bits() + 1)
        } else {
            -f64::MIN_POSITIVE
        }
    }

    #[test]
    fn a_point_hits_exactly_when_it_floors_to_the_remembered_cell() {
        let mut memo = CellMemo::<u32>::default();
        assert_eq!(memo.get(0.5, 0.5), None);
        let mut rng = Rng::new(9);
        for i in 0..100_000u32 {
            let (gx, gy) = (40.0 * rng.uniform() - 20.0, 40.0 * rng.uniform() - 20.0);
            // Cell boundaries and the floats next to them too.
            let (gx, gy) = match i % 4 {
                0 => (gx.round(), gy),
                1 => (below(gx.round()), gy.round()),
                _ => (gx, gy),
            };
            let (ix, iy) = (fast_floor(gx), fast_floor(gy));
            let (x0, y0) = memo.corner();
            let same = ix as f64 == x0 && iy as f64 == y0;
            assert_eq!(
                memo.get(gx, gy).is_some(),
                same,
                "{gx} {gy} vs cell {x0} {y0}"
            );
            if i % 3 == 0 {
                memo.set(ix, iy, i);
                assert_eq!(memo.get(gx, gy), Some(i));
            }
        }
    }
}
