//! The profile plot: the nominal section seen in its best 2-D view, with
//! amplified deviation needles along the nominal normals.

use nalgebra::SymmetricEigen;

use super::markup::fixed;
use super::model::{FeatureReport, PointReport};
use super::plots::{out_of_tolerance, EMPTY_PLOT_HEIGHT, PLOT_WIDTH};
use super::svg::{empty_plot, nice_floor, px_text, range, step_decimals, PixelTexts, Svg};
use crate::math::{Mat3, Vec3};

/// Largest height of the profile plot, px (its width is [`PLOT_WIDTH`]);
/// a flat profile gets a lower plot, since both axes share one scale.
pub const PROFILE_HEIGHT: f64 = 460.0;
/// Smallest height of the drawing area of the profile plot, px.
const MIN_DRAWING_HEIGHT: f64 = 80.0;
/// Space kept free around the drawing inside the plot, px.
const PROFILE_MARGIN: f64 = 30.0;
/// Space for the two text lines at the top of the plot, px.
const PROFILE_TOP: f64 = 44.0;
/// The largest needle (or tolerance offset) is drawn about this fraction of
/// the drawing's larger extent; the amplification factor is rounded down
/// to 1, 2 or 5 times a power of ten and stated in the plot.
const NEEDLE_FRACTION: f64 = 0.08;
/// A section is drawn closed when its end gap is at most this many median
/// point spacings.
const CLOSING_GAP: f64 = 1.5;
/// Radius of a nominal touch point's dot, px.
const NOMINAL_DOT_PX: f64 = 2.5;
/// Smallest extent of the drawing, mm (a single point still gets a scale).
const MIN_EXTENT_MM: f64 = 1.0;
/// Typical bytes of one point's needle and curve vertices in the plot.
const POINT_MARKUP_BYTES: usize = 130;

/// An orthonormal 2-D view of 3-D points: `(p - origin) . u` across,
/// `(p - origin) . v` up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Centroid of the points.
    pub origin: Vec3,
    /// First principal direction (largest spread), unit.
    pub u: Vec3,
    /// Second principal direction, unit, orthogonal to `u`.
    pub v: Vec3,
}

impl View {
    /// The plane spanned by the two largest principal directions of the
    /// points (eigenvectors of their 3x3 covariance), each with its largest
    /// component made positive, so that the view does not flip between runs
    /// and "up" is the positive sense of the dominant axis (a section in the
    /// x-z plane shows +z up). Viewed from either side, a planar section is
    /// shown undistorted. Without points: the x-y plane.
    pub fn principal(points: &[Vec3]) -> View {
        if points.is_empty() {
            return View {
                origin: Vec3::zeros(),
                u: Vec3::x(),
                v: Vec3::y(),
            };
        }
        let origin = points.iter().sum::<Vec3>() / points.len() as f64;
        let eigen = SymmetricEigen::new(covariance(points, &origin));
        let mut order = [0usize, 1, 2];
        order.sort_by(|a, b| eigen.eigenvalues[*b].total_cmp(&eigen.eigenvalues[*a]));
        let axis = |k: usize| canonical_sign(eigen.eigenvectors.column(order[k]).into_owned());
        View {
            origin,
            u: axis(0),
            v: axis(1),
        }
    }

    /// View coordinates of a point, mm.
    pub fn project(&self, p: &Vec3) -> (f64, f64) {
        let d = p - self.origin;
        (d.dot(&self.u), d.dot(&self.v))
    }
}

/// The covariance matrix of points about their centroid `origin`.
fn covariance(points: &[Vec3], origin: &Vec3) -> Mat3 {
    let outer = |p: &Vec3| (p - origin) * (p - origin).transpose();
    points.iter().map(outer).sum::<Mat3>() / points.len().max(1) as f64
}

/// The vector or its negative, whichever has its largest component positive.
fn canonical_sign(v: Vec3) -> Vec3 {
    let largest = v
        .iter()
        .copied()
        .fold(0.0, |m: f64, c| if c.abs() > m.abs() { c } else { m });
    if largest < 0.0 {
        -v
    } else {
        v
    }
}

/// Whether a section closes on itself: its ends are no farther apart than
/// [`CLOSING_GAP`] times the median spacing of its points.
fn is_closed(points: &[Vec3]) -> bool {
    let mut steps: Vec<f64> = points.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    let middle = steps.len() / 2;
    let median = match steps.get(middle) {
        Some(_) => *steps.select_nth_unstable_by(middle, f64::total_cmp).1,
        None => 0.0,
    };
    let gap = match (points.first(), points.last()) {
        (Some(a), Some(b)) => (b - a).norm(),
        _ => f64::INFINITY,
    };
    points.len() >= 3 && gap <= CLOSING_GAP * median
}

/// Coordinates with the first appended when the curve is closed.
fn closed_if(mut coords: Vec<(f64, f64)>, closed: bool) -> Vec<(f64, f64)> {
    if let (true, Some(first)) = (closed, coords.first().copied()) {
        coords.push(first);
    }
    coords
}

/// Equal-scale map from view coordinates (mm) into the plot's pixels.
#[derive(Debug, Clone, Copy)]
struct Fit {
    /// px per mm.
    scale: f64,
    /// Pixel position of view coordinate (0, 0).
    zero: (f64, f64),
    /// Height of the whole plot, px.
    height: f64,
}

impl Fit {
    /// Fits the bounding box of the coordinates (all layers, in order) into
    /// the drawing area.
    fn new(layers: [&[(f64, f64)]; 4]) -> Fit {
        let coords = || layers.iter().flat_map(|layer| layer.iter());
        let (u0, u1) = range(coords().map(|c| c.0)).unwrap_or((0.0, 0.0));
        let (v0, v1) = range(coords().map(|c| c.1)).unwrap_or((0.0, 0.0));
        let width = PLOT_WIDTH - 2.0 * PROFILE_MARGIN;
        let most = PROFILE_HEIGHT - PROFILE_TOP - 2.0 * PROFILE_MARGIN;
        let scale = (width / (u1 - u0).max(MIN_EXTENT_MM)).min(most / (v1 - v0).max(MIN_EXTENT_MM));
        let height = (scale * (v1 - v0)).clamp(MIN_DRAWING_HEIGHT, most);
        let centre_px = (
            PLOT_WIDTH / 2.0,
            PROFILE_TOP + PROFILE_MARGIN + height / 2.0,
        );
        let zero = (
            centre_px.0 - scale * (u0 + u1) / 2.0,
            centre_px.1 + scale * (v0 + v1) / 2.0,
        );
        Fit {
            scale,
            zero,
            height: height + PROFILE_TOP + 2.0 * PROFILE_MARGIN,
        }
    }

    /// Pixel position of view coordinates (v pointing up).
    fn map(&self, c: (f64, f64)) -> (f64, f64) {
        (
            self.zero.0 + self.scale * c.0,
            self.zero.1 - self.scale * c.1,
        )
    }
}

/// A point as a nalgebra vector.
fn vec3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

/// The nominal point moved along its normal by `offset` mm.
fn along_normal(point: &PointReport, offset: f64) -> Vec3 {
    vec3(point.nominal) + vec3(point.normal) * offset
}

/// Deviation amplification: the largest of |deviation| and |tolerance|
/// becomes about [`NEEDLE_FRACTION`] of the drawing's extent.
fn amplification(feature: &FeatureReport, points: &[&PointReport], view: &View) -> f64 {
    let coords: Vec<(f64, f64)> = points
        .iter()
        .map(|p| view.project(&vec3(p.nominal)))
        .collect();
    let (u0, u1) = range(coords.iter().map(|c| c.0)).unwrap_or((0.0, 0.0));
    let (v0, v1) = range(coords.iter().map(|c| c.1)).unwrap_or((0.0, 0.0));
    let extent = (u1 - u0).max(v1 - v0).max(MIN_EXTENT_MM);
    let tol = feature.tolerance_mm;
    let devs = points.iter().map(|p| p.deviation_mm.abs());
    let largest = devs
        .chain([tol.lower.abs(), tol.upper.abs()])
        .fold(0.0, f64::max);
    nice_floor(NEEDLE_FRACTION * extent / largest)
}

/// The profile plot of a feature (see the module documentation): nominal
/// polyline, dashed tolerance limits and needles of length deviation x
/// amplification, green inside and red outside the tolerance. Appended to
/// `out`.
pub fn profile_plot(out: &mut Vec<u8>, feature: &FeatureReport) {
    let title = format!("{}: profile with amplified deviations", feature.name);
    let finite = |a: [f64; 3]| a.iter().all(|c| c.is_finite());
    let points: Vec<&PointReport> = feature
        .points
        .iter()
        .filter(|p| finite(p.nominal) && finite(p.normal) && p.deviation_mm.is_finite())
        .collect();
    if points.is_empty() {
        let message = "no points measured";
        return empty_plot(out, PLOT_WIDTH, EMPTY_PLOT_HEIGHT, &title, message);
    }
    let nominals: Vec<Vec3> = points.iter().map(|p| vec3(p.nominal)).collect();
    let view = View::principal(&nominals);
    let amp = amplification(feature, &points, &view);
    let layers = Layers::new(feature, &points, &nominals, &view, amp);
    let mut svg = Svg::new(out, PLOT_WIDTH, layers.fit.height, &title);
    svg.reserve(points.len() * POINT_MARKUP_BYTES);
    layers.draw(
        &mut svg,
        feature.kind != crate::report::FeatureKind::TouchPoints,
    );
    draw_captions(&mut svg, &view, amp, &layers.fit);
    svg.finish()
}

/// The projected geometry of a profile plot, in view coordinates (mm).
struct Layers {
    nominal: Vec<(f64, f64)>,
    needle_ends: Vec<(f64, f64)>,
    upper: Vec<(f64, f64)>,
    lower: Vec<(f64, f64)>,
    outside: Vec<bool>,
    closed: bool,
    fit: Fit,
}

impl Layers {
    /// Projects the nominal points (`nominals` their positions), needle
    /// ends and tolerance limits.
    fn new(
        feature: &FeatureReport,
        points: &[&PointReport],
        nominals: &[Vec3],
        view: &View,
        amp: f64,
    ) -> Layers {
        let tol = feature.tolerance_mm;
        let shifted = |offset: &dyn Fn(&PointReport) -> f64| -> Vec<(f64, f64)> {
            points
                .iter()
                .map(|p| view.project(&along_normal(p, offset(p) * amp)))
                .collect()
        };
        let nominal = shifted(&|_| 0.0);
        let needle_ends = shifted(&|p| p.deviation_mm);
        let upper = shifted(&|_| tol.upper);
        let lower = shifted(&|_| tol.lower);
        let outside = points
            .iter()
            .map(|p| out_of_tolerance(p.deviation_mm, tol))
            .collect();
        let fit = Fit::new([&nominal, &needle_ends, &upper, &lower]);
        let closed = is_closed(nominals);
        Layers {
            nominal,
            needle_ends,
            upper,
            lower,
            outside,
            closed,
            fit,
        }
    }

    /// Draws the layers; `section` joins the points into polylines.
    fn draw(&self, svg: &mut Svg<'_>, section: bool) {
        let nominal = PixelTexts::new(self.nominal.iter().map(|c| self.fit.map(*c)));
        if section {
            svg.polyline(&self.pixels(&self.upper), "tol-line");
            svg.polyline(&self.pixels(&self.lower), "tol-line");
            svg.polyline_texts(&nominal, self.closed, "nominal");
        }
        self.draw_needles(svg, &nominal);
        if !section {
            let radius = px_text(NOMINAL_DOT_PX);
            for k in 0..nominal.count() {
                svg.circle_at(&nominal, k, &radius, "nominal-pt");
            }
        }
    }

    /// A curve in pixels, closed when the section is.
    fn pixels(&self, coords: &[(f64, f64)]) -> Vec<(f64, f64)> {
        let mut pixels = Vec::with_capacity(coords.len() + 1);
        pixels.extend(coords.iter().map(|c| self.fit.map(*c)));
        closed_if(pixels, self.closed)
    }

    /// One needle per point from the nominal point (`nominal` in pixels),
    /// coloured by tolerance.
    fn draw_needles(&self, svg: &mut Svg<'_>, nominal: &PixelTexts) {
        for (k, (end, out)) in self.needle_ends.iter().zip(&self.outside).enumerate() {
            let class = if *out { "needle-out" } else { "needle-in" };
            svg.line_from(nominal, k, self.fit.map(*end), class);
        }
    }
}

/// The amplification statement, the view axes and a scale bar.
fn draw_captions(svg: &mut Svg<'_>, view: &View, amp: f64, fit: &Fit) {
    svg.text((10.0, 18.0), "start", "legend", &amplification_caption(amp));
    svg.text((10.0, 36.0), "start", "legend", &view_caption(view));
    let bar_mm = nice_floor(PLOT_WIDTH / 5.0 / fit.scale);
    let bar_px = bar_mm * fit.scale;
    let (x, y) = (PLOT_WIDTH - PROFILE_MARGIN - bar_px, fit.height - 12.0);
    svg.line((x, y), (x + bar_px, y), "scale");
    let label = format!("{} mm", fixed(bar_mm, step_decimals(bar_mm)));
    svg.text((x + bar_px / 2.0, y - 6.0), "middle", "tick-label", &label);
}

/// "deviations amplified x50: ...".
fn amplification_caption(amp: f64) -> String {
    let factor = fixed(amp, step_decimals(amp));
    format!(
        "deviations amplified x{factor}: needles along the nominal normal \
         (green in, red out of tolerance); dashed: tolerance limits x{factor}"
    )
}

/// "view: right = (...), up = (...)".
fn view_caption(view: &View) -> String {
    let dir = |d: Vec3| format!("({}, {}, {})", fixed(d.x, 3), fixed(d.y, 3), fixed(d.z, 3));
    format!(
        "view: right = {}, up = {} (principal directions of the nominal points)",
        dir(view.u),
        dir(view.v)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn principal_view_of_a_tilted_circle_spans_its_plane() {
        let normal = Vec3::new(1.0, 1.0, 1.0).normalize();
        let a = normal.cross(&Vec3::x()).normalize();
        let b = normal.cross(&a);
        let points: Vec<Vec3> = (0..36)
            .map(|k| {
                let t = k as f64 * std::f64::consts::PI / 18.0;
                Vec3::new(5.0, 0.0, 0.0) + (a * t.cos() + b * t.sin()) * 10.0
            })
            .collect();
        let view = View::principal(&points);
        assert!(view.u.dot(&normal).abs() < 1e-9);
        assert!(view.v.dot(&normal).abs() < 1e-9);
        assert!(view.u.dot(&view.v).abs() < 1e-9);
        assert!((view.origin - Vec3::new(5.0, 0.0, 0.0)).norm() < 1e-9);
        assert!(is_closed(&points));
        assert!(!is_closed(&points[..30]));
    }

    #[test]
    fn canonical_sign_makes_the_largest_component_positive() {
        assert_eq!(
            canonical_sign(Vec3::new(0.1, -0.9, 0.0)),
            Vec3::new(-0.1, 0.9, 0.0)
        );
    }
}
