//! Image formation: one ray per pixel (four per pixel on edges between surfaces when
//! anti-aliasing), texture times illumination, vignetting, optical blur, Gaussian read noise and
//! shot noise, exposure jitter, 8-bit quantisation. Also returns the label of each pixel centre.
//!
//! Deterministic: the noise of frame `frame_index` comes from `derive_seed(seed, frame_index)`,
//! and textures are fixed to the world.

use floorscan_core::{Point2, Pose2};

use crate::camera::{CameraPlacement, CameraRays};
use crate::clearance::{sector_of, Clearance};
use crate::error::{invalid_option, Result};
use crate::rng::{derive_seed, Rng};
use crate::scene::{Hit, Scene, Surface};
use crate::texture::{CoveringClass, Footprint};
use crate::truth::PixelLabel;

/// Reusable buffers of a render (so rendering a run allocates once).
#[derive(Debug, Clone, Default)]
pub struct RenderBuffers {
    radiance: Vec<f32>,
    ids: Vec<u32>,
    scratch: Vec<f32>,
    /// The rendered 8-bit image, row-major.
    pub image: Vec<u8>,
    /// The [`PixelLabel`] code of each pixel centre, row-major.
    pub labels: Vec<u8>,
    /// The exposure used for this frame (mean exposure times the jitter).
    pub exposure: f64,
}

const ID_NOTHING: u32 = 0;
const ID_CEILING: u32 = 1;
const ID_SIDE: u32 = 1 << 30;
const ID_CAP: u32 = 1 << 31;

/// A shaded sample: radiance (albedo times illumination), surface identity (for finding
/// edges) and label.
struct Sample {
    radiance: f32,
    id: u32,
    label: PixelLabel,
}

/// Shades a hit seen along `d` by a pixel of angle `pixel_angle` [rad].
#[inline]
fn shade(scene: &Scene, hit: &Hit, pixel_angle: f32, floor_footprint: Footprint) -> Sample {
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
            let c = scene.covering_at(p);
            let covering = &scene.coverings[c];
            let albedo = covering.albedo_at(p, floor_footprint);
            let label = match covering.covering.class {
                CoveringClass::Carpet => PixelLabel::Carpet,
                CoveringClass::Other => PixelLabel::OtherCovering,
                CoveringClass::Paper => PixelLabel::Paper,
            };
            Sample {
                radiance: albedo * scene.light.at(p),
                id: 2 + c as u32,
                label,
            }
        }
        Surface::Side { face, s } => {
            let f = &scene.sides[face as usize];
            let solid = &world.solids[f.solid as usize];
            let app = &world.appearances[solid.appearance];
            let albedo = app.albedo_at(
                s,
                hit.point[2],
                Footprint::new(hit.t * pixel_angle as f64),
                f.seed,
            );
            // Faces turned differently are lit differently (a fixed main light direction).
            let (nx, ny) = ((f.b.y - f.a.y) / f.length, -(f.b.x - f.a.x) / f.length);
            let turn = 0.88 + 0.12 * (0.6 * nx + 0.8 * ny) as f32;
            let radiance = albedo * scene.light.at(p) * world.lighting.wall_factor as f32 * turn;
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
                scene.light.at(p)
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

/// Renders the view of a robot at `world_from_robot` into `out` (image and labels).
pub fn render_into(
    scene: &Scene,
    rays: &CameraRays,
    world_from_robot: Pose2,
    seed: u64,
    frame_index: u64,
    out: &mut RenderBuffers,
) -> Result<()> {
    if !world_from_robot.is_finite() {
        return Err(invalid_option("pose", "robot pose must be finite"));
    }
    let cam = &rays.camera;
    let (w, h) = (cam.width, cam.height);
    let n = w * h;
    out.radiance.resize(n, 0.0);
    out.ids.resize(n, 0);
    out.labels.resize(n, 0);
    out.image.resize(n, 0);
    let place = CameraPlacement::new(rays, world_from_robot);
    let clear = Clearance::new(
        &scene.world.solids,
        &scene.solid_bounds,
        place.world_from_camera.translation(),
    );
    let yaw = place.world_from_camera.yaw;

    for k in 0..n {
        let d0 = rays.dirs[k];
        if d0[0].is_nan() {
            out.radiance[k] = 0.0;
            out.ids[k] = ID_NOTHING;
            out.labels[k] = PixelLabel::Nothing as u8;
            continue;
        }
        let d = place.to_world(d0);
        let sector = clear.sector(sector_of(rays.azimuth[k] + yaw));
        let hit = scene.trace_clear(place.origin, d, sector, rays.horizontal[k]);
        let sample = shade(scene, &hit, rays.pixel_angle[k], rays.floor_footprint[k]);
        out.ids[k] = sample.id;
        out.labels[k] = sample.label as u8;
        out.radiance[k] = sample.radiance;
    }

    if cam.imaging.antialias {
        antialias(scene, rays, &place, &clear, out);
    }
    if cam.imaging.blur_sigma_px > 0.0 {
        gaussian_blur(
            &mut out.radiance,
            &mut out.scratch,
            w,
            h,
            cam.imaging.blur_sigma_px,
        );
    }

    let mut rng = Rng::new(derive_seed(seed, frame_index));
    let lighting = &scene.world.lighting;
    let jitter = if lighting.exposure_jitter > 0.0 {
        (lighting.exposure_jitter * rng.normal()).exp()
    } else {
        1.0
    };
    out.exposure = lighting.exposure * jitter;
    let scale = (255.0 * out.exposure / (0.9 * scene.light.typical as f64)) as f32;
    let read = cam.imaging.read_noise_dn as f32;
    let shot = cam.imaging.shot_noise_gain as f32;
    let noisy = read > 0.0 || shot > 0.0;
    for k in 0..n {
        let mut v = out.radiance[k] * rays.gain[k] * scale;
        if noisy {
            let sigma = (read * read + shot * v.max(0.0)).sqrt();
            v += sigma * rng.normal_fast();
        }
        // Round half up (no libm call); the clamp keeps it in range.
        out.image[k] = (v.clamp(0.0, 255.0) + 0.5) as u8;
    }
    Ok(())
}

/// Offsets of the extra anti-aliasing samples [px]; with the pixel centre they sample four
/// distinct rows and four distinct columns (a rotated grid).
const AA_OFFSETS: [(f64, f64); 3] = [(-0.375, -0.125), (0.125, -0.375), (0.25, 0.25)];

/// Re-renders pixels that differ in surface from a 4-neighbour with four samples each (the
/// centre and three more).
fn antialias(
    scene: &Scene,
    rays: &CameraRays,
    place: &CameraPlacement,
    clear: &Clearance,
    out: &mut RenderBuffers,
) {
    let (w, h) = (rays.camera.width, rays.camera.height);
    let yaw = place.world_from_camera.yaw;
    let ids = &out.ids;
    for v in 0..h {
        for u in 0..w {
            let k = v * w + u;
            let id = ids[k];
            let edge = (u + 1 < w && ids[k + 1] != id)
                || (u > 0 && ids[k - 1] != id)
                || (v + 1 < h && ids[k + w] != id)
                || (v > 0 && ids[k - w] != id);
            if !edge || rays.dirs[k][0].is_nan() {
                continue;
            }
            // Samples lie within 0.53 px of the pixel centre: their azimuths within 0.6 pixel
            // angles of the centre's.
            let sector = clear.within(rays.azimuth[k] + yaw, 0.6 * rays.pixel_angle[k] as f64);
            let mut sum = out.radiance[k];
            for (du, dv) in AA_OFFSETS {
                let d = place.to_world(rays.interpolated(u as f64 + du, v as f64 + dv));
                let hit =
                    scene.trace_clear(place.origin, d, sector, (d[0] * d[0] + d[1] * d[1]).sqrt());
                sum += shade(scene, &hit, rays.pixel_angle[k], rays.floor_footprint[k]).radiance;
            }
            out.radiance[k] = sum / (AA_OFFSETS.len() + 1) as f32;
        }
    }
}

/// Separable Gaussian blur with clamped borders.
fn gaussian_blur(img: &mut [f32], tmp: &mut Vec<f32>, w: usize, h: usize, sigma: f64) {
    let r = ((3.0 * sigma).ceil() as usize).min(w.min(h) / 2).max(1);
    let mut kernel: Vec<f32> = (0..=2 * r)
        .map(|i| (-((i as f64 - r as f64).powi(2)) / (2.0 * sigma * sigma)).exp() as f32)
        .collect();
    let s: f32 = kernel.iter().sum();
    kernel.iter_mut().for_each(|k| *k /= s);
    tmp.clear();
    tmp.resize(w * h, 0.0);
    // Horizontal pass into tmp: clamped at the borders, straight in the interior.
    for v in 0..h {
        let row = &img[v * w..(v + 1) * w];
        let out = &mut tmp[v * w..(v + 1) * w];
        for u in 0..w {
            if u < r || u + r >= w {
                out[u] = kernel
                    .iter()
                    .enumerate()
                    .map(|(i, k)| k * row[(u + i).saturating_sub(r).min(w - 1)])
                    .sum();
            } else {
                out[u] = kernel
                    .iter()
                    .zip(&row[u - r..=u + r])
                    .map(|(k, x)| k * x)
                    .sum();
            }
        }
    }
    // Vertical pass back into img: whole rows at a time (contiguous, vectorisable).
    for v in 0..h {
        let out = &mut img[v * w..(v + 1) * w];
        out.fill(0.0);
        for (i, k) in kernel.iter().enumerate() {
            let vv = (v + i).saturating_sub(r).min(h - 1);
            let src = &tmp[vv * w..(vv + 1) * w];
            for (o, x) in out.iter_mut().zip(src) {
                *o += k * x;
            }
        }
    }
}

#[cfg(test)]
mod blur_tests {
    use super::gaussian_blur;

    #[test]
    fn blur_keeps_constants_and_mass_and_spreads_a_point() {
        let (w, h) = (9, 7);
        let mut img = vec![3.0f32; w * h];
        let mut tmp = Vec::new();
        gaussian_blur(&mut img, &mut tmp, w, h, 0.8);
        assert!(img.iter().all(|v| (v - 3.0).abs() < 1e-5));
        let mut img = vec![0.0f32; w * h];
        img[3 * w + 4] = 1.0;
        gaussian_blur(&mut img, &mut tmp, w, h, 0.8);
        let sum: f32 = img.iter().sum();
        assert!((sum - 1.0).abs() < 1e-5);
        assert!(
            img[3 * w + 4] < 0.5
                && img[3 * w + 5] > 0.0
                && (img[3 * w + 5] - img[3 * w + 3]).abs() < 1e-7
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::builtin_world;
    use crate::camera::{Camera, Imaging};
    use crate::world_file::parse_world;

    fn corridor_view(seed: u64, frame: u64) -> RenderBuffers {
        let scene = Scene::new(builtin_world("corridor").unwrap());
        let rays = CameraRays::new(Camera::default()).unwrap();
        let mut buf = RenderBuffers::default();
        render_into(
            &scene,
            &rays,
            Pose2::new(3.0, 0.2, 0.3),
            seed,
            frame,
            &mut buf,
        )
        .unwrap();
        buf
    }

    #[test]
    fn the_same_seed_gives_the_same_bytes() {
        let (a, b) = (corridor_view(7, 3), corridor_view(7, 3));
        assert_eq!(a.image, b.image);
        assert_eq!(a.labels, b.labels);
        // Another seed or frame changes the noise, not the labels.
        let (c, d) = (corridor_view(8, 3), corridor_view(7, 4));
        assert_ne!(a.image, c.image);
        assert_ne!(a.image, d.image);
        assert_eq!(a.labels, c.labels);
    }

    #[test]
    fn labels_switch_exactly_where_the_exact_mapping_crosses_a_covering_edge() {
        // Paper covers the floor beyond x = 1.2 m (camera ground frame): a pixel sees paper
        // exactly when pixel_to_ground says its floor point lies beyond that line.
        let cam = Camera {
            imaging: Imaging::ideal(),
            ..Default::default()
        };
        let pose = crate::calibration::robot_pose(&cam);
        let scene = Scene::new(
            parse_world("name = \"p\"\n[start]\nx = 0\ny = 0\n[[regions]]\ncovering = \"paper\"\nrect = [1.2, -1000, 1000, 1000]\n", "p")
                .unwrap(),
        );
        let rays = CameraRays::new(cam.clone()).unwrap();
        let mut buf = RenderBuffers::default();
        render_into(&scene, &rays, pose, 0, 0, &mut buf).unwrap();
        let (mut paper, mut carpet) = (0, 0);
        for v in 0..cam.height {
            for u in 0..cam.width {
                let label = buf.labels[v * cam.width + u];
                match cam.pixel_to_ground(u as f64, v as f64, 1e9) {
                    Some(p) if (p.x - 1.2).abs() > 1e-9 && p.x < 40.0 => {
                        let want = if p.x > 1.2 {
                            PixelLabel::Paper
                        } else {
                            PixelLabel::Carpet
                        };
                        assert_eq!(label, want as u8, "pixel ({u}, {v}) sees {p:?}");
                        if p.x > 1.2 {
                            paper += 1
                        } else {
                            carpet += 1
                        }
                    }
                    Some(_) => {}
                    None => assert_ne!(label, PixelLabel::Carpet as u8),
                }
            }
        }
        assert!(
            paper > 5000 && carpet > 20000,
            "paper {paper}, carpet {carpet}"
        );
        // Paper is brighter than carpet in the image.
        let mean = |l: PixelLabel| {
            let v: Vec<f64> = buf
                .labels
                .iter()
                .zip(&buf.image)
                .filter(|(a, _)| **a == l as u8)
                .map(|(_, &b)| b as f64)
                .collect();
            v.iter().sum::<f64>() / v.len() as f64
        };
        assert!(mean(PixelLabel::Paper) > mean(PixelLabel::Carpet) + 50.0);
    }

    #[test]
    fn non_finite_poses_are_errors() {
        let scene = Scene::new(builtin_world("room").unwrap());
        let rays = CameraRays::new(Camera::default()).unwrap();
        let mut buf = RenderBuffers::default();
        assert!(render_into(
            &scene,
            &rays,
            Pose2::new(f64::NAN, 0.0, 0.0),
            0,
            0,
            &mut buf
        )
        .is_err());
    }
}
