//! Tests of the `log_odds` module.

use super::*;

#[test]
fn zero_is_one_half() {
    assert_eq!(LogOdds::UNKNOWN.probability(), 0.5);
    assert_eq!(LogOdds::from_probability(0.5), Some(LogOdds(0)));
    assert_eq!(log_odds_from_probability(0.5), 0.0);
}

#[test]
fn known_values_match_the_definition() {
    // ln(0.7 / 0.3) and ln(0.4 / 0.6), OctoMap's default hit and miss.
    assert!((log_odds_from_probability(0.7) - (0.7f64 / 0.3).ln()).abs() < 1e-15);
    assert!((log_odds_from_probability(0.4) - (0.4f64 / 0.6).ln()).abs() < 1e-15);
    assert_eq!(LogOdds::from_probability(0.7), Some(LogOdds(847)));
    assert_eq!(LogOdds::from_probability(0.4), Some(LogOdds(-405)));
    assert!((probability_from_log_odds(1.0) - 1.0 / (1.0 + (-1.0f64).exp())).abs() < 1e-16);
}

/// Every representable unit within the valid range round-trips through its probability,
/// and probabilities increase strictly with log-odds.
#[test]
fn every_unit_round_trips_and_is_strictly_monotone() {
    let mut previous = 0.0;
    for u in -MAX_ABS_UNITS..=MAX_ABS_UNITS {
        let p = LogOdds(u).probability();
        assert!(p > previous, "not increasing at {u}");
        previous = p;
        assert_eq!(
            LogOdds::from_probability(p),
            Some(LogOdds(u)),
            "round trip of {u}"
        );
        // Symmetry: L(1 - p) = -L(p).
        assert_eq!(
            LogOdds::from_probability(1.0 - p),
            Some(LogOdds(-u)),
            "symmetry of {u}"
        );
    }
}

#[test]
fn every_i16_gives_a_probability_in_the_unit_interval() {
    let mut previous = 0.0;
    for u in i16::MIN..=i16::MAX {
        let p = LogOdds(u).probability();
        assert!((0.0..=1.0).contains(&p) && p >= previous);
        previous = p;
    }
}

#[test]
fn out_of_domain_inputs_are_refused() {
    for p in [0.0, 1.0, -0.1, 1.5, f64::NAN, 1e-12, 1.0 - 1e-12] {
        assert_eq!(LogOdds::from_probability(p), None, "{p}");
    }
    for l in [f64::INFINITY, f64::NAN, 16.001, -25.0, 1e300] {
        assert_eq!(LogOdds::from_nats(l), None, "{l}");
    }
    assert_eq!(LogOdds::from_nats(-16.0), Some(LogOdds(-16_000)));
}

#[test]
fn evidence_from_error_rates_is_the_likelihood_ratio() {
    let e = Evidence::from_error_rates(0.1, 0.1).unwrap();
    assert!((e.hit_nats - 9.0f64.ln()).abs() < 1e-12);
    assert!((e.miss_nats + 9.0f64.ln()).abs() < 1e-12);
    // Bayes: a prior of 0.5 and one positive report give P(occupied | report) = 0.9.
    assert!((probability_from_log_odds(e.hit_nats) - 0.9).abs() < 1e-12);
    assert!(Evidence::from_error_rates(0.0, 0.1).is_err());
    assert!(Evidence::from_error_rates(0.1, 0.6).is_err());
}

#[test]
fn evidence_validation_names_the_problem() {
    let bad = Evidence {
        hit_nats: -1.0,
        miss_nats: -0.4,
    };
    assert!(bad
        .validate("laser")
        .unwrap_err()
        .to_string()
        .contains("hit_nats"));
    let bad = Evidence {
        hit_nats: 1.0,
        miss_nats: 0.4,
    };
    assert!(bad
        .validate("laser")
        .unwrap_err()
        .to_string()
        .contains("miss_nats"));
    assert!(Evidence {
        hit_nats: 0.0001,
        miss_nats: -0.4
    }
    .validate("x")
    .is_err());
    assert_eq!(
        Evidence {
            hit_nats: 0.85,
            miss_nats: -0.4
        }
        .units(),
        (850, -400)
    );
}
