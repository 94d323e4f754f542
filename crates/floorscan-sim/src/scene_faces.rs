//! A scene's grid items for the ray walk: side faces four at a time (one ray met with four
//! faces in SSE2 lanes, the same bits as one by one) and each cell's items as runs of such
//! quads between solids' caps.

use super::*;

/// Four side faces' end points, lane by lane (padding lanes NaN: never met).
#[derive(Debug, Clone, Copy)]
pub(super) struct FaceQuad {
    ax: [f64; 4],
    ay: [f64; 4],
    bx: [f64; 4],
    by: [f64; 4],
}

impl FaceQuad {
    /// The first four of `faces` (NaN lanes after the last).
    pub(super) fn of(faces: &[SideFace]) -> FaceQuad {
        let mut q = FaceQuad {
            ax: [f64::NAN; 4],
            ay: [f64::NAN; 4],
            bx: [f64::NAN; 4],
            by: [f64::NAN; 4],
        };
        for (lane, f) in faces.iter().take(4).enumerate() {
            (q.ax[lane], q.ay[lane]) = (f.a.x, f.a.y);
            (q.bx[lane], q.by[lane]) = (f.b.x, f.b.y);
        }
        q
    }

    /// [`ray_segment`] of the ground track o + t d with the four faces: a bit per lane
    /// whose face the track meets, and each lane's (t, s) (meaningful where met). Each
    /// lane does ray_segment's operations in its order (IEEE operations, no fused
    /// multiply-add), so the same bits.
    #[inline(always)]
    pub(super) fn ray(&self, o: Point2, d: Point2) -> (u32, [f64; 4], [f64; 4]) {
        #[cfg(target_arch = "x86_64")]
        {
            // SSE2 is part of x86-64.
            self.ray_sse2(o, d)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self.ray_portable(o, d)
        }
    }

    /// [`Self::ray`] one lane at a time.
    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    pub(super) fn ray_portable(&self, o: Point2, d: Point2) -> (u32, [f64; 4], [f64; 4]) {
        let mut met = 0u32;
        let (mut ts, mut ss) = ([0.0; 4], [0.0; 4]);
        for lane in 0..4 {
            let (a, b) = (
                Point2::new(self.ax[lane], self.ay[lane]),
                Point2::new(self.bx[lane], self.by[lane]),
            );
            if let Some((t, s)) = ray_segment(o, d, a, b) {
                met |= 1 << lane;
                (ts[lane], ss[lane]) = (t, s);
            }
        }
        (met, ts, ss)
    }

    /// [`Self::ray`] in two SSE2 registers of two lanes.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn ray_sse2(&self, o: Point2, d: Point2) -> (u32, [f64; 4], [f64; 4]) {
        use std::arch::x86_64::*;
        // SAFETY (every block below): SSE2 is part of x86-64; the loads and stores are of
        // [f64; 4] arrays at offsets 0 and 2 (two f64 each, unaligned).
        unsafe {
            let (ox, oy) = (_mm_set1_pd(o.x), _mm_set1_pd(o.y));
            let (dx, dy) = (_mm_set1_pd(d.x), _mm_set1_pd(d.y));
            let sign = _mm_set1_pd(-0.0);
            let (zero, tiny) = (_mm_setzero_pd(), _mm_set1_pd(1e-300));
            let mut met = 0u32;
            let (mut ts, mut ss) = ([0.0f64; 4], [0.0f64; 4]);
            let mut parts = [(zero, zero, zero); 2];
            for (half, part) in parts.iter_mut().enumerate() {
                let at = |v: &[f64; 4]| _mm_loadu_pd(v.as_ptr().add(2 * half));
                let (ax, ay, bx, by) = (at(&self.ax), at(&self.ay), at(&self.bx), at(&self.by));
                let (ex, ey) = (_mm_sub_pd(bx, ax), _mm_sub_pd(by, ay));
                let denom = _mm_sub_pd(_mm_mul_pd(dx, ey), _mm_mul_pd(dy, ex));
                let (wx, wy) = (_mm_sub_pd(ax, ox), _mm_sub_pd(ay, oy));
                let tn = _mm_sub_pd(_mm_mul_pd(wx, ey), _mm_mul_pd(wy, ex));
                let sn = _mm_sub_pd(_mm_mul_pd(wx, dy), _mm_mul_pd(wy, dx));
                // Negated (the sign bit flipped) where denom < 0.
                let flip = _mm_and_pd(_mm_cmplt_pd(denom, zero), sign);
                let (tn, sn, dn) = (
                    _mm_xor_pd(tn, flip),
                    _mm_xor_pd(sn, flip),
                    _mm_xor_pd(denom, flip),
                );
                let ok = _mm_and_pd(
                    _mm_and_pd(_mm_cmpgt_pd(dn, tiny), _mm_cmpge_pd(tn, zero)),
                    _mm_and_pd(_mm_cmpge_pd(sn, zero), _mm_cmple_pd(sn, dn)),
                );
                met |= (_mm_movemask_pd(ok) as u32) << (2 * half);
                *part = (tn, sn, dn);
            }
            if met != 0 {
                let one = _mm_set1_pd(1.0);
                for (half, &(tn, sn, dn)) in parts.iter().enumerate() {
                    let inv = _mm_div_pd(one, dn);
                    _mm_storeu_pd(ts.as_mut_ptr().add(2 * half), _mm_mul_pd(tn, inv));
                    _mm_storeu_pd(ss.as_mut_ptr().add(2 * half), _mm_mul_pd(sn, inv));
                }
            }
            (met, ts, ss)
        }
    }
}

/// A run of a grid cell's items: up to four side faces in a row (`ids`; the quad's lanes
/// beyond them NaN, never met), or the cap of a solid.
#[derive(Debug, Clone, Copy)]
pub(super) enum CellRun {
    Faces { quad: FaceQuad, ids: [u32; 4] },
    Cap(u32),
}

/// Each grid cell's items as runs, in the cell's order (faces grouped four by four between
/// caps).
#[derive(Debug, Clone)]
pub(super) struct CellRuns {
    offsets: Vec<u32>,
    runs: Vec<CellRun>,
}

impl CellRuns {
    pub(super) fn build(cells: &CellLists, sides: &[SideFace], cell_count: usize) -> CellRuns {
        let mut offsets = Vec::with_capacity(cell_count + 1);
        let mut runs = Vec::new();
        offsets.push(0);
        for cell in 0..cell_count {
            let mut faces: Vec<u32> = Vec::with_capacity(4);
            let flush = |faces: &mut Vec<u32>, runs: &mut Vec<CellRun>| {
                if !faces.is_empty() {
                    let group: Vec<SideFace> = faces.iter().map(|&id| sides[id as usize]).collect();
                    let mut ids = [u32::MAX; 4];
                    ids[..faces.len()].copy_from_slice(faces);
                    runs.push(CellRun::Faces {
                        quad: FaceQuad::of(&group),
                        ids,
                    });
                    faces.clear();
                }
            };
            for &item in cells.get(cell) {
                if item & CAP_BIT == 0 {
                    faces.push(item);
                    if faces.len() == 4 {
                        flush(&mut faces, &mut runs);
                    }
                } else {
                    flush(&mut faces, &mut runs);
                    runs.push(CellRun::Cap(item & !CAP_BIT));
                }
            }
            flush(&mut faces, &mut runs);
            offsets.push(runs.len() as u32);
        }
        CellRuns { offsets, runs }
    }

    #[inline]
    pub(super) fn get(&self, cell: usize) -> &[CellRun] {
        &self.runs[self.offsets[cell] as usize..self.offsets[cell + 1] as usize]
    }
}

/// Grid items: side faces are stored as their index, caps with this bit set.
pub(super) const CAP_BIT: u32 = 1 << 31;
