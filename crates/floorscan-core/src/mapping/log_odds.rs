//! Probability <-> log-odds maths (paper eq. 5-7), apart from any storage.
//!
//! A cell stores the log-odds `L(o) = ln(p / (1 - p))` of being occupied, in fixed point:
//! [`LogOdds`] is an `i16` counting thousandths of a nat ([`UNITS_PER_NAT`] = 1000), so the
//! update `L(o|m) = L(m|o) + L(o)` (eq. 7) is one integer addition and a clamp. 0 is p = 0.5 (no
//! information, the prior). Every value the maps use lies within [`MAX_ABS_NATS`] (16 nats,
//! p within 1.2e-7 of 0 or 1), where the conversions round-trip exactly and are strictly monotone
//! (tested over every value).

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// Fixed-point scale: stored units per nat of log-odds.
pub const UNITS_PER_NAT: f64 = 1000.0;

/// Largest magnitude of log-odds [nats] accepted anywhere (clamp bounds, increments): 16 nats,
/// i.e. probabilities in [1.1e-7, 1 - 1.1e-7]. A value plus an increment then always fits an
/// i16 (2 x 16 000 < 32 767), so updates need no saturating arithmetic.
pub const MAX_ABS_NATS: f64 = 16.0;

/// Largest magnitude in stored units (16 000).
pub const MAX_ABS_UNITS: i16 = 16_000;

/// A log-odds value in fixed point (thousandths of a nat). `LogOdds(0)` is p = 0.5.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize,
)]
pub struct LogOdds(pub i16);

impl LogOdds {
    /// The prior: p = 0.5, no evidence either way.
    pub const UNKNOWN: LogOdds = LogOdds(0);

    /// From log-odds in nats, rounded to the nearest unit; `None` if not finite or if it
    /// rounds beyond +-[`MAX_ABS_UNITS`].
    pub fn from_nats(nats: f64) -> Option<LogOdds> {
        let units = (nats * UNITS_PER_NAT).round();
        // NaN fails the comparison too.
        (units.abs() <= f64::from(MAX_ABS_UNITS)).then_some(LogOdds(units as i16))
    }

    /// From a probability in (0, 1); `None` outside [`MAX_ABS_NATS`] or for NaN.
    pub fn from_probability(p: f64) -> Option<LogOdds> {
        if !(p > 0.0 && p < 1.0) {
            return None;
        }
        LogOdds::from_nats(log_odds_from_probability(p))
    }

    /// The value in nats.
    pub fn nats(self) -> f64 {
        f64::from(self.0) / UNITS_PER_NAT
    }

    /// The probability of occupancy, `1 / (1 + exp(-L))`.
    pub fn probability(self) -> f64 {
        probability_from_log_odds(self.nats())
    }
}

/// `p = 1 / (1 + exp(-l))`, computed without overflow for any finite `l`.
pub fn probability_from_log_odds(l: f64) -> f64 {
    if l >= 0.0 {
        1.0 / (1.0 + (-l).exp())
    } else {
        let e = l.exp();
        e / (1.0 + e)
    }
}

/// `l = ln(p / (1 - p))` for p in (0, 1) (infinite at 0 and 1, NaN outside).
pub fn log_odds_from_probability(p: f64) -> f64 {
    if p <= 0.5 {
        p.ln() - (-p).ln_1p()
    } else {
        // 1 - p is exact for p > 0.5 (Sterbenz), so this branch keeps full precision near 1.
        -((1.0 - p).ln() - p.ln())
    }
}

/// How much one observation moves a cell [nats]: the paper's tunable evidence accumulator.
///
/// Choose the values from the sensor's error rates (see [`Evidence::from_error_rates`]): a
/// sensor that is rarely wrong gets large steps (few observations decide a cell, the robot may
/// drive faster); a noisy one gets small steps (many observations needed).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Evidence {
    /// Added to a cell observed occupied [nats], in (0, 16].
    pub hit_nats: f64,
    /// Added to a cell observed free [nats], in [-16, 0).
    pub miss_nats: f64,
}

impl Evidence {
    /// Log-likelihood ratios of a binary detector: `false_alarm` = P(says occupied | free),
    /// `miss_rate` = P(says free | occupied), both in (0, 0.5). Then
    /// `hit = ln((1 - miss_rate) / false_alarm)` and `miss = ln(miss_rate / (1 - false_alarm))`.
    /// Example: 10 % of each gives hit = +2.20 nats, miss = -2.20 nats.
    pub fn from_error_rates(false_alarm: f64, miss_rate: f64) -> Result<Evidence> {
        for (name, v) in [("false_alarm", false_alarm), ("miss_rate", miss_rate)] {
            if !(v > 0.0 && v < 0.5) {
                return Err(invalid_option(
                    name,
                    format!("must be in (0, 0.5), got {v}"),
                ));
            }
        }
        let e = Evidence {
            hit_nats: ((1.0 - miss_rate) / false_alarm).ln(),
            miss_nats: (miss_rate / (1.0 - false_alarm)).ln(),
        };
        e.validate("evidence")?;
        Ok(e)
    }

    /// Checks the ranges; `name` prefixes the option name in the error (e.g. `laser`).
    pub fn validate(&self, name: &'static str) -> Result<()> {
        if !(self.hit_nats > 0.0 && self.hit_nats <= MAX_ABS_NATS) {
            return Err(invalid_option(
                name,
                format!("hit_nats must be in (0, 16], got {}", self.hit_nats),
            ));
        }
        if !(self.miss_nats < 0.0 && self.miss_nats >= -MAX_ABS_NATS) {
            return Err(invalid_option(
                name,
                format!("miss_nats must be in [-16, 0), got {}", self.miss_nats),
            ));
        }
        let (hit, miss) = self.units();
        if hit == 0 || miss == 0 {
            return Err(invalid_option(
                name,
                "hit and miss must be at least 0.001 nats in magnitude",
            ));
        }
        Ok(())
    }

    /// The increments in stored units (hit > 0, miss < 0).
    pub fn units(&self) -> (i16, i16) {
        (
            (self.hit_nats * UNITS_PER_NAT).round() as i16,
            (self.miss_nats * UNITS_PER_NAT).round() as i16,
        )
    }
}

#[cfg(test)]
mod tests {
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
}
