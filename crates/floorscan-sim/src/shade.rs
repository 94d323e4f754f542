//! Shading a ray's hit: the radiance (albedo times illumination) a pixel sees, the identity of
//! the surface (so the renderer can find edges between surfaces) and its label.

use floorscan_core::Point2;

use crate::cell_memo::CellMemo;
use crate::lightmap::LightBatch;
use crate::noise_cell::NoiseCell;
use crate::noise_lanes::NoiseBatch;
use crate::scene::{Hit, Scene, Surface};
use crate::texture::{CarpetAlbedo, CarpetCells, CoveringClass, Footprint, WallAlbedo};
use crate::truth::PixelLabel;

pub(crate) const ID_NOTHING: u32 = 0;
const ID_CEILING: u32 = 1;
const ID_SIDE: u32 = 1 << 30;
const ID_CAP: u32 = 1 << 31;

/// A shaded sample: radiance (albedo times illumination), surface identity (for finding
/// edges) and label.
pub(crate) struct Sample {
    pub radiance: f32,
    pub id: u32,
    pub label: PixelLabel,
}

/// Texture lattice cells kept from one shaded sample to the next: neighbouring pixels mostly
/// fall in the same cells, and then skip the hashing. Any state gives the same samples.
#[derive(Debug, Clone, Default)]
pub(crate) struct ShadeCache {
    carpet: CarpetCells,
    wall: NoiseCell,
    covering: CellMemo<usize>,
    light: CellMemo<[f32; 4]>,
}

/// Shades a hit seen along `d` by a pixel of angle `pixel_angle` [rad].
#[inline]
pub(crate) fn shade(
    scene: &Scene,
    hit: &Hit,
    pixel_angle: f32,
    floor_footprint: Footprint,
    cache: &mut ShadeCache,
) -> Sample {
    let world = &scene.world;
    let p = Point2::new(hit.point[0], hit.point[1]);
    match hit.surface {
        Surface::Nothing => Sample {
            radiance: 0.0,
            id: ID_NOTHING,
            label: PixelLabel::Nothing,
        },
        Surface::Ceiling => Sample {
            radiance: world.lighting.ceiling_brightness as f32,
            id: ID_CEILING,
            label: PixelLabel::Ceiling,
        },
        Surface::Floor => {
            let c = scene.covering_cached(p, &mut cache.covering);
            let covering = &scene.coverings[c];
            let albedo = covering.albedo_cached(p, floor_footprint, &mut cache.carpet);
            let label = floor_label(covering.covering.class);
            Sample {
                radiance: albedo * scene.light.at_cached(p, &mut cache.light) * scene.shadow_at(p),
                id: 2 + c as u32,
                label,
            }
        }
        Surface::Side { face, s } => {
            let f = &scene.sides[face as usize];
            let solid = &world.solids[f.solid as usize];
            let app = &world.appearances[solid.appearance];
            let albedo = app.albedo_cached(
                s,
                hit.point[2],
                Footprint::new(hit.t * pixel_angle as f64),
                f.seed,
                &mut cache.wall,
            );
            // Faces turned differently are lit differently (a fixed main light direction).
            let turn = f.turn;
            let radiance = albedo
                * scene.light.at_cached(p, &mut cache.light)
                * world.lighting.wall_factor as f32
                * turn;
            Sample {
                radiance,
                id: ID_SIDE | face,
                label: PixelLabel::Obstacle,
            }
        }
        Surface::Cap { solid, up } => {
            let app = &world.appearances[world.solids[solid as usize].appearance];
            let albedo = app.albedo_at_point(p, Footprint::new(hit.t * pixel_angle as f64));
            let light = if up {
                scene.light.at_cached(p, &mut cache.light)
            } else {
                0.4 * world.lighting.ambient as f32
            };
            Sample {
                radiance: albedo * light,
                id: ID_CAP | solid << 1 | up as u32,
                label: PixelLabel::Obstacle,
            }
        }
    }
}

/// A shaded sample's radiance, possibly waiting for texture noise and light that batches
/// evaluate for many pixels at once (see [`shade_pending`]).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Pending {
    Done(f32),
    /// Carpet: albedo times the light (request `light` of the light batch) times the contact
    /// shadow's factor.
    Carpet {
        albedo: CarpetAlbedo,
        light: u32,
        shadow: f32,
    },
    /// A wall: albedo times the light, times the wall factor and the face's turn.
    Wall {
        albedo: WallAlbedo,
        light: u32,
        wall_factor: f32,
        turn: f32,
    },
}

impl Pending {
    /// The radiance, once `noise` and `lights` are evaluated: [`shade`]'s, bit for bit.
    #[inline(always)]
    pub(crate) fn finish(&self, noise: &NoiseBatch, lights: &LightBatch) -> f32 {
        match *self {
            Pending::Done(radiance) => radiance,
            Pending::Carpet {
                albedo,
                light,
                shadow,
            } => albedo.finish(noise) * lights.value(light) * shadow,
            Pending::Wall {
                albedo,
                light,
                wall_factor,
                turn,
            } => albedo.finish(noise) * lights.value(light) * wall_factor * turn,
        }
    }
}

/// [`shade`] with the smooth texture noise of plain carpets and of walls asked of `noise`
/// and their light asked of `lights` instead of computed: the radiance is
/// [`Pending::finish`]ed once the batches are evaluated (the same bits). Returns it with the
/// sample's identity and label.
#[inline]
pub(crate) fn shade_pending(
    scene: &Scene,
    hit: &Hit,
    pixel_angle: f32,
    floor_footprint: Footprint,
    cache: &mut ShadeCache,
    noise: &mut NoiseBatch,
    lights: &mut LightBatch,
) -> (Pending, u32, PixelLabel) {
    let world = &scene.world;
    let p = Point2::new(hit.point[0], hit.point[1]);
    match hit.surface {
        Surface::Floor => {
            let c = scene.covering_cached(p, &mut cache.covering);
            let covering = &scene.coverings[c];
            if let Some(albedo) = covering.carpet_albedo(p, floor_footprint, noise) {
                let label = floor_label(covering.covering.class);
                let light = lights.push(p);
                let shadow = scene.shadow_at(p);
                return (
                    Pending::Carpet {
                        albedo,
                        light,
                        shadow,
                    },
                    2 + c as u32,
                    label,
                );
            }
        }
        Surface::Side { face, s } => {
            let f = &scene.sides[face as usize];
            let solid = &world.solids[f.solid as usize];
            let app = &world.appearances[solid.appearance];
            let fp = Footprint::new(hit.t * pixel_angle as f64);
            if let Ok(albedo) = app.wall_albedo(s, hit.point[2], fp, f.seed, noise) {
                let pending = Pending::Wall {
                    albedo,
                    light: lights.push(p),
                    wall_factor: world.lighting.wall_factor as f32,
                    turn: f.turn,
                };
                return (pending, ID_SIDE | face, PixelLabel::Obstacle);
            }
        }
        _ => {}
    }
    let sample = shade(scene, hit, pixel_angle, floor_footprint, cache);
    (Pending::Done(sample.radiance), sample.id, sample.label)
}

/// The label of a floor covering's class.
#[inline(always)]
fn floor_label(class: CoveringClass) -> PixelLabel {
    match class {
        CoveringClass::Carpet => PixelLabel::Carpet,
        CoveringClass::Other => PixelLabel::OtherCovering,
        CoveringClass::Paper => PixelLabel::Paper,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::{builtin_names, builtin_world};
    use crate::camera::{Camera, CameraPlacement, CameraRays};
    use crate::rng::Rng;
    use floorscan_core::Pose2;

    #[test]
    fn remembered_cells_shade_exactly_as_fresh_lookups_in_every_builtin_world() {
        // The renderer keeps one ShadeCache across a frame; a fresh cache per sample is the
        // plain computation (every lookup misses). Both must give the same bits, on views from
        // random poses in every built-in world (carpets, tiles, wood, patterns, walls, caps).
        let rays = CameraRays::new(Camera::wide_angle(96, 72)).unwrap();
        let mut rng = Rng::new(21);
        for name in builtin_names() {
            let scene = Scene::new(builtin_world(name).unwrap());
            let b = scene.world.bounds();
            for _ in 0..4 {
                let pose = Pose2::new(
                    b.min.x + (b.max.x - b.min.x) * rng.uniform(),
                    b.min.y + (b.max.y - b.min.y) * rng.uniform(),
                    std::f64::consts::TAU * rng.uniform(),
                );
                let place = CameraPlacement::new(&rays, pose);
                let mut kept = ShadeCache::default();
                for (k, d0) in rays.dirs.iter().enumerate() {
                    if d0[0].is_nan() {
                        continue;
                    }
                    let hit = scene.trace(place.origin, place.to_world(*d0));
                    let (angle, fp) = (rays.pixel_angle[k], rays.floor_footprint[k]);
                    let a = shade(&scene, &hit, angle, fp, &mut kept);
                    let b = shade(&scene, &hit, angle, fp, &mut ShadeCache::default());
                    assert_eq!(
                        a.radiance.to_bits(),
                        b.radiance.to_bits(),
                        "{name} pixel {k}"
                    );
                    assert_eq!((a.id, a.label), (b.id, b.label), "{name} pixel {k}");
                }
            }
        }
    }
}
