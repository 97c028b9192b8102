//! The move that ends a program: up to the clearance height when a way up
//! is clear, and `Blocked` (reported `aborted`) when the design data shows
//! none, rather than `completed` with the probe left down in the part.
mod common;

use cmm::host::modes::{park, FreeSpace, HostProbe, ModeOptions, Outcome};
use cmm::host::observe::Unobserved;
use cmm::math::{Point3, Vec3};
use cmm::seam::Cmm;
use cmm::world::as_machined::AsMachined;
use common::*;

/// Free space with a lid at machine z 68..72 over everything (an
/// independent obstacle, sampled): no way up from below it.
struct Lid;

impl FreeSpace for Lid {
    fn segment_clear(&self, from: Point3, to: Point3) -> bool {
        (0..=200).all(|k| {
            let p = from + (to - from) * (k as f64 / 200.0);
            !(68.0..=72.0).contains(&p.z)
        })
    }
}

/// Free space with nothing in it.
struct Open;

impl FreeSpace for Open {
    fn segment_clear(&self, _: Point3, _: Point3) -> bool {
        true
    }
}

/// The ball's machine z after parking from the middle of the block's
/// pocket (part (50, 50, 35), machine z 55) with `free`, and how the move
/// ended.
fn park_from_pocket(free: &dyn FreeSpace) -> (f64, Result<(), Outcome>) {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let mut sim = pocket_machine((&wp, &am), (pv, 1.5, 1.0), Point3::new(50.0, 50.0, 35.0));
    let opts = ModeOptions {
        clearance_z_mm: Some(150.0),
        ..ModeOptions::default()
    };
    let probe = HostProbe::nominal(pv, 1.5);
    let ended = park(&mut Unobserved(&mut sim), probe, Some(free), &opts);
    let z = (sim.readings().scales + pv).z;
    (z, ended.map_err(|stop| stop.outcome))
}

#[test]
fn the_end_move_rises_to_the_clearance_height_when_the_way_is_clear() {
    let (z, ended) = park_from_pocket(&Open);
    assert_eq!(ended, Ok(()));
    assert!((z - 150.0).abs() < 0.01, "ball at z {z}");
}

#[test]
fn an_end_move_with_no_way_up_is_not_completed() {
    let (z, ended) = park_from_pocket(&Lid);
    assert_eq!(ended, Err(Outcome::Blocked));
    assert!((z - 55.0).abs() < 0.01, "ball at z {z}");
}
