//! The drive's avoidance map updates (`floorscan.drive.AvoidanceMap`): a square log-odds
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

/// The planner's layers (`floorscan.drive.AvoidanceMap`'s `plan_*`), updated with the map's
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

/// How much of its free evidence a believed obstacle's cell takes (`AvoidanceMap::apply`).
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
pub struct AvoidanceMap {
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

impl AvoidanceMap {
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

    /// Adds one visual scan seen by the camera at `camera` (world_from_camera, odometry frame)
    /// to `log_odds` (the window, row major), whose cell (0, 0) is world cell `origin_cells`;
    /// `confirmed` (the same cells) records which cells a hit from `confirm_range_m` or
    /// farther made confirmed obstacles (1; 0 once the cell's log odds are not positive).
    ///
    /// `plan`, when given, is the planner's layers: they take the same evidence, except that
    /// their confirmed obstacles clear by `confirmed_clearing` of the free evidence, while
    /// `log_odds` then clear in full (the map's probabilities keep their calibration, the
    /// planner keeps a contradicted obstacle for several frames), and that a hit nearer than
    /// `persist_range_m` makes an obstacle there only when it persists
    /// (`VisualModel::persist_range_m`).
    /// Without them, `confirmed_clearing` applies to `log_odds` and every hit enters.
    #[allow(clippy::too_many_arguments)]
    pub fn insert_visual(
        &mut self,
        log_odds: &mut [f32],
        confirmed: &mut [u8],
        plan: Option<PlanLayers<'_>>,
        origin_cells: (i64, i64),
        camera: Pose2,
        readings: &VisualReadings<'_>,
        model: &VisualModel,
    ) -> Result<()> {
        self.check_layer(log_odds)?;
        if confirmed.len() != log_odds.len() {
            return Err(Error::LengthMismatch(format!(
                "the confirmed layer has {} cells, the map {}",
                confirmed.len(),
                log_odds.len()
            )));
        }
        if let Some(p) = &plan {
            let n = log_odds.len();
            if p.log_odds.len() != n || p.confirmed.len() != n || p.near_hits.len() != n {
                return Err(Error::LengthMismatch(format!(
                    "the planner's layers have {}, {} and {} cells, the map {n}",
                    p.log_odds.len(),
                    p.confirmed.len(),
                    p.near_hits.len(),
                )));
            }
        }
        let n = readings.status.len();
        if n > MAX_READINGS {
            return Err(Error::LengthMismatch(format!(
                "{n} readings > {MAX_READINGS}"
            )));
        }
        for (name, len) in [
            ("x", readings.x_m.len()),
            ("y", readings.y_m.len()),
            ("near_x", readings.near_x_m.len()),
            ("near_y", readings.near_y_m.len()),
            ("footprints", readings.footprint_m.len()),
            ("errors", readings.error_m.len()),
        ] {
            if len != n {
                return Err(Error::LengthMismatch(format!(
                    "{n} status codes but {len} {name}"
                )));
            }
        }
        if !(camera.x.is_finite() && camera.y.is_finite() && camera.yaw.is_finite()) {
            return Err(Error::InvalidGeometry("camera pose not finite".into()));
        }
        if !(0.0..=1.0).contains(&model.no_boundary_clearing) {
            return Err(invalid_option(
                "no_boundary_clearing",
                format!("must be in [0, 1], got {}", model.no_boundary_clearing),
            ));
        }
        if !(model.confirmed_nats.is_finite() && model.confirmed_nats >= 0.0) {
            return Err(invalid_option(
                "confirmed_nats",
                format!("must be finite and >= 0, got {}", model.confirmed_nats),
            ));
        }
        if !(model.confirm_range_m.is_finite() && model.confirm_range_m >= 0.0) {
            return Err(invalid_option(
                "confirm_range_m",
                format!("must be finite and >= 0, got {}", model.confirm_range_m),
            ));
        }
        if !(model.confirmed_clearing > 0.0 && model.confirmed_clearing <= 1.0) {
            return Err(invalid_option(
                "confirmed_clearing",
                format!("must be in (0, 1], got {}", model.confirmed_clearing),
            ));
        }
        if !(model.persist_range_m.is_finite() && model.persist_range_m >= 0.0) {
            return Err(invalid_option(
                "persist_range_m",
                format!("must be finite and >= 0, got {}", model.persist_range_m),
            ));
        }
        let weak_clearing = model.no_boundary_clearing < 1.0;
        let cell = self.cell_m;
        let (ox, oy) = (origin_cells.0 as f64, origin_cells.1 as f64);
        let (c, s) = (camera.yaw.cos(), camera.yaw.sin());
        let to_cells = |gx: f64, gy: f64| {
            let wx = camera.x + c * gx - s * gy;
            let wy = camera.y + s * gx + c * gy;
            [wx / cell - ox, wy / cell - oy]
        };
        let cam_c = [camera.x / cell - ox, camera.y / cell - oy];
        let q = 0.25 * (cell * cell);
        self.near_c.clear();
        self.end_c.clear();
        self.point_c.clear();
        self.sigma.clear();
        self.valid.clear();
        self.ok.clear();
        self.hit_nats.clear();
        for k in 0..n {
            let (px, py) = (readings.x_m[k], readings.y_m[k]);
            let (nx, ny) = (readings.near_x_m[k], readings.near_y_m[k]);
            let status = readings.status[k];
            let bnd = status == BOUNDARY;
            let rng = px.hypot(py);
            let err = if bnd { readings.error_m[k] } else { f64::NAN };
            let e = if err.is_finite() {
                err
            } else {
                model.default_error_m
            };
            let fp = readings.footprint_m[k];
            let f = if fp.is_finite() { fp } else { 0.0 };
            let sigma = (e * e + 0.25 * f * f + q).sqrt();
            // free space ends margin_sigmas before a boundary, never nearer than the near edge
            let near_r = nx.hypot(ny);
            let end_r = if bnd {
                rng - model.margin_sigmas * sigma
            } else {
                rng
            };
            let end_r = nan_max(end_r, near_r);
            let scale = if rng > 0.0 { end_r / rng } else { 0.0 };
            let (ex, ey) = (px * scale, py * scale);
            let seen = status == BOUNDARY || status == NO_BOUNDARY;
            self.valid.push(seen && (ex + ey + nx + ny).is_finite());
            self.near_c.push(to_cells(nx, ny));
            self.end_c.push(to_cells(ex, ey));
            let pc = to_cells(px, py);
            self.ok.push(bnd && (pc[0] + pc[1]).is_finite());
            self.point_c.push(pc);
            self.sigma.push(sigma);
            self.hit_nats
                .push(model.fusion_weight * (model.hit_a + model.hit_b * rng));
        }
        // hits nearer than persist_range_m that the planner's layers do not take yet: no hit
        // in the last insertion at their cell or a neighbour, no believed obstacle there
        let side = self.side;
        self.near_hit.clear();
        self.held_back.clear();
        self.hit_cell.clear();
        for k in 0..n {
            let (gx, gy) = match readings.status[k] {
                BOUNDARY if self.ok[k] => (readings.x_m[k], readings.y_m[k]),
                TOO_CLOSE => (readings.near_x_m[k], readings.near_y_m[k]),
                _ => (f64::NAN, f64::NAN),
            };
            let [cx, cy] = to_cells(gx, gy);
            let inside = cx >= 0.0 && cx < side as f64 && cy >= 0.0 && cy < side as f64;
            let cell = inside.then(|| cy as usize * side + cx as usize);
            let near = gx.hypot(gy) < model.persist_range_m;
            let held_back = match &plan {
                Some(p) if near => !cell.is_some_and(|c| persists(p, side, c)),
                _ => false,
            };
            self.near_hit.push(near);
            self.held_back.push(held_back);
            self.hit_cell.push(cell);
        }
        // the obstacle's faces between adjacent close boundary points
        let close = |k: usize, me: &Self| {
            let gap = (readings.x_m[k + 1] - readings.x_m[k])
                .hypot(readings.y_m[k + 1] - readings.y_m[k]);
            me.ok[k] && me.ok[k + 1] && gap < 2.0 * (me.sigma[k] + me.sigma[k + 1]) + 2.0 * cell
        };
        let mut longest = f64::NEG_INFINITY;
        let mut any = false;
        for k in 0..n.saturating_sub(1) {
            if close(k, self) {
                any = true;
                let [x0, y0] = self.point_c[k];
                let [x1, y1] = self.point_c[k + 1];
                longest = nan_max(longest, (x1 - x0).hypot(y1 - y0));
            }
        }
        // checked before anything is drawn, so a refused scan leaves the scratch layers clean
        let steps = if any {
            let steps = (2.0 * longest).ceil() + 2.0;
            if !(steps.is_finite() && steps <= MAX_FACE_SAMPLES as f64) {
                return Err(Error::InvalidGeometry(format!(
                    "an obstacle face of {longest} cells between adjacent boundary points"
                )));
            }
            steps as usize
        } else {
            0
        };
        let mut rows = RowSpan::EMPTY;
        // the floor quadrilaterals between neighbouring valid readings, filled at once (those
        // beside a no-boundary column apart, first, when they clear less)
        self.quads.clear();
        self.weak_quads.clear();
        for k in 0..n.saturating_sub(1) {
            if self.valid[k] && self.valid[k + 1] {
                let quad = fan_quad(
                    self.near_c[k],
                    self.near_c[k + 1],
                    self.end_c[k],
                    self.end_c[k + 1],
                    cam_c,
                );
                rows.cover_vertices(&quad, side);
                let weak =
                    readings.status[k] == NO_BOUNDARY || readings.status[k + 1] == NO_BOUNDARY;
                if weak_clearing && weak {
                    self.weak_quads.push(quad);
                } else {
                    self.quads.push(quad);
                }
            }
        }
        self.fill_quads();
        // hit discs around the boundary points, in reading order (a later one wins)
        for k in 0..n {
            if !self.ok[k] {
                continue;
            }
            let [x, y] = self.point_c[k];
            let sig = if self.sigma[k].is_nan() {
                0.0
            } else {
                self.sigma[k].clamp(f64::MIN, f64::MAX)
            };
            let r = (sig / cell).max(0.5);
            let far = readings.x_m[k].hypot(readings.y_m[k]) >= model.confirm_range_m;
            stamp_disc(
                (&mut self.hit, &mut self.confirms, &mut self.unheld),
                side,
                x,
                y,
                r,
                (self.hit_nats[k] as f32, far, self.held_back[k]),
                &mut rows,
            );
        }
        // the obstacle's faces between adjacent close boundary points
        if steps > 0 {
            let step = 1.0 / (steps - 1) as f64;
            for k in 0..n - 1 {
                if !close(k, self) {
                    continue;
                }
                let [x0, y0] = self.point_c[k];
                let [x1, y1] = self.point_c[k + 1];
                let v = nan_min(self.hit_nats[k], self.hit_nats[k + 1]) as f32;
                let far = readings.x_m[k].hypot(readings.y_m[k]) >= model.confirm_range_m
                    && readings.x_m[k + 1].hypot(readings.y_m[k + 1]) >= model.confirm_range_m;
                let unheld = self.held_back[k] || self.held_back[k + 1];
                for t in 0..steps {
                    let t = if t + 1 == steps {
                        1.0
                    } else {
                        t as f64 * step + 0.0
                    };
                    let pi = (x0 + t * (x1 - x0)).floor();
                    let pj = (y0 + t * (y1 - y0)).floor();
                    if pi >= 0.0 && pi < side as f64 && pj >= 0.0 && pj < side as f64 {
                        let (i, j) = (pi as usize, pj as usize);
                        self.hit[j * side + i] = v;
                        self.confirms[j * side + i] = far;
                        self.unheld[j * side + i] = unheld;
                        rows.cover(j);
                    }
                }
            }
        }
        // too close: the near edge of view
        let too_close = (model.fusion_weight * model.too_close_logit) as f32;
        for k in 0..n {
            let (nx, ny) = (readings.near_x_m[k], readings.near_y_m[k]);
            if readings.status[k] != TOO_CLOSE || !(nx + ny).is_finite() {
                continue;
            }
            let [tx, ty] = to_cells(nx, ny);
            if tx >= 0.0 && tx < side as f64 && ty >= 0.0 && ty < side as f64 {
                let (i, j) = (tx as usize, ty as usize);
                self.hit[j * side + i] = too_close;
                self.confirms[j * side + i] = nx.hypot(ny) >= model.confirm_range_m;
                self.unheld[j * side + i] = self.held_back[k];
                rows.cover(j);
            }
        }
        // free evidence by range (f32, as numpy computed it), then hits, then the clamps
        let fw = model.fusion_weight as f32;
        let (fa, fb) = (model.free_a as f32, model.free_b as f32);
        let weak = Clearing {
            no_boundary: model.no_boundary_clearing as f32,
            confirmed: model.confirmed_clearing as f32,
            believed_nats: model.confirmed_nats as f32,
            holds_back: false,
        };
        let free = |i: usize, j: usize| {
            let r = ((i as f64 + 0.5 - cam_c[0]).hypot(j as f64 + 0.5 - cam_c[1]) * cell) as f32;
            fw * (fa + fb * r)
        };
        match plan {
            None => self.apply(&mut [Layer::visual(log_odds, confirmed, weak)], &rows, free),
            Some(plan) => {
                // this insertion's near hits are the next one's to persist
                plan.near_hits.fill(0);
                for (near, cell) in self.near_hit.iter().zip(&self.hit_cell) {
                    if let (true, Some(c)) = (near, cell) {
                        plan.near_hits[*c] = 1;
                    }
                }
                let full = Clearing {
                    confirmed: 1.0,
                    ..weak
                };
                let held = Clearing {
                    holds_back: true,
                    ..weak
                };
                let mut layers = [
                    Layer::visual(log_odds, confirmed, full),
                    Layer::visual(plan.log_odds, plan.confirmed, held),
                ];
                self.apply(&mut layers, &rows, free)
            }
        }
        Ok(())
    }

    /// Adds an ideal 2-D laser scan: the fan from the sensor's cell coordinates `sensor_c`
    /// to each beam's end `end_c` [cells] (the return, or the range limit; a non-finite end
    /// is no reading) gets `miss_nats`, the cell of each end where `returned` gets `hit_nats`
    /// (cell coordinates truncated towards zero, as numpy's cast); `plan`, the planner's
    /// layer, when given, the same.
    #[allow(clippy::too_many_arguments)]
    pub fn insert_laser(
        &mut self,
        log_odds: &mut [f32],
        plan: Option<&mut [f32]>,
        sensor_c: [f64; 2],
        end_c: &[[f64; 2]],
        returned: &[bool],
        hit_nats: f32,
        miss_nats: f32,
    ) -> Result<()> {
        self.check_layer(log_odds)?;
        if let Some(p) = &plan {
            self.check_layer(p)?;
        }
        let n = end_c.len();
        if n > MAX_READINGS {
            return Err(Error::LengthMismatch(format!("{n} beams > {MAX_READINGS}")));
        }
        if returned.len() != n {
            return Err(Error::LengthMismatch(format!(
                "{n} beam ends but {} return flags",
                returned.len()
            )));
        }
        if !(sensor_c[0].is_finite() && sensor_c[1].is_finite()) {
            return Err(Error::InvalidGeometry("sensor position not finite".into()));
        }
        let side = self.side;
        let mut rows = RowSpan::EMPTY;
        let valid = |e: &[f64; 2]| (e[0] + e[1]).is_finite();
        self.quads.clear();
        for k in 0..n.saturating_sub(1) {
            if valid(&end_c[k]) && valid(&end_c[k + 1]) {
                let quad = fan_quad(sensor_c, sensor_c, end_c[k], end_c[k + 1], sensor_c);
                rows.cover_vertices(&quad, side);
                self.quads.push(quad);
            }
        }
        self.fill_quads();
        for (e, &hit) in end_c.iter().zip(returned) {
            if !hit {
                continue;
            }
            let (i, j) = (e[0].trunc(), e[1].trunc());
            if i >= 0.0 && i < side as f64 && j >= 0.0 && j < side as f64 {
                self.hit[j as usize * side + i as usize] = hit_nats;
                rows.cover(j as usize);
            }
        }
        let free = |_: usize, _: usize| miss_nats;
        match plan {
            None => self.apply(&mut [Layer::laser(log_odds)], &rows, free),
            Some(p) => self.apply(&mut [Layer::laser(log_odds), Layer::laser(p)], &rows, free),
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

#[cfg(test)]
#[path = "avoidance_map_tests.rs"]
mod tests;
