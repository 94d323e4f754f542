//! The avoidance map's updates: a visual scan (each column's floor quadrilateral cleared up to
//! its reading, its boundary stamped, weak and confirmed evidence kept apart) and a laser scan
//! (each beam's fan of free cells and its end).

use super::*;

impl AvoidanceUpdates {
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
}
