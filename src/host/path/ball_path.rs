//! The ball-centre path: a chain of cubic segments with a global arc-length
//! parameter `s` and the nominal data every path point came from.

use super::offset::{offset_points, OffsetPoint};
use super::pcc::CubicSegment;
use super::{spline, PathError, PathOptions};
use crate::math::{Point3, Vec3};

/// A path point (spline knot) with the nominal point and normal it came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSample {
    /// The nominal (design) surface point, mm.
    pub nominal: Point3,
    /// Unit outward nominal normal; the direction along which deflection
    /// is controlled.
    pub normal: Vec3,
    /// The ball centre: `nominal + offset * normal`, mm.
    pub centre: Point3,
    /// Arc-length parameter of the ball centre on the path, mm.
    pub s: f64,
}

/// A point of a path: segment, local parameter and global arc length. The
/// per-cycle scanning loop keeps one so the next closest-point query starts
/// from it without converting arc length back into a parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathLocation {
    /// Segment index.
    pub segment: usize,
    /// Local parameter on the segment.
    pub u: f64,
    /// Global arc length, mm.
    pub s: f64,
}

/// Ball-centre path of design-value scanning: a C2 chain of parametric cubic
/// curve segments through the offset points, parameterised by arc length
/// `s` in `[0, length]`. Segment `i` runs from sample `i` to sample `i + 1`
/// (to sample 0 for the closing segment of a closed path).
#[derive(Debug, Clone, PartialEq)]
pub struct BallPath {
    samples: Vec<PathSample>,
    segments: Vec<CubicSegment>,
    /// Arc length at each segment start, plus the total length at the end.
    starts: Vec<f64>,
    closed: bool,
    opts: PathOptions,
}

impl BallPath {
    /// Builds the path through `points` (nominal point, outward normal;
    /// normals are normalised) each offset by `offset_mm` along its normal
    /// (pass `r - Ep`). A closed path must not repeat its first point.
    pub fn from_section(
        points: &[(Point3, Vec3)],
        closed: bool,
        offset_mm: f64,
        opts: PathOptions,
    ) -> Result<BallPath, PathError> {
        let offset = offset_points(points, closed, offset_mm, &opts)?;
        let centres: Vec<Point3> = offset.iter().map(|p| p.centre).collect();
        let segments = spline::segments(&centres, closed, opts.end, opts.quad_panels);
        let starts = cumulative(&segments);
        let samples = offset.iter().zip(&starts).map(sample).collect();
        Ok(BallPath {
            samples,
            segments,
            starts,
            closed,
            opts,
        })
    }

    /// Whether the path closes on itself.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// Total arc length, mm.
    pub fn length(&self) -> f64 {
        self.starts.last().copied().unwrap_or(0.0)
    }

    /// The options the path was built with.
    pub fn options(&self) -> &PathOptions {
        &self.opts
    }

    /// The spline knots with their nominal data, in path order.
    pub fn samples(&self) -> &[PathSample] {
        &self.samples
    }

    /// The cubic segments, in path order.
    pub fn segments(&self) -> &[CubicSegment] {
        &self.segments
    }

    /// Arc length at the start of segment `i` (`length()` for `i` = number
    /// of segments), mm; `None` beyond.
    pub fn segment_start(&self, i: usize) -> Option<f64> {
        self.starts.get(i).copied()
    }

    /// Ball-centre position at arc length `s`, mm.
    pub fn position(&self, s: f64) -> Point3 {
        let (i, u) = self.locate(s);
        self.segments[i].position(u)
    }

    /// Unit tangent (direction of travel) at `s`.
    pub fn tangent(&self, s: f64) -> Vec3 {
        let (i, u) = self.locate(s);
        self.segments[i].d1(u).normalize()
    }

    /// Curvature at `s`, 1/mm.
    pub fn curvature(&self, s: f64) -> f64 {
        let (i, u) = self.locate(s);
        self.segments[i].curvature(u)
    }

    /// Path normal at `s`: the nominal normals of the two neighbouring
    /// samples blended linearly by arc length and normalised (the nearer
    /// one where they cancel).
    pub fn normal(&self, s: f64) -> Vec3 {
        let s = self.wrap(s);
        self.normal_on(self.segment_index(s), s)
    }

    /// The location of arc length `s`.
    pub fn location(&self, s: f64) -> PathLocation {
        let (segment, u) = self.locate(s);
        PathLocation {
            segment,
            u,
            s: self.wrap(s),
        }
    }

    /// Position, unit tangent and path normal ([`Self::normal`]) at a
    /// location (no arc-length inversion).
    pub fn frame(&self, at: &PathLocation) -> (Point3, Vec3, Vec3) {
        let i = at.segment.min(self.segments.len() - 1);
        let seg = &self.segments[i];
        let tangent = seg.d1(at.u).try_normalize(0.0).unwrap_or_else(Vec3::zeros);
        (seg.position(at.u), tangent, self.normal_on(i, at.s))
    }

    fn normal_on(&self, i: usize, s: f64) -> Vec3 {
        let t = ((s - self.starts[i]) / self.segments[i].arc_len()).clamp(0.0, 1.0);
        let n0 = self.samples[i].normal;
        let n1 = self.samples[(i + 1) % self.samples.len()].normal;
        let blend = n0 * (1.0 - t) + n1 * t;
        match blend.try_normalize(0.0) {
            Some(n) => n,
            None if t < 0.5 => n0,
            None => n1,
        }
    }

    /// `s` wrapped into `[0, length)` on a closed path, clamped to
    /// `[0, length]` on an open one.
    pub fn wrap(&self, s: f64) -> f64 {
        let len = self.length();
        if self.closed {
            // `rem_euclid` (an fmod) returns `s` itself inside [0, len).
            if (0.0..len).contains(&s) {
                s
            } else {
                s.rem_euclid(len)
            }
        } else {
            s.clamp(0.0, len)
        }
    }

    /// Segment index containing the (wrapped) arc length `s`.
    pub(crate) fn segment_index(&self, s: f64) -> usize {
        let above = self.starts.partition_point(|&x| x <= s);
        above.saturating_sub(1).min(self.segments.len() - 1)
    }

    /// Segment index and local parameter `u` at arc length `s`.
    pub(crate) fn locate(&self, s: f64) -> (usize, f64) {
        let s = self.wrap(s);
        let i = self.segment_index(s);
        let seg = &self.segments[i];
        let u = seg.param_at_arc(
            s - self.starts[i],
            self.opts.arc_tol_mm,
            self.opts.arc_max_iters,
        );
        (i, u)
    }

    /// Global arc length of local parameter `u` on segment `i`.
    pub(crate) fn arc_of(&self, i: usize, u: f64) -> f64 {
        self.starts[i] + self.segments[i].arc_len_to(u)
    }
}

/// Arc length at every segment start plus the total.
fn cumulative(segments: &[CubicSegment]) -> Vec<f64> {
    let mut starts = Vec::with_capacity(segments.len() + 1);
    starts.push(0.0);
    let mut total = 0.0;
    for seg in segments {
        total += seg.arc_len();
        starts.push(total);
    }
    starts
}

fn sample((p, s): (&OffsetPoint, &f64)) -> PathSample {
    PathSample {
        nominal: p.nominal,
        normal: p.normal,
        centre: p.centre,
        s: *s,
    }
}
