//! Whether the probe can measure a program's features, from the design
//! data alone (`cmm check`; the scan checks each feature the same way
//! before measuring it).
use crate::host::inspect::clearance::{ClearanceOptions, PartClearance, ProbeBody};
use crate::host::inspect::corners::{own_faces, section_design, CornerOptions};
use crate::host::inspect::correction::DesignPoint;
use crate::host::inspect::reach::{Reach, Unreachable};
use crate::host::modes::{HostProbe, ModeOptions};
use crate::program::limits::start_position;
use crate::program::{Feature, Program, Travel};

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

/// `base` with the program's clearance margins, and its sampling step no
/// longer than the ball radius plus the tight margin (the distance the
/// tightest check keeps): a point of a move called clear then keeps at
/// least `1 - 1/sqrt(2)` of it, and a wall thinner than the step cannot
/// pass unseen between the samples of a small probe's move (a 0.3 mm ball
/// with a 0.1 mm margin is checked every 0.25 mm, not every 2 mm).
pub fn program_margins(program: &Program, base: ClearanceOptions) -> ClearanceOptions {
    let m = program.clearance;
    let tightest = program.probe.tip_radius_mm + m.tight_margin_mm;
    ClearanceOptions {
        margin_mm: m.margin_mm,
        tight_margin_mm: m.tight_margin_mm,
        posture_margin_mm: m.posture_margin_mm,
        step_mm: base.step_mm.min(tightest),
        ..base
    }
}

/// The box the program's machine moves its probe mount in, `(lo, hi)`,
/// machine coordinates, mm ([`ModeOptions::travel_mm`]).
pub fn travel_box(program: &Program) -> ([f64; 3], [f64; 3]) {
    let t = Travel::of(&program.machine);
    (t.lo, t.hi)
}

/// The name [`unreachable_features`] gives the alignment's touch points.
pub const ALIGNMENT: &str = "alignment";

/// Every feature (name, section curve index or touch point index) that the
/// program's nominal probe cannot measure, and why; the alignment's touch
/// points first, named [`ALIGNMENT`].
pub fn unreachable_features(program: &Program) -> Vec<(String, usize, Unreachable)> {
    let probe = HostProbe::nominal(program.probe_vector(), program.probe.tip_radius_mm);
    let margins = program_margins(program, ClearanceOptions::default());
    let free = part_clearance(program, probe, margins);
    let modes = ModeOptions {
        clearance_z_mm: Some(start_position(program).1),
        travel_mm: Some(travel_box(program)),
        ..ModeOptions::default()
    };
    let reach = Reach {
        free: &free,
        pose: program.placement,
        probe,
        modes: &modes,
        press_mm: 0.0,
    };
    let design = |point, normal| DesignPoint { point, normal };
    let mut out = Vec::new();
    for (k, p) in program.alignment.iter().flatten().enumerate() {
        if let Err(u) = reach.touch(&design(p.point, p.normal)) {
            out.push((ALIGNMENT.to_string(), k, u));
        }
    }
    for f in &program.features {
        match f {
            Feature::Section {
                name,
                curves,
                plane,
                settings,
                ..
            } => {
                let reach = Reach {
                    press_mm: settings.deflection_mm,
                    ..reach
                };
                for (k, c) in curves.iter().enumerate() {
                    let pts: Vec<DesignPoint> =
                        c.points.iter().map(|p| design(p.point, p.normal)).collect();
                    let (r, opts) = (probe.tip_radius_mm, CornerOptions::default());
                    let on = (&program.workpiece, plane.normal());
                    let own = own_faces(c);
                    let pts = section_design((&pts, &own), c.closed, on, r, &opts);
                    let checked = match pts.len() {
                        0 | 1 => Err(Unreachable::TooNarrow),
                        _ => reach.curve_either_way(&pts, c.closed).0,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::host::modes::FreeSpace;
    use crate::math::{Mat3, Point3, Vec3};
    use crate::program::{load, Pose};
    use crate::workpiece::examples::reference_sphere;
    use crate::workpiece::Workpiece;

    /// A 0.3 mm ball on a short stylus moving along x at height `z` past a
    /// sphere of radius 25 (the program's margins, its step as
    /// [`program_margins`] sets it): the ball's path keeps `|z| - 25.15`
    /// from the sphere when it passes above it, and crosses the sphere's
    /// surface twice when it runs through it.
    fn small_ball_clear(z: f64, base: ClearanceOptions) -> bool {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("part-programs");
        let mut program = load(&dir.join("bore-circles.json")).unwrap_or_else(|e| panic!("{e}"));
        program.probe.tip_radius_mm = 0.15;
        program.clearance.margin_mm = 0.5;
        program.clearance.tight_margin_mm = 0.1;
        let wp = Workpiece::from_file(&reference_sphere(50.0), "sphere.json".as_ref())
            .unwrap_or_else(|e| panic!("{e}"));
        let free = PartClearance {
            workpiece: &wp,
            pose: Pose {
                rotation: Mat3::identity(),
                translation: Vec3::zeros(),
            },
            stylus: Vec3::new(0.0, 0.0, 0.5),
            tip_radius_mm: 0.15,
            shaft_radius_mm: 0.075,
            body: None,
            opts: program_margins(&program, base),
        };
        let (a, b) = (Point3::new(-40.0, 0.3, z), Point3::new(40.0, 0.3, z));
        free.segment_clear_with(a, b, true)
    }

    #[test]
    fn a_small_ball_s_moves_are_sampled_finely_enough_to_see_the_surface() {
        let base = ClearanceOptions::default();
        // Through the sphere (its ends outside it): never clear, however
        // the surface falls between the samples.
        for k in 0..20 {
            let z = 20.0 + 0.25 * k as f64;
            assert!(!small_ball_clear(z, base), "through the sphere at z = {z}");
        }
        // Above it by more than the ball and the tight margin: clear.
        assert!(small_ball_clear(25.6, base));
        assert!(!small_ball_clear(25.2, base));
    }
}
