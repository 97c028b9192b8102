//! Parsing and number validation of machine profiles, with JSON paths.
use std::path::Path;

use super::profile::{MachineProfile, ProfileError, PROFILE_FORMAT};

/// What a number must satisfy.
#[derive(Debug, Clone, Copy)]
enum Rule {
    /// Finite and > 0.
    Positive,
    /// Finite and >= 0.
    NonNegative,
    /// Finite.
    Finite,
}

impl Rule {
    fn holds(self, v: f64) -> bool {
        match self {
            Rule::Positive => v.is_finite() && v > 0.0,
            Rule::NonNegative => v.is_finite() && v >= 0.0,
            Rule::Finite => v.is_finite(),
        }
    }

    fn requirement(self) -> &'static str {
        match self {
            Rule::Positive => "finite and positive",
            Rule::NonNegative => "finite and non-negative",
            Rule::Finite => "finite",
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
    let mut out: Vec<(String, f64, Rule)> = [
        ("control_cycle_s", p.control_cycle_s, Rule::Positive),
        (
            "linear.max_velocity_mm_s",
            l.max_velocity_mm_s,
            Rule::Positive,
        ),
        (
            "linear.max_acceleration_mm_s2",
            l.max_acceleration_mm_s2,
            Rule::Positive,
        ),
        ("linear.servo_lag_s", l.servo_lag_s, Rule::NonNegative),
        (
            "linear.scale_resolution_mm",
            l.scale_resolution_mm,
            Rule::NonNegative,
        ),
        ("linear.scale_noise_mm", l.scale_noise_mm, Rule::NonNegative),
        (
            "rotary.max_velocity_rad_s",
            r.max_velocity_rad_s,
            Rule::Positive,
        ),
        (
            "rotary.max_acceleration_rad_s2",
            r.max_acceleration_rad_s2,
            Rule::Positive,
        ),
        ("rotary.servo_lag_s", r.servo_lag_s, Rule::NonNegative),
        (
            "rotary.scale_resolution_rad",
            r.scale_resolution_rad,
            Rule::NonNegative,
        ),
        (
            "rotary.scale_noise_rad",
            r.scale_noise_rad,
            Rule::NonNegative,
        ),
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
