//! Tests of [`super`] (render.rs).

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
    let bits = |b: &RenderBuffers| -> Vec<u32> { b.radiance.iter().map(|r| r.to_bits()).collect() };
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
