//! Correcting the odometry pose with the robot's own scans: a correlative scan-to-map matcher
//! (Olson 2009; cartographer's real-time correlative scan matcher, hector_mapping's role)
//! whose matches an extended Kalman filter fuses with odometry ([`crate::match_filter`]). The
//! drive loop and the pipeline's local scan matching share it (`floorscan.mapping.ScanMatcher`
//! wraps it); its options are [`ScanMatcherOptions`] (`[slam.matcher]`).
//!
//! The robot keeps a persistent map of where its scans ended: hit counts on a fixed grid of
//! `size_m` centred on its start ([`crate::hit_map`]). Each frame, the scan's end points are
//! tried at every pose of a small window around the odometry pose
//! ([`crate::correlative_search`]); each pose scores the mean of a likelihood field
//! (exp(-d^2 / 2 sigma^2), d the distance to the nearest hit, 0 beyond three sigmas) at the
//! points, times a prior that keeps the pose near odometry where the scan does not decide. The
//! best pose is kept when enough points score; then the scan's points the map does not already
//! explain (no hit within `novelty_m`) join the map at the pose kept. Storing only what is new
//! keeps the map as it was first seen: a robot that comes back with drifted odometry matches
//! the walls as they were, not its own drifted copies of them.
//!
//! The field is kept over a square [`CACHE_MARGIN_M`] wider than one match needs and reused,
//! new hits stamped into it, while the robot stays within it.

use crate::correlative_search::{refine, search, Field, SearchWindow};
use crate::error::{Error, Result};
use crate::hit_map::{FieldMut, HitMap, MAX_POINTS};
use crate::match_filter::{MatchFilter, MatchResult};
use crate::match_information::match_information;
use crate::pose::Pose2;
use crate::scan_matcher_options::ScanMatcherOptions;

/// The likelihood field is made this much [m] beyond what one match needs, and reused while
/// the robot stays within it.
pub const CACHE_MARGIN_M: f64 = 1.0;

/// The field is 0 beyond this many sigmas from every hit (exp(-4.5) = 0.011).
pub const STAMP_SIGMAS: f64 = 3.0;

/// The likelihood field kept over part of the grid: `width` x `height` values (row major, row
/// 0 = lowest y) whose cell (0, 0) is the grid's cell (`i0`, `j0`).
#[derive(Debug, Clone, PartialEq)]
pub struct CachedField {
    pub values: Vec<f32>,
    pub width: usize,
    pub height: usize,
    pub i0: i64,
    pub j0: i64,
}

/// The matcher: its hit map, the field kept over part of it, and the filter.
#[derive(Debug, Clone)]
pub struct ScanMatcher {
    options: ScanMatcherOptions,
    side: usize,
    origin_m: (f64, f64),
    hits: Vec<u8>,
    hit_map: HitMap,
    frames: u64,
    field: Option<CachedField>,
    field_nonzero: bool,
    /// The filter's state (the pose kept last, the covariance, odometry's calibration).
    pub filter: MatchFilter,
    matched: Vec<[f64; 2]>,
}

/// Cell offsets (di, dj) within `radius_m` [m] of the centre cell in a square of half-side `r`
/// cells (rows of dj, di fastest), and their distances [m].
fn disc(r: i64, cell_m: f64, radius_m: f64) -> Vec<(i64, i64, f64)> {
    let mut out = Vec::new();
    for dj in -r..=r {
        for di in -r..=r {
            let dist = (di as f64).hypot(dj as f64) * cell_m;
            if dist <= radius_m + 1e-12 {
                out.push((di, dj, dist));
            }
        }
    }
    out
}

impl ScanMatcher {
    /// An empty map of `options.size_m` centred on `center` [m] (world frame).
    pub fn new(options: ScanMatcherOptions, center: (f64, f64)) -> Result<Self> {
        options.validate()?;
        if !(center.0.is_finite() && center.1.is_finite()) {
            return Err(Error::InvalidGeometry(format!(
                "the map's centre must be finite, got {center:?}"
            )));
        }
        let cell = options.cell_size_m;
        let side = (options.size_m / cell).ceil() as usize;
        let half = 0.5 * side as f64 * cell;
        let origin_m = (center.0 - half, center.1 - half);
        let radius = STAMP_SIGMAS * options.sigma_m;
        let sigma = options.sigma_m;
        let stamp = disc((radius / cell).floor() as i64, cell, radius)
            .into_iter()
            .map(|(di, dj, d)| (di, dj, (-0.5 * ((d / sigma) * (d / sigma))).exp() as f32))
            .collect();
        let r = (options.novelty_m / cell).floor() as i64;
        let novelty = if r > 0 {
            disc(r, cell, r as f64 * cell)
                .into_iter()
                .map(|(di, dj, _)| (di, dj))
                .collect()
        } else {
            Vec::new()
        };
        let hit_map = HitMap::new(side, cell, origin_m, options.range_max_m, novelty, stamp)?;
        Ok(Self {
            filter: MatchFilter::new(&options),
            options,
            side,
            origin_m,
            hits: vec![0; side * side],
            hit_map,
            frames: 0,
            field: None,
            field_nonzero: false,
            matched: Vec::new(),
        })
    }

    pub fn options(&self) -> &ScanMatcherOptions {
        &self.options
    }

    /// Cells on a side of the grid.
    pub fn side(&self) -> usize {
        self.side
    }

    /// The grid's cell (0, 0)'s lower-left corner [m].
    pub fn origin_m(&self) -> (f64, f64) {
        self.origin_m
    }

    /// The hit counts (row major, row 0 = lowest y), saturating at 255.
    pub fn hits(&self) -> &[u8] {
        &self.hits
    }

    /// Scans stored so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The field kept last (None before a match made one).
    pub fn cached_field(&self) -> Option<&CachedField> {
        self.field.as_ref()
    }

    /// Cells (i0, j0, i1, j1), end exclusive, of the square of half-side `half_m` [m] around
    /// (x0, y0), cut to the grid.
    fn window(&self, x0: f64, y0: f64, half_m: f64) -> (i64, i64, i64, i64) {
        let cell = self.options.cell_size_m;
        let ci = ((x0 - self.origin_m.0) / cell).floor() as i64;
        let cj = ((y0 - self.origin_m.1) / cell).floor() as i64;
        let r = (half_m / cell).ceil() as i64;
        let n = self.side as i64;
        (
            ci.saturating_sub(r).max(0),
            cj.saturating_sub(r).max(0),
            ci.saturating_add(r).saturating_add(1).min(n),
            cj.saturating_add(r).saturating_add(1).min(n),
        )
    }

    /// A fresh likelihood field over the square of half-side `half_m` [m] around (x0, y0),
    /// cut to the grid (empty when the square misses it).
    pub fn field_around(&self, x0: f64, y0: f64, half_m: f64) -> Result<CachedField> {
        if !(x0.is_finite() && y0.is_finite() && half_m.is_finite() && half_m >= 0.0) {
            return Err(Error::InvalidGeometry(format!(
                "a field's centre and half-side must be finite (half-side >= 0), got ({x0}, \
                 {y0}), {half_m}"
            )));
        }
        let (i0, j0, i1, j1) = self.window(x0, y0, half_m);
        let (width, height) = ((i1 - i0).max(0) as usize, (j1 - j0).max(0) as usize);
        if width == 0 || height == 0 {
            return Ok(CachedField {
                values: Vec::new(),
                width: 0,
                height: 0,
                i0,
                j0,
            });
        }
        let mut values = vec![0.0f32; width * height];
        self.hit_map.fill_field(
            &self.hits,
            FieldMut {
                values: &mut values,
                width,
                height,
                i0,
                j0,
            },
        )?;
        Ok(CachedField {
            values,
            width,
            height,
            i0,
            j0,
        })
    }

    /// Makes the kept field cover at least `half_m` around (x0, y0): the kept one when it
    /// does, else a fresh one [`CACHE_MARGIN_M`] larger.
    pub fn cover(&mut self, x0: f64, y0: f64, half_m: f64) -> Result<&CachedField> {
        if !(x0.is_finite() && y0.is_finite() && half_m.is_finite() && half_m >= 0.0) {
            return Err(Error::InvalidGeometry(format!(
                "a field's centre and half-side must be finite (half-side >= 0), got ({x0}, \
                 {y0}), {half_m}"
            )));
        }
        let covered = self.field.as_ref().is_some_and(|f| {
            let (lo_i, lo_j, hi_i, hi_j) = self.window(x0, y0, half_m);
            f.i0 <= lo_i
                && f.j0 <= lo_j
                && hi_i <= f.i0 + f.width as i64
                && hi_j <= f.j0 + f.height as i64
        });
        if !covered {
            let f = self.field_around(x0, y0, half_m + CACHE_MARGIN_M)?;
            self.field_nonzero = f.values.iter().any(|&v| v != 0.0);
            self.field = Some(f);
        }
        Ok(self.field.as_ref().expect("just made"))
    }

    /// The finite `points` within `range_max_m`, at most `max_points` of them evenly spaced
    /// along the scan (numpy's `linspace(0, n - 1, max_points).round()`), into `self.matched`.
    fn take_matched(&mut self, points: &[[f64; 2]]) {
        let range = self.options.range_max_m;
        self.matched.clear();
        // a non-finite coordinate makes the distance NaN or inf: one test drops both
        self.matched
            .extend(points.iter().filter(|p| p[0].hypot(p[1]) <= range));
        let (n, max) = (self.matched.len(), self.options.max_points as usize);
        if n > max {
            let step = (n - 1) as f64 / (max - 1) as f64;
            for k in 0..max {
                let at = if k + 1 == max {
                    n - 1
                } else {
                    (k as f64 * step).round_ties_even() as usize
                };
                self.matched[k] = self.matched[at];
            }
            self.matched.truncate(max);
        }
    }

    /// The field kept as a [`Field`] (world geometry).
    fn field_view<'a>(&self, f: &'a CachedField) -> Field<'a> {
        let cell = self.options.cell_size_m;
        Field {
            values: &f.values,
            width: f.width,
            height: f.height,
            origin_m: (
                self.origin_m.0 + f.i0 as f64 * cell,
                self.origin_m.1 + f.j0 as f64 * cell,
            ),
            cell_m: cell,
        }
    }

    /// The best pose for `points` [m, robot frame] near `prior` (world_from_robot), refined
    /// below a cell; `score` is its mean field value; not accepted (the prior kept) before
    /// any scan is stored, with fewer than `min_points` usable points, an empty field, or a
    /// mean below `min_score`. Does not change the map.
    pub fn match_scan(&mut self, points: &[[f64; 2]], prior: Pose2) -> Result<MatchResult> {
        if !prior.is_finite() {
            return Err(Error::InvalidGeometry(format!(
                "the prior pose must be finite, got {prior:?}"
            )));
        }
        let o = self.options.clone();
        self.take_matched(points);
        let refused = |score: f64, points: usize| MatchResult {
            pose: prior,
            score,
            accepted: false,
            points,
        };
        let n = self.matched.len();
        if n < o.min_points as usize || self.frames == 0 {
            return Ok(refused(0.0, n));
        }
        let half = o.range_max_m + o.search_xy_m + STAMP_SIGMAS * o.sigma_m;
        self.cover(prior.x, prior.y, half)?;
        let f = self.field.as_ref().expect("covered");
        if f.values.is_empty() || !self.field_nonzero {
            return Ok(refused(0.0, n));
        }
        let field = self.field_view(f);
        let window = SearchWindow {
            xy_steps: (o.search_xy_m / o.cell_size_m).round_ties_even() as u32,
            yaw_steps: (o.search_yaw_rad / o.yaw_step_rad).round_ties_even() as u32,
            yaw_step_rad: o.yaw_step_rad,
            prior_xy_m: o.prior_xy_m,
            prior_yaw_rad: o.prior_yaw_rad,
        };
        let found = search(&field, &self.matched, prior, &window)?;
        let r = refine(&field, &self.matched, found.pose, prior, &window);
        if r.mean < o.min_score {
            return Ok(refused(r.mean, n));
        }
        Ok(MatchResult {
            pose: r.pose,
            score: r.mean,
            accepted: true,
            points: n,
        })
    }

    /// Stores the `points` [m, robot frame] seen from `pose` (counts saturate at 255);
    /// `novel_only`: only those without a stored hit within `novelty_m` (every point is new
    /// in the first scan). Returns how many were stored.
    pub fn insert(&mut self, points: &[[f64; 2]], pose: Pose2, novel_only: bool) -> Result<usize> {
        let field = self.field.as_mut().map(|f| FieldMut {
            values: &mut f.values,
            width: f.width,
            height: f.height,
            i0: f.i0,
            j0: f.j0,
        });
        let novel_only = novel_only && self.frames > 0;
        let stored = self
            .hit_map
            .insert(&mut self.hits, points, pose, novel_only, field)?;
        if stored > 0 {
            if let Some(f) = &self.field {
                self.field_nonzero = self.field_nonzero || f.values.iter().any(|&v| v != 0.0);
            }
        }
        self.frames += 1;
        Ok(stored)
    }

    /// The information matrix of the match of `points` at `pose` on the kept field
    /// ([`match_information`]); zeros before any field was made.
    pub fn information(&mut self, points: &[[f64; 2]], pose: Pose2) -> Result<[[f64; 3]; 3]> {
        if self.field.is_none() {
            return Ok([[0.0; 3]; 3]);
        }
        self.take_matched(points);
        let f = self.field.as_ref().expect("checked");
        match_information(
            &self.field_view(f),
            &self.matched,
            pose,
            self.options.yaw_step_rad,
        )
    }

    /// One frame: the prediction from odometry's `prior` ([`MatchFilter::predict`]), the
    /// match near it, fused with it ([`MatchFilter::fuse`]), then what the scan shows that the
    /// map does not hold yet stored at the pose kept (the prediction when the match is
    /// refused).
    pub fn correct(&mut self, points: &[[f64; 2]], prior: Pose2) -> Result<MatchResult> {
        if !prior.is_finite() {
            return Err(Error::InvalidGeometry(format!(
                "the prior pose must be finite, got {prior:?}"
            )));
        }
        // refused before the filter moves: an error leaves the state as it was
        if points.len() > MAX_POINTS {
            return Err(Error::LengthMismatch(format!(
                "{} points > {MAX_POINTS}",
                points.len()
            )));
        }
        let o = self.options.clone();
        let prior = self.filter.predict(&o, prior);
        let found = self.match_scan(points, prior)?;
        let information = if found.accepted && o.match_variance_scale > 0.0 {
            self.information(points, found.pose)?
        } else {
            [[0.0; 3]; 3]
        };
        let result = self.filter.fuse(&o, found, prior, &information);
        self.insert(points, result.pose, true)?;
        Ok(result)
    }
}

#[cfg(test)]
#[path = "scan_matcher_tests.rs"]
mod tests;
