//! Scan paths planned before the measuring starts.
//!
//! The first design-value scan of a section curve follows the nominal
//! design data in the program's placement, so its ball-centre path and its
//! speeds can be planned from the program alone, the way a CMM's
//! programming software prepares scan paths offline before the part is on
//! the machine. Each plan keeps every input it was made from; a scan uses a
//! prepared plan only when its own inputs are exactly the same (the same
//! design points, pose, offset, options and scan kind), so a corrected
//! design, an aligned pose or a learned correction is always planned anew
//! and the measured result is the same bit for bit either way.
use super::correction::DesignPoint;
use crate::host::modes::{ScanKind, ScanPlan};
use crate::host::path::{BallPath, PathOptions, SpeedOptions};
use crate::math::{Point3, Vec3};
use crate::program::{Feature, Mode, Pose, Program};

/// Everything a scan's path and speed plan are made from.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanInputs {
    /// Design points (position, outward normal), machine frame.
    pub design: Vec<(Point3, Vec3)>,
    /// Whether the section curve is closed.
    pub closed: bool,
    /// Offset of the ball centre along the normal, `r - Ep`, mm.
    pub offset_mm: f64,
    /// Path construction options.
    pub path: PathOptions,
    /// Speed planning options.
    pub speed: SpeedOptions,
    /// Passive or active.
    pub kind: ScanKind,
}

impl ScanInputs {
    /// The inputs of a scan of `design` (part frame) placed by `pose`.
    pub fn new(
        design: &[DesignPoint],
        pose: &Pose,
        closed: bool,
        offset_mm: f64,
        speed: SpeedOptions,
        kind: ScanKind,
    ) -> ScanInputs {
        let design = (design.iter())
            .map(|d| (pose.to_machine(d.point), pose.dir_to_machine(d.normal)))
            .collect();
        ScanInputs {
            design,
            closed,
            offset_mm,
            path: PathOptions::default(),
            speed,
            kind,
        }
    }
}

/// Why a scan could not be planned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanFailure {
    /// No ball-centre path could be built from the design data.
    Path,
    /// Speed planning failed on the path.
    Speed,
}

impl PlanFailure {
    /// The note a failed attempt carries in the report.
    pub fn note(self) -> &'static str {
        match self {
            PlanFailure::Path => "could not build a scanning path from the design data",
            PlanFailure::Speed => "speed planning failed",
        }
    }
}

/// A scan's path and speed plan with the inputs they were made from.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedScan {
    inputs: ScanInputs,
    /// The ball-centre path (machine frame).
    pub path: BallPath,
    /// What the scan needs of the speed planning.
    pub plan: ScanPlan,
}

impl PreparedScan {
    /// Plans a scan from its inputs.
    pub fn new(inputs: ScanInputs) -> Result<PreparedScan, PlanFailure> {
        let path =
            BallPath::from_section(&inputs.design, inputs.closed, inputs.offset_mm, inputs.path)
                .map_err(|_| PlanFailure::Path)?;
        let plan =
            ScanPlan::new(&path, inputs.kind, &inputs.speed).map_err(|_| PlanFailure::Speed)?;
        Ok(PreparedScan { inputs, path, plan })
    }

    /// Whether this plan was made from exactly `inputs`.
    pub fn fits(&self, inputs: &ScanInputs) -> bool {
        self.inputs == *inputs
    }
}

/// Plans prepared per section feature and curve (`None` where nothing was
/// prepared).
#[derive(Debug, Default)]
pub struct Prepared(Vec<Vec<Option<PreparedScan>>>);

impl Prepared {
    /// Plans the first scan of every section curve of `program` whose mode
    /// starts with a design-value scan, in the program's placement, for a
    /// probe of tip radius `tip_radius_mm` and a control cycle `cycle_s`.
    pub fn for_program(
        program: &Program,
        tip_radius_mm: f64,
        base: SpeedOptions,
        cycle_s: f64,
    ) -> Prepared {
        let per_feature = (program.features.iter())
            .map(|f| prepare_feature(f, &program.placement, tip_radius_mm, base, cycle_s))
            .collect();
        Prepared(per_feature)
    }

    /// The plan prepared for curve `curve` of feature `feature`.
    pub fn get(&self, feature: usize, curve: usize) -> Option<&PreparedScan> {
        self.0.get(feature)?.get(curve)?.as_ref()
    }
}

fn prepare_feature(
    feature: &Feature,
    pose: &Pose,
    tip_radius_mm: f64,
    base: SpeedOptions,
    cycle_s: f64,
) -> Vec<Option<PreparedScan>> {
    let Feature::Section {
        curves, settings, ..
    } = feature
    else {
        return Vec::new();
    };
    let kind = match settings.mode {
        Mode::Auto | Mode::Active => ScanKind::Active,
        Mode::AutoPassive | Mode::Passive => ScanKind::Passive,
        Mode::Autonomous => return Vec::new(),
    };
    let speed = scan_speed(base, settings.speed_mm_s, cycle_s);
    let offset = tip_radius_mm - settings.deflection_mm;
    (curves.iter())
        .map(|c| {
            let design: Vec<DesignPoint> = (c.points.iter())
                .map(|p| DesignPoint {
                    point: p.point,
                    normal: p.normal,
                })
                .collect();
            let inputs = ScanInputs::new(&design, pose, c.closed, offset, speed, kind);
            PreparedScan::new(inputs).ok()
        })
        .collect()
}

/// Speed options of a scan at `speed_mm_s` from the mode's accelerations
/// (`base`) and the machine's control cycle.
pub fn scan_speed(base: SpeedOptions, speed_mm_s: f64, cycle_s: f64) -> SpeedOptions {
    SpeedOptions {
        speed_mm_s,
        cycle_s,
        ..base
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::SectionCurve as Curve;
    use crate::host::modes::ModeOptions;
    use crate::inspect::supervisor::base_speed;
    use crate::inspect::{run_program, RunOptions};
    use crate::program::load;
    use std::path::Path;

    fn program(name: &str) -> Program {
        let file = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("part-programs")
            .join(name);
        load(&file).unwrap_or_else(|e| panic!("{e}"))
    }

    fn design(c: &Curve) -> Vec<DesignPoint> {
        (c.points.iter())
            .map(|p| DesignPoint {
                point: p.point,
                normal: p.normal,
            })
            .collect()
    }

    /// The inputs the supervisor gives the first scan of `curve` of a
    /// section feature (nominal design, program placement, default modes,
    /// 1 ms cycle).
    fn first_scan_inputs(p: &Program, feature: &Feature, curve: &Curve) -> ScanInputs {
        let Feature::Section { settings, .. } = feature else {
            panic!("not a section feature");
        };
        let speed = scan_speed(
            base_speed(&ModeOptions::default()),
            settings.speed_mm_s,
            0.001,
        );
        let offset = p.probe.tip_radius_mm - settings.deflection_mm;
        ScanInputs::new(
            &design(curve),
            &p.placement,
            curve.closed,
            offset,
            speed,
            ScanKind::Active,
        )
    }

    fn prepared(p: &Program) -> Prepared {
        let base = base_speed(&ModeOptions::default());
        Prepared::for_program(p, p.probe.tip_radius_mm, base, 0.001)
    }

    /// Every section curve of an `auto` program gets a plan, and it is the
    /// one its first scan asks for, at the right (feature, curve) index.
    #[test]
    fn first_scans_fit_their_prepared_plans() {
        let p = program("blade-batch.json");
        let plans = prepared(&p);
        let mut curves = 0;
        for (i, f) in p.features.iter().enumerate() {
            let Feature::Section { curves: cs, .. } = f else {
                continue;
            };
            for (k, c) in cs.iter().enumerate() {
                let plan = plans
                    .get(i, k)
                    .unwrap_or_else(|| panic!("no plan for {i}/{k}"));
                assert!(plan.fits(&first_scan_inputs(&p, f, c)), "plan {i}/{k}");
                curves += 1;
            }
        }
        assert!(curves >= 2, "only {curves} curves");
        assert!(plans.get(p.features.len(), 0).is_none());
    }

    /// A plan does not fit a scan whose inputs differ in any way.
    #[test]
    fn other_inputs_do_not_fit() {
        let p = program("blade-z60.json");
        let f = &p.features[0];
        let Feature::Section { curves, .. } = f else {
            panic!("not a section feature");
        };
        let inputs = first_scan_inputs(&p, f, &curves[0]);
        let plan = PreparedScan::new(inputs.clone()).unwrap_or_else(|e| panic!("{e:?}"));
        assert!(plan.fits(&inputs));
        let mut moved = inputs.clone();
        moved.design[3].0.x += 1e-6;
        let mut passive = inputs.clone();
        passive.kind = ScanKind::Passive;
        let mut deeper = inputs.clone();
        deeper.offset_mm -= 0.01;
        let mut slower = inputs.clone();
        slower.speed.speed_mm_s *= 0.5;
        let mut shifted_pose = p.placement;
        shifted_pose.translation.y += 0.001;
        let shifted = ScanInputs::new(
            &design(&curves[0]),
            &shifted_pose,
            inputs.closed,
            inputs.offset_mm,
            inputs.speed,
            inputs.kind,
        );
        for (what, other) in [
            ("moved point", moved),
            ("passive", passive),
            ("offset", deeper),
            ("speed", slower),
            ("pose", shifted),
        ] {
            assert!(!plan.fits(&other), "{what}");
        }
    }

    fn report_json(p: &Program, prepare_scans: bool) -> serde_json::Value {
        let opts = RunOptions {
            prepare_scans,
            ..RunOptions::default()
        };
        let (mut report, _) = run_program(p, &opts).unwrap_or_else(|e| panic!("{e}"));
        report.wall_time_s = 0.0;
        serde_json::to_value(&report).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Planning ahead changes nothing measured: the same report with and
    /// without prepared plans, also where corrections rescan other designs
    /// (an autonomous correction on blade-gouge, a geometric one on
    /// blade-overcut), which must not use the nominal plan.
    #[test]
    fn reports_do_not_depend_on_prepared_scans() {
        for name in ["blade-gouge.json", "blade-overcut.json"] {
            let p = program(name);
            let with = report_json(&p, true);
            assert!(with["features"][0]["corrections"]
                .as_array()
                .is_some_and(|c| !c.is_empty()));
            assert_eq!(with, report_json(&p, false), "{name}");
        }
    }
}
