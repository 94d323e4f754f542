//! Tests of the `drive_run_options` module.

use super::*;

#[test]
fn defaults_pass_and_each_rule_names_its_field() {
    DriveRunOptions::default().validate().unwrap();
    let bad = |o: DriveRunOptions, field: &str| {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    };
    let d = DriveRunOptions::default;
    bad(
        DriveRunOptions {
            speed_m_s: 0.0,
            ..d()
        },
        "speed_m_s",
    );
    bad(
        DriveRunOptions {
            speed_m_s: f64::NAN,
            ..d()
        },
        "speed_m_s",
    );
    bad(
        DriveRunOptions {
            seconds: 2e5,
            ..d()
        },
        "seconds",
    );
    bad(
        DriveRunOptions {
            bump_backup_m: -0.1,
            ..d()
        },
        "bump_backup_m",
    );
    bad(DriveRunOptions { columns: 1, ..d() }, "columns");
    bad(
        DriveRunOptions {
            laser_beams: 0,
            ..d()
        },
        "laser_beams",
    );
    bad(
        DriveRunOptions {
            replan_every: 0,
            ..d()
        },
        "replan_every",
    );
    bad(
        DriveRunOptions {
            mid_contrast: -1.0,
            ..d()
        },
        "mid_contrast",
    );
    bad(
        DriveRunOptions {
            mid_range_m: Some(vec![1.2, 0.6]),
            ..d()
        },
        "mid_range_m",
    );
    DriveRunOptions {
        mid_range_m: None,
        bump_backup_m: 0.0,
        ..d()
    }
    .validate()
    .unwrap();
}

#[test]
fn the_sensor_table_and_ranger_read_as_the_command_line_spells_them() {
    let o: DriveRunOptions =
        serde_json::from_str(r#"{"sensor": "laser", "table": "exact", "ranger": "fused"}"#)
            .unwrap();
    assert_eq!(
        (o.sensor, o.table, o.ranger),
        (DriveSensor::Laser, DriveTable::Exact, DriveRanger::Fused)
    );
    assert!(serde_json::from_str::<DriveRunOptions>(r#"{"sensor": "sonar"}"#).is_err());
    let none: DriveRunOptions = serde_json::from_str(r#"{"mid_range_m": null}"#).unwrap();
    assert_eq!(none.mid_range_m, None);
}
