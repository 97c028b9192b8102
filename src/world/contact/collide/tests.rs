//! The check's margin: a stylus shaft running close beside a small, dense
//! part (the link rods' rings, a 0.3 mm ball) looks at the leaves near it
//! only, and answers as a check with the full margin does.
use super::*;
use crate::math::Vec3;
use crate::world::contact::ContactSearch;

/// Shaft radius (a 0.3 mm ball's), mm.
const RS: f64 = 0.075;

/// The link rods (three rings, 6000 leaves).
fn linkrods() -> Workpiece {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/linkrods.step");
    Workpiece::from_path(&path).unwrap()
}

/// Points of the part's surface: the feet and outward normals of the
/// grid points 0.3 to 1 mm from the part at the height of the rings'
/// middle.
fn feet(wp: &Workpiece, am: &AsMachined) -> Vec<(Point3, Vec3)> {
    let mut search = ContactSearch::new(wp, am, &ContactOptions::default());
    let opts = ProjectionOptions::default();
    let mut out = Vec::new();
    for k in 0..1600 {
        let y = Point3::new(
            -10.0 + f64::from(k % 40) * 0.5,
            -10.0 + f64::from(k / 40) * 0.5,
            1.0,
        );
        if let Ok(Some(c)) = search.query((wp, am), y, 1.0, &opts) {
            if c.distance > 0.3 && !c.edge {
                out.push((c.point, c.push));
            }
        }
    }
    out
}

/// Runs 40 checks of a 10 mm shaft whose axis passes `gap` (mm) outside
/// the surface at `foot` (normal `n`) along the surface, moved 0.02 mm a
/// check; the answers and the leaf bounds looked at.
fn run(
    (wp, am, ix): (&Workpiece, &AsMachined, &PartIndex),
    (foot, n): (Point3, Vec3),
    opts: &CollisionOptions,
    gap: f64,
) -> (Vec<bool>, u64) {
    let t = n.cross(&Vec3::z()).try_normalize(1e-9).unwrap_or(Vec3::x());
    let along = n.cross(&t);
    let mut check = PartCheck::new(&ContactOptions::default(), opts);
    let popts = ProjectionOptions::default();
    let answers = (0..40)
        .map(|i| {
            let q = foot + n * (RS + gap) + t * (0.02 * f64::from(i));
            let (a, b) = (q - along * 5.0, q + along * 5.0);
            let cyl = Cylinder::between(a, b, RS).unwrap();
            let hit = check.check((ix, (wp, am)), &cyl, (a, b), &popts);
            hit.unwrap().is_some()
        })
        .collect();
    (answers, check.bounds_looked)
}

#[test]
fn a_shaft_close_beside_the_part_looks_at_the_leaves_near_it() {
    let adaptive = CollisionOptions::default();
    let full = CollisionOptions {
        min_margin_mm: adaptive.margin_mm,
        ..adaptive
    };
    let wp = linkrods();
    let am = AsMachined::nominal();
    let ix = PartIndex::new(&wp, &am, &ContactOptions::default().leaves);
    let part = (&wp, &am, &ix);
    // Places where the shaft runs free of the part all along.
    let free: Vec<_> = (feet(&wp, &am).into_iter())
        .filter(|&f| run(part, f, &full, 0.02).0.iter().all(|hit| !hit))
        .take(3)
        .collect();
    assert!(free.len() >= 3, "{}", free.len());
    let (mut looked, mut looked_full) = (0, 0);
    for &f in &free {
        let (hits, n) = run(part, f, &adaptive, 0.02);
        assert!(hits.iter().all(|hit| !hit));
        looked += n;
        looked_full += run(part, f, &full, 0.02).1;
    }
    eprintln!("leaf bounds looked at: {looked} (full margin {looked_full})");
    assert!(looked * 2 < looked_full, "{looked} vs {looked_full}");
}

/// Checks of a probe body (12.5 mm radius, 80 mm long, standing on its
/// bottom cap at `z`) over the middle of the link rods: the strikes, the
/// leaf bounds looked at and the free-air bounds left behind.
fn body_checks(
    (wp, am, ix): (&Workpiece, &AsMachined, &PartIndex),
    check: PartCheck,
    heights: &[f64],
) -> (Vec<bool>, u64, Vec<f64>) {
    let mut check = check;
    let popts = ProjectionOptions::default();
    let mut floors = Vec::new();
    let hits = (heights.iter())
        .map(|&z| {
            check.reset();
            let (a, b) = (Point3::new(5.7, 3.2, z), Point3::new(5.7, 3.2, z + 80.0));
            let cyl = Cylinder::between(a, b, 12.5).unwrap();
            let hit = check.check((ix, (wp, am)), &cyl, (a, b), &popts);
            floors.push(check.anchor.map_or(f64::NAN, |k| k.floor));
            hit.unwrap().is_some()
        })
        .collect();
    (hits, check.bounds_looked, floors)
}

/// A probe body wider than the part standing above it: its end caps clear
/// the leaves below its bottom cap, so the check looks at few of the
/// part's 6000 leaves and leaves a free-air bound of about the body's
/// height above the part (the rings' tops are at z = 2; the fillets'
/// boxes reach a little higher), where the axis distance alone looks at
/// all of them and leaves at most the margin; a body lowered into the
/// rings strikes either way.
#[test]
fn a_body_above_the_part_is_cleared_by_its_end_caps() {
    let wp = linkrods();
    let am = AsMachined::nominal();
    let ix = PartIndex::new(&wp, &am, &ContactOptions::default().leaves);
    let part = (&wp, &am, &ix);
    let opts = CollisionOptions::default();
    let contact = ContactOptions::default();
    let capped = || PartCheck::new(&contact, &opts).with_caps();
    let plain = || PartCheck::new(&contact, &opts);
    // Heights more than the margin and the list's slack above the rings:
    // no leaf's box is listed at all.
    let high = [5.0, 10.0];
    let (_, looked, _) = body_checks(part, capped(), &high);
    let (_, plain_looked, _) = body_checks(part, plain(), &high);
    assert!(plain_looked > 10_000, "{plain_looked}");
    assert!(looked * 20 < plain_looked, "{looked} of {plain_looked}");
    let above = [2.5, 5.0, 10.0];
    let (hits, _, floors) = body_checks(part, capped(), &above);
    let (plain_hits, _, plain_floors) = body_checks(part, plain(), &above);
    assert_eq!(hits, [false; 3]);
    assert_eq!(plain_hits, hits);
    for (k, z) in above.iter().enumerate() {
        let free_air = contact.free_air_ratio * (z - 2.0 - 0.15);
        assert!(floors[k] >= free_air, "z {z}: {floors:?}");
        assert!(plain_floors[k] <= opts.margin_mm, "z {z}: {plain_floors:?}");
    }
    let inside = |check| body_checks(part, check, &[1.0]).0;
    assert_eq!(inside(capped()), [true]);
    assert_eq!(inside(plain()), [true]);
}
