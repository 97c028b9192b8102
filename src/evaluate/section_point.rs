//! The design section's point next to a nominal point: what a section
//! scan's fitted element is compared with.
//!
//! A measured point's nearest design point lies off the section plane
//! wherever the surface slopes to it (a sphere, a cone, a torus): a part
//! offset by `h` along its normal puts the nominal point `h cos` off the
//! plane, and the circle through such points is the design's section at
//! another height (on a sphere cut at 37 degrees, 0.02 mm of offset moves
//! its diameter by 0.04 mm). The design's element is the one through the
//! design's section, in the plane.
use crate::geometry::nurbs::surface::NurbsSurface;
use crate::geometry::Jet2;
use crate::geometry::Plane;
use crate::math::{Point3, Vec2, Vec3};

/// A section point lies this close (mm) to the plane.
pub const ON_PLANE_MM: f64 = 1e-10;

/// The least share of the plane's normal that the surface's tangent
/// plane holds (sin of about 6 degrees) for a point to be taken into the
/// plane: the way there is at most the start's distance from the plane
/// over this. Where the surface runs nearly along the plane the nominal
/// point is kept.
pub const MIN_SECTION_SLOPE: f64 = 0.1;

/// The point of a surface through `p` (outward unit normal `normal`
/// there) in `plane`, reached from `p` along the surface: the step along
/// the plane normal's share of the tangent plane, `t = m - (m . n) n`,
/// that zeroes the plane distance `e`, `p - t e / |t|^2` (first order: off
/// the surface by the curvature times the step squared, nanometres for
/// the micrometres a scan's point lies off its plane). A fitted element
/// then sees the section, not a scan's wander across the plane on a
/// sloped face. `None` where the surface runs along the plane
/// ([`MIN_SECTION_SLOPE`]).
pub fn slide_into(p: Point3, normal: Vec3, plane: &Plane) -> Option<Point3> {
    let m = plane.normal();
    let t = m - normal * m.dot(&normal);
    let k = t.norm_squared();
    (k >= MIN_SECTION_SLOPE * MIN_SECTION_SLOPE).then(|| p - t * (plane.signed_distance(p) / k))
}

/// How far (mm) a point's first-order slide into the plane
/// ([`slide_into`]) may leave the surface for the point to stand for the
/// section in a fit: a tenth of a micrometre.
pub const SLIDE_ERROR_MM: f64 = 1e-4;

/// How far (mm) [`slide_into`] leaves the surface from the point at `uv`
/// of `surface` (unit normal `normal` there) that lies `e` (mm) off
/// `plane`: half the surface's normal curvature along the slide times the
/// slide's length squared. A probe on a wall square to the plane of a
/// part set up a degree off touches the wall up to `r sin 1` off the
/// plane (0.05 mm with a 6 mm ball), and the slide along the wall is
/// exact; a sphere's point 0.07 mm off the plane (where the plane hold
/// let go) slides 0.3 um off a 12.5 mm sphere. `None` where the surface
/// runs along the plane ([`MIN_SECTION_SLOPE`]) or its tangents are
/// degenerate.
pub fn slide_error(
    surface: &NurbsSurface,
    uv: Vec2,
    normal: Vec3,
    (plane, e): (&Plane, f64),
) -> Option<f64> {
    let m = plane.normal();
    let t = m - normal * m.dot(&normal);
    let k = t.norm_squared();
    if k < MIN_SECTION_SLOPE * MIN_SECTION_SLOPE {
        return None;
    }
    let mut d = Jet2 {
        d: [Vec3::zeros(); 6],
    };
    surface.jet2_into(uv.x, uv.y, &mut d);
    let (su, sv) = (d.su(), d.sv());
    let (ee, f, g) = (su.dot(&su), su.dot(&sv), sv.dot(&sv));
    let det = ee * g - f * f;
    // The slide's direction in the parameters: G^-1 (su . t, sv . t).
    let (a, b) = (su.dot(&t), sv.dot(&t));
    let w = Vec2::new(g * a - f * b, ee * b - f * a) / det;
    let first = w.x * w.x * ee + 2.0 * w.x * w.y * f + w.y * w.y * g;
    let second = w.x * w.x * d.suu().dot(&normal)
        + 2.0 * w.x * w.y * d.suv().dot(&normal)
        + w.y * w.y * d.svv().dot(&normal);
    let curvature = second / first;
    let length2 = e * e / k;
    let error = 0.5 * curvature.abs() * length2;
    (det > 0.0 && error.is_finite()).then_some(error)
}

/// Newton steps allowed to reach the plane (each at least doubles the
/// correct digits from a start micrometres off it).
pub const MAX_SECTION_STEPS: usize = 8;

/// The point of `surface` in `plane` reached from the parameters `uv` along
/// the surface's steepest way to the plane (Newton on the plane distance
/// `g`, each step the shortest on the surface that zeroes `g`'s linear
/// part: `du = -g G^-1 grad g / (grad g . G^-1 grad g)` with `G` the first
/// fundamental form). `None` where the surface runs along the plane (no
/// step reaches it), the step leaves the surface's domain, or Newton does
/// not settle, or the way is longer than [`MIN_SECTION_SLOPE`] allows.
pub fn onto_section(surface: &NurbsSurface, uv: Vec2, plane: &Plane) -> Option<Point3> {
    let ((u0, u1), (v0, v1)) = surface.domain();
    let n = plane.normal();
    let mut uv = uv;
    // The power-basis jet: the fast evaluation the contact search uses.
    let mut d = Jet2 {
        d: [Vec3::zeros(); 6],
    };
    surface.jet2_into(uv.x, uv.y, &mut d);
    let start = d.point();
    let farthest = plane.signed_distance(start).abs() / MIN_SECTION_SLOPE + ON_PLANE_MM;
    for _ in 0..MAX_SECTION_STEPS {
        let g = plane.signed_distance(d.point());
        if g.abs() <= ON_PLANE_MM {
            return ((d.point() - start).norm() <= farthest).then(|| d.point());
        }
        let (su, sv) = (d.su(), d.sv());
        let (e, f, gg) = (su.dot(&su), su.dot(&sv), sv.dot(&sv));
        let det = e * gg - f * f;
        let grad = Vec2::new(su.dot(&n), sv.dot(&n));
        // G^-1 grad g, and its share of the plane's normal.
        let w = Vec2::new(gg * grad.x - f * grad.y, e * grad.y - f * grad.x) / det;
        let reach = grad.dot(&w);
        if !(det > 0.0 && reach.is_finite() && reach > 0.0) {
            return None;
        }
        uv -= w * (g / reach);
        if uv.x < u0 || uv.x > u1 || uv.y < v0 || uv.y > v1 {
            return None;
        }
        surface.jet2_into(uv.x, uv.y, &mut d);
    }
    None
}

#[cfg(test)]
mod slide_tests {
    use super::*;
    use crate::workpiece::{examples, Workpiece, WorkpieceFile};

    fn load(file: &WorkpieceFile) -> Workpiece {
        match Workpiece::from_file(file, std::path::Path::new("example.json")) {
            Ok(wp) => wp,
            Err(e) => panic!("{e}"),
        }
    }

    /// The slide's error against the analytic surfaces: zero along a
    /// cylinder's straight line (a bore's wall, the plane across its axis
    /// tilted by 1 degree), half the curvature times the slide squared on
    /// a sphere.
    #[test]
    fn a_slide_leaves_the_surface_by_its_curvature() {
        let bore = load(&examples::bore(50.0, 20.0));
        let tilted = Plane::try_new(
            Point3::new(0.0, 0.0, 10.0),
            Vec3::new(1f64.to_radians().sin(), 0.0, 1f64.to_radians().cos()),
        )
        .unwrap();
        let p = Point3::new(25.0, 0.0, 10.05);
        let foot = bore.closest_point(p).unwrap();
        let (face, f) = (&bore.faces[foot.face], foot.projection);
        let e = tilted.signed_distance(p);
        let err = slide_error(&face.surface, f.uv, f.normal, (&tilted, e)).unwrap();
        assert!(e.abs() > 0.04 && err < 1e-12, "{e} {err}");

        let sphere = load(&examples::reference_sphere(25.0));
        let flat = Plane::try_new(Point3::new(0.0, 0.0, 8.0), Vec3::z()).unwrap();
        let q = Point3::new(0.0, (12.5_f64.powi(2) - 8.07_f64.powi(2)).sqrt(), 8.07);
        let foot = sphere.closest_point(q).unwrap();
        let (face, f) = (&sphere.faces[foot.face], foot.projection);
        let e = flat.signed_distance(q);
        let err = slide_error(&face.surface, f.uv, f.normal, (&flat, e)).unwrap();
        // The slide runs along the meridian, sin(angle) = |t| = 1 - (z/R)^2
        // under the root.
        let t2 = 1.0 - (8.07_f64 / 12.5).powi(2);
        let want = 0.5 / 12.5 * e * e / t2;
        assert!((err - want).abs() < 1e-3 * want, "{err} {want}");
    }
}
