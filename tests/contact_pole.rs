//! The world's per-cycle contact search where a face's parameterisation
//! collapses: the poles of a rational sphere (one parameter line shrinks to
//! a point), on an as-machined copy moved off the axis by a few
//! micrometres, so that the foot of a ball coming down the axis lies next
//! to the pole, not on it. Every query within reach must feel the surface,
//! at the analytic distance (within 10 nm; the simulator asks 0.1 um): a
//! lost contact would read as a free stylus
//! while the ball is pressed into the part.
mod common;

use cmm::math::{Point3, Vec3};
use cmm::world::as_machined::{AsMachined, AsMachinedSpec};
use cmm::world::cmm::contact_options;
use cmm::world::contact::{ContactOptions, ContactSearch};
use common::*;

/// Radius of the generated sphere, mm.
const RADIUS: f64 = 12.5;

fn moved_sphere(t: [f64; 3], offset: f64) -> AsMachined {
    let json = format!(
        r#"{{"transform":{{"translate_mm":[{},{},{}]}},"form":[{{"kind":"offset","mm":{offset}}}]}}"#,
        t[0], t[1], t[2]
    );
    let spec: AsMachinedSpec = serde_json::from_str(&json).unwrap();
    AsMachined::from_spec(&spec, &example("sphere")).unwrap()
}

#[test]
fn a_ball_coming_down_onto_a_pole_feels_the_surface_every_cycle() {
    let wp = example("sphere");
    let opts = contact_options(&wp.options);
    let reach = 2.0;
    let mut checked = 0;
    for (k, t) in [
        [0.0, 0.0, 0.0],
        [0.008, -0.0017, 0.004],
        [-0.013, 0.006, -0.002],
        [1e-6, 0.0, 0.0],
        [0.0, 0.02, 0.01],
    ]
    .into_iter()
    .enumerate()
    {
        let off = [0.01, 0.0, -0.02, 0.0, 0.03][k];
        let am = moved_sphere(t, off);
        let centre = Point3::from(Vec3::from(t));
        let radius = RADIUS + off;
        for pole in [1.0, -1.0] {
            for lateral in [0.0, 0.001, 0.03] {
                let mut search = ContactSearch::new(&wp, &am, &ContactOptions::default());
                // Down the axis at 10 mm/s in 1 ms cycles, the ball centre
                // from 3 mm out to 0.6 mm deflection (a touch trigger and
                // beyond), then back out; and on, the centre inside the
                // material (a shaft's axis there must read inside).
                let descent: Vec<f64> = (0..=450).map(|i| 3.0 - i as f64 * 0.01).collect();
                let ascent: Vec<f64> = descent.iter().rev().copied().collect();
                for (i, h) in descent.into_iter().chain(ascent).enumerate() {
                    let y = Point3::new(lateral, 0.0, pole * (radius + h));
                    let want = (y - centre).norm() - radius;
                    let got = search.query((&wp, &am), y, reach, &opts).unwrap();
                    match got {
                        Some(c) => assert!(
                            (c.distance - want).abs() < 1e-5,
                            "case {k} pole {pole} lateral {lateral} cycle {i}: {c:?} vs {want}"
                        ),
                        None => assert!(
                            want.abs() >= reach - 1e-9,
                            "case {k} pole {pole} lateral {lateral} cycle {i}: no contact at {want}"
                        ),
                    }
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 20_000, "{checked}");
}
