//! Tests of [`super`] (ground_table.rs).

use super::*;
use proptest::prelude::*;

fn affine(u: f64, v: f64) -> Point2 {
    Point2::new(3.0 - 0.01 * v + 0.002 * u, 0.5 - 0.004 * u + 0.0007 * v)
}

#[test]
fn power_of_two_spacing_divides_exactly() {
    for p in 0..20u32 {
        let s = (1usize << p) as f64;
        let inv = f64::from_bits((1023 - p as u64) << 52);
        assert_eq!(inv, 1.0 / s);
        for u in [0.0, 0.25, 1.0, 3.7, 100.5, 639.49, 12345.678] {
            assert_eq!(u * inv, u / s, "{u} / {s}");
        }
    }
}

#[test]
fn node_counts_cover_the_image() {
    assert_eq!(node_counts(320, 240, 8), (41, 31));
    assert_eq!(node_counts(321, 240, 8), (41, 31));
    assert_eq!(node_counts(322, 240, 8), (42, 31));
    assert_eq!(node_counts(2, 2, 16), (2, 2));
}

proptest! {
    #[test]
    fn interpolation_is_exact_on_an_affine_mapping(u in 0.0..319.0f64, v in 0.0..239.0f64, s in 1usize..20) {
        let t = GroundTable::from_fn(320, 240, s, |u, v| Some(affine(u, v))).unwrap();
        let p = t.lookup(u, v).unwrap();
        let e = affine(u, v);
        prop_assert!((p.x - e.x).abs() < 1e-9 && (p.y - e.y).abs() < 1e-9);
    }
}

#[test]
fn no_ground_propagates_to_the_four_surrounding_cells() {
    // Node (2, 2) at pixel (16, 16) has no ground.
    let t = GroundTable::from_fn(64, 64, 8, |u, v| {
        (!(u == 16.0 && v == 16.0)).then(|| affine(u, v))
    })
    .unwrap();
    for (u, v) in [
        (9.0, 9.0),
        (23.0, 9.0),
        (9.0, 23.0),
        (23.0, 23.0),
        (16.0, 16.0),
    ] {
        assert!(t.lookup(u, v).is_none(), "({u}, {v}) should be no ground");
    }
    for (u, v) in [(7.0, 7.0), (25.0, 25.0), (30.0, 12.0)] {
        assert!(t.lookup(u, v).is_some(), "({u}, {v}) should have ground");
    }
}

#[test]
fn outside_the_image_is_no_ground() {
    let t = GroundTable::from_fn(32, 24, 8, |u, v| Some(affine(u, v))).unwrap();
    assert!(t.lookup(-1.0, 5.0).is_none());
    assert!(t.lookup(5.0, 23.6).is_none());
    assert!(t.lookup(f64::NAN, 5.0).is_none());
    assert!(t.lookup(31.0, 23.0).is_some());
}

#[test]
fn json_round_trip_keeps_every_node_and_the_metadata() {
    let mut t = GroundTable::from_fn(40, 30, 8, |u, v| (v > 8.0).then(|| affine(u, v))).unwrap();
    t.metadata
        .insert("source".into(), serde_json::json!("test"));
    let back = GroundTable::from_json(&t.to_json()).unwrap();
    assert_eq!(back, t);
}

#[test]
fn damaged_and_foreign_files_are_errors() {
    let t = GroundTable::from_fn(40, 30, 8, |u, v| Some(affine(u, v))).unwrap();
    let json = t.to_json();
    let truncated = &json[..json.len() / 2];
    assert!(matches!(
        GroundTable::from_json(truncated),
        Err(Error::Malformed { .. })
    ));
    let v3 = json.replace("\"version\":1", "\"version\":3");
    assert!(matches!(
        GroundTable::from_json(&v3),
        Err(Error::UnsupportedVersion { found: 3, .. })
    ));
    let v1_with_errors = t
        .clone()
        .with_errors(&vec![0.01; 30])
        .unwrap()
        .to_json()
        .replace("\"version\":2", "\"version\":1");
    assert!(matches!(
        GroundTable::from_json(&v1_with_errors),
        Err(Error::Malformed { .. })
    ));
    let foreign = json.replace(GROUND_TABLE_FORMAT, "something.else");
    assert!(matches!(
        GroundTable::from_json(&foreign),
        Err(Error::Malformed { .. })
    ));
    let short = json.replace("\"nodes_u\":6", "\"nodes_u\":7");
    assert!(matches!(
        GroundTable::from_json(&short),
        Err(Error::Malformed { .. })
    ));
}

#[test]
fn declared_sizes_whose_products_overflow_or_exceed_the_limits_are_errors() {
    // nodes_u * nodes_v = 2^33 * 2^31 wraps to 0 in usize: must be an error, not a table.
    let json = format!(
        r#"{{"format":"{GROUND_TABLE_FORMAT}","version":1,"image_width":{},"image_height":{},"spacing_px":1,"nodes_u":{},"nodes_v":{},"x_m":[],"y_m":[]}}"#,
        1u64 << 33,
        1u64 << 31,
        1u64 << 33,
        1u64 << 31
    );
    assert!(matches!(
        GroundTable::from_json(&json),
        Err(Error::Malformed { .. })
    ));
    // A 1e9 x 1e9 image with 2 x 2 nodes: small file, absurd image.
    let json = format!(
        r#"{{"format":"{GROUND_TABLE_FORMAT}","version":1,"image_width":1000000000,"image_height":1000000000,"spacing_px":1000000000,"nodes_u":2,"nodes_v":2,"x_m":[1,1,2,2],"y_m":[0,1,0,1]}}"#
    );
    assert!(matches!(
        GroundTable::from_json(&json),
        Err(Error::Malformed { .. })
    ));
    assert!(GroundTable::from_fn(1 << 20, 4, 1 << 20, |_, _| None).is_err());
    assert!(checked_node_shape(usize::MAX, usize::MAX, 1).is_err());
    assert!(checked_node_shape(MAX_IMAGE_SIDE_PX, MAX_IMAGE_PIXELS / MAX_IMAGE_SIDE_PX, 8).is_ok());
}

#[test]
fn node_errors_interpolate_round_trip_and_follow_the_ground() {
    // Errors affine in the node position interpolate exactly; a table without errors
    // writes version 1, one with errors version 2, and both read back equal.
    let t = GroundTable::from_fn(40, 30, 8, |u, v| (v > 8.0).then(|| affine(u, v))).unwrap();
    assert!(t.lookup_error(20.0, 20.0).is_none());
    assert!(t.to_json().contains("\"version\":1"));
    let (nu, nv) = t.node_shape();
    let e: Vec<f64> = (0..nv)
        .flat_map(|j| (0..nu).map(move |i| 0.01 + 0.001 * i as f64 + 0.002 * j as f64))
        .collect();
    let te = t.clone().with_errors(&e).unwrap();
    let got = te.lookup_error(12.0, 20.0).unwrap();
    let want = 0.01 + 0.001 * 12.0 / 8.0 + 0.002 * 20.0 / 8.0;
    assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    // No ground above v = 8 means no error there either.
    assert!(te.lookup_error(12.0, 4.0).is_none());
    assert!(te.errors().unwrap()[0].is_none());
    let json = te.to_json();
    assert!(json.contains("\"version\":2") && json.contains("error_m"));
    assert_eq!(GroundTable::from_json(&json).unwrap(), te);
    assert!(t.clone().with_errors(&e[1..]).is_err());
    let mut negative = e.clone();
    negative[7] = -1.0;
    assert!(t.with_errors(&negative).is_err());
}

#[test]
fn wrong_node_count_and_zero_spacing_are_errors() {
    assert!(GroundTable::from_nodes(40, 30, 8, vec![None; 5]).is_err());
    assert!(GroundTable::from_fn(40, 30, 0, |_, _| None).is_err());
    assert!(GroundTable::from_arrays(40, 30, 8, &[0.0; 30], &[0.0; 29]).is_err());
}

#[test]
fn derivatives_are_the_cells_bilinear_slopes_and_the_point_is_lookups() {
    // a non-affine surface, so the slopes change across and within cells
    let f =
        |u: f64, v: f64| Point2::new(2.0 + 0.01 * u + 1e-4 * u * v, 0.3 - 0.02 * v + 3e-5 * u * u);
    let t = GroundTable::from_fn(97, 61, 8, |u, v| Some(f(u, v))).unwrap();
    for (u, v) in [
        (3.3, 4.1),
        (17.0, 22.9),
        (40.5, 8.0),
        (95.7, 59.2),
        (64.0, 32.0),
    ] {
        let (p, [a, b, c, d]) = t.lookup_with_derivatives(u, v).unwrap();
        assert_eq!(Some(p), t.lookup(u, v));
        // along u (v fixed) and along v (u fixed) the interpolation is linear within a cell:
        // a small step's difference quotient is the slope, to rounding
        let h = 1e-3;
        let (su, sv) = (
            if u + h <= 96.0 { h } else { -h },
            if v + h <= 60.0 { h } else { -h },
        );
        let (pu, pv) = (t.lookup(u + su, v).unwrap(), t.lookup(u, v + sv).unwrap());
        for (got, want) in [
            (a, (pu.x - p.x) / su),
            (b, (pv.x - p.x) / sv),
            (c, (pu.y - p.y) / su),
            (d, (pv.y - p.y) / sv),
        ] {
            assert!((got - want).abs() < 1e-9, "({u}, {v}): {got} {want}");
        }
    }
    assert!(t.lookup_with_derivatives(-3.0, 0.0).is_none());
}
