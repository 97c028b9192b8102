//! Probing the reference sphere through the [`Cmm`] seam: the 25 touch
//! points and the circle scans. Only readings are kept.
use super::pattern::{circle_directions, iso_25_directions, ScanPlane};
use super::{CalibrateError, CalibrationOptions};
use crate::host::modes::{
    design_value_scan, touch_point, HostProbe, Measured, ModeOptions, Outcome, ScanKind, ScanPlan,
    ScanTargets,
};
use crate::host::observe::Machine;
use crate::host::path::{BallPath, PathOptions, SpeedOptions};
use crate::math::{Point3, Vec3};

/// One circle scan's readings and its conditions.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanRecord {
    /// The plane scanned.
    pub plane: ScanPlane,
    /// Counter-clockwise (positive about the plane's normal axis).
    pub ccw: bool,
    /// Wanted deflection, mm.
    pub deflection_mm: f64,
    /// The readings taken at the scan pitch.
    pub samples: Vec<Measured>,
}

/// Everything measured on the sphere.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereReadings {
    /// The 25 touch points (ISO 10360-5 pattern).
    pub touches: Vec<Measured>,
    /// The circle scans.
    pub scans: Vec<ScanRecord>,
}

/// Measures the 25 touch points and every requested scan.
pub fn measure_sphere(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    opts: &CalibrationOptions,
) -> Result<SphereReadings, CalibrateError> {
    let touches = touches(cmm, probe, opts)?;
    let mut scans = Vec::new();
    for &plane in &opts.planes {
        for &ccw in &opts.directions {
            for &ep in &opts.deflections_mm {
                scans.push(scan(cmm, probe, opts, plane, ccw, ep)?);
            }
        }
    }
    Ok(SphereReadings { touches, scans })
}

/// Mode options with moves through the clearance height above the sphere.
pub fn modes(opts: &CalibrationOptions, probe: &HostProbe) -> ModeOptions {
    let top = opts.sphere_center_mm.z + opts.sphere_radius() + probe.tip_radius_mm;
    ModeOptions {
        clearance_z_mm: Some(top + opts.clearance_mm),
        ..opts.modes
    }
}

fn touches(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    opts: &CalibrationOptions,
) -> Result<Vec<Measured>, CalibrateError> {
    let dirs = iso_25_directions();
    touch_pattern(cmm, probe, opts.sphere_center_mm, &dirs, opts)
}

/// Touches the sphere once along every outward direction in `dirs`; the
/// sphere's centre is expected at `centre` in the host's uncorrected ball
/// coordinates (scales + probe vector).
pub fn touch_pattern(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    centre: Point3,
    dirs: &[Vec3],
    opts: &CalibrationOptions,
) -> Result<Vec<Measured>, CalibrateError> {
    let modes = modes(opts, &probe);
    let radius = opts.sphere_radius();
    let mut out = Vec::new();
    for (index, n) in dirs.iter().enumerate() {
        let a = touch_point(
            cmm,
            (probe, None),
            centre + n * radius,
            *n,
            opts.touch_search_mm,
            &modes,
        );
        match (a.outcome, a.points.first()) {
            (Outcome::Completed, Some(m)) => out.push(*m),
            (outcome, _) => return Err(CalibrateError::Touch { index, outcome }),
        }
    }
    Ok(out)
}

fn scan(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    opts: &CalibrationOptions,
    plane: ScanPlane,
    ccw: bool,
    ep: f64,
) -> Result<ScanRecord, CalibrateError> {
    let dirs = circle_directions(
        plane,
        opts.circle_points,
        (
            opts.arc_below_equator_for(probe.tip_radius_mm),
            opts.xy_elevation_deg,
        ),
        ccw,
    );
    let (c, radius) = (opts.sphere_center_mm, opts.sphere_radius());
    let section: Vec<(Point3, Vec3)> = dirs.iter().map(|n| (c + n * radius, *n)).collect();
    let closed = plane == ScanPlane::Xy;
    let failed = |outcome| CalibrateError::Scan {
        plane,
        ccw,
        deflection_mm: ep,
        outcome,
    };
    let path = BallPath::from_section(
        &section,
        closed,
        probe.tip_radius_mm - ep,
        PathOptions::default(),
    )
    .map_err(|_| failed(Outcome::Aborted))?;
    let speed = SpeedOptions {
        speed_mm_s: opts.scan_speed_mm_s,
        a_lat_mm_s2: opts.modes.lateral_accel_mm_s2,
        a_tan_mm_s2: opts.modes.tangential_accel_mm_s2,
        cycle_s: cmm.cycle_s(),
        ..SpeedOptions::default()
    };
    let plan =
        ScanPlan::new(&path, ScanKind::Active, &speed).map_err(|_| failed(Outcome::Aborted))?;
    let targets = ScanTargets {
        deflection_mm: ep,
        pitch_mm: opts.scan_pitch_mm,
        trajectory_tolerance_mm: opts.trajectory_tolerance_mm,
        plane_normal: None,
    };
    let modes = modes(opts, &probe);
    let a = design_value_scan(cmm, (probe, None), &path, &plan, targets, &modes);
    if a.outcome != Outcome::Completed {
        return Err(failed(a.outcome));
    }
    Ok(ScanRecord {
        plane,
        ccw,
        deflection_mm: ep,
        samples: a.points,
    })
}
