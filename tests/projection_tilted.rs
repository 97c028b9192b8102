//! Global closest points on rational spheres and tori whose axes are tilted
//! away from z (poles, seams and collapsed edges anywhere in space), against
//! the analytic distances: every seeded random query is answered, confirmed,
//! with the analytic signed distance.
mod common;

use cmm::geometry::projection::SearchStatus;
use cmm::math::{Point3, Vec3};
use cmm::workpiece::{SurfaceSpec, Workpiece, WorkpieceFile};
use common::*;

/// A rigid placement: rotation by `angle` about the unit `axis`, then a
/// shift to `center`.
#[derive(Clone, Copy)]
struct Placement {
    axis: Vec3,
    angle: f64,
    center: Vec3,
}

impl Placement {
    fn random(r: &mut TestRng) -> Placement {
        Placement {
            axis: random_direction(r),
            angle: uniform(r, 0.05, 3.1),
            center: Vec3::new(
                uniform(r, -80.0, 80.0),
                uniform(r, -80.0, 80.0),
                uniform(r, -80.0, 80.0),
            ),
        }
    }

    /// The rotated vector (Rodrigues' formula).
    fn rotate(&self, v: Vec3) -> Vec3 {
        let (s, c) = self.angle.sin_cos();
        let a = self.axis;
        v * c + a.cross(&v) * s + a * (a.dot(&v) * (1.0 - c))
    }

    fn apply(&self, x: [f64; 3]) -> [f64; 3] {
        let q = self.rotate(Vec3::from(x)) + self.center;
        [q.x, q.y, q.z]
    }

    /// `spec` moved (a rigid motion of the control points keeps the
    /// rational surface exact).
    fn place(&self, mut spec: SurfaceSpec) -> SurfaceSpec {
        for cp in spec.control_points.iter_mut().flatten() {
            *cp = self.apply(*cp);
        }
        spec
    }
}

fn one_surface(spec: SurfaceSpec) -> Workpiece {
    from_file(&WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: spec.name.clone(),
        units: "mm".into(),
        surfaces: vec![spec],
    })
}

fn sphere_spec(radius: f64) -> SurfaceSpec {
    let file = cmm::workpiece::examples::reference_sphere(2.0 * radius);
    file.surfaces.into_iter().next().unwrap()
}

fn torus_spec(major: f64, minor: f64) -> SurfaceSpec {
    let (circle, weights, knots) = cmm::workpiece::examples::unit_circle();
    let profile: Vec<[f64; 2]> = circle
        .iter()
        .map(|[a, b]| [major + minor * a, minor * b])
        .collect();
    cmm::workpiece::examples::revolve("torus", &profile, &weights, knots, false)
}

/// Checks one query against the analytic signed distance `want`: the
/// answer is confirmed, the distance equal to 1e-9 mm, the sign right
/// (where the point is not on the surface), over the whole workpiece and
/// by the face's own index.
fn check(wp: &Workpiece, p: Point3, want: f64, what: &str) {
    let fp = cmm::evaluate::closest_point(wp, p).unwrap_or_else(|e| panic!("{what}: {e}"));
    let pr = fp.projection;
    assert_eq!(pr.status, SearchStatus::Confirmed, "{what} at {p}");
    assert!(
        (pr.signed_distance - want).abs() < 1e-9,
        "{what} at {p}: {} vs {want}",
        pr.signed_distance
    );
    let face = &wp.faces[0];
    let own = face.index().project(&face.surface, p).unwrap();
    assert_eq!(own.status, SearchStatus::Confirmed, "{what} (index) at {p}");
    assert!(
        (own.distance - want.abs()).abs() < 1e-9,
        "{what} (index) at {p}: {} vs {want}",
        own.distance
    );
}

#[test]
fn tilted_spheres_answer_every_point_with_the_analytic_distance() {
    let mut r = rng(61);
    for case in 0..25 {
        let place = Placement::random(&mut r);
        let radius = uniform(&mut r, 2.0, 40.0);
        let wp = one_surface(place.place(sphere_spec(radius)));
        let pole = place.rotate(Vec3::z());
        let mut dirs: Vec<Vec3> = (0..150).map(|_| random_direction(&mut r)).collect();
        // The poles, nearly the poles, and the seam (the rotated +x half
        // plane).
        for s in [1.0, -1.0] {
            dirs.push(pole * s);
            let off = pole.cross(&random_direction(&mut r)).normalize();
            for e in [1e-9, 1e-6, 1e-3] {
                dirs.push((pole * s + off * e).normalize());
            }
        }
        dirs.push(place.rotate(Vec3::new(1.0, 1e-12, 0.2)).normalize());
        for (k, dir) in dirs.iter().enumerate() {
            let rho = uniform(&mut r, 0.05, 2.5) * radius;
            let p = Point3::from(place.center + dir * rho);
            check(&wp, p, rho - radius, &format!("sphere {case} point {k}"));
        }
    }
}

#[test]
fn tilted_tori_answer_every_point_with_the_analytic_distance() {
    let mut r = rng(62);
    for case in 0..20 {
        let place = Placement::random(&mut r);
        let major = uniform(&mut r, 10.0, 50.0);
        let minor = uniform(&mut r, 1.0, 0.8 * major);
        let wp = one_surface(place.place(torus_spec(major, minor)));
        let axis = place.rotate(Vec3::z());
        let mut checked = 0;
        while checked < 150 {
            let reach = major + 2.0 * minor;
            let p = Point3::from(
                place.center
                    + Vec3::new(
                        uniform(&mut r, -reach, reach),
                        uniform(&mut r, -reach, reach),
                        uniform(&mut r, -reach, reach),
                    ),
            );
            let q = p.coords - place.center;
            let h = q.dot(&axis);
            let rho = (q - axis * h).norm();
            let want = ((rho - major).powi(2) + h * h).sqrt() - minor;
            // Points near the axis have a whole circle of closest points
            // on the inner equator; kept, away from the tube's own centre
            // circle (every point of a tube circle equally close).
            if want + minor < 1e-3 * minor {
                continue;
            }
            checked += 1;
            check(&wp, p, want, &format!("torus {case} point {checked}"));
        }
    }
}
