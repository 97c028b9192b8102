//! Parsing and number validation of machine profiles, with JSON paths.
use std::path::Path;

use super::profile::{MachineProfile, ProfileError, PROFILE_FORMAT};

/// What a number must satisfy.
#[derive(Debug, Clone, Copy)]
enum Rule {
    /// Finite.
    Finite,
    /// Finite, within `[lo, hi]` (a physical range).
    Within(f64, f64),
    /// Finite, in `(0, hi]`.
    UpTo(f64),
}

/// Controller cycles accepted, s: 10 us to 100 ms (real CMM controllers
/// run at 0.5 to 5 ms; a longer cycle cannot follow a scan, a shorter one
/// only multiplies the simulation's work).
pub const CONTROL_CYCLE_RANGE_S: (f64, f64) = (1e-5, 0.1);
/// Largest linear axis speed accepted, mm/s.
pub const MAX_LINEAR_VELOCITY_MM_S: f64 = 5_000.0;
/// Largest linear axis acceleration accepted, mm/s^2 (about 5 g).
pub const MAX_LINEAR_ACCELERATION_MM_S2: f64 = 50_000.0;
/// Largest rotary axis speed accepted, rad/s.
pub const MAX_ROTARY_VELOCITY_RAD_S: f64 = 100.0;
/// Largest rotary axis acceleration accepted, rad/s^2.
pub const MAX_ROTARY_ACCELERATION_RAD_S2: f64 = 10_000.0;
/// Largest servo lag time constant accepted, s.
pub const MAX_SERVO_LAG_S: f64 = 1.0;
/// Largest scale resolution or noise accepted, mm.
pub const MAX_SCALE_ERROR_MM: f64 = 0.1;
/// Largest encoder resolution or noise accepted, rad.
pub const MAX_ENCODER_ERROR_RAD: f64 = 0.01;

impl Rule {
    fn holds(self, v: f64) -> bool {
        match self {
            Rule::Finite => v.is_finite(),
            Rule::Within(lo, hi) => v.is_finite() && v >= lo && v <= hi,
            Rule::UpTo(hi) => v.is_finite() && v > 0.0 && v <= hi,
        }
    }

    fn requirement(self) -> String {
        match self {
            Rule::Finite => "finite".into(),
            Rule::Within(lo, hi) => format!("within [{lo:e}, {hi}]"),
            Rule::UpTo(hi) => format!("positive and at most {hi}"),
        }
    }
}

/// Deserialises with JSON paths in error messages.
pub(super) fn parse(text: &str, file: &Path) -> Result<MachineProfile, ProfileError> {
    Ok(crate::jsonfile::parse_json(text, file)?)
}

/// Format tag and every number in range.
pub(super) fn validate(profile: &MachineProfile, file: &Path) -> Result<(), ProfileError> {
    if profile.format != PROFILE_FORMAT {
        let found = profile.format.clone();
        return Err(ProfileError::Format {
            file: file.to_path_buf(),
            found,
        });
    }
    let failed = numbers(profile)
        .into_iter()
        .find(|(_, v, rule)| !rule.holds(*v));
    match failed {
        None => Ok(()),
        Some((json_path, value, rule)) => Err(ProfileError::Invalid {
            file: file.to_path_buf(),
            json_path,
            value,
            requirement: rule.requirement(),
        }),
    }
}

/// Every number of the profile with its JSON path and rule.
fn numbers(p: &MachineProfile) -> Vec<(String, f64, Rule)> {
    let (l, r) = (&p.linear, &p.rotary);
    let (cycle_lo, cycle_hi) = CONTROL_CYCLE_RANGE_S;
    let lag = Rule::Within(0.0, MAX_SERVO_LAG_S);
    let scale = Rule::Within(0.0, MAX_SCALE_ERROR_MM);
    let encoder = Rule::Within(0.0, MAX_ENCODER_ERROR_RAD);
    let mut out: Vec<(String, f64, Rule)> = [
        (
            "control_cycle_s",
            p.control_cycle_s,
            Rule::Within(cycle_lo, cycle_hi),
        ),
        (
            "linear.max_velocity_mm_s",
            l.max_velocity_mm_s,
            Rule::UpTo(MAX_LINEAR_VELOCITY_MM_S),
        ),
        (
            "linear.max_acceleration_mm_s2",
            l.max_acceleration_mm_s2,
            Rule::UpTo(MAX_LINEAR_ACCELERATION_MM_S2),
        ),
        ("linear.servo_lag_s", l.servo_lag_s, lag),
        ("linear.scale_resolution_mm", l.scale_resolution_mm, scale),
        ("linear.scale_noise_mm", l.scale_noise_mm, scale),
        (
            "rotary.max_velocity_rad_s",
            r.max_velocity_rad_s,
            Rule::UpTo(MAX_ROTARY_VELOCITY_RAD_S),
        ),
        (
            "rotary.max_acceleration_rad_s2",
            r.max_acceleration_rad_s2,
            Rule::UpTo(MAX_ROTARY_ACCELERATION_RAD_S2),
        ),
        ("rotary.servo_lag_s", r.servo_lag_s, lag),
        (
            "rotary.scale_resolution_rad",
            r.scale_resolution_rad,
            encoder,
        ),
        ("rotary.scale_noise_rad", r.scale_noise_rad, encoder),
    ]
    .into_iter()
    .map(|(path, v, rule)| (format!("$.{path}"), v, rule))
    .collect();
    out.extend(geometric_numbers(p));
    out
}

/// Polynomial coefficients and squareness angles: finite.
fn geometric_numbers(p: &MachineProfile) -> Vec<(String, f64, Rule)> {
    let g = &p.geometric;
    let mut out = Vec::new();
    for (axis, errors) in g.axes() {
        for (term, poly) in errors.terms() {
            for (k, c) in poly.0.iter().enumerate() {
                out.push((format!("$.geometric.{axis}.{term}[{k}]"), *c, Rule::Finite));
            }
        }
    }
    let s = &g.squareness;
    for (name, v) in [
        ("xy_rad", s.xy_rad),
        ("xz_rad", s.xz_rad),
        ("yz_rad", s.yz_rad),
    ] {
        out.push((format!("$.geometric.squareness.{name}"), v, Rule::Finite));
    }
    out
}
