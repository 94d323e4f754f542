//! The world file's coverings and appearances: the built-in ones, replaced or extended by the
//! file's, checked and indexed by name.

use super::build::positive;
use super::*;

/// The world's coverings and appearances, and their indices by name.
pub(super) struct Materials {
    pub(super) coverings: Vec<Covering>,
    pub(super) appearances: Vec<Appearance>,
    cov_index: BTreeMap<String, usize>,
    app_index: BTreeMap<String, usize>,
}

impl Materials {
    pub(super) fn new(file: &WorldFile, err: &dyn Fn(String) -> Error) -> Result<Self> {
        let mut cov_files = default_coverings();
        cov_files.extend(file.coverings.clone());
        let mut coverings = Vec::new();
        let mut cov_index = BTreeMap::new();
        for (name, c) in &cov_files {
            let seed = derive_seed(file.seed, name_hash(name));
            let field = format!("coverings.{name}");
            let (class, albedo, pattern) = covering_of(c, &field, err)?;
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
        Ok(Self {
            coverings,
            appearances,
            cov_index,
            app_index,
        })
    }

    /// The index of the covering `name`; an error naming `field` and the known ones.
    pub(super) fn covering(
        &self,
        name: &str,
        field: String,
        err: &dyn Fn(String) -> Error,
    ) -> Result<usize> {
        self.cov_index.get(name).copied().ok_or_else(|| {
            err(format!(
                "{field}: unknown covering {name:?} (known: {:?})",
                self.cov_index.keys().collect::<Vec<_>>()
            ))
        })
    }

    /// The index of the appearance `name`; an error naming `field` and the known ones.
    pub(super) fn appearance(
        &self,
        name: &str,
        field: String,
        err: &dyn Fn(String) -> Error,
    ) -> Result<usize> {
        self.app_index.get(name).copied().ok_or_else(|| {
            err(format!(
                "{field}: unknown appearance {name:?} (known: {:?})",
                self.app_index.keys().collect::<Vec<_>>()
            ))
        })
    }
}

/// A covering's class, brightness and pattern from its file form, its lengths checked.
fn covering_of(
    c: &CoveringFile,
    field: &str,
    err: &dyn Fn(String) -> Error,
) -> Result<(CoveringClass, f64, FloorPattern)> {
    Ok(match c.clone() {
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
    })
}
