//! The world file's solids: walls cut at their doors, boxes, tables with their legs and chairs
//! with legs and backrests, each checked and given its appearance.

use super::build::{positive, pt, shape_polygon, Shape};
use super::materials::Materials;
use super::*;

/// Every solid of the file, walls first.
pub(super) fn solids(
    file: &WorldFile,
    ceiling: f64,
    materials: &Materials,
    err: &dyn Fn(String) -> Error,
) -> Result<Vec<Solid>> {
    let appearance = |name: &str, field: String| materials.appearance(name, field, err);
    let mut solids = Vec::new();
    walls(file, ceiling, &appearance, err, &mut solids)?;
    boxes(file, &appearance, err, &mut solids)?;
    tables(file, &appearance, err, &mut solids)?;
    chairs(file, &appearance, err, &mut solids)?;
    Ok(solids)
}

type AppearanceOf<'a> = dyn Fn(&str, String) -> Result<usize> + 'a;

/// The file's walls cut at their doors, each piece's outer ends extended by half the thickness so corners close.
fn walls(
    file: &WorldFile,
    ceiling: f64,
    appearance: &AppearanceOf,
    err: &dyn Fn(String) -> Error,
    solids: &mut Vec<Solid>,
) -> Result<()> {
    for (i, w) in file.walls.iter().enumerate() {
        let field = format!("walls[{i}]");
        let height = positive(
            w.height_m.unwrap_or(ceiling),
            format!("{field}.height_m"),
            &err,
        )?;
        let thickness = positive(w.thickness_m, format!("{field}.thickness_m"), &err)?;
        let app = appearance(&w.appearance, format!("{field}.appearance"))?;
        let (a, b) = (pt(w.from), pt(w.to));
        let length = (b.x - a.x).hypot(b.y - a.y);
        if !(length > 0.0 && length.is_finite()) {
            return Err(err(format!(
                "{field}: `from` and `to` must differ and be finite"
            )));
        }
        // Pieces between the doors, as offsets along the wall.
        let mut pieces = Vec::new();
        let mut s = 0.0;
        for (k, d) in w.doors.iter().enumerate() {
            if !(d[0] >= s && d[1] > d[0] && d[1] <= length) {
                return Err(err(format!(
                    "{field}.doors[{k}]: needs {s} <= start < end <= {length:.3} (offsets along the wall, in order), got {d:?}"
                )));
            }
            pieces.push((s, d[0]));
            s = d[1];
        }
        pieces.push((s, length));
        let dir = Point2::new((b.x - a.x) / length, (b.y - a.y) / length);
        for (s0, s1) in pieces {
            // Extend the wall's outer ends by half its thickness, so corners close.
            let e0 = if s0 == 0.0 { -thickness / 2.0 } else { s0 };
            let e1 = if s1 == length {
                length + thickness / 2.0
            } else {
                s1
            };
            if e1 - e0 <= 1e-9 {
                continue;
            }
            let mid = (e0 + e1) / 2.0;
            let center = Point2::new(a.x + dir.x * mid, a.y + dir.y * mid);
            solids.push(Solid {
                polygon: rotated_rect(center, [e1 - e0, thickness], dir.y.atan2(dir.x)),
                base_m: 0.0,
                top_m: height,
                appearance: app,
                kind: "wall".into(),
            });
        }
    }
    Ok(())
}

/// The file's boxes (any shape), standing on the floor or raised to `base_m`.
fn boxes(
    file: &WorldFile,
    appearance: &AppearanceOf,
    err: &dyn Fn(String) -> Error,
    solids: &mut Vec<Solid>,
) -> Result<()> {
    for (i, bx) in file.boxes.iter().enumerate() {
        let field = format!("boxes[{i}]");
        let polygon = shape_polygon(
            Shape {
                rect: bx.rect,
                polygon: bx.polygon.as_ref(),
                center: bx.center,
                size: bx.size,
                radius: bx.radius,
                yaw: bx.yaw,
            },
            &field,
            &err,
        )?;
        positive(bx.height_m, format!("{field}.height_m"), &err)?;
        if !(bx.base_m >= 0.0 && bx.base_m < bx.height_m) {
            return Err(err(format!(
                "{field}.base_m: must be in [0, height_m), got {}",
                bx.base_m
            )));
        }
        solids.push(Solid {
            polygon,
            base_m: bx.base_m,
            top_m: bx.height_m,
            appearance: appearance(&bx.appearance, format!("{field}.appearance"))?,
            kind: "box".into(),
        });
    }
    Ok(())
}

/// The file's tables: the top, overhanging its four legs inset 5 cm from the corners.
fn tables(
    file: &WorldFile,
    appearance: &AppearanceOf,
    err: &dyn Fn(String) -> Error,
    solids: &mut Vec<Solid>,
) -> Result<()> {
    for (i, t) in file.tables.iter().enumerate() {
        let field = format!("tables[{i}]");
        let app = appearance(&t.appearance, format!("{field}.appearance"))?;
        positive(t.height_m, format!("{field}.height_m"), &err)?;
        positive(t.top_m, format!("{field}.top_m"), &err)?;
        positive(t.leg_m, format!("{field}.leg_m"), &err)?;
        if !(t.size[0] > 2.0 * t.leg_m + 0.1
            && t.size[1] > 2.0 * t.leg_m + 0.1
            && t.top_m < t.height_m)
        {
            return Err(err(format!(
                "{field}: size must exceed its legs, and top_m < height_m"
            )));
        }
        let c = pt(t.center);
        solids.push(Solid {
            polygon: rotated_rect(c, t.size, t.yaw),
            base_m: t.height_m - t.top_m,
            top_m: t.height_m,
            appearance: app,
            kind: "table".into(),
        });
        // Legs inset 5 cm from the corners: the top overhangs them.
        let (hx, hy) = (
            t.size[0] / 2.0 - 0.05 - t.leg_m / 2.0,
            t.size[1] / 2.0 - 0.05 - t.leg_m / 2.0,
        );
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let leg = Pose2::new(c.x, c.y, t.yaw).transform_point(Point2::new(sx * hx, sy * hy));
            solids.push(Solid {
                polygon: rotated_rect(leg, [t.leg_m, t.leg_m], t.yaw),
                base_m: 0.0,
                top_m: t.height_m - t.top_m,
                appearance: app,
                kind: "table".into(),
            });
        }
    }
    Ok(())
}

/// The file's chairs: the seat, four legs, and the backrest on the chair's -x side.
fn chairs(
    file: &WorldFile,
    appearance: &AppearanceOf,
    err: &dyn Fn(String) -> Error,
    solids: &mut Vec<Solid>,
) -> Result<()> {
    for (i, ch) in file.chairs.iter().enumerate() {
        let field = format!("chairs[{i}]");
        let app = appearance(&ch.appearance, format!("{field}.appearance"))?;
        positive(ch.seat_m, format!("{field}.seat_m"), &err)?;
        positive(ch.size, format!("{field}.size"), &err)?;
        positive(ch.leg_m, format!("{field}.leg_m"), &err)?;
        if ch.size <= 2.0 * ch.leg_m + 0.05 || ch.seat_m <= 0.03 {
            return Err(err(format!("{field}: size must exceed its legs")));
        }
        let pose = Pose2::new(ch.center[0], ch.center[1], ch.yaw);
        let c = pt(ch.center);
        let seat_t = 0.03;
        solids.push(Solid {
            polygon: rotated_rect(c, [ch.size, ch.size], ch.yaw),
            base_m: ch.seat_m - seat_t,
            top_m: ch.seat_m,
            appearance: app,
            kind: "chair".into(),
        });
        let h = ch.size / 2.0 - ch.leg_m / 2.0 - 0.01;
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            solids.push(Solid {
                polygon: rotated_rect(
                    pose.transform_point(Point2::new(sx * h, sy * h)),
                    [ch.leg_m, ch.leg_m],
                    ch.yaw,
                ),
                base_m: 0.0,
                top_m: ch.seat_m - seat_t,
                appearance: app,
                kind: "chair".into(),
            });
        }
        if ch.back {
            // The backrest stands on the chair's -x side (it faces +x).
            let back = pose.transform_point(Point2::new(-ch.size / 2.0 + 0.015, 0.0));
            solids.push(Solid {
                polygon: rotated_rect(back, [0.03, ch.size], ch.yaw),
                base_m: ch.seat_m,
                top_m: ch.seat_m + 0.4,
                appearance: app,
                kind: "chair".into(),
            });
        }
    }

    Ok(())
}
