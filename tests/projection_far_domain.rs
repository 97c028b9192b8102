//! Closest points on patches whose parameter domain lies far from 0 (u or
//! v in [1000.1, 1000.7] or [123.456, 123.789]), where a Newton step
//! clamped into the box can point uphill and the parameters round to steps
//! of about 1e-13, against an independent reference: the least distance
//! over the box that a dense grid of points evaluated from the NURBS
//! definition, refined by shrinking grids around the best point, finds.
//! Every search must confirm its foot; a cold search's foot is at the
//! reference's least distance, a warm search's (Newton from a hint) there
//! or at a local minimum of another basin, which shrinking grids around
//! the foot cannot lower.
mod bounds_support;
mod common;

use bounds_support::{
    local_reference, reference, rounding_sweep, workpiece, SweepPatch, ROUNDING_SWEEP_SEED,
};
use cmm::geometry::projection::{project_from, SearchStatus};
use cmm::geometry::ProjectionOptions;
use cmm::math::{Point3, Vec2};
use common::*;

/// A parameter box whose lower corner has a coordinate at least this far
/// from 0 is far from 0.
const FAR_FROM_ZERO: f64 = 100.0;

/// A foot may differ by at most this (mm) from the reference's distance.
const REFERENCE_TOL_MM: f64 = 1e-9;

/// The patches of the rounding sweep whose domain lies far from 0.
fn far_patches() -> Vec<SweepPatch> {
    let sweep = rounding_sweep(&mut rng(ROUNDING_SWEEP_SEED));
    let far = |sp: &SweepPatch| sp.lo.iter().any(|&x| x >= FAR_FROM_ZERO);
    sweep.into_iter().filter(far).collect()
}

/// Where a confirmed warm search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ending {
    /// At the reference's least distance over the box.
    Global,
    /// At a local minimum farther away.
    Local,
}

/// The warm search from `hint` confirms a foot at the reference's least
/// distance `want` (mm) or at a local minimum no closer than `want`; a
/// description of the failure otherwise.
fn check_warm(sp: &SweepPatch, p: Point3, hint: Vec2, want: f64) -> Result<Ending, String> {
    let s = sp.spec.to_surface().map_err(|e| e.to_string())?;
    let at = format!("p {p} from {hint:?} in [{:?}, {:?}]", sp.lo, sp.hi);
    let w = project_from(&s, p, hint, &ProjectionOptions::default())
        .map_err(|e| format!("{at}: {e}"))?;
    if w.status != SearchStatus::Confirmed {
        return Err(format!("{at}: {:?}", w.status));
    }
    let foot = format!(
        "{at}: foot {:?} at {} mm, reference {want} mm",
        w.uv, w.distance
    );
    if (w.distance - want).abs() <= REFERENCE_TOL_MM {
        return Ok(Ending::Global);
    }
    if w.distance < want {
        return Err(format!("{foot}: closer than the reference"));
    }
    let near = local_reference(&sp.spec, p, w.uv, sp.lo, sp.hi);
    if w.distance - near > REFERENCE_TOL_MM {
        return Err(format!("{foot}, {near} mm near it"));
    }
    Ok(Ending::Local)
}

/// The cold search for `p` on the patch confirms a foot at the reference's
/// least distance `want` (mm).
fn check_cold(sp: &SweepPatch, p: Point3, want: f64) -> Result<(), String> {
    let wp = workpiece(sp.spec.clone());
    let at = format!("cold search for p {p} in [{:?}, {:?}]", sp.lo, sp.hi);
    let fp = cmm::evaluate::closest_point(&wp, p).map_err(|e| format!("{at}: {e}"))?;
    let got = fp.projection;
    if got.status != SearchStatus::Confirmed || (got.distance - want).abs() > REFERENCE_TOL_MM {
        return Err(format!(
            "{at}: {:?}, foot {:?} at {} mm, reference {want} mm",
            got.status, got.uv, got.distance
        ));
    }
    Ok(())
}

/// The sweep's example: on the patch over u in [0, 1/3], v in
/// [1000.1, 1000.7] the clamped Newton step from this hint points uphill
/// (its v component is cut at the upper bound); a line search along it
/// found only decreases made by the rounding of the parameters and crept
/// on, 75 um from the minimum, until the iteration limit.
#[test]
fn clamped_uphill_newton_step_on_a_far_domain_reaches_the_minimum() {
    let sweep = rounding_sweep(&mut rng(ROUNDING_SWEEP_SEED));
    let sp = sweep.get(4).expect("the sweep has 36 patches");
    assert_eq!((sp.lo, sp.hi), ([0.0, 1000.1], [1.0 / 3.0, 1000.7]));
    let p = Point3::new(5.657027923120032, 6.107323652448924, -1.060292962893301);
    let hint = Vec2::new(0.292326250577968, 1000.6740399447766);
    let want = reference(&sp.spec, p, sp.lo, sp.hi);
    let ending = check_warm(sp, p, hint, want).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ending, Ending::Global);
}

#[test]
fn searches_on_far_domains_end_confirmed_at_minima() {
    let (mut failures, mut warm, mut global) = (Vec::new(), 0, 0);
    for sp in far_patches() {
        for (p, hints) in &sp.queries {
            let want = reference(&sp.spec, *p, sp.lo, sp.hi);
            if let Err(e) = check_cold(&sp, *p, want) {
                failures.push(e);
            }
            for hint in hints {
                warm += 1;
                match check_warm(&sp, *p, *hint, want) {
                    Ok(Ending::Global) => global += 1,
                    Ok(Ending::Local) => {}
                    Err(e) => failures.push(e),
                }
            }
        }
    }
    println!(
        "{global} of {warm} warm searches end at the global minimum, the others at local minima"
    );
    let first: Vec<&str> = failures.iter().take(5).map(String::as_str).collect();
    assert!(
        failures.is_empty(),
        "{} searches fail:\n{}",
        failures.len(),
        first.join("\n")
    );
}
