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

#[path = "world_file_build.rs"]
mod build;
#[path = "world_file_materials.rs"]
mod materials;
#[path = "world_file_solids.rs"]
mod solids;
use build::build;

#[cfg(test)]
#[path = "world_file_tests.rs"]
mod tests;
