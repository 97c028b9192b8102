//! Tests of the probe body's check: part edges and pins under the flat
//! end, ledges into its side, moves past edges, and a dense reference on
//! random postures and moves.
use super::super::tests::{direction, sphere_clearance, Tally};
use super::super::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::path::Path;

/// The box `lo..hi` as six plane faces, normals outward.
fn block(lo: [f64; 3], hi: [f64; 3]) -> Workpiece {
    let [dx, dy, dz] = [0, 1, 2].map(|k| hi[k] - lo[k]);
    let face = |name: &str, o: [f64; 3], a: [f64; 3], b: [f64; 3]| {
        let at = |s: f64, t: f64| [0, 1, 2].map(|k| o[k] + s * a[k] + t * b[k]);
        crate::workpiece::SurfaceSpec {
            name: name.into(),
            degree: [1, 1],
            knots_u: vec![0.0, 0.0, 1.0, 1.0],
            knots_v: vec![0.0, 0.0, 1.0, 1.0],
            control_points: vec![
                vec![at(0.0, 0.0), at(0.0, 1.0)],
                vec![at(1.0, 0.0), at(1.0, 1.0)],
            ],
            weights: None,
            reversed: false,
            trim: None,
        }
    };
    let (x, y, z) = ([dx, 0.0, 0.0], [0.0, dy, 0.0], [0.0, 0.0, dz]);
    let surfaces = vec![
        face("bottom", lo, y, x),
        face("top", [lo[0], lo[1], hi[2]], x, y),
        face("x0", lo, z, y),
        face("x1", [hi[0], lo[1], lo[2]], y, z),
        face("y0", lo, x, z),
        face("y1", [lo[0], hi[1], lo[2]], z, x),
    ];
    let file = crate::workpiece::WorkpieceFile {
        format: crate::workpiece::WORKPIECE_FORMAT.into(),
        name: "block".into(),
        units: "mm".into(),
        surfaces,
    };
    match Workpiece::from_file(&file, Path::new("block.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    }
}

/// A block whose top face lies at `top` and whose wall faces the probe at
/// `x = wall` (it reaches to x = 200, y = +-60, z = -100).
fn step_block(wall: f64, top: f64) -> Workpiece {
    block([wall, -60.0, -100.0], [200.0, 60.0, top])
}

/// The probe of [`sphere_clearance`] (ball radius 1.5 mm, 50 mm stylus
/// straight up) with the default body (12.5 mm radius, 80 mm long): with
/// the ball centre at the origin the body's flat end lies at z = 50.
fn body_clearance(wp: &Workpiece) -> PartClearance<'_> {
    PartClearance {
        stylus: Vec3::new(0.0, 0.0, 50.0),
        body: Some(ProbeBody {
            radius_mm: 12.5,
            length_mm: 80.0,
        }),
        ..sphere_clearance(wp)
    }
}

/// A block's top edge 2 mm into the ring round the body's flat end (2 mm
/// inside its rim, 2 mm above its flat end): the capsule over the flat end
/// keeps 14.85 mm from the edge, more than the body radius plus the
/// posture margin (12.6 mm), yet the body stands in the block; so it does
/// with the top 0.5 mm above the flat end (less than the sampling step
/// into the body). Lowered 0.15 mm below the flat end (more than the
/// 0.1 mm margin) the block is clear; 0.05 mm below it is not. With the
/// edge 3 mm from the axis, the stylus hanging down beside the block, the
/// same holds. An edge just inside the rim (0.5 and 0.2 mm) and just above
/// the flat end (0.05 and 0.2 mm) strikes too (the shrunk region's round
/// rim, 0.2 mm in for the 0.1 mm margin, reaches it); a wall 0.2 mm
/// beyond the rim is clear.
#[test]
fn a_part_edge_under_the_flat_ends_rim_strikes_the_body() {
    let ball = Point3::origin();
    for (wall, top, strikes) in [
        (10.5, 52.0, true),
        (10.5, 50.5, true),
        (10.5, 49.85, false),
        (10.5, 49.95, true),
        (3.0, 50.5, true),
        (3.0, 50.05, true),
        (3.0, 49.85, false),
        (3.0, 49.95, true),
        (12.0, 50.05, true),
        (12.3, 50.2, true),
        (12.7, 50.5, false),
    ] {
        let wp = step_block(wall, top);
        let want = strikes.then_some(ProbePart::Body);
        assert_eq!(
            body_clearance(&wp).posture(ball),
            want,
            "wall {wall}, top {top}"
        );
    }
}

/// A pin 1 mm square, 6 mm beside the axis, its top 0.02 mm above the
/// flat end: only the flat end's disc comes near it (the capsule keeps
/// 13.9 mm, more than 12.6 mm; the side 5.5 mm), yet the body stands on
/// it. 0.15 mm below the flat end it is clear.
#[test]
fn a_pin_under_the_flat_end_strikes_the_body() {
    let pin = |top: f64| block([6.0, -0.5, -100.0], [7.0, 0.5, top]);
    for (top, want) in [(50.02, Some(ProbePart::Body)), (49.85, None)] {
        let wp = pin(top);
        assert_eq!(
            body_clearance(&wp).posture(Point3::origin()),
            want,
            "top {top}"
        );
    }
}

/// The body passing the block's top edge along it (ball centre along y at
/// x = 0, z = 0, from y = -100 to 100; the block at y = +-60): with a 1 mm
/// margin it is clear only with the block's top more than 1 mm below the
/// flat end, although with the top 2 mm above it the capsule keeps
/// 14.85 mm (more than 13.5 mm) and both ends of the move are far from
/// the block. Moving down onto the block's top beside the wall (the flat
/// end stops over it) the same holds.
#[test]
fn a_move_past_a_part_edge_sweeps_the_flat_end() {
    let opts = ClearanceOptions {
        margin_mm: 1.0,
        ..ClearanceOptions::default()
    };
    let along = (Point3::new(0.0, -100.0, 0.0), Point3::new(0.0, 100.0, 0.0));
    let down = (Point3::new(0.0, 0.0, 40.0), Point3::origin());
    for (top, clear) in [(52.0, false), (49.1, false), (48.9, true)] {
        let wp = step_block(10.5, top);
        let c = PartClearance {
            opts,
            ..body_clearance(&wp)
        };
        for (from, to) in [along, down] {
            assert_eq!(
                c.segment_clear(from, to),
                clear,
                "top {top}: {from} -> {to}"
            );
        }
    }
}

/// Grid spacing of the body's reference surface, mm.
const BODY_GRID_MM: f64 = 0.25;

/// How far the reference surface reaches up the body, mm: the part below
/// the body is a block whose top lies near the flat end, and a body
/// tilted less than 45 degrees comes no nearer it higher up.
const BODY_GRID_HEIGHT_MM: f64 = 20.0;

/// The signed distance from `p` to the box `lo..hi` (negative inside), mm.
fn box_distance(p: Point3, (lo, hi): ([f64; 3], [f64; 3])) -> f64 {
    let q = Vec3::from_fn(|k, _| (lo[k] - p[k]).max(p[k] - hi[k]));
    q.map(|x| x.max(0.0)).norm() + q.max().min(0.0)
}

/// The smallest signed distance from the box `block` over a grid of the
/// lower body's surface (its flat end and its side up to
/// [`BODY_GRID_HEIGHT_MM`]; every surface point within the grid spacing
/// of a grid point), the mount at `mount` and the body along the unit
/// vector `up`, radius `r`.
fn body_reference(mount: Point3, (up, r): (Vec3, f64), block: ([f64; 3], [f64; 3])) -> f64 {
    use std::f64::consts::TAU;
    let x = up
        .cross(&Vec3::x())
        .try_normalize(0.1)
        .unwrap_or_else(|| up.cross(&Vec3::y()).normalize());
    let y = up.cross(&x);
    let ring = |rho: f64| {
        let n = ((TAU * rho / BODY_GRID_MM).ceil() as usize).max(1);
        (0..n).map(move |k| {
            let phi = TAU * k as f64 / n as f64;
            (x * phi.cos() + y * phi.sin()) * rho
        })
    };
    let steps = |len: f64| {
        let n = (len / BODY_GRID_MM).ceil() as usize;
        (0..=n).map(move |k| len * k as f64 / n as f64)
    };
    let disc = steps(r).flat_map(&ring);
    let side = steps(BODY_GRID_HEIGHT_MM).flat_map(|h| ring(r).map(move |e| e + up * h));
    (disc.chain(side)).fold(f64::INFINITY, |d, v| d.min(box_distance(mount + v, block)))
}

/// Random postures and short moves of a tilted body round a block's top
/// edge, checked with a 0.5 mm sampling step, against the reference
/// surface: the body called clear keeps the margin less the sampling step
/// (the guarantee at the flat end's rim), and the body called striking
/// comes within the margin (plus the reference grid's spacing): the check
/// of the flat end is never more careful than the margin.
#[test]
fn random_body_postures_and_moves_agree_with_a_dense_surface() {
    let (lo, hi) = ([10.5, -60.0, -100.0], [200.0, 60.0, 50.0]);
    let wp = block(lo, hi);
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let (step, body) = (
        0.5,
        ProbeBody {
            radius_mm: 12.5,
            length_mm: 80.0,
        },
    );
    let mut tally = Tally::default();
    for k in 0..120 {
        let tilt = direction(&mut rng, (0.0, 0.5));
        let up = (Vec3::z() + Vec3::new(tilt.x, tilt.y, 0.0)).normalize();
        let c = PartClearance {
            stylus: up * 50.0,
            ..body_clearance(&wp)
        };
        let mount = Point3::new(-5.0, 0.0, 50.0)
            + Vec3::new(17.0, 10.0, 6.0)
                .component_mul(&Vec3::from_fn(|_, _| rng.random::<f64>() - 0.5));
        let shift = if k % 2 == 0 {
            Vec3::zeros()
        } else {
            direction(&mut rng, (0.0, 10.0))
        };
        let margin = if k % 2 == 0 { 0.1 } else { 1.0 };
        let ball = mount - c.stylus;
        let clear = c.body_clear((ball, ball + shift), &body, margin, step);
        let n = (shift.norm() / BODY_GRID_MM).ceil() as usize;
        let min = (0..=n.max(1)).fold(f64::INFINITY, |d, i| {
            let at = mount + shift * (i as f64 / n.max(1) as f64);
            d.min(body_reference(at, (up, body.radius_mm), (lo, hi)))
        });
        assert!(!clear || min >= margin - step, "{k}: clear at {min} mm");
        assert!(
            clear || min < margin + BODY_GRID_MM,
            "{k}: striking at {min} mm"
        );
        tally.add(clear, min, margin);
    }
    eprintln!("body: {tally:?}");
    assert!(tally.clear > 20 && tally.touching > 20, "{tally:?}");
}

/// A thin ledge (0.5 mm thick, 4.5 mm above the flat end) reaching 0.5 mm
/// into the body's side, beside the body standing at the origin and
/// beside its move along y: only the body's side comes near it (the
/// capsule keeps 14.15 mm, the flat end's disc 4.5 mm), yet the body stands
/// in it. 0.2 mm beyond the body's side it is clear of the 0.1 mm posture
/// margin, and 1.1 mm beyond it of a 1 mm margin on the move.
#[test]
fn a_ledge_into_the_body_side_strikes_it() {
    let ledge = |x: f64| block([x, -60.0, 54.5], [200.0, 60.0, 55.0]);
    let opts = ClearanceOptions {
        margin_mm: 1.0,
        ..ClearanceOptions::default()
    };
    let along = (Point3::new(0.0, -100.0, 0.0), Point3::new(0.0, 100.0, 0.0));
    for (x, posture, clear) in [
        (12.0, Some(ProbePart::Body), false),
        (12.7, None, false),
        (13.6, None, true),
    ] {
        let wp = ledge(x);
        let c = PartClearance {
            opts,
            ..body_clearance(&wp)
        };
        assert_eq!(c.posture(Point3::origin()), posture, "ledge at {x}");
        assert_eq!(c.segment_clear(along.0, along.1), clear, "ledge at {x}");
    }
}
