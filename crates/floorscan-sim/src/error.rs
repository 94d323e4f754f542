//! The one error type of the simulator crate. World-file problems get their own variant (its
//! message names the line or the field); everything else reuses the core's variants, so each
//! still maps to its own Python exception class.

/// Errors returned by floorscan-sim. The simulator never panics on user-supplied data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A world file is not valid TOML, has an unknown or ill-typed key, or describes impossible
    /// geometry. The message names the line (syntax, types) or the field path (values), for
    /// example `walls[3].height_m: must be > 0, got -1`.
    #[error("invalid world {source_name}: {reason}")]
    InvalidWorld { source_name: String, reason: String },
    /// An option, geometry or length error from the core's vocabulary.
    #[error(transparent)]
    Core(#[from] floorscan_core::Error),
}

/// Result alias of the simulator crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Shorthand for a core [`floorscan_core::Error::InvalidOption`].
pub(crate) fn invalid_option(name: &'static str, reason: impl Into<String>) -> Error {
    Error::Core(floorscan_core::Error::InvalidOption {
        name,
        reason: reason.into(),
    })
}

/// Checks that `value` is finite and inside `[lo, hi]`, naming the option otherwise.
pub(crate) fn check_range(name: &'static str, value: f64, lo: f64, hi: f64) -> Result<()> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(invalid_option(
            name,
            format!("must be finite and in [{lo}, {hi}], got {value}"),
        ))
    }
}
