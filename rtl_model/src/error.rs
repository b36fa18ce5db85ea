//! Configuration and input errors. Every error names the field at fault.

/// An invalid configuration or input. `field` is the dotted path of the offending
/// field (e.g. `texture_sampler.texel_bits`), so a user can find it in a scene file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// A number outside its allowed range `min ..= max`.
    #[error("{field}: {} is out of range (allowed {} ..= {})", short(*.value), short(*.min), short(*.max))]
    OutOfRange {
        /// Dotted path of the field at fault, e.g. `modulate.bits`.
        field: String,
        /// The value given.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
    /// A NaN or ±∞ where a finite number is needed.
    #[error("{field}: {} is not a finite number", short(*.value))]
    NotFinite {
        /// Dotted path of the field at fault.
        field: String,
        /// The value given (NaN or ±∞).
        value: f64,
    },
    /// A value that no range describes (a wrong combination, an unknown name, a
    /// zero direction vector); `reason` says what is wrong.
    #[error("{field}: {reason}")]
    Invalid {
        /// Dotted path of the field at fault.
        field: String,
        /// What is wrong, as a sentence for the user.
        reason: String,
    },
}

impl ConfigError {
    /// An [`ConfigError::OutOfRange`] error naming `field`.
    pub fn out_of_range(field: &str, value: f64, min: f64, max: f64) -> Self {
        ConfigError::OutOfRange {
            field: field.to_string(),
            value,
            min,
            max,
        }
    }

    /// A [`ConfigError::NotFinite`] error naming `field`.
    pub fn not_finite(field: &str, value: f64) -> Self {
        ConfigError::NotFinite {
            field: field.to_string(),
            value,
        }
    }

    /// A [`ConfigError::Invalid`] error naming `field`, with a sentence saying why.
    pub fn invalid(field: &str, reason: &str) -> Self {
        ConfigError::Invalid {
            field: field.to_string(),
            reason: reason.to_string(),
        }
    }

    /// The field at fault.
    pub fn field(&self) -> &str {
        match self {
            ConfigError::OutOfRange { field, .. }
            | ConfigError::NotFinite { field, .. }
            | ConfigError::Invalid { field, .. } => field,
        }
    }

    /// The same error naming `field` instead (a unit's error mapped onto the scene
    /// field that configured it).
    pub fn renamed(self, field: &str) -> Self {
        let field = field.to_string();
        match self {
            ConfigError::OutOfRange {
                value, min, max, ..
            } => ConfigError::OutOfRange {
                field,
                value,
                min,
                max,
            },
            ConfigError::NotFinite { value, .. } => ConfigError::NotFinite { field, value },
            ConfigError::Invalid { reason, .. } => ConfigError::Invalid { field, reason },
        }
    }

    /// The same error with `prefix.` put before the field (for nested configs).
    pub fn within(self, prefix: &str) -> Self {
        let join = |f: String| format!("{prefix}.{f}");
        match self {
            ConfigError::OutOfRange {
                field,
                value,
                min,
                max,
            } => ConfigError::OutOfRange {
                field: join(field),
                value,
                min,
                max,
            },
            ConfigError::NotFinite { field, value } => ConfigError::NotFinite {
                field: join(field),
                value,
            },
            ConfigError::Invalid { field, reason } => ConfigError::Invalid {
                field: join(field),
                reason,
            },
        }
    }
}

/// A number as an error message shows it: as Rust prints it when that is short
/// (`8192`, `0.5`, `1000000`), in scientific notation when it would be long
/// (`1e308`, not 309 digits; `1e-300`; `1.2345e20`).
pub fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 18 {
        plain
    } else {
        format!("{x:e}")
    }
}

/// Check that an integer config field lies in `min..=max`.
pub fn check_range(field: &str, value: u64, min: u64, max: u64) -> Result<(), ConfigError> {
    if value < min || value > max {
        Err(ConfigError::out_of_range(
            field,
            value as f64,
            min as f64,
            max as f64,
        ))
    } else {
        Ok(())
    }
}

/// Check that a float input is finite (NaN and ±∞ are refused).
pub fn check_finite(field: &str, value: f64) -> Result<f64, ConfigError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ConfigError::not_finite(field, value))
    }
}
