//! The trim segments' chords against dense samples of the segments' true
//! images: every sample lies within the chord's slack of it, on a real
//! part with curved trimmed faces (the flange's cylinders, tori and holed
//! planes) as machined with a form and a transform.
use super::leaves::{LeafOptions, Leaves, Pieces};
use crate::math::Point3;
use crate::workpiece::Workpiece;
use crate::world::as_machined::{AsMachined, AsMachinedSpec};

fn distance_to_chord(p: Point3, a: Point3, b: Point3) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(&d) / d.norm_squared().max(1e-300)).clamp(0.0, 1.0);
    (p - (a + d * t)).norm()
}

#[test]
fn every_trim_segment_lies_within_its_chords_slack() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/io1-flange.stp");
    let wp = Workpiece::from_path(&path).unwrap();
    let spec: AsMachinedSpec = serde_json::from_str(
        r#"{"transform":{"translate_mm":[0.1,-0.2,0.05],"rotate_deg":[0.2,-0.1,0.3],"scale":1.001},
            "form":[{"kind":"offset","mm":0.01},
                    {"kind":"bump","center_mm":[6,32.5,18.75],"radius_mm":3,"height_mm":0.05}]}"#,
    )
    .unwrap();
    let machined = AsMachined::from_spec(&spec, &wp).unwrap();
    let pieces = Pieces::new(&wp, &LeafOptions::default());
    // The nominal part (no form: the slack is the sag bound alone) and the
    // machined one.
    let mut checked = 0;
    for am in [AsMachined::nominal(), machined] {
        checked += check(&wp, &am, &pieces);
    }
    assert!(checked > 60_000, "{checked}");
}

fn check(wp: &Workpiece, am: &AsMachined, pieces: &Pieces) -> usize {
    let leaves = Leaves::of(pieces, am);
    let chords = (0..leaves.leaves.len()).map(|id| leaves.trim_chords(pieces, id, am).count());
    assert!(chords.sum::<usize>() > 1000);
    let mut checked = 0;
    for (id, leaf) in leaves.leaves.iter().enumerate() {
        for (seg, chord) in leaves.trim_chords(pieces, id, am) {
            for k in 0..=32 {
                let uv = seg.0 + (seg.1 - seg.0) * (k as f64 / 32.0);
                let q = am.true_point(wp, leaf.face, uv);
                let off = distance_to_chord(q, chord.a, chord.b);
                assert!(
                    off <= chord.slack,
                    "face {} {seg:?}: {off} > {}",
                    leaf.face,
                    chord.slack
                );
                // The lower bound never exceeds the distance to a point of
                // the segment's image.
                let probe = q + nalgebra::Vector3::new(0.3, -0.2, 0.1) * (k as f64 * 0.1);
                assert!(chord.lower_bound(probe) <= (probe - q).norm() + 1e-12);
                checked += 1;
            }
        }
    }
    checked
}
