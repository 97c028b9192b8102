//! The world's contact distance where an as-machined offset parts the
//! faces of an edge: the io1 flange's bore (two half cylinders split at
//! z = 0) under its top face at x = 31. An offset of -4 um moves the top
//! face down along its normal and the bore's wall out along its own, so
//! the bore's rim stands 4 um over the top face. A ball coming down over
//! the rim at the seam is in free air until it touches: the reference is
//! the part's extent, no material beyond x = 31 + 0.005 (the translation),
//! so the signed distance is at least the ball's height over that.
use cmm::geometry::ProjectionOptions;
use cmm::math::Point3;
use cmm::workpiece::Workpiece;
use cmm::world::as_machined::AsMachined;
use cmm::world::cmm::contact_options;
use cmm::world::contact::{ContactOptions, ContactSearch};

mod common;

#[test]
fn a_ball_over_a_bore_rim_on_the_seam_is_outside_the_part() {
    let wp = Workpiece::from_path(&common::repo("workpieces/io1-flange.stp"))
        .unwrap_or_else(|e| panic!("{e}"));
    let spec = serde_json::from_str(
        r#"{ "transform": { "translate_mm": [0.005, -0.01, 0.01] },
             "form": [{ "kind": "offset", "mm": -0.004 }] }"#,
    )
    .unwrap();
    let am = AsMachined::from_spec(&spec, &wp).unwrap();
    let opts = contact_options(&ProjectionOptions::default());
    let mut search = ContactSearch::new(&wp, &am, &ContactOptions::default());
    // Coming down at 10 mm/s in 1 ms cycles, from 1.5 mm over the rim to
    // 0.2 mm over it, on the seam and just beside it.
    for z in [0.0, 1e-4, -1e-4] {
        for k in 0..=130 {
            let x = 32.505 - 0.01 * f64::from(k);
            let y = Point3::new(x, 18.0, z);
            let Some(c) = search.query((&wp, &am), y, 1.0, &opts).unwrap() else {
                continue;
            };
            let above = x - 31.005;
            assert!(c.distance >= above - 1e-9, "at {y:?}: {} mm", c.distance);
        }
    }
}
