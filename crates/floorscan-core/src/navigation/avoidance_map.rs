//! The drive's avoidance map (`floorscan.drive.AvoidanceMap`, [`AvoidanceMap`]: its layers,
//! scrolling, forgetting and views, in `avoidance_map_layers.rs`) and its updates
//! ([`AvoidanceUpdates`]): a square log-odds
//! window of `side` x `side` cells in the odometry frame (row 0 = lowest y; cell (i, j) spans
//! [i, i + 1) x [j, j + 1) in cell coordinates, the window's cell (0, 0) being world cell
//! `origin_cells`), updated in place from one visual scan through the calibrated inverse
//! sensor model:
//!
//! - each pair of neighbouring valid readings fills the floor quadrilateral between their near
//!   edges of view and the nearer of their two ends (filled as OpenCV's `fillPoly` fills it,
//!   [`crate::polygon_fill`]); those cells get free evidence fusion_weight x (free_a + free_b r),
//!   r [m] the distance of the cell's centre from the camera;
//! - boundary readings mark the cells whose centre lies within max(sigma, cell / 2) of the
//!   boundary point, and the cells the face between two close boundary points passes through,
//!   occupied with fusion_weight x (hit_a + hit_b range) (the face takes the smaller of its two
//!   points' values); `too_close` readings mark the cell of their near edge with
//!   fusion_weight x too_close_logit. Hits take priority over free evidence, a later reading's
//!   hit over an earlier one's;
//! - a quadrilateral beside a `no_boundary` column (a column that found no boundary: no
//!   return, in a laser's terms) adds only `no_boundary_clearing` x its free evidence to a cell
//!   whose log odds exceed `confirmed_nats` (the drive's default 0: believed occupied) and
//!   that a hit from `confirm_range_m` or farther confirmed (the `confirmed` layer): a camera
//!   that sees no edge over an obstacle it mapped from farther away (a face the colour of the
//!   floor) is more likely wrong than the independent frames the evidence assumes, as a ROS
//!   costmap does not clear through a laser's no-return beams, while a cell only ever hit
//!   from nearer (a fleck of carpet near the robot, where the floor's grain is magnified) is
//!   cleared as any other; a quadrilateral between two boundaries clears in full (the camera
//!   saw the floor end farther on), and where the two kinds overlap the full one wins; in the
//!   planner's layers, when given, it adds only `confirmed_clearing` x its free evidence to a
//!   cell believed occupied and confirmed (a thin leg that the camera loses close up, seeing
//!   the floor end beyond it, clears over several frames, as OctoMap's miss is smaller than
//!   its hit), while the map's own log odds, whose calibrated probabilities must mean what
//!   they say, clear in full;
//! - every cell is then clamped to `clamp_nats`.
//!
//! The arithmetic follows the numpy implementation it replaced operation for operation (cell
//! coordinates and geometry in `f64`, free evidence in `f32`), so both give the same map.
//! Scratch layers are allocated once, with the map; an insertion allocates nothing.

use crate::error::{invalid_option, Error, Result};
use crate::polygon_fill::{Canvas, PolygonFill};
use crate::pose::Pose2;
pub use crate::visual_sensor_model::VisualModel;

/// The largest window side [cells]: 10^8 cells (the options' 100 m at 1 cm).
pub const MAX_SIDE: usize = 10_000;

/// The most readings one insertion takes (columns of a scan).
pub const MAX_READINGS: usize = 1 << 16;

/// Sub-cell precision of the filled quadrilaterals' corners: 1 / 16 cell.
const SHIFT: u32 = 4;

/// Most samples along one obstacle face between adjacent boundary points.
const MAX_FACE_SAMPLES: usize = 1 << 16;

/// The planner's layers ([`AvoidanceMap`]'s `plan_*`), updated with the map's
/// own: its log odds, its confirmed obstacles (cleared by `confirmed_clearing`) and the cells
/// the last insertion hit from nearer than `persist_range_m` (1, else 0), which each insertion
/// rewrites.
#[derive(Debug)]
pub struct PlanLayers<'a> {
    pub log_odds: &'a mut [f32],
    pub confirmed: &'a mut [u8],
    pub near_hits: &'a mut [u8],
}

/// One scan's readings, column by column, in the camera's ground frame [m]: status codes
/// (0 boundary, 1 no boundary, 2 too close, 3 invalid; `ColumnStatus`), the boundary (or
/// farthest) point, the near edge of view, the footprint of a pixel row there and the table's
/// predicted error (NaN where unknown).
#[derive(Debug, Clone, Copy)]
pub struct VisualReadings<'a> {
    pub status: &'a [u8],
    pub x_m: &'a [f64],
    pub y_m: &'a [f64],
    pub near_x_m: &'a [f64],
    pub near_y_m: &'a [f64],
    pub footprint_m: &'a [f64],
    pub error_m: &'a [f64],
}

const BOUNDARY: u8 = 0;
const NO_BOUNDARY: u8 = 1;
const TOO_CLOSE: u8 = 2;

/// np.maximum / np.minimum: NaN when either is NaN.
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else if a >= b {
        a
    } else {
        b
    }
}

fn nan_min(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else if a <= b {
        a
    } else {
        b
    }
}

/// How much of its free evidence a believed obstacle's cell takes (`AvoidanceUpdates::apply`).
#[derive(Debug, Clone, Copy)]
struct Clearing {
    /// inside only quadrilaterals beside a `no_boundary` column
    no_boundary: f32,
    /// inside a quadrilateral between two boundaries
    confirmed: f32,
    /// log odds above which a cell is believed occupied
    believed_nats: f32,
    /// whether a hit that did not persist leaves the cell as it was (the planner's layers)
    holds_back: bool,
}

impl Clearing {
    /// Every cell takes its free evidence in full (the laser's insertion).
    const FULL: Self = Self {
        no_boundary: 1.0,
        confirmed: 1.0,
        believed_nats: 0.0,
        holds_back: false,
    };
}

/// The avoidance map's insertion machinery: its geometry, clamps and scratch layers.
#[derive(Debug, Clone)]
pub struct AvoidanceUpdates {
    side: usize,
    cell_m: f64,
    clamp: (f32, f32),
    /// cells inside a floor quadrilateral this insertion: 1, or 2 inside only quadrilaterals
    /// beside a `no_boundary` column (weak clearing); else 0
    mask: Vec<u8>,
    /// the hit evidence of this insertion, NaN where none
    hit: Vec<f32>,
    /// where `hit` is set: whether the hit confirms the cell (a boundary at least
    /// `confirm_range_m` away)
    confirms: Vec<bool>,
    /// where `hit` is set: whether the hit is held back from the planner's layers (nearer
    /// than `persist_range_m` and not persisting)
    unheld: Vec<bool>,
    /// per reading: whether its hit is nearer than `persist_range_m`, and whether it is held
    /// back from the planner's layers
    near_hit: Vec<bool>,
    held_back: Vec<bool>,
    /// per reading: the window cell of its hit (boundary point or `too_close` near edge)
    hit_cell: Vec<Option<usize>>,
    /// per reading: cell coordinates of the near edge, the free end, the boundary point
    near_c: Vec<[f64; 2]>,
    end_c: Vec<[f64; 2]>,
    point_c: Vec<[f64; 2]>,
    sigma: Vec<f64>,
    valid: Vec<bool>,
    ok: Vec<bool>,
    hit_nats: Vec<f64>,
    quads: Vec<[[i64; 2]; 4]>,
    weak_quads: Vec<[[i64; 2]; 4]>,
    fill: PolygonFill,
}

impl AvoidanceUpdates {
    /// A map of `side` x `side` cells of `cell_m` [m], clamped to `clamp_nats` (min < 0 < max).
    pub fn new(side: usize, cell_m: f64, clamp_nats: (f64, f64)) -> Result<Self> {
        if !(1..=MAX_SIDE).contains(&side) {
            return Err(invalid_option(
                "side",
                format!("must be in 1..={MAX_SIDE} cells, got {side}"),
            ));
        }
        if !(cell_m.is_finite() && cell_m > 0.0) {
            return Err(invalid_option(
                "cell_size_m",
                format!("must be > 0, got {cell_m}"),
            ));
        }
        let (lo, hi) = (clamp_nats.0 as f32, clamp_nats.1 as f32);
        if !(lo.is_finite() && hi.is_finite() && lo < 0.0 && 0.0 < hi) {
            return Err(invalid_option(
                "clamp_nats",
                format!("need min < 0 < max, got {clamp_nats:?}"),
            ));
        }
        Ok(Self {
            side,
            cell_m,
            clamp: (lo, hi),
            mask: vec![0; side * side],
            hit: vec![f32::NAN; side * side],
            confirms: vec![false; side * side],
            unheld: vec![false; side * side],
            near_hit: Vec::new(),
            held_back: Vec::new(),
            hit_cell: Vec::new(),
            near_c: Vec::new(),
            end_c: Vec::new(),
            point_c: Vec::new(),
            sigma: Vec::new(),
            valid: Vec::new(),
            ok: Vec::new(),
            hit_nats: Vec::new(),
            quads: Vec::new(),
            weak_quads: Vec::new(),
            fill: PolygonFill::default(),
        })
    }

    /// Side of the window [cells].
    pub fn side(&self) -> usize {
        self.side
    }

    fn check_layer(&self, log_odds: &[f32]) -> Result<()> {
        if log_odds.len() != self.side * self.side {
            return Err(Error::LengthMismatch(format!(
                "a {0} x {0} map needs {1} cells, got {2}",
                self.side,
                self.side * self.side,
                log_odds.len()
            )));
        }
        Ok(())
    }

    /// Marks the cells of this insertion's quadrilaterals in the mask (one `fillPoly` per
    /// kind): the weakly clearing ones with 2, then the fully clearing ones with 1, which
    /// overwrite the cells both cover.
    fn fill_quads(&mut self) {
        for (quads, value) in [(&self.weak_quads, 2u8), (&self.quads, 1u8)] {
            if quads.is_empty() {
                continue;
            }
            let mut canvas = Canvas {
                cells: &mut self.mask,
                width: self.side,
                height: self.side,
            };
            self.fill.fill(&mut canvas, quads, SHIFT, value);
        }
    }

    /// Adds this insertion's evidence on the touched rows to each layer (a cell's hit, else
    /// its free evidence `free(i, j)` when inside a quadrilateral; a believed obstacle's cell,
    /// its log odds above `weak.believed_nats` and confirmed where the layer has a
    /// `confirmed` layer, takes `weak.no_boundary` of it inside only weakly clearing
    /// quadrilaterals and `weak.confirmed` inside fully clearing ones), resets the scratch
    /// layers there, and clamps every cell.
    fn apply(
        &mut self,
        layers: &mut [Layer<'_>],
        rows: &RowSpan,
        free: impl Fn(usize, usize) -> f32,
    ) {
        let side = self.side;
        for j in rows.lo..rows.hi.min(side) {
            let row = j * side;
            for i in 0..side {
                let k = row + i;
                let (h, mask) = (self.hit[k], self.mask[k]);
                let confirms = h.is_finite() && self.confirms[k];
                let unheld = h.is_finite() && self.unheld[k];
                let f = if mask != 0 && !h.is_finite() {
                    free(i, j)
                } else {
                    0.0
                };
                for layer in layers.iter_mut() {
                    layer.update(k, h, mask, confirms, f, unheld);
                }
                self.hit[k] = f32::NAN;
                self.confirms[k] = false;
                self.unheld[k] = false;
                self.mask[k] = 0;
            }
        }
        let (lo, hi) = self.clamp;
        for layer in layers.iter_mut() {
            for v in layer.log_odds.iter_mut() {
                *v = v.clamp(lo, hi);
            }
        }
    }
}

/// One layer of evidence an insertion updates: its log odds, its confirmed flags (a visual
/// map's; none for a laser's) and how its believed obstacles clear.
struct Layer<'a> {
    log_odds: &'a mut [f32],
    confirmed: Option<&'a mut [u8]>,
    weak: Clearing,
}

impl<'a> Layer<'a> {
    fn visual(log_odds: &'a mut [f32], confirmed: &'a mut [u8], weak: Clearing) -> Self {
        Self {
            log_odds,
            confirmed: Some(confirmed),
            weak,
        }
    }

    fn laser(log_odds: &'a mut [f32]) -> Self {
        Self {
            log_odds,
            confirmed: None,
            weak: Clearing::FULL,
        }
    }

    /// Cell `k`'s update: its hit `h` (NaN: none), the quadrilateral mask, whether the hit
    /// confirms, the free evidence `f` where the mask is set and there is no hit, and whether
    /// the hit is held back from a layer that `holds_back` (which then keeps the cell as it
    /// was but for a confirmation its log odds no longer support).
    #[inline]
    fn update(&mut self, k: usize, h: f32, mask: u8, confirms: bool, f: f32, unheld: bool) {
        let w = self.weak;
        let held = unheld && w.holds_back;
        let confirms = confirms && !held;
        let l = &mut self.log_odds[k];
        let mut believed = *l > w.believed_nats;
        if let Some(c) = self.confirmed.as_deref_mut() {
            if *l <= 0.0 {
                c[k] = 0; // forgotten or cleared since its confirming hit
            }
            believed &= c[k] != 0;
            if confirms {
                c[k] = 1;
            }
        }
        if held {
            // a near hit that did not persist: no evidence
        } else if h.is_finite() {
            *l += h;
        } else if mask == 1 && believed {
            *l += w.confirmed * f;
        } else if mask == 1 || (mask == 2 && !believed) {
            *l += f;
        } else if mask == 2 {
            *l += w.no_boundary * f;
        }
    }
}

/// The quadrilateral between two neighbouring readings [cells x 16, OpenCV's pixel
/// coordinates]: their near edges, then both rays cut at the nearer of the two ends (the floor
/// seen past an obstacle's corner by one ray never clears the corner).
fn fan_quad(
    n0: [f64; 2],
    n1: [f64; 2],
    end0: [f64; 2],
    end1: [f64; 2],
    cam: [f64; 2],
) -> [[i64; 2]; 4] {
    let d0 = [end0[0] - cam[0], end0[1] - cam[1]];
    let d1 = [end1[0] - cam[0], end1[1] - cam[1]];
    let (r0, r1) = (d0[0].hypot(d0[1]), d1[0].hypot(d1[1]));
    let r = nan_min(r0, r1);
    let (q0, q1) = (r / nan_max(r0, 1e-9), r / nan_max(r1, 1e-9));
    let e0 = [cam[0] + d0[0] * q0, cam[1] + d0[1] * q0];
    let e1 = [cam[0] + d1[0] * q1, cam[1] + d1[1] * q1];
    // OpenCV's pixel p is centred on p; cell p spans [p, p + 1): half a cell back
    let fixed = |p: [f64; 2]| {
        let f = |v: f64| {
            let t = ((v - 0.5) * (1 << SHIFT) as f64).round_ties_even();
            // numpy's cast to int32; far-off corners are clipped by the fill anyway
            t.clamp(i32::MIN as f64, i32::MAX as f64) as i64
        };
        [f(p[0]), f(p[1])]
    };
    [fixed(n0), fixed(n1), fixed(e1), fixed(e0)]
}

/// The rows an insertion touched, so only they are applied and reset.
struct RowSpan {
    lo: usize,
    hi: usize,
}

impl RowSpan {
    const EMPTY: RowSpan = RowSpan {
        lo: usize::MAX,
        hi: 0,
    };

    fn cover(&mut self, j: usize) {
        self.lo = self.lo.min(j);
        self.hi = self.hi.max(j + 1);
    }

    /// The rows a polygon with these corners [cells x 16] can touch, within `0..side`.
    fn cover_vertices(&mut self, quad: &[[i64; 2]], side: usize) {
        let half = (1i64 << SHIFT) >> 1;
        for v in quad {
            let j = ((v[1] + half) >> SHIFT).clamp(0, side as i64 - 1) as usize;
            self.cover(j);
        }
    }
}

/// Sets the cells whose centre lies within `r` [cells] of (x, y) [cells] to `value` (as the
/// numpy code did: (i + 0.5 - x)^2 + (j + 0.5 - y)^2 <= r^2).
/// Sets the cells whose centre lies within `r` of (x, y) [cells] to `value` (hit evidence,
/// whether it confirms the cell).
fn stamp_disc(
    (hit, confirms, unheld): (&mut [f32], &mut [bool], &mut [bool]),
    side: usize,
    x: f64,
    y: f64,
    r: f64,
    (value, confirm, held_back): (f32, bool, bool),
    rows: &mut RowSpan,
) {
    let (fx, fy) = (x.floor(), y.floor());
    let m = r.ceil() + 1.0;
    let n = side as f64;
    let (i_lo, i_hi) = ((fx - m).max(0.0), (fx + m).min(n - 1.0));
    let (j_lo, j_hi) = ((fy - m).max(0.0), (fy + m).min(n - 1.0));
    if !(i_lo <= i_hi && j_lo <= j_hi) {
        return;
    }
    let rr = r * r;
    for j in j_lo as usize..=j_hi as usize {
        let b = j as f64 + 0.5 - y;
        for i in i_lo as usize..=i_hi as usize {
            let a = i as f64 + 0.5 - x;
            if a * a + b * b <= rr {
                hit[j * side + i] = value;
                confirms[j * side + i] = confirm;
                unheld[j * side + i] = held_back;
                rows.cover(j);
            }
        }
    }
}

/// Whether a hit at window cell `cell` persists for the planner's layers: the last insertion
/// hit it or one of its eight neighbours from near, or the planner has evidence that one is occupied.
fn persists(plan: &PlanLayers<'_>, side: usize, cell: usize) -> bool {
    let (i, j) = (cell % side, cell / side);
    for jj in j.saturating_sub(1)..=(j + 1).min(side - 1) {
        for ii in i.saturating_sub(1)..=(i + 1).min(side - 1) {
            let q = jj * side + ii;
            if plan.near_hits[q] != 0 || plan.log_odds[q] > 0.0 {
                return true;
            }
        }
    }
    false
}

/// Forgetting: every value times `factor` (in [0, 1]).
pub fn decay(values: &mut [f32], factor: f32) {
    for v in values {
        *v *= factor;
    }
}

#[path = "avoidance_map_updates.rs"]
mod updates;

#[path = "avoidance_map_layers.rs"]
mod layers;
pub use layers::{AvoidanceMap, LASER_HIT_NATS, LASER_MISS_NATS, NO_EVIDENCE_NATS};

#[cfg(test)]
#[path = "avoidance_map_tests.rs"]
mod tests;
