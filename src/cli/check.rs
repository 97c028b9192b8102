//! `cmm check PROGRAM.json...`: validates programs and their workpieces
//! without measuring.
use std::path::PathBuf;

use super::{CliError, Status};
use crate::program::Feature;

/// Arguments of `cmm check`.
#[derive(Debug, clap::Args)]
pub struct CheckArgs {
    /// Part program files.
    #[arg(required = true)]
    pub programs: Vec<PathBuf>,
}

/// Runs `cmm check`.
pub fn run(args: &CheckArgs) -> Result<Status, CliError> {
    let mut status = Status::Pass;
    for path in &args.programs {
        // The scenario is validated too (a program's `as_machined` block).
        let program = crate::app::load(path)?.program;
        let unreachable = crate::app::reach::unreachable_features(&program);
        let verdict = if unreachable.is_empty() {
            "ok"
        } else {
            status = Status::Incomplete;
            "not measurable as programmed"
        };
        let mut lines = vec![format!(
            "{}: {verdict}: program '{}', workpiece '{}' ({} surfaces), {} features",
            path.display(),
            program.name,
            program.workpiece.name,
            program.workpiece.faces.len(),
            program.features.len()
        )];
        if let Some(points) = &program.alignment {
            lines.push(format!("  alignment: {} touch points", points.len()));
            let free = crate::host::inspect::align::undetermined(points);
            lines.extend(free.iter().map(|note| format!("  alignment: note: {note}")));
            let targets: Vec<_> = (program.features.iter())
                .flat_map(|f| crate::app::nominal_form::design_points(f).0)
                .collect();
            let opts = crate::host::inspect::align_weak::WeakOptions::default();
            let weak = crate::host::inspect::align_weak::weakly_fixed(points, &targets, &opts);
            lines.extend(weak.iter().map(|note| format!("  alignment: note: {note}")));
        }
        for f in &program.features {
            lines.push(format!("  {}", describe(f)));
        }
        for (name, k, why) in unreachable {
            lines.push(format!("  {name} [{k}]: not reachable: {why}"));
        }
        for f in crate::app::nominal_form::form_over_tolerance(&program) {
            lines.push(format!(
                "  {}: note: the design's own {} has a form error of {:.4} mm, over the form tolerance {} mm: the fit fails on a perfect part",
                f.feature,
                f.element.name(),
                f.nominal_form_mm,
                f.form_mm
            ));
        }
        super::say(&(lines.join("\n") + "\n"))?;
    }
    Ok(status)
}

fn describe(f: &Feature) -> String {
    match f {
        Feature::Section {
            name,
            curves,
            settings,
            ..
        } => {
            let closed = curves.iter().filter(|c| c.closed).count();
            let length: f64 = curves.iter().map(|c| c.length()).sum();
            format!(
                "{name}: section scan, {} curve(s) ({closed} closed), {length:.1} mm, mode {:?}, {} mm/s",
                curves.len(),
                settings.mode,
                settings.speed_mm_s
            )
        }
        Feature::Touch { name, points, .. } => format!("{name}: {} touch points", points.len()),
    }
}
