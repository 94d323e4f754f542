//! Illumination of the floor, precomputed on a raster (ambient light plus ceiling lights, each
//! falling off as a point source: (h^2 / (h^2 + d^2))^1.5), looked up bilinearly.
//! No shadows: rooms are lit by many lights and by indirect light, and the world's baseboards
//! already darken the foot of the walls.

use floorscan_core::Point2;

use crate::cell_memo::CellMemo;
use crate::geometry::Aabb;
use crate::noise_lanes::NoiseKernel;
use crate::rng::fast_floor;
use crate::world::Lighting;

/// Raster resolution of the light map [m].
pub const LIGHT_CELL_M: f64 = 0.1;
/// Most (cell, light) pairs the light map evaluates (a bound on its build time).
pub const MAX_LIGHT_EVALUATIONS: f64 = 4.0e8;

#[derive(Debug, Clone)]
pub struct LightMap {
    origin: Point2,
    nx: usize,
    inv_cell: f64,
    /// (nx - 1, ny - 1) as floats: the raster's extent in cells (a conversion per lookup
    /// otherwise).
    extent: (f64, f64),
    values: Vec<f32>,
    ambient: f32,
    /// Median illumination over the raster: the exposure reference.
    pub typical: f32,
}

impl LightMap {
    /// Illumination over `bounds`; the exposure reference is the median over `reference`.
    pub fn new(lighting: &Lighting, bounds: Aabb, reference: Aabb) -> LightMap {
        let mut cell = LIGHT_CELL_M;
        let (w, h) = (bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y);
        // At most 4 M cells and 4e8 light evaluations: a huge world, or one with a light grid
        // of thousands of lights, gets a coarser (still smooth) light map, never minutes of work.
        let lights = lighting.lights.len().max(1) as f64;
        while (w / cell) * (h / cell) > 4.0e6
            || (w / cell) * (h / cell) * lights > MAX_LIGHT_EVALUATIONS
        {
            cell *= 2.0;
        }
        let nx = (w / cell).ceil() as usize + 2;
        let ny = (h / cell).ceil() as usize + 2;
        let mut values = vec![lighting.ambient as f32; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                let p = Point2::new(
                    bounds.min.x + i as f64 * cell,
                    bounds.min.y + j as f64 * cell,
                );
                values[j * nx + i] += illuminance(lighting, p) as f32;
            }
        }
        let mut sorted: Vec<f32> = (0..nx * ny)
            .filter(|k| {
                let p = Point2::new(
                    bounds.min.x + (k % nx) as f64 * cell,
                    bounds.min.y + (k / nx) as f64 * cell,
                );
                reference.contains(p)
            })
            .map(|k| values[k])
            .collect();
        if sorted.is_empty() {
            sorted.push(lighting.ambient as f32);
        }
        sorted.sort_by(f32::total_cmp);
        let typical = sorted[sorted.len() / 2].max(1e-6);
        LightMap {
            origin: bounds.min,
            nx,
            inv_cell: 1.0 / cell,
            extent: ((nx - 1) as f64, (ny - 1) as f64),
            values,
            ambient: lighting.ambient as f32,
            typical,
        }
    }

    /// Floor illuminance at `p` (ambient outside the raster).
    pub fn at(&self, p: Point2) -> f32 {
        self.at_cached(p, &mut CellMemo::default())
    }

    /// [`Self::at`], remembering the corner values of the last cell in `memo`.
    #[inline(always)]
    pub fn at_cached(&self, p: Point2, memo: &mut CellMemo<[f32; 4]>) -> f32 {
        let gx = (p.x - self.origin.x) * self.inv_cell;
        let gy = (p.y - self.origin.y) * self.inv_cell;
        let corners = match memo.get(gx, gy) {
            Some(corners) => corners,
            None => match self.enter(gx, gy, memo) {
                Some(corners) => corners,
                None => return self.ambient,
            },
        };
        // The fractions (gx - floor(gx)), (gy - floor(gy)), with the remembered floors.
        let (x0, y0) = memo.corner();
        let (fx, fy) = ((gx - x0) as f32, (gy - y0) as f32);
        let [t0, t1, b0, b1] = corners;
        let top = t0 + (t1 - t0) * fx;
        let bottom = b0 + (b1 - b0) * fx;
        top + (bottom - top) * fy
    }

    /// The corner values of the cell holding raster coordinates (gx, gy), remembered in `memo`;
    /// None outside the raster (out of line: the rarer path).
    #[inline(never)]
    fn enter(&self, gx: f64, gy: f64, memo: &mut CellMemo<[f32; 4]>) -> Option<[f32; 4]> {
        if !(gx >= 0.0 && gy >= 0.0 && gx < self.extent.0 && gy < self.extent.1) {
            return None;
        }
        // In range (checked above), so the fast floor is exact and non-negative.
        let (i, j) = (fast_floor(gx), fast_floor(gy));
        let k = j as usize * self.nx + i as usize;
        // The cell's two rows of two corners (one bounds check each).
        let (t, b) = (
            &self.values[k..k + 2],
            &self.values[k + self.nx..k + self.nx + 2],
        );
        let corners = [t[0], t[1], b[0], b[1]];
        memo.set(i, j, corners);
        Some(corners)
    }
}

/// Light requests and their values, for many points at once (see [`LightMap::evaluate`]):
/// [`LightBatch::start`] with room for the requests to come, push points, evaluate, read the
/// values by the indices `push` returned.
#[derive(Debug, Clone, Default)]
pub struct LightBatch {
    x: Vec<f64>,
    y: Vec<f64>,
    n: usize,
    values: Vec<f32>,
}

impl LightBatch {
    /// Forgets the requests and makes room for `room` of them (at least).
    #[inline]
    pub fn start(&mut self, room: usize) {
        if self.x.len() < room {
            self.x.resize(room, 0.0);
            self.y.resize(room, 0.0);
            self.values.resize(room, 0.0);
        }
        self.n = 0;
    }

    /// Asks for the light at `p`; returns the index of its value.
    #[inline(always)]
    pub fn push(&mut self, p: Point2) -> u32 {
        let i = self.n;
        if i >= self.x.len().min(self.y.len()) {
            self.start_more();
        }
        self.x[i] = p.x;
        self.y[i] = p.y;
        self.n = i + 1;
        i as u32
    }

    #[cold]
    #[inline(never)]
    fn start_more(&mut self) {
        let n = self.n;
        self.start(2 * n + 16);
        self.n = n;
    }

    /// How many points were asked for since the last start.
    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The value of request `i` (after [`LightMap::evaluate`]; 0 for an index never pushed).
    #[inline(always)]
    pub fn value(&self, i: u32) -> f32 {
        self.values.get(i as usize).copied().unwrap_or(0.0)
    }
}

impl LightMap {
    /// [`Self::at`] of every point requested in `batch`, four points per step in AVX2 lanes
    /// (the corners gathered) where `kernel` says and the CPU has them: the same bits.
    pub fn evaluate(&self, kernel: NoiseKernel, batch: &mut LightBatch) {
        let n = batch.n;
        if batch.values.len() < n {
            batch.values.resize(n, 0.0);
        }
        let (x, y, out) = (&batch.x[..n], &batch.y[..n], &mut batch.values[..n]);
        let done = match kernel {
            #[cfg(target_arch = "x86_64")]
            NoiseKernel::Avx2 if std::arch::is_x86_feature_detected!("avx2") => {
                let chunks = n / 4;
                // SAFETY: AVX2 is present (checked above); x, y and out hold n >= chunks * 4
                // elements; the gathers read only cells the scalar lookup would (see the
                // kernel).
                unsafe { x86::light_avx2(self, x, y, out, chunks) };
                chunks * 4
            }
            _ => 0,
        };
        for i in done..n {
            out[i] = self.at(Point2::new(x[i], y[i]));
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::LightMap;
    use crate::noise_lanes::x86::floor4;

    /// [`LightMap::at`] of `chunks` groups of four points.
    ///
    /// # Safety
    /// The CPU must have AVX2; `x`, `y` and `out` must hold at least `chunks * 4` elements.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn light_avx2(
        map: &LightMap,
        x: &[f64],
        y: &[f64],
        out: &mut [f32],
        chunks: usize,
    ) {
        let (ox, oy) = (_mm256_set1_pd(map.origin.x), _mm256_set1_pd(map.origin.y));
        let inv = _mm256_set1_pd(map.inv_cell);
        let (ex, ey) = (_mm256_set1_pd(map.extent.0), _mm256_set1_pd(map.extent.1));
        let zero = _mm256_setzero_pd();
        // The raster holds nx * ny <= a few million cells: row offsets fit an i32.
        let nx = _mm_set1_epi32(map.nx as i32);
        let ambient = _mm_set1_ps(map.ambient);
        let low_halves = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
        let values = map.values.as_ptr();
        for c in 0..chunks {
            let i = c * 4;
            // SAFETY: i + 4 <= chunks * 4, within x and y (the caller's contract).
            let (xv, yv) = unsafe {
                (
                    _mm256_loadu_pd(x.as_ptr().add(i)),
                    _mm256_loadu_pd(y.as_ptr().add(i)),
                )
            };
            let gx = _mm256_mul_pd(_mm256_sub_pd(xv, ox), inv);
            let gy = _mm256_mul_pd(_mm256_sub_pd(yv, oy), inv);
            // In the raster, as the scalar's test (false for NaN).
            let inside = _mm256_and_pd(
                _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_GE_OQ>(gx, zero),
                    _mm256_cmp_pd::<_CMP_GE_OQ>(gy, zero),
                ),
                _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_LT_OQ>(gx, ex),
                    _mm256_cmp_pd::<_CMP_LT_OQ>(gy, ey),
                ),
            );
            let inside32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
                _mm256_castpd_si256(inside),
                low_halves,
            ));
            let (fx0, ix) = floor4(gx);
            let (fy0, iy) = floor4(gy);
            // The cell's first corner; cell 0 outside the raster (its value is not used).
            let k = _mm_and_si128(_mm_add_epi32(_mm_mullo_epi32(iy, nx), ix), inside32);
            let k_below = _mm_add_epi32(k, nx);
            // SAFETY: inside the raster 0 <= i <= nx - 2 and 0 <= j <= ny - 2 (gx < nx - 1,
            // gy < ny - 1, floors exact there), so k, k + 1, k + nx and k + nx + 1 index
            // values (nx * ny long), as the scalar lookup's slices do; outside, k = 0 and the
            // same four offsets are below nx + 2 <= nx * ny (nx, ny >= 2).
            let (t0, t1, b0, b1) = unsafe {
                (
                    _mm_i32gather_ps::<4>(values, k),
                    _mm_i32gather_ps::<4>(values.add(1), k),
                    _mm_i32gather_ps::<4>(values, k_below),
                    _mm_i32gather_ps::<4>(values.add(1), k_below),
                )
            };
            let fx = _mm256_cvtpd_ps(_mm256_sub_pd(gx, fx0));
            let fy = _mm256_cvtpd_ps(_mm256_sub_pd(gy, fy0));
            let top = _mm_add_ps(t0, _mm_mul_ps(_mm_sub_ps(t1, t0), fx));
            let bottom = _mm_add_ps(b0, _mm_mul_ps(_mm_sub_ps(b1, b0), fx));
            let v = _mm_add_ps(top, _mm_mul_ps(_mm_sub_ps(bottom, top), fy));
            let v = _mm_blendv_ps(ambient, v, _mm_castsi128_ps(inside32));
            // SAFETY: i + 4 <= chunks * 4, within out.
            unsafe { _mm_storeu_ps(out.as_mut_ptr().add(i), v) };
        }
    }
}

/// Direct illuminance on the floor at `p` from the lights (no ambient).
pub fn illuminance(lighting: &Lighting, p: Point2) -> f64 {
    lighting
        .lights
        .iter()
        .map(|l| {
            let d2 = (p.x - l.position.x).powi(2) + (p.y - l.position.y).powi(2);
            let h2 = l.height_m * l.height_m;
            let r = h2 / (h2 + d2);
            l.power * r * r.sqrt()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Light;

    #[test]
    fn light_map_matches_the_point_source_formula() {
        let lighting = Lighting {
            ambient: 0.3,
            lights: vec![Light {
                position: Point2::new(2.0, 1.0),
                height_m: 2.5,
                power: 0.8,
            }],
            exposure: 1.0,
            exposure_jitter: 0.0,
            wall_factor: 0.7,
            ceiling_brightness: 0.5,
            contact_shadow: Default::default(),
        };
        let b = Aabb {
            min: Point2::new(0.0, 0.0),
            max: Point2::new(5.0, 4.0),
        };
        let m = LightMap::new(&lighting, b, b);
        // Right below the light: ambient + power.
        assert!((m.at(Point2::new(2.0, 1.0)) - 1.1).abs() < 1e-4);
        for p in [Point2::new(0.33, 0.71), Point2::new(4.2, 3.3)] {
            let exact = 0.3 + illuminance(&lighting, p);
            assert!((m.at(p) as f64 - exact).abs() < 2e-3, "{p:?}");
        }
        assert_eq!(m.at(Point2::new(-10.0, 0.0)), 0.3);
    }

    #[test]
    fn lanes_equal_the_scalar_lookup_bit_for_bit() {
        // Random points inside, on cell edges, on the raster's border and outside it (and
        // NaN), through the AVX2 lanes (where the CPU has them) and the forced portable loop.
        use crate::rng::Rng;
        let lighting = Lighting {
            ambient: 0.3,
            lights: vec![Light {
                position: Point2::new(2.0, 1.0),
                height_m: 2.5,
                power: 0.8,
            }],
            exposure: 1.0,
            exposure_jitter: 0.0,
            wall_factor: 0.7,
            ceiling_brightness: 0.5,
            contact_shadow: Default::default(),
        };
        let b = Aabb {
            min: Point2::new(-1.3, 0.2),
            max: Point2::new(5.0, 4.0),
        };
        let m = LightMap::new(&lighting, b, b);
        let mut rng = Rng::new(9);
        let mut coord = |i: usize, lo: f64, hi: f64| match i % 5 {
            0 => lo - 2.0 + (hi - lo + 4.0) * rng.uniform(),
            1 => lo + ((hi - lo) * rng.uniform() * 10.0).floor() / 10.0,
            2 => [lo, hi, lo - 1e-12, hi + 0.3][(rng.uniform() * 4.0) as usize],
            3 => 1e6 * (rng.uniform() - 0.5),
            _ => lo + (hi - lo) * rng.uniform(),
        };
        let points: Vec<Point2> = (0..5003)
            .map(|i| Point2::new(coord(i, -1.3, 5.0), coord(i / 3 + 1, 0.2, 4.0)))
            .chain([Point2::new(f64::NAN, 1.0), Point2::new(1.0, f64::INFINITY)])
            .collect();
        for kernel in [
            NoiseKernel::Portable,
            NoiseKernel::detect(),
            NoiseKernel::Avx2,
        ] {
            let mut batch = LightBatch::default();
            batch.start(16);
            let ids: Vec<u32> = points.iter().map(|&p| batch.push(p)).collect();
            assert_eq!(batch.len(), points.len());
            m.evaluate(kernel, &mut batch);
            for (p, id) in points.iter().zip(ids) {
                assert_eq!(
                    batch.value(id).to_bits(),
                    m.at(*p).to_bits(),
                    "{kernel:?} {p:?}"
                );
            }
        }
    }

    #[test]
    fn a_huge_world_with_a_light_grid_gets_a_bounded_light_map() {
        // Issue 12 fuzzing: a 2 km region in the lab world with its light grid took 38 s to
        // build. The work (cells x lights) is now bounded, whatever the world.
        let lights: Vec<Light> = (0..10_000)
            .map(|k| Light {
                position: Point2::new((k % 100) as f64 * 40.0, (k / 100) as f64 * 40.0),
                height_m: 2.5,
                power: 0.1,
            })
            .collect();
        let lighting = Lighting {
            ambient: 0.3,
            lights,
            exposure: 1.0,
            exposure_jitter: 0.0,
            wall_factor: 0.7,
            ceiling_brightness: 0.5,
            contact_shadow: Default::default(),
        };
        let b = Aabb {
            min: Point2::new(-2000.0, -2000.0),
            max: Point2::new(2000.0, 2000.0),
        };
        let m = LightMap::new(&lighting, b, b);
        let evaluations = m.values.len() as f64 * lighting.lights.len() as f64;
        // The bound, plus the two border rows and columns of cells.
        assert!(evaluations <= MAX_LIGHT_EVALUATIONS * 1.1, "{evaluations}");
        assert!(m.at(Point2::new(0.0, 0.0)) >= 0.3);
    }
}
