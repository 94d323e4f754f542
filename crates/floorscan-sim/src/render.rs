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
#[path = "render_tests.rs"]
mod tests;
