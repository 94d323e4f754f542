//! How an obstacle face looks ([`Appearance`]): painted walls with a dark baseboard, wood,
//! metal; its albedo at a point of a face, and waiting for a batch of noise values.

use super::*;

/// How an obstacle face looks: painted walls with a dark baseboard, wood, metal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Appearance {
    pub name: String,
    /// Mean albedo in [0, 1].
    pub albedo: f64,
    /// Relative amplitude of the surface texture (paint, grain).
    pub texture: f64,
    /// Scale of the texture [m].
    pub texture_m: f64,
    /// Height of a baseboard strip at the bottom of the face [m] (0 for none).
    pub baseboard_m: f64,
    pub baseboard_albedo: f64,
    pub seed: u64,
}

impl Appearance {
    /// Albedo at position `s` along the face and height `z` [m], footprint `fp`.
    pub fn albedo_at(&self, s: f64, z: f64, fp: Footprint, face_seed: u64) -> f32 {
        self.albedo_cached(s, z, fp, face_seed, &mut NoiseCell::default())
    }

    /// [`Self::albedo_at`], the texture's lattice cell kept in `cell` between calls.
    #[inline]
    pub fn albedo_cached(
        &self,
        s: f64,
        z: f64,
        fp: Footprint,
        face_seed: u64,
        cell: &mut NoiseCell,
    ) -> f32 {
        if z < self.baseboard_m {
            return self.baseboard_albedo as f32;
        }
        let k = detail(self.texture_m, fp);
        let inv = 1.0 / self.texture_m;
        let n = cell.value_noise(s * inv, z * inv, self.seed ^ face_seed);
        self.albedo as f32 * (1.0 + self.texture as f32 * 2.4 * k * n)
    }

    /// [`Self::albedo_cached`] with the texture noise asked of `batch` (evaluated later, for
    /// many pixels at once): Err(albedo) on the baseboard (no noise), else the terms that
    /// [`WallAlbedo::finish`] completes.
    #[inline]
    pub(crate) fn wall_albedo(
        &self,
        s: f64,
        z: f64,
        fp: Footprint,
        face_seed: u64,
        batch: &mut NoiseBatch,
    ) -> Result<WallAlbedo, f32> {
        if z < self.baseboard_m {
            return Err(self.baseboard_albedo as f32);
        }
        let k = detail(self.texture_m, fp);
        let inv = 1.0 / self.texture_m;
        let lane = batch.push(s * inv, z * inv, seed32(self.seed ^ face_seed));
        Ok(WallAlbedo {
            albedo: self.albedo as f32,
            weight: self.texture as f32 * 2.4 * k,
            lane,
        })
    }

    /// Albedo of a horizontal face (table tops, undersides) at `p`.
    pub fn albedo_at_point(&self, p: Point2, fp: Footprint) -> f32 {
        let k = detail(self.texture_m, fp);
        let n = value_noise(
            p.x / self.texture_m,
            p.y / (3.0 * self.texture_m),
            self.seed,
        );
        self.albedo as f32 * (1.0 + self.texture as f32 * 1.7 * k * n)
    }
}

/// A wall's textured albedo waiting for its noise value (see [`Appearance::wall_albedo`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct WallAlbedo {
    albedo: f32,
    weight: f32,
    lane: u32,
}

impl WallAlbedo {
    /// The albedo, once `batch` has evaluated the noise.
    #[inline(always)]
    pub(crate) fn finish(&self, batch: &NoiseBatch) -> f32 {
        self.albedo * (1.0 + self.weight * batch.value(self.lane))
    }
}
