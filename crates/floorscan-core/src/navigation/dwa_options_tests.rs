//! Tests of the `dwa_options` module.

use super::*;

#[test]
fn defaults_are_valid_and_bad_values_name_their_field() {
    DwaOptions::default().validate().unwrap();
    let d = DwaOptions::default;
    for (o, field) in [
        (
            DwaOptions {
                max_speed_m_s: 4.0,
                ..d()
            },
            "max_speed_m_s",
        ),
        (
            DwaOptions {
                vx_samples: 0,
                ..d()
            },
            "vx_samples",
        ),
        (
            DwaOptions {
                sim_time_s: -1.0,
                ..d()
            },
            "sim_time_s",
        ),
    ] {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
}
