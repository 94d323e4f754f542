//! The world file (TOML), documented in docs/simulator.md: the schema, defaults, and its
//! conversion to a [`World`]. Syntax and type errors name the line and column (from the TOML
//! parser); value errors name the field path, e.g. `walls[3].height_m`.

use std::collections::BTreeMap;

use floorscan_core::{Point2, Pose2};
use serde::Deserialize;

use crate::contact_shadow::ContactShadow;
use crate::error::{Error, Result};
use crate::geometry::{circle_polygon, rotated_rect};
use crate::rng::derive_seed;
use crate::texture::{Appearance, Covering, CoveringClass, FloorPattern};
use crate::world::{FloorRegion, Light, Lighting, Solid, World};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WorldFile {
    name: String,
    #[serde(default)]
    description: String,
    #[serde(default)]
    seed: u64,
    #[serde(default = "default_ceiling")]
    ceiling_m: f64,
    start: StartFile,
    #[serde(default)]
    tour: Vec<[f64; 2]>,
    #[serde(default)]
    floor: FloorFile,
    #[serde(default)]
    coverings: BTreeMap<String, CoveringFile>,
    #[serde(default)]
    appearances: BTreeMap<String, AppearanceFile>,
    #[serde(default)]
    regions: Vec<RegionFile>,
    #[serde(default)]
    walls: Vec<WallFile>,
    #[serde(default)]
    boxes: Vec<BoxFile>,
    #[serde(default)]
    tables: Vec<TableFile>,
    #[serde(default)]
    chairs: Vec<ChairFile>,
    #[serde(default)]
    lighting: LightingFile,
}

fn default_ceiling() -> f64 {
    2.6
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StartFile {
    x: f64,
    y: f64,
    #[serde(default)]
    yaw: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FloorFile {
    covering: String,
}

impl Default for FloorFile {
    fn default() -> Self {
        Self {
            covering: "carpet".into(),
        }
    }
}

#[derive(Deserialize, Clone)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum CoveringFile {
    Carpet {
        brightness: f64,
        #[serde(default = "d_contrast")]
        contrast: f64,
        #[serde(default = "d_grain")]
        grain_m: f64,
        #[serde(default = "d_mottle")]
        mottle: f64,
        #[serde(default = "d_mottle_m")]
        mottle_m: f64,
    },
    Linoleum {
        brightness: f64,
        #[serde(default = "d_mottle")]
        mottle: f64,
        #[serde(default = "d_mottle_m")]
        mottle_m: f64,
        #[serde(default = "d_speckle")]
        speckle: f64,
    },
    Tiles {
        brightness: f64,
        #[serde(default = "d_tile")]
        tile_m: f64,
        #[serde(default = "d_grout")]
        grout_m: f64,
        #[serde(default = "d_grout_brightness")]
        grout_brightness: f64,
        #[serde(default = "d_variation")]
        variation: f64,
    },
    Wood {
        brightness: f64,
        #[serde(default = "d_plank")]
        plank_m: f64,
        #[serde(default = "d_plank_length")]
        length_m: f64,
        #[serde(default = "d_wood_grain")]
        grain: f64,
        #[serde(default = "d_variation")]
        variation: f64,
        #[serde(default = "d_joint")]
        joint_m: f64,
        #[serde(default = "d_joint_brightness")]
        joint_brightness: f64,
    },
    PatternedCarpet {
        brightness: f64,
        #[serde(default = "d_contrast")]
        contrast: f64,
        #[serde(default = "d_grain")]
        grain_m: f64,
        #[serde(default = "d_mottle")]
        mottle: f64,
        #[serde(default = "d_mottle_m")]
        mottle_m: f64,
        #[serde(default = "d_pattern")]
        pattern_m: f64,
        #[serde(default = "d_pattern_contrast")]
        pattern_contrast: f64,
    },
    Paper {
        brightness: f64,
    },
}

fn d_plank() -> f64 {
    0.12
}
fn d_plank_length() -> f64 {
    1.2
}
fn d_wood_grain() -> f64 {
    0.08
}
fn d_joint() -> f64 {
    0.002
}
fn d_joint_brightness() -> f64 {
    0.35
}
fn d_pattern() -> f64 {
    0.3
}
fn d_pattern_contrast() -> f64 {
    0.2
}

fn d_contrast() -> f64 {
    0.06
}
fn d_grain() -> f64 {
    0.004
}
fn d_mottle() -> f64 {
    0.03
}
fn d_mottle_m() -> f64 {
    0.5
}
fn d_speckle() -> f64 {
    0.03
}
fn d_tile() -> f64 {
    0.3
}
fn d_grout() -> f64 {
    0.008
}
fn d_grout_brightness() -> f64 {
    0.25
}
fn d_variation() -> f64 {
    0.12
}

#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
struct AppearanceFile {
    brightness: f64,
    #[serde(default = "d_texture")]
    texture: f64,
    #[serde(default = "d_texture_m")]
    texture_m: f64,
    #[serde(default)]
    baseboard_m: f64,
    #[serde(default = "d_baseboard_brightness")]
    baseboard_brightness: f64,
}

fn d_texture() -> f64 {
    0.03
}
fn d_texture_m() -> f64 {
    0.05
}
fn d_baseboard_brightness() -> f64 {
    0.15
}

/// A shape: exactly one of `rect = [xmin, ymin, xmax, ymax]`, `polygon = [[x, y], ...]`,
/// `center` + `size` (+ `yaw`), `center` + `radius`.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RegionFile {
    covering: String,
    rect: Option<[f64; 4]>,
    polygon: Option<Vec<[f64; 2]>>,
    center: Option<[f64; 2]>,
    size: Option<[f64; 2]>,
    radius: Option<f64>,
    #[serde(default)]
    yaw: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WallFile {
    from: [f64; 2],
    to: [f64; 2],
    #[serde(default)]
    doors: Vec<[f64; 2]>,
    height_m: Option<f64>,
    #[serde(default = "d_thickness")]
    thickness_m: f64,
    #[serde(default = "d_wall")]
    appearance: String,
}

fn d_thickness() -> f64 {
    0.1
}
fn d_wall() -> String {
    "wall".into()
}
fn d_wood() -> String {
    "wood".into()
}
fn d_metal() -> String {
    "metal".into()
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BoxFile {
    rect: Option<[f64; 4]>,
    polygon: Option<Vec<[f64; 2]>>,
    center: Option<[f64; 2]>,
    size: Option<[f64; 2]>,
    radius: Option<f64>,
    #[serde(default)]
    yaw: f64,
    #[serde(default)]
    base_m: f64,
    height_m: f64,
    #[serde(default = "d_wood")]
    appearance: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TableFile {
    center: [f64; 2],
    size: [f64; 2],
    #[serde(default)]
    yaw: f64,
    #[serde(default = "d_table_height")]
    height_m: f64,
    #[serde(default = "d_table_top")]
    top_m: f64,
    #[serde(default = "d_table_leg")]
    leg_m: f64,
    #[serde(default = "d_wood")]
    appearance: String,
}

fn d_table_height() -> f64 {
    0.72
}
fn d_table_top() -> f64 {
    0.03
}
fn d_table_leg() -> f64 {
    0.05
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ChairFile {
    center: [f64; 2],
    #[serde(default)]
    yaw: f64,
    #[serde(default = "d_seat")]
    seat_m: f64,
    #[serde(default = "d_chair_size")]
    size: f64,
    #[serde(default = "d_chair_leg")]
    leg_m: f64,
    #[serde(default = "d_true")]
    back: bool,
    #[serde(default = "d_metal")]
    appearance: String,
}

fn d_seat() -> f64 {
    0.45
}
fn d_chair_size() -> f64 {
    0.42
}
fn d_chair_leg() -> f64 {
    0.025
}
fn d_true() -> bool {
    true
}

/// `[lighting]`: every field has a default (`impl Default`), so a world may leave any out.
#[derive(Deserialize)]
#[serde(default, deny_unknown_fields)]
struct LightingFile {
    ambient: f64,
    exposure: f64,
    exposure_jitter: f64,
    wall_factor: f64,
    ceiling_brightness: f64,
    lights: Vec<LightFile>,
    grid: Option<LightGridFile>,
    contact_shadow: ContactShadow,
}

impl Default for LightingFile {
    fn default() -> Self {
        Self {
            ambient: 0.45,
            exposure: 1.0,
            exposure_jitter: 0.03,
            wall_factor: 0.75,
            ceiling_brightness: 0.6,
            lights: vec![],
            grid: None,
            contact_shadow: ContactShadow::default(),
        }
    }
}
fn d_power() -> f64 {
    0.8
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFile {
    position: [f64; 2],
    height_m: Option<f64>,
    #[serde(default = "d_power")]
    power: f64,
}

/// Lights on a regular grid over `area = [xmin, ymin, xmax, ymax]` (default: the world's
/// bounds), `spacing_m` apart, at the ceiling.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightGridFile {
    spacing_m: f64,
    #[serde(default = "d_power")]
    power: f64,
    area: Option<[f64; 4]>,
}

/// Stable 64-bit hash of a name (FNV-1a), for texture seeds.
fn name_hash(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

fn default_coverings() -> BTreeMap<String, CoveringFile> {
    let mut m = BTreeMap::new();
    m.insert(
        "carpet".into(),
        CoveringFile::Carpet {
            brightness: 0.32,
            contrast: d_contrast(),
            grain_m: d_grain(),
            mottle: d_mottle(),
            mottle_m: d_mottle_m(),
        },
    );
    m.insert(
        "linoleum".into(),
        CoveringFile::Linoleum {
            brightness: 0.55,
            mottle: 0.04,
            mottle_m: 0.25,
            speckle: d_speckle(),
        },
    );
    m.insert(
        "tiles".into(),
        CoveringFile::Tiles {
            brightness: 0.62,
            tile_m: d_tile(),
            grout_m: d_grout(),
            grout_brightness: d_grout_brightness(),
            variation: d_variation(),
        },
    );
    m.insert("paper".into(), CoveringFile::Paper { brightness: 0.85 });
    m
}

fn default_appearances() -> BTreeMap<String, AppearanceFile> {
    let a = |brightness, texture, texture_m, baseboard_m| AppearanceFile {
        brightness,
        texture,
        texture_m,
        baseboard_m,
        baseboard_brightness: d_baseboard_brightness(),
    };
    let mut m = BTreeMap::new();
    m.insert("wall".into(), a(0.62, 0.025, 0.06, 0.08));
    m.insert("wood".into(), a(0.38, 0.08, 0.02, 0.0));
    m.insert("metal".into(), a(0.22, 0.03, 0.05, 0.0));
    m.insert("door".into(), a(0.5, 0.04, 0.03, 0.0));
    m.insert("cabinet".into(), a(0.55, 0.02, 0.08, 0.0));
    m
}

/// Parses a world file. `source_name` (a path or a built-in name) prefixes the messages.
pub fn parse_world(text: &str, source_name: &str) -> Result<World> {
    let err = |reason: String| Error::InvalidWorld {
        source_name: source_name.to_string(),
        reason,
    };
    let file: WorldFile =
        toml::from_str(text).map_err(|e| err(e.to_string().trim_end().to_string()))?;
    let mut world = build(file, source_name)?;
    world.source = Some(text.to_string());
    Ok(world)
}

fn pt(p: [f64; 2]) -> Point2 {
    Point2::new(p[0], p[1])
}

struct Shape<'a> {
    rect: Option<[f64; 4]>,
    polygon: Option<&'a Vec<[f64; 2]>>,
    center: Option<[f64; 2]>,
    size: Option<[f64; 2]>,
    radius: Option<f64>,
    yaw: f64,
}

fn shape_polygon(s: Shape, field: &str, err: &dyn Fn(String) -> Error) -> Result<Vec<Point2>> {
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

fn positive(v: f64, field: String, err: &dyn Fn(String) -> Error) -> Result<f64> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(err(format!("{field}: must be > 0, got {v}")))
    }
}

fn build(file: WorldFile, source_name: &str) -> Result<World> {
    let err = |reason: String| Error::InvalidWorld {
        source_name: source_name.to_string(),
        reason,
    };
    let ceiling = positive(file.ceiling_m, "ceiling_m".into(), &err)?;

    // Coverings and appearances: the defaults, replaced or extended by the file's.
    let mut cov_files = default_coverings();
    cov_files.extend(file.coverings.clone());
    let mut coverings = Vec::new();
    let mut cov_index = BTreeMap::new();
    for (name, c) in &cov_files {
        let seed = derive_seed(file.seed, name_hash(name));
        let field = format!("coverings.{name}");
        let (class, albedo, pattern) = match c.clone() {
            CoveringFile::Carpet {
                brightness,
                contrast,
                grain_m,
                mottle,
                mottle_m,
            } => {
                positive(grain_m, format!("{field}.grain_m"), &err)?;
                positive(mottle_m, format!("{field}.mottle_m"), &err)?;
                (
                    CoveringClass::Carpet,
                    brightness,
                    FloorPattern::Carpet {
                        contrast,
                        grain_m,
                        mottle,
                        mottle_m,
                    },
                )
            }
            CoveringFile::Linoleum {
                brightness,
                mottle,
                mottle_m,
                speckle,
            } => {
                positive(mottle_m, format!("{field}.mottle_m"), &err)?;
                (
                    CoveringClass::Other,
                    brightness,
                    FloorPattern::Linoleum {
                        mottle,
                        mottle_m,
                        speckle,
                    },
                )
            }
            CoveringFile::Tiles {
                brightness,
                tile_m,
                grout_m,
                grout_brightness,
                variation,
            } => {
                positive(tile_m, format!("{field}.tile_m"), &err)?;
                positive(grout_m, format!("{field}.grout_m"), &err)?;
                (
                    CoveringClass::Other,
                    brightness,
                    FloorPattern::Tiles {
                        tile_m,
                        grout_m,
                        grout_albedo: grout_brightness,
                        variation,
                    },
                )
            }
            CoveringFile::Wood {
                brightness,
                plank_m,
                length_m,
                grain,
                variation,
                joint_m,
                joint_brightness,
            } => {
                positive(plank_m, format!("{field}.plank_m"), &err)?;
                positive(length_m, format!("{field}.length_m"), &err)?;
                positive(joint_m, format!("{field}.joint_m"), &err)?;
                (
                    CoveringClass::Other,
                    brightness,
                    FloorPattern::Wood {
                        plank_m,
                        length_m,
                        grain,
                        variation,
                        joint_m,
                        joint_albedo: joint_brightness,
                    },
                )
            }
            CoveringFile::PatternedCarpet {
                brightness,
                contrast,
                grain_m,
                mottle,
                mottle_m,
                pattern_m,
                pattern_contrast,
            } => {
                positive(grain_m, format!("{field}.grain_m"), &err)?;
                positive(mottle_m, format!("{field}.mottle_m"), &err)?;
                positive(pattern_m, format!("{field}.pattern_m"), &err)?;
                if !(0.0..1.0).contains(&pattern_contrast) {
                    return Err(err(format!(
                        "{field}.pattern_contrast: must be in [0, 1), got {pattern_contrast}"
                    )));
                }
                (
                    CoveringClass::Other,
                    brightness,
                    FloorPattern::PatternedCarpet {
                        contrast,
                        grain_m,
                        mottle,
                        mottle_m,
                        pattern_m,
                        pattern_contrast,
                    },
                )
            }
            CoveringFile::Paper { brightness } => {
                (CoveringClass::Paper, brightness, FloorPattern::Paper)
            }
        };
        if !(0.0..=1.0).contains(&albedo) {
            return Err(err(format!(
                "{field}.brightness: must be in [0, 1], got {albedo}"
            )));
        }
        cov_index.insert(name.clone(), coverings.len());
        coverings.push(Covering {
            name: name.clone(),
            class,
            albedo,
            pattern,
            seed,
        });
    }
    let mut app_files = default_appearances();
    app_files.extend(file.appearances.clone());
    let mut appearances = Vec::new();
    let mut app_index = BTreeMap::new();
    for (name, a) in &app_files {
        let field = format!("appearances.{name}");
        if !(0.0..=1.0).contains(&a.brightness) {
            return Err(err(format!(
                "{field}.brightness: must be in [0, 1], got {}",
                a.brightness
            )));
        }
        positive(a.texture_m, format!("{field}.texture_m"), &err)?;
        app_index.insert(name.clone(), appearances.len());
        appearances.push(Appearance {
            name: name.clone(),
            albedo: a.brightness,
            texture: a.texture,
            texture_m: a.texture_m,
            baseboard_m: a.baseboard_m,
            baseboard_albedo: a.baseboard_brightness,
            seed: derive_seed(file.seed, name_hash(name) ^ 0xA5A5),
        });
    }
    let covering = |name: &str, field: String| -> Result<usize> {
        cov_index.get(name).copied().ok_or_else(|| {
            err(format!(
                "{field}: unknown covering {name:?} (known: {:?})",
                cov_index.keys().collect::<Vec<_>>()
            ))
        })
    };
    let appearance = |name: &str, field: String| -> Result<usize> {
        app_index.get(name).copied().ok_or_else(|| {
            err(format!(
                "{field}: unknown appearance {name:?} (known: {:?})",
                app_index.keys().collect::<Vec<_>>()
            ))
        })
    };

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

    let mut solids = Vec::new();
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
        coverings,
        appearances,
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

#[cfg(test)]
#[path = "world_file_tests.rs"]
mod tests;
