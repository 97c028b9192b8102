//! Whether the probe can measure a program's features, from the design
//! data alone (`cmm check`; the scan checks each feature the same way
//! before measuring it).
use crate::host::inspect::clearance::{ClearanceOptions, PartClearance, ProbeBody};
use crate::host::inspect::corners::{own_faces, section_design, CornerOptions};
use crate::host::inspect::correction::DesignPoint;
use crate::host::inspect::reach::{Reach, Unreachable};
use crate::host::modes::{HostProbe, ModeOptions};
use crate::program::limits::start_position;
use crate::program::{Feature, Program};

/// The nominal part's free space for the probe `probe` of `program`.
pub fn part_clearance<'p>(
    program: &'p Program,
    probe: HostProbe,
    opts: ClearanceOptions,
) -> PartClearance<'p> {
    PartClearance {
        workpiece: &program.workpiece,
        pose: program.placement,
        stylus: -probe.probe_vector,
        tip_radius_mm: probe.tip_radius_mm,
        shaft_radius_mm: program.probe.shaft_radius_mm,
        body: Some(ProbeBody {
            radius_mm: program.probe.body_radius_mm,
            length_mm: program.probe.body_length_mm,
        }),
        opts,
    }
}

/// `base` with the program's clearance margins.
pub fn program_margins(program: &Program, base: ClearanceOptions) -> ClearanceOptions {
    let m = program.clearance;
    ClearanceOptions {
        margin_mm: m.margin_mm,
        tight_margin_mm: m.tight_margin_mm,
        posture_margin_mm: m.posture_margin_mm,
        ..base
    }
}

/// Every feature (name, section curve index or touch point index) that the
/// program's nominal probe cannot measure, and why.
pub fn unreachable_features(program: &Program) -> Vec<(String, usize, Unreachable)> {
    let probe = HostProbe::nominal(program.probe_vector(), program.probe.tip_radius_mm);
    let margins = program_margins(program, ClearanceOptions::default());
    let free = part_clearance(program, probe, margins);
    let modes = ModeOptions {
        clearance_z_mm: Some(start_position(program).1),
        ..ModeOptions::default()
    };
    let reach = Reach {
        free: &free,
        pose: program.placement,
        probe,
        modes: &modes,
    };
    let design = |point, normal| DesignPoint { point, normal };
    let mut out = Vec::new();
    for f in &program.features {
        match f {
            Feature::Section {
                name,
                curves,
                plane,
                ..
            } => {
                for (k, c) in curves.iter().enumerate() {
                    let pts: Vec<DesignPoint> =
                        c.points.iter().map(|p| design(p.point, p.normal)).collect();
                    let (r, opts) = (probe.tip_radius_mm, CornerOptions::default());
                    let on = (&program.workpiece, plane.normal());
                    let own = own_faces(c);
                    let pts = section_design((&pts, &own), c.closed, on, r, &opts);
                    let checked = match pts.len() {
                        0 | 1 => Err(Unreachable::TooNarrow),
                        _ => reach.curve(&pts),
                    };
                    if let Err(u) = checked {
                        out.push((name.clone(), k, u));
                    }
                }
            }
            Feature::Touch { name, points, .. } => {
                for (k, p) in points.iter().enumerate() {
                    if let Err(u) = reach.touch(&design(p.point, p.normal)) {
                        out.push((name.clone(), k, u));
                    }
                }
            }
        }
    }
    out
}
