//! Image formation: one ray per pixel (four per pixel on edges between surfaces when
//! anti-aliasing), texture times illumination, vignetting, optical blur, Gaussian read noise and
//! shot noise, exposure jitter, 8-bit quantisation. Also returns the label of each pixel centre.
//!
//! Deterministic: the noise of frame `frame_index` comes from `derive_seed(seed, frame_index)`,
//! and textures are fixed to the world.

use floorscan_core::Pose2;

use crate::camera::{CameraPlacement, CameraRays};
use crate::clearance::{sector_of, Clearance};
use crate::error::{invalid_option, Result};
use crate::lightmap::LightBatch;
use crate::noise_lanes::{NoiseBatch, NoiseKernel};
use crate::rng::{derive_seed, Rng};
use crate::scene::{Scene, Surface};
use crate::shade::{shade, shade_pending, Pending, ShadeCache, ID_NOTHING};
use crate::truth::PixelLabel;

/// Reusable buffers of a render (so rendering a run allocates once).
#[derive(Debug, Clone, Default)]
pub struct RenderBuffers {
    radiance: Vec<f32>,
    ids: Vec<u32>,
    scratch: Vec<f32>,
    /// A row's texture noise requests and its pixels' pending radiances.
    noise: NoiseBatch,
    lights: LightBatch,
    /// A row's anti-aliasing flags.
    edges: Vec<bool>,
    pending: Vec<Pending>,
    /// The rendered 8-bit image, row-major.
    pub image: Vec<u8>,
    /// The [`PixelLabel`] code of each pixel centre, row-major.
    pub labels: Vec<u8>,
    /// The exposure used for this frame (mean exposure times the jitter).
    pub exposure: f64,
}

/// How the main pass shades (the images are the same bits either way).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Shading {
    /// Each pixel completely before the next (texture noise one point at a time): the
    /// reference the tests compare the lanes with.
    #[cfg_attr(not(test), allow(dead_code))]
    PerPixel,
    /// A row's texture noise and light of carpets and walls evaluated together with this
    /// kernel.
    Lanes(NoiseKernel),
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
    let shading = Shading::Lanes(NoiseKernel::detect());
    render_with(
        scene,
        rays,
        world_from_robot,
        seed,
        frame_index,
        out,
        shading,
    )
}

/// [`render_into`] shading the main pass as `shading` says.
pub(crate) fn render_with(
    scene: &Scene,
    rays: &CameraRays,
    world_from_robot: Pose2,
    seed: u64,
    frame_index: u64,
    out: &mut RenderBuffers,
    shading: Shading,
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
    let mut cache = ShadeCache::default();
    match shading {
        #[cfg(target_arch = "x86_64")]
        Shading::Lanes(NoiseKernel::Avx2) if std::arch::is_x86_feature_detected!("avx2") => {
            // SAFETY: AVX2 is present (checked above).
            unsafe { main_pass_avx2(scene, rays, &place, &clear, out, &mut cache, shading) }
        }
        _ => main_pass(scene, rays, &place, &clear, out, &mut cache, shading),
    }

    if cam.imaging.antialias {
        antialias(scene, rays, &place, &clear, out, &mut cache);
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
    let (image, radiance, gain) = (&mut out.image[..n], &out.radiance[..n], &rays.gain[..n]);
    // Round half up (no libm call); the clamp keeps it in range.
    let quantise = |v: f32| (v.clamp(0.0, 255.0) + 0.5) as u8;
    if noisy {
        // The generator's draws first (one per pixel, in pixel order, as it is sequential),
        // then the pixels with no generator in the loop (vectorisable): the same values.
        out.scratch.resize(n, 0.0);
        let draws = &mut out.scratch[..n];
        for z in draws.iter_mut() {
            *z = rng.normal_fast();
        }
        let pixels = image.iter_mut().zip(radiance).zip(gain).zip(&*draws);
        for (((byte, &radiance), &gain), &z) in pixels {
            let v = radiance * gain * scale;
            let sigma = (read * read + shot * v.max(0.0)).sqrt();
            *byte = quantise(v + sigma * z);
        }
    } else {
        for ((byte, &radiance), &gain) in image.iter_mut().zip(radiance).zip(gain) {
            *byte = quantise(radiance * gain * scale);
        }
    }
    Ok(())
}

/// The main pass: every pixel traced and shaded (one row at a time, see [`render_with`]).
#[inline(always)]
fn main_pass(
    scene: &Scene,
    rays: &CameraRays,
    place: &CameraPlacement,
    clear: &Clearance,
    out: &mut RenderBuffers,
    cache: &mut ShadeCache,
    shading: Shading,
) {
    let yaw = place.world_from_camera.yaw;
    let n = rays.camera.width * rays.camera.height;
    let w = rays.camera.width;
    // Every per-pixel array cut to n (so the loop indexes them without bounds checks).
    let (dirs, azimuth, horizontal) = (&rays.dirs[..n], &rays.azimuth[..n], &rays.horizontal[..n]);
    let (pixel_angle, footprint) = (&rays.pixel_angle[..n], &rays.floor_footprint[..n]);
    let floor_t = &rays.floor_t[..n];
    let (radiance, ids, labels) = (
        &mut out.radiance[..n],
        &mut out.ids[..n],
        &mut out.labels[..n],
    );
    // One row at a time: trace and shade each pixel, the texture noise of carpets and walls
    // left pending; evaluate the row's noise in lanes; finish the radiances.
    let (batch, lights, pending) = (&mut out.noise, &mut out.lights, &mut out.pending);
    for row in (0..n).step_by(w.max(1)) {
        let end = (row + w).min(n);
        // At most two noise requests a pixel (a carpet's fibres and mottling).
        batch.start(2 * (end - row));
        lights.start(end - row);
        if pending.len() < end - row {
            pending.resize(end - row, Pending::Done(0.0));
        }
        for (k, slot) in (row..end).zip(pending.iter_mut()) {
            let d0 = dirs[k];
            if d0[0].is_nan() {
                *slot = Pending::Done(0.0);
                ids[k] = ID_NOTHING;
                labels[k] = PixelLabel::Nothing as u8;
                continue;
            }
            let d = place.to_world(d0);
            let sector = clear.sector(sector_of(azimuth[k] + yaw));
            // The floor's t is the camera's, in any pose (o[2] is the mount height, d[2] d0[2]).
            let limit = if floor_t[k].is_nan() {
                scene.limit(place.origin, d)
            } else {
                (floor_t[k], Surface::Floor)
            };
            let hit = scene.trace_clear_from(place.origin, d, sector, horizontal[k], limit);
            let (p, id, label) = match shading {
                Shading::Lanes(_) => shade_pending(
                    scene,
                    &hit,
                    pixel_angle[k],
                    footprint[k],
                    cache,
                    batch,
                    lights,
                ),
                Shading::PerPixel => {
                    let sample = shade(scene, &hit, pixel_angle[k], footprint[k], cache);
                    (Pending::Done(sample.radiance), sample.id, sample.label)
                }
            };
            *slot = p;
            ids[k] = id;
            labels[k] = label as u8;
        }
        if let Shading::Lanes(kernel) = shading {
            batch.evaluate(kernel);
            scene.light.evaluate(kernel, lights);
        }
        for (r, p) in radiance[row..end].iter_mut().zip(pending.iter()) {
            *r = p.finish(batch, lights);
        }
    }
}

/// [`main_pass`] compiled for AVX2 (the same operations in the same order, no fused
/// multiply-add: AVX2 does not enable it, and Rust never contracts).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn main_pass_avx2(
    scene: &Scene,
    rays: &CameraRays,
    place: &CameraPlacement,
    clear: &Clearance,
    out: &mut RenderBuffers,
    cache: &mut ShadeCache,
    shading: Shading,
) {
    main_pass(scene, rays, place, clear, out, cache, shading)
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
    cache: &mut ShadeCache,
) {
    let (w, h) = (rays.camera.width, rays.camera.height);
    let yaw = place.world_from_camera.yaw;
    let ids = &out.ids;
    let mut edges = std::mem::take(&mut out.edges);
    for v in 0..h {
        edge_flags(ids, w, h, v, &mut edges);
        for u in (0..w).filter(|&u| edges[u]) {
            let k = v * w + u;
            if rays.dirs[k][0].is_nan() {
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
                let pixel_angle = rays.pixel_angle[k];
                sum += shade(scene, &hit, pixel_angle, rays.floor_footprint[k], cache).radiance;
            }
            out.radiance[k] = sum / (AA_OFFSETS.len() + 1) as f32;
        }
    }
    out.edges = edges;
}

/// Whether each pixel of row `v` differs in surface from a 4-neighbour (into `edges[..w]`):
/// the interior of the row compares whole rows (vectorisable), the two ends one by one.
fn edge_flags(ids: &[u32], w: usize, h: usize, v: usize, edges: &mut Vec<bool>) {
    edges.clear();
    edges.resize(w, false);
    let at = |v: usize| &ids[v * w..(v + 1) * w];
    let row = at(v);
    // Above and below: the row itself at the image's top and bottom (no difference).
    let up = if v > 0 { at(v - 1) } else { row };
    let down = if v + 1 < h { at(v + 1) } else { row };
    let one = |u: usize| {
        let id = row[u];
        (u + 1 < w && row[u + 1] != id)
            || (u > 0 && row[u - 1] != id)
            || up[u] != id
            || down[u] != id
    };
    if w < 3 {
        for (u, e) in edges.iter_mut().enumerate() {
            *e = one(u);
        }
        return;
    }
    let inner = row[1..w - 1]
        .iter()
        .zip(&row[2..])
        .zip(&row[..w - 2])
        .zip(up[1..w - 1].iter().zip(&down[1..w - 1]));
    for (e, (((id, right), left), (above, below))) in edges[1..w - 1].iter_mut().zip(inner) {
        *e = (right != id) | (left != id) | (above != id) | (below != id);
    }
    edges[0] = one(0);
    edges[w - 1] = one(w - 1);
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
    // Horizontal pass into tmp: clamped at the borders; in the interior tap by tap along the
    // row (each pixel's sum in the same order as one pixel at a time, and vectorisable).
    for v in 0..h {
        let row = &img[v * w..(v + 1) * w];
        let out = &mut tmp[v * w..(v + 1) * w];
        let inner = w - 2 * r; // r <= w / 2
        out[r..w - r].fill(0.0);
        for (i, k) in kernel.iter().enumerate() {
            for (o, x) in out[r..w - r].iter_mut().zip(&row[i..i + inner]) {
                *o += k * x;
            }
        }
        for u in (0..r).chain(w - r..w) {
            out[u] = kernel
                .iter()
                .enumerate()
                .map(|(i, k)| k * row[(u + i).saturating_sub(r).min(w - 1)])
                .sum();
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
    use super::{edge_flags, gaussian_blur};

    #[test]
    fn edge_flags_are_the_four_neighbour_test() {
        // Random ids of few values, in images of every small size.
        let mut rng = crate::rng::Rng::new(2);
        let mut edges = Vec::new();
        for (w, h) in [(1, 1), (1, 4), (2, 3), (3, 1), (3, 3), (5, 2), (17, 9)] {
            let ids: Vec<u32> = (0..w * h).map(|_| (rng.next_u64() % 3) as u32).collect();
            for v in 0..h {
                edge_flags(&ids, w, h, v, &mut edges);
                for (u, &edge) in edges.iter().enumerate() {
                    let k = v * w + u;
                    let id = ids[k];
                    let want = (u + 1 < w && ids[k + 1] != id)
                        || (u > 0 && ids[k - 1] != id)
                        || (v + 1 < h && ids[k + w] != id)
                        || (v > 0 && ids[k - w] != id);
                    assert_eq!(edge, want, "{w}x{h} ({u}, {v})");
                }
            }
        }
    }

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
        let (cam, pose) = ideal_camera_at_origin();
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
    fn each_pixels_floor_t_is_the_scenes_floor_limit_in_any_pose() {
        // The renderer takes the floor's t from CameraRays::floor_t instead of Scene::limit:
        // the same bits, for every pixel and pose (poses turn about the vertical).
        let scene = Scene::new(builtin_world("corridor").unwrap());
        let rays = CameraRays::new(Camera::default()).unwrap();
        for pose in [Pose2::new(3.0, 0.2, 0.3), Pose2::new(-7.1, 4.4, -2.9)] {
            let place = CameraPlacement::new(&rays, pose);
            for (d0, &t) in rays.dirs.iter().zip(&rays.floor_t) {
                if d0[0].is_nan() {
                    continue;
                }
                let (want_t, want) = scene.limit(place.origin, place.to_world(*d0));
                if t.is_nan() {
                    assert_ne!(want, Surface::Floor);
                } else {
                    assert_eq!((t.to_bits(), Surface::Floor), (want_t.to_bits(), want));
                }
            }
        }
    }

    /// Renders the view with the row batches of texture noise (the portable kernel and the
    /// one this CPU dispatches to) and pixel by pixel, asserts the same radiance bits, image
    /// bytes and labels, and returns the per-pixel render.
    fn lanes_match_per_pixel(
        scene: &Scene,
        rays: &CameraRays,
        pose: Pose2,
        frame: u64,
        what: &str,
    ) -> RenderBuffers {
        let render = |shading| {
            let mut buf = RenderBuffers::default();
            render_with(scene, rays, pose, 3, frame, &mut buf, shading).unwrap();
            buf
        };
        let want = render(Shading::PerPixel);
        let bits =
            |b: &RenderBuffers| -> Vec<u32> { b.radiance.iter().map(|r| r.to_bits()).collect() };
        for kernel in [NoiseKernel::Portable, NoiseKernel::detect()] {
            let got = render(Shading::Lanes(kernel));
            assert_eq!(bits(&got), bits(&want), "{what} {kernel:?}");
            assert_eq!(got.image, want.image, "{what} {kernel:?}");
            assert_eq!(got.labels, want.labels, "{what} {kernel:?}");
        }
        want
    }

    #[test]
    fn lanes_render_exactly_as_per_pixel_shading_in_every_builtin_world() {
        // The row batches of texture noise (the AVX2 lanes where the CPU has them, and the
        // forced portable kernel) against shading each pixel completely: the same radiance
        // bits before blur and noise, the same image bytes and labels, from random poses.
        use crate::builtin::builtin_names;
        use crate::rng::Rng;
        let mut rng = Rng::new(5);
        for (w, h) in [(96, 72), (61, 37)] {
            let rays = CameraRays::new(Camera::wide_angle(w, h)).unwrap();
            for name in builtin_names() {
                let scene = Scene::new(builtin_world(name).unwrap());
                let b = scene.world.bounds();
                for i in 0..3 {
                    let pose = Pose2::new(
                        b.min.x + (b.max.x - b.min.x) * rng.uniform(),
                        b.min.y + (b.max.y - b.min.y) * rng.uniform(),
                        std::f64::consts::TAU * rng.uniform(),
                    );
                    lanes_match_per_pixel(&scene, &rays, pose, i, &format!("{name} {pose:?}"));
                }
            }
        }
    }

    /// The default camera without imaging effects, and the robot pose that puts its ground
    /// frame at the world's origin (so world points are pixel_to_ground's).
    fn ideal_camera_at_origin() -> (Camera, Pose2) {
        let cam = Camera {
            imaging: Imaging::ideal(),
            ..Default::default()
        };
        let pose = crate::calibration::robot_pose(&cam);
        (cam, pose)
    }

    /// A 1 x 2 m box 1.5 m ahead of the camera (its ground frame), with contact shadows of
    /// `strength` and length 4 cm.
    fn box_scene(strength: f64) -> Scene {
        let text = format!(
            "name = \"s\"\n[start]\nx = 0\ny = 0\n[lighting]\n\
             contact_shadow = {{ strength = {strength}, length_m = 0.04 }}\n\
             [[boxes]]\nrect = [1.5, -1.0, 2.5, 1.0]\nheight_m = 0.5\n"
        );
        Scene::new(parse_world(&text, "s").unwrap())
    }

    #[test]
    fn contact_shadows_darken_the_floor_by_the_factor_of_its_distance_to_the_foot() {
        // Each floor pixel's radiance, with shadows over without, against the model's factor
        // at its exact floor point (pixel_to_ground): distance to, and span of, the box's footprint.
        use crate::contact_shadow::ContactShadow;
        use floorscan_core::Point2;
        let (cam, pose) = ideal_camera_at_origin();
        let rays = CameraRays::new(cam.clone()).unwrap();
        let render = |scene: &Scene| {
            let mut buf = RenderBuffers::default();
            render_into(scene, &rays, pose, 0, 0, &mut buf).unwrap();
            buf
        };
        let (lit, dark) = (render(&box_scene(0.0)), render(&box_scene(0.5)));
        assert_eq!(lit.labels, dark.labels);
        let model = ContactShadow {
            strength: 0.5,
            length_m: 0.04,
        };
        let footprint = [
            Point2::new(1.5, -1.0),
            Point2::new(2.5, -1.0),
            Point2::new(2.5, 1.0),
            Point2::new(1.5, 1.0),
        ];
        let (mut near, mut far) = (0, 0);
        for v in 0..cam.height {
            for u in 0..cam.width {
                let k = v * cam.width + u;
                if lit.labels[k] != PixelLabel::Carpet as u8 {
                    continue;
                }
                let Some(p) = cam.pixel_to_ground(u as f64, v as f64, 1e9) else {
                    continue;
                };
                let dx = (1.5 - p.x).max(p.x - 2.5).max(0.0);
                let dy = (p.y.abs() - 1.0).max(0.0);
                let d = dx.hypot(dy);
                let ratio = (dark.radiance[k] / lit.radiance[k]) as f64;
                if d > 5.0 * 0.04 + 0.02 {
                    assert_eq!(ratio, 1.0, "pixel ({u}, {v}) {d} m away");
                    far += 1;
                } else {
                    let want = model.factor_of(p, &footprint);
                    assert!(
                        (ratio - want).abs() < 0.02,
                        "({u}, {v}) d {d}: {ratio} vs {want}"
                    );
                    near += usize::from(d < 0.1);
                }
            }
        }
        assert!(near > 100 && far > 10_000, "near {near}, far {far}");
        assert!(
            dark.image.iter().map(|&b| b as u64).sum::<u64>()
                < lit.image.iter().map(|&b| b as u64).sum::<u64>()
        );
    }

    #[test]
    fn contact_shadows_render_alike_in_lanes_and_per_pixel() {
        let scene = box_scene(0.6);
        let rays = CameraRays::new(Camera::wide_angle(96, 72)).unwrap();
        let pose = Pose2::new(0.2, 0.1, 0.05);
        let want = lanes_match_per_pixel(&scene, &rays, pose, 0, "shadowed box");
        // the view holds shadowed floor
        let mut unshadowed = RenderBuffers::default();
        let lit = box_scene(0.0);
        render_with(&lit, &rays, pose, 3, 0, &mut unshadowed, Shading::PerPixel).unwrap();
        let darker = (want.radiance.iter().zip(&unshadowed.radiance))
            .filter(|(a, b)| a < b)
            .count();
        assert!(darker > 20, "{darker} shadowed pixels");
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
