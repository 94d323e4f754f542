//! A parsed world file turned into a [`World`]: materials, floor regions, solids, lights,
//! every value checked, errors naming the field path.

use super::materials::Materials;
use super::solids::solids;
use super::*;

/// The world a parsed file describes, every value checked (errors name the field path).
pub(super) fn build(file: WorldFile, source_name: &str) -> Result<World> {
    let err = |reason: String| Error::InvalidWorld {
        source_name: source_name.to_string(),
        reason,
    };
    let ceiling = positive(file.ceiling_m, "ceiling_m".into(), &err)?;

    let materials = Materials::new(&file, &err)?;
    let covering = |name: &str, field: String| materials.covering(name, field, &err);

    let mut regions = Vec::new();
    for (i, r) in file.regions.iter().enumerate() {
        let field = format!("regions[{i}]");
        let polygon = shape_polygon(
            Shape {
                rect: r.rect,
                polygon: r.polygon.as_ref(),
                center: r.center,
                size: r.size,
                radius: r.radius,
                yaw: r.yaw,
            },
            &field,
            &err,
        )?;
        regions.push(FloorRegion {
            polygon,
            covering: covering(&r.covering, format!("{field}.covering"))?,
        });
    }

    let solids = solids(&file, ceiling, &materials, &err)?;

    let l = &file.lighting;
    let mut lights = Vec::new();
    for (i, lf) in l.lights.iter().enumerate() {
        let h = positive(
            lf.height_m.unwrap_or(ceiling),
            format!("lighting.lights[{i}].height_m"),
            &err,
        )?;
        lights.push(Light {
            position: pt(lf.position),
            height_m: h,
            power: lf.power,
        });
    }
    let mut world = World {
        name: file.name.clone(),
        description: file.description.clone(),
        ceiling_m: ceiling,
        start: Pose2::new(file.start.x, file.start.y, file.start.yaw),
        tour: file.tour.iter().copied().map(pt).collect(),
        solids,
        regions,
        floor_covering: covering(&file.floor.covering, "floor.covering".into())?,
        coverings: materials.coverings,
        appearances: materials.appearances,
        lighting: Lighting {
            ambient: l.ambient,
            lights,
            exposure: l.exposure,
            exposure_jitter: l.exposure_jitter,
            wall_factor: l.wall_factor,
            ceiling_brightness: l.ceiling_brightness,
            contact_shadow: l.contact_shadow,
        },
        source: None,
    };
    if let Some(g) = &l.grid {
        let spacing = positive(g.spacing_m, "lighting.grid.spacing_m".into(), &err)?;
        let b = world.bounds();
        let area = g.area.unwrap_or([b.min.x, b.min.y, b.max.x, b.max.y]);
        let nx = (((area[2] - area[0]) / spacing).floor() as i64).clamp(0, 10_000) + 1;
        let ny = (((area[3] - area[1]) / spacing).floor() as i64).clamp(0, 10_000) + 1;
        if nx * ny > 100_000 {
            return Err(err("lighting.grid: more than 100000 lights".into()));
        }
        // Centre the grid in the area.
        let x0 = (area[0] + area[2]) / 2.0 - (nx - 1) as f64 * spacing / 2.0;
        let y0 = (area[1] + area[3]) / 2.0 - (ny - 1) as f64 * spacing / 2.0;
        for i in 0..nx {
            for j in 0..ny {
                world.lighting.lights.push(Light {
                    position: Point2::new(x0 + i as f64 * spacing, y0 + j as f64 * spacing),
                    height_m: ceiling,
                    power: g.power,
                });
            }
        }
    }
    World::new(world).map_err(|e| match e {
        Error::InvalidWorld { reason, .. } => err(reason),
        other => other,
    })
}

pub(super) fn pt(p: [f64; 2]) -> Point2 {
    Point2::new(p[0], p[1])
}

pub(super) struct Shape<'a> {
    pub(super) rect: Option<[f64; 4]>,
    pub(super) polygon: Option<&'a Vec<[f64; 2]>>,
    pub(super) center: Option<[f64; 2]>,
    pub(super) size: Option<[f64; 2]>,
    pub(super) radius: Option<f64>,
    pub(super) yaw: f64,
}

pub(super) fn shape_polygon(
    s: Shape,
    field: &str,
    err: &dyn Fn(String) -> Error,
) -> Result<Vec<Point2>> {
    let given = [
        s.rect.is_some(),
        s.polygon.is_some(),
        s.size.is_some(),
        s.radius.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        return Err(err(format!(
            "{field}: give exactly one of `rect`, `polygon`, `center` + `size`, `center` + `radius`"
        )));
    }
    if let Some(r) = s.rect {
        if !(r[2] > r[0] && r[3] > r[1]) {
            return Err(err(format!(
                "{field}.rect: needs xmin < xmax and ymin < ymax, got {r:?}"
            )));
        }
        return Ok(vec![
            pt([r[0], r[1]]),
            pt([r[2], r[1]]),
            pt([r[2], r[3]]),
            pt([r[0], r[3]]),
        ]);
    }
    if let Some(p) = s.polygon {
        return Ok(p.iter().copied().map(pt).collect());
    }
    let center = s
        .center
        .ok_or_else(|| err(format!("{field}: `size` and `radius` need a `center`")))?;
    if let Some(size) = s.size {
        if !(size[0] > 0.0 && size[1] > 0.0) {
            return Err(err(format!("{field}.size: must be > 0, got {size:?}")));
        }
        return Ok(rotated_rect(pt(center), size, s.yaw));
    }
    let r = s.radius.unwrap_or(0.0);
    if !(r > 0.0 && r.is_finite()) {
        return Err(err(format!("{field}.radius: must be > 0, got {r}")));
    }
    Ok(circle_polygon(pt(center), r, 12))
}

pub(super) fn positive(v: f64, field: String, err: &dyn Fn(String) -> Error) -> Result<f64> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(err(format!("{field}: must be > 0, got {v}")))
    }
}
