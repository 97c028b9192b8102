//! File formats that more than one side reads, as plain serde types.
//!
//! - [`as_machined`]: the `as_machined` block of a part program (the
//!   simulated scenario: how the machined part differs from its design).
//!   Only the world and the application layer that builds it read it; the
//!   measuring side never does.
//! - [`workpiece`]: the `cmm-workpiece/1` file (rational B-spline
//!   surfaces with optional trims), read by the design side and written
//!   by the CAD import.
//! - [`probe_truth`]: the simulator's true probe, written beside a
//!   simulated calibration for comparison only.

pub mod as_machined;
pub mod probe_truth;
pub mod workpiece;

/// The serde name of a unit enum variant (`Outcome::LostContact` ->
/// `lost_contact`), the same name its JSON carries; `?` for a value that
/// serialises to no string.
pub fn serde_name<T: serde::Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(name)) => name,
        Ok(other) => other.to_string(),
        Err(_) => "?".to_string(),
    }
}
