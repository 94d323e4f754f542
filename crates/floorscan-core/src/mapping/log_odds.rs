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
#[path = "log_odds_tests.rs"]
mod tests;
