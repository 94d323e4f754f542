//! What surfaces look like: floor coverings (carpet, linoleum, tiles, paper, calibration
//! patterns) and the appearance of obstacle faces (walls, furniture). Textures are functions of
//! the position on the surface, seeded per world, so a place looks the same on every visit.
//!
//! Albedo is in [0, 1]; the renderer multiplies it by the illumination and the exposure.
//! Texture detail finer than a pixel's footprint is attenuated (an area average of many fibres
//! varies less than one fibre), so far carpet looks smoother than near carpet, as in real images.

use floorscan_core::Point2;
use serde::{Deserialize, Serialize};

use crate::noise_cell::NoiseCell;
use crate::noise_lanes::NoiseBatch;
use crate::rng::{fast_floor, hash2, seed32, value_noise};

/// How a floor covering is labelled in the ground truth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CoveringClass {
    /// Carpet: even, fine, low-contrast texture (the paper's texture assumption holds).
    Carpet,
    /// Any other floor covering (linoleum, tiles, a calibration pattern).
    Other,
    /// A scrap of paper lying on the floor: not an obstacle, but it looks like one.
    Paper,
}

/// The procedural pattern of a floor covering.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum FloorPattern {
    /// Fibres of size `grain_m` with relative amplitude `contrast`, plus low-frequency mottling
    /// (`mottle` relative amplitude at the scale `mottle_m`).
    Carpet {
        contrast: f64,
        grain_m: f64,
        mottle: f64,
        mottle_m: f64,
    },
    /// Smooth, slightly mottled sheet with fine speckles.
    Linoleum {
        mottle: f64,
        mottle_m: f64,
        speckle: f64,
    },
    /// Square tiles of side `tile_m` (axis-aligned in the world), separated by grout lines
    /// `grout_m` wide of albedo `grout_albedo`; each tile's albedo varies by `variation`.
    Tiles {
        tile_m: f64,
        grout_m: f64,
        grout_albedo: f64,
        variation: f64,
    },
    /// Wooden planks (parquet, laminate) running along world x: `plank_m` wide, `length_m`
    /// long, each row's joints staggered; each plank's tone varies by `variation`, grain
    /// streaks along the plank have relative amplitude `grain`, and the joints between planks
    /// are dark lines `joint_m` wide of albedo `joint_albedo`.
    Wood {
        plank_m: f64,
        length_m: f64,
        grain: f64,
        variation: f64,
        joint_m: f64,
        joint_albedo: f64,
    },
    /// Carpet (as [`FloorPattern::Carpet`]) printed with a diamond pattern of period
    /// `pattern_m` whose two tones differ by `pattern_contrast` (relative): a textured floor
    /// with large regular edges, as in offices, hotels and malls.
    PatternedCarpet {
        contrast: f64,
        grain_m: f64,
        mottle: f64,
        mottle_m: f64,
        pattern_m: f64,
        pattern_contrast: f64,
    },
    /// Plain paper with a faint texture.
    Paper,
    /// A checkerboard: squares of side `square_m` whose inner corners are at
    /// `origin + i square across + j square away` (i < `corners[0]`, j < `corners[1]`), with
    /// dark squares of albedo `dark_albedo` and a white margin of `margin_m` around it.
    Checkerboard {
        origin: Point2,
        across: Point2,
        away: Point2,
        square_m: f64,
        corners: [u32; 2],
        dark_albedo: f64,
        margin_m: f64,
    },
    /// Dark lines `width_m` wide, `spacing_m` apart: `lines[0]` running away (at across offsets
    /// i spacing from `origin`) and `lines[1]` running across (at away offsets j spacing), each
    /// extending `overhang_m` past the outermost crossings.
    Lines {
        origin: Point2,
        across: Point2,
        away: Point2,
        spacing_m: f64,
        lines: [u32; 2],
        width_m: f64,
        line_albedo: f64,
        overhang_m: f64,
    },
}

/// A floor covering: base albedo and pattern.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Covering {
    pub name: String,
    pub class: CoveringClass,
    /// Mean albedo in [0, 1].
    pub albedo: f64,
    pub pattern: FloorPattern,
    /// Texture seed (derived from the world seed and the covering's name).
    pub seed: u64,
}

/// Standard deviations of [`value_noise`] and of [`hash2`] (uniform on [-1, 1]).
const VALUE_NOISE_STD: f32 = 0.42;
const HASH_STD: f32 = 0.577_350_3;

/// A pixel's footprint on a surface [m], with its inverse (so texture code multiplies).
#[derive(Debug, Clone, Copy)]
pub struct Footprint {
    pub m: f64,
    pub inv: f64,
}

impl Footprint {
    pub fn new(m: f64) -> Footprint {
        let m = m.max(1e-9);
        Footprint { m, inv: 1.0 / m }
    }
}

/// Fraction of a feature's contrast that survives averaging over a footprint: 1 for footprints
/// smaller than the feature, falling as feature / footprint beyond.
#[inline]
fn detail(feature_m: f64, fp: Footprint) -> f32 {
    (feature_m * fp.inv).min(1.0) as f32
}

/// Coverage (0..1) of a line of `width` centred on offset 0, at offset `d`, box-filtered over
/// the footprint (so thin lines fade instead of flickering when they are far).
#[inline]
fn line_coverage(d: f64, width: f64, fp: Footprint) -> f64 {
    let lo = (d - fp.m / 2.0).max(-width / 2.0);
    let hi = (d + fp.m / 2.0).min(width / 2.0);
    ((hi - lo) * fp.inv).clamp(0.0, 1.0)
}

impl Covering {
    /// The covering with its scales inverted, ready for shading.
    pub fn prepare(&self) -> PreparedCovering {
        let (a, b) = match &self.pattern {
            FloorPattern::Carpet {
                grain_m, mottle_m, ..
            } => (1.0 / grain_m, 1.0 / mottle_m),
            FloorPattern::Linoleum { mottle_m, .. } => (1.0 / mottle_m, 0.0),
            FloorPattern::Tiles { tile_m, .. } => (1.0 / tile_m, 0.0),
            FloorPattern::Wood {
                plank_m, length_m, ..
            } => (1.0 / plank_m, 1.0 / length_m),
            FloorPattern::PatternedCarpet {
                grain_m, mottle_m, ..
            } => (1.0 / grain_m, 1.0 / mottle_m),
            _ => (0.0, 0.0),
        };
        PreparedCovering {
            covering: self.clone(),
            inv_a: a,
            inv_b: b,
        }
    }

    /// Albedo at world point `p`, for a pixel whose footprint on the floor is `footprint_m`.
    pub fn albedo_at(&self, p: Point2, footprint_m: f64) -> f32 {
        self.prepare().albedo_at(p, Footprint::new(footprint_m))
    }
}

/// The lattice cells of a carpet's two noises kept from one shaded pixel to the next (see
/// [`NoiseCell`]): pass the same one to [`PreparedCovering::albedo_cached`] for consecutive
/// pixels. Any value is correct; only the speed depends on it.
#[derive(Debug, Clone, Default)]
pub struct CarpetCells {
    fine: NoiseCell,
    coarse: NoiseCell,
}

/// No noise request: the value is given.
pub(crate) const NO_LANE: u32 = u32::MAX;

/// A carpet's albedo waiting for its noise values (see [`PreparedCovering::carpet_albedo`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CarpetAlbedo {
    albedo: f32,
    fine_weight: f32,
    /// The fine term's value when `fine_lane` is [`NO_LANE`] (hashed fibres, or none).
    fine: f32,
    fine_lane: u32,
    coarse_weight: f32,
    coarse_lane: u32,
}

impl CarpetAlbedo {
    /// The albedo, once `batch` has evaluated the noise.
    #[inline(always)]
    pub(crate) fn finish(&self, batch: &NoiseBatch) -> f32 {
        let fine = if self.fine_lane == NO_LANE {
            self.fine
        } else {
            batch.value(self.fine_lane)
        };
        let coarse = batch.value(self.coarse_lane);
        self.albedo * (1.0 + self.fine_weight * fine + self.coarse_weight * coarse)
    }
}

/// A [`Covering`] with inverted scales (see [`Covering::prepare`]).
#[derive(Debug, Clone)]
pub struct PreparedCovering {
    pub covering: Covering,
    inv_a: f64,
    inv_b: f64,
}

impl PreparedCovering {
    /// A carpet's relative texture at `p` (1 on average): fibres of size `grain_m` with
    /// amplitude `contrast` and mottling (scale 1 / inv_b) of amplitude `mottle`. Fibres are
    /// smooth noise where a pixel resolves them; where it spans several, one hashed value per
    /// fibre cell (same spread, a quarter of the work); none where averaging has smoothed
    /// them away.
    #[inline]
    fn carpet_texture(
        &self,
        p: Point2,
        fp: Footprint,
        contrast: f64,
        grain_m: f64,
        mottle: f64,
        cells: &mut CarpetCells,
    ) -> f32 {
        let seed = self.covering.seed;
        let k = detail(grain_m, fp);
        let (gx, gy) = (p.x * self.inv_a, p.y * self.inv_a);
        let fine = if k >= 0.5 {
            cells.fine.value_noise(gx, gy, seed)
        } else if k > 0.02 {
            VALUE_NOISE_STD / HASH_STD * hash2(fast_floor(gx), fast_floor(gy), seed)
        } else {
            0.0
        };
        let coarse = cells
            .coarse
            .value_noise(p.x * self.inv_b, p.y * self.inv_b, seed ^ 0xAA);
        1.0 + contrast as f32 * 2.4 * k * fine + mottle as f32 * 2.4 * coarse
    }

    /// Albedo at world point `p` for a pixel footprint `fp`.
    pub fn albedo_at(&self, p: Point2, fp: Footprint) -> f32 {
        self.albedo_cached(p, fp, &mut CarpetCells::default())
    }

    /// For a plain carpet ([`FloorPattern::Carpet`]), its albedo at `p` with the smooth noise
    /// asked of `batch` (evaluated later, for many pixels at once): the same terms as
    /// [`Self::albedo_cached`], finished by [`CarpetAlbedo::finish`]. None for other patterns.
    #[inline]
    pub(crate) fn carpet_albedo(
        &self,
        p: Point2,
        fp: Footprint,
        batch: &mut NoiseBatch,
    ) -> Option<CarpetAlbedo> {
        let FloorPattern::Carpet {
            contrast,
            grain_m,
            mottle,
            ..
        } = &self.covering.pattern
        else {
            return None;
        };
        // As carpet_texture, term by term.
        let seed = self.covering.seed;
        let k = detail(*grain_m, fp);
        let (gx, gy) = (p.x * self.inv_a, p.y * self.inv_a);
        let (fine, fine_lane) = if k >= 0.5 {
            (0.0, batch.push(gx, gy, seed32(seed)))
        } else if k > 0.02 {
            let v = VALUE_NOISE_STD / HASH_STD * hash2(fast_floor(gx), fast_floor(gy), seed);
            (v, NO_LANE)
        } else {
            (0.0, NO_LANE)
        };
        let coarse_lane = batch.push(p.x * self.inv_b, p.y * self.inv_b, seed32(seed ^ 0xAA));
        Some(CarpetAlbedo {
            albedo: self.covering.albedo as f32,
            fine_weight: *contrast as f32 * 2.4 * k,
            fine,
            fine_lane,
            coarse_weight: *mottle as f32 * 2.4,
            coarse_lane,
        })
    }

    /// [`Self::albedo_at`], the carpet noise's lattice cells kept in `cells` between calls.
    #[inline]
    pub fn albedo_cached(&self, p: Point2, fp: Footprint, cells: &mut CarpetCells) -> f32 {
        let c = &self.covering;
        let a = c.albedo as f32;
        let seed = c.seed;
        match &c.pattern {
            FloorPattern::Carpet {
                contrast,
                grain_m,
                mottle,
                ..
            } => a * self.carpet_texture(p, fp, *contrast, *grain_m, *mottle, cells),
            FloorPattern::Linoleum {
                mottle, speckle, ..
            } => {
                let coarse = value_noise(p.x * self.inv_a, p.y * self.inv_a, seed);
                let fine = hash2(
                    fast_floor(p.x * (1.0 / 0.003)),
                    fast_floor(p.y * (1.0 / 0.003)),
                    seed ^ 0x33,
                );
                a * (1.0
                    + *mottle as f32 * 2.4 * coarse
                    + *speckle as f32 * detail(0.003, fp) * fine)
            }
            FloorPattern::Tiles {
                tile_m,
                grout_m,
                grout_albedo,
                variation,
            } => {
                let (tx, ty) = (p.x * self.inv_a, p.y * self.inv_a);
                let (ix, iy) = (fast_floor(tx), fast_floor(ty));
                let tile = a * (1.0 + *variation as f32 * hash2(ix, iy, seed));
                let speck =
                    0.03 * detail(0.004, fp) * value_noise(p.x * 250.0, p.y * 250.0, seed ^ 7);
                // Distance to the nearest grout line in each direction [m].
                let dx = (tx - ix as f64 - 0.5).abs() * tile_m;
                let dy = (ty - iy as f64 - 0.5).abs() * tile_m;
                let half = tile_m / 2.0;
                let g = line_coverage(half - dx, *grout_m, fp).max(line_coverage(
                    half - dy,
                    *grout_m,
                    fp,
                )) as f32;
                (tile * (1.0 + speck)) * (1.0 - g) + *grout_albedo as f32 * g
            }
            FloorPattern::Wood {
                plank_m,
                length_m,
                grain,
                variation,
                joint_m,
                joint_albedo,
            } => {
                // Plank rows across y; along x, each row's joints shifted by a hashed fraction
                // of the plank length (a staggered floor, not a grid).
                let ty = p.y * self.inv_a;
                let row = fast_floor(ty);
                let shift = 0.5 * (1.0 + hash2(row, 0, seed ^ 0x5EED) as f64);
                let tx = p.x * self.inv_b + shift;
                let col = fast_floor(tx);
                let plank = a * (1.0 + *variation as f32 * hash2(col, row, seed));
                // Grain: streaks along the plank (stretched noise), fading with the footprint.
                let streak =
                    value_noise(p.x * (1.0 / 0.15), p.y * (1.0 / 0.0025), seed ^ col as u64);
                let wood = plank * (1.0 + *grain as f32 * 2.4 * detail(0.0025, fp) * streak);
                // Joints: along the plank edges (offset 0 in y) and at the butt ends (in x).
                let dy = (ty - row as f64 - 0.5).abs() * plank_m;
                let dx = (tx - col as f64 - 0.5).abs() * length_m;
                let g = line_coverage(plank_m / 2.0 - dy, *joint_m, fp).max(line_coverage(
                    length_m / 2.0 - dx,
                    *joint_m,
                    fp,
                )) as f32;
                wood * (1.0 - g) + *joint_albedo as f32 * g
            }
            FloorPattern::PatternedCarpet {
                contrast,
                grain_m,
                mottle,
                pattern_m,
                pattern_contrast,
                ..
            } => {
                // Diamonds: squares turned 45 degrees, blended across their edges over the
                // pixel's footprint (anti-aliased like the checkerboard).
                let u = (p.x + p.y) / pattern_m;
                let v = (p.x - p.y) / pattern_m;
                let parity = (fast_floor(u) + fast_floor(v)).rem_euclid(2) == 0;
                let edge = (u - u.round()).abs().min((v - v.round()).abs()) * pattern_m
                    / std::f64::consts::SQRT_2;
                let w = ((edge * fp.inv) + 0.5).clamp(0.5, 1.0) as f32;
                let pc = *pattern_contrast as f32;
                let (own, other) = if parity {
                    (1.0 + pc, 1.0 - pc)
                } else {
                    (1.0 - pc, 1.0 + pc)
                };
                let tone = own * w + other * (1.0 - w);
                a * tone * self.carpet_texture(p, fp, *contrast, *grain_m, *mottle, cells)
            }
            FloorPattern::Paper => {
                a * (1.0 + 0.02 * detail(0.002, fp) * value_noise(p.x * 500.0, p.y * 500.0, seed))
            }
            FloorPattern::Checkerboard {
                origin,
                across,
                away,
                square_m,
                corners,
                dark_albedo,
                margin_m,
            } => {
                let q = Point2::new(p.x - origin.x, p.y - origin.y);
                let i = (q.x * across.x + q.y * across.y) / square_m;
                let j = (q.x * away.x + q.y * away.y) / square_m;
                let (n_i, n_j) = (corners[0] as f64, corners[1] as f64);
                let m = margin_m / square_m;
                if i < -1.0 - m || j < -1.0 - m || i > n_i + m || j > n_j + m {
                    return a; // outside the sheet: shouldn't happen within its region
                }
                if i < -1.0 || j < -1.0 || i > n_i || j > n_j {
                    return a; // white margin
                }
                // Anti-aliased squares: blend by the distance to the nearest square edge.
                let parity = ((i.floor() as i64 + j.floor() as i64).rem_euclid(2)) == 0;
                let di = (i - i.round()).abs() * square_m;
                let dj = (j - j.round()).abs() * square_m;
                let near_edge = di.min(dj);
                let w = ((near_edge * fp.inv) + 0.5).clamp(0.5, 1.0) as f32;
                let (own, other) = if parity {
                    (*dark_albedo as f32, a)
                } else {
                    (a, *dark_albedo as f32)
                };
                own * w + other * (1.0 - w)
            }
            FloorPattern::Lines {
                origin,
                across,
                away,
                spacing_m,
                lines,
                width_m,
                line_albedo,
                overhang_m,
            } => {
                let q = Point2::new(p.x - origin.x, p.y - origin.y);
                let s_across = q.x * across.x + q.y * across.y;
                let s_away = q.x * away.x + q.y * away.y;
                let extent_across = (lines[0].max(1) - 1) as f64 * spacing_m;
                let extent_away = (lines[1].max(1) - 1) as f64 * spacing_m;
                let mut cover: f64 = 0.0;
                // Lines running away: constant across-offset, within the away extent.
                if s_away >= -overhang_m && s_away <= extent_away + overhang_m {
                    let k = (s_across / spacing_m)
                        .round()
                        .clamp(0.0, (lines[0].max(1) - 1) as f64);
                    cover = cover.max(line_coverage(s_across - k * spacing_m, *width_m, fp));
                }
                if s_across >= -overhang_m && s_across <= extent_across + overhang_m {
                    let k = (s_away / spacing_m)
                        .round()
                        .clamp(0.0, (lines[1].max(1) - 1) as f64);
                    cover = cover.max(line_coverage(s_away - k * spacing_m, *width_m, fp));
                }
                // Tape on carpet: the background keeps a carpet's fine texture.
                let k = detail(0.004, fp);
                let bg = a * (1.0 + 0.1 * k * value_noise(p.x * 250.0, p.y * 250.0, seed));
                let c = cover as f32;
                bg * (1.0 - c) + *line_albedo as f32 * c
            }
        }
    }
}

#[path = "texture_appearance.rs"]
mod appearance;
pub use appearance::Appearance;
pub(crate) use appearance::WallAlbedo;

#[cfg(test)]
#[path = "texture_tests.rs"]
mod tests;
