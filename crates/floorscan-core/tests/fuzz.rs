//! Fuzzing the core's parsers and untrusted-input entry points (issue 12): ground table JSON
//! (mutated valid files and hostile declared sizes), grid options and extents, ranger options
//! JSON, and lasers at hostile poses. Each property: no panic, a typed error or a value that
//! keeps its invariants, and memory bounded by the options.
//!
//! `cargo test` runs a short deterministic corpus (fixed seed, 200 cases per property);
//! `make fuzz` sets FLOORSCAN_FUZZ=1 and PROPTEST_CASES for a longer random search.

use floorscan_core::grid::TILE_CELLS;
use floorscan_core::ground_table::GroundTable;
use floorscan_core::{
    BeamAngles, Bounds, CellIndex, Grid, GridOptions, ImageView, Inserter, InserterOptions,
    LaserScan, LogOdds, Point2, Pose2, RangerOptions, VisualRanger,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn config() -> Config {
    let base = Config::default(); // reads PROPTEST_CASES and PROPTEST_RNG_SEED
    if std::env::var_os("FLOORSCAN_FUZZ").is_some() {
        Config {
            failure_persistence: None,
            ..base
        }
    } else {
        Config {
            cases: 200,
            rng_seed: RngSeed::Fixed(0x1551_0012),
            failure_persistence: None,
            ..base
        }
    }
}

fn valid_table_json() -> String {
    GroundTable::from_fn(24, 18, 4, |u, v| {
        (v > 4.0).then(|| Point2::new(3.0 - 0.01 * v, 0.02 * (u - 12.0)))
    })
    .unwrap()
    .to_json()
}

/// Values a hostile file would put in a numeric field.
fn hostile_number() -> impl Strategy<Value = String> {
    prop_oneof![
        (0u64..64).prop_map(|v| v.to_string()),
        any::<u64>().prop_map(|v| v.to_string()),
        (0u32..64).prop_map(|b| (1u128 << b).to_string()),
        Just("18446744073709551615".to_string()),
        Just("1e9".to_string()),
        Just("-1".to_string()),
        Just("null".to_string()),
        Just("1.5".to_string()),
    ]
}

fn check_table(t: &GroundTable, probes: &[(f64, f64)]) {
    let (nu, nv) = t.node_shape();
    assert_eq!(t.nodes().len(), nu * nv);
    for &(u, v) in probes {
        let _ = t.lookup(u, v);
    }
    assert_eq!(&GroundTable::from_json(&t.to_json()).unwrap(), t);
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn ground_table_json_mutations_never_panic(
        cuts in proptest::collection::vec((0usize..2000, 0usize..8, any::<u8>()), 0..6),
        probes in proptest::collection::vec((-5.0..40.0f64, -5.0..30.0f64), 0..8),
    ) {
        let mut bytes = valid_table_json().into_bytes();
        for (at, len, b) in cuts {
            let at = at % (bytes.len() + 1);
            let end = (at + len).min(bytes.len());
            bytes.splice(at..end, std::iter::once(b));
        }
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(t) = GroundTable::from_json(&text) {
            check_table(&t, &probes);
        }
    }

    #[test]
    fn ground_table_declared_sizes_never_panic(
        w in hostile_number(), h in hostile_number(), s in hostile_number(),
        nu in hostile_number(), nv in hostile_number(), n in 0usize..40,
    ) {
        let xs = vec!["1.0"; n].join(",");
        let text = format!(
            r#"{{"format":"floorscan.ground_table","version":1,"image_width":{w},"image_height":{h},"spacing_px":{s},"nodes_u":{nu},"nodes_v":{nv},"x_m":[{xs}],"y_m":[{xs}]}}"#
        );
        if let Ok(t) = GroundTable::from_json(&text) {
            check_table(&t, &[(0.0, 0.0), (1e9, 1e9), (f64::NAN, 0.0)]);
            prop_assert!(t.image_width() * t.image_height() <= floorscan_core::ground_table::MAX_IMAGE_PIXELS);
        }
    }

    #[test]
    fn grid_options_and_extents_never_panic_and_memory_stays_bounded(
        cell in prop_oneof![Just(0.0), Just(f64::NAN), 0.0005..20.0f64],
        bound in prop_oneof![Just(None), (-1e7..1e7f64, -1e7..1e7f64, 0.0..1e7f64, 0.0..1e7f64).prop_map(Some)],
        max_cells in prop_oneof![Just(0u64), 1u64..(1 << 20), Just(1u64 << 25), Just(u64::MAX)],
        cells in proptest::collection::vec((any::<i32>(), any::<i32>()), 0..12),
        rect in (any::<i64>(), any::<i64>(), any::<u64>(), any::<u64>()),
    ) {
        let options = GridOptions {
            cell_size_m: cell,
            bounds_m: bound.map(|(x, y, w, h)| Bounds { min: Point2::new(x, y), max: Point2::new(x + w, y + h) }),
            max_cells,
            ..Default::default()
        };
        let Ok(mut g) = Grid::new(options) else { return Ok(()) };
        for (x, y) in cells {
            let _ = g.set(CellIndex::new(x, y), LogOdds(100));
        }
        // Tiles (2 bytes a cell) never exceed max_cells, plus one tile of rounding per side.
        let tile_bytes = TILE_CELLS * 2;
        let budget = (max_cells as usize).saturating_mul(2).saturating_add(8 * tile_bytes);
        prop_assert!(g.allocated_tiles() * tile_bytes <= budget);
        if let Ok(r) = g.checked_rect(rect.0, rect.1, rect.2, rect.3) {
            prop_assert!((r.width() as u64) * (r.height() as u64) <= max_cells);
            let mut out = Vec::new();
            g.read_rect(r, &mut out);
            prop_assert_eq!(out.len(), r.width() * r.height());
        }
    }

    #[test]
    fn lasers_at_hostile_poses_are_errors_or_bounded_updates(
        x in prop_oneof![-1e3..1e3f64, Just(1e6), Just(-1e12), Just(f64::NAN), Just(f64::INFINITY)],
        y in -1e3..1e3f64,
        yaw in -10.0..10.0f64,
        ranges in proptest::collection::vec(prop_oneof![0.0..30.0f64, Just(f64::INFINITY), Just(f64::NAN), Just(-1.0), Just(1e300)], 1..40),
        increment in prop_oneof![Just(0.0), Just(f64::NAN), 1e-6..0.5f64],
    ) {
        let mut g = Grid::new(GridOptions { cell_size_m: 0.05, ..Default::default() }).unwrap();
        let mut ins = Inserter::new(InserterOptions::default()).unwrap();
        let scan = LaserScan {
            ranges_m: &ranges,
            angles: BeamAngles::Uniform { min_rad: -1.0, increment_rad: increment },
            range_min_m: 0.0,
            range_max_m: 30.0,
        };
        let _ = ins.insert_laser(&mut g, &scan, &Pose2::new(x, y, yaw), &Pose2::IDENTITY);
        prop_assert!(g.memory_bytes() <= (g.options().max_cells as usize) * 2 + (64 << 20));
    }

    #[test]
    fn ranger_options_json_never_panics(
        half in hostile_number(), thr in prop_oneof![Just("-1".to_string()), Just("1e308".to_string()), (0u32..100).prop_map(|v| v.to_string())],
        count in hostile_number(), margin in hostile_number(),
    ) {
        let text = format!(
            r#"{{"half_width_px":{half},"threshold":{thr},"refinement":"sub_pixel","columns":{count},"start":{{"bottom_margin":{margin}}},"max_range_m":3.0}}"#
        );
        let Ok(options) = serde_json::from_str::<RangerOptions>(&text) else { return Ok(()) };
        let table = GroundTable::from_fn(32, 24, 8, |_, v| Some(Point2::new(5.0 - 0.1 * v, 0.0))).unwrap();
        if let Ok(mut r) = VisualRanger::new(table, options) {
            let pixels = vec![100u8; 32 * 24];
            let image = ImageView::new(&pixels, 32, 24).unwrap();
            let _ = r.scan(&image, 0.0);
        }
    }
}
