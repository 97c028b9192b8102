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
