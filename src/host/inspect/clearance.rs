//! Free space around the nominal part for direct moves between
//! measurements ([`crate::host::modes::direct_move`]).
//!
//! A straight move sweeps the stylus (ball centre to probe mount) over a
//! parallelogram, one side of which is the ball centre's path. The move is
//! clear when that area keeps the ball radius plus a margin (`need`) from
//! every nominal surface. The area is cut in halves while its pieces may
//! come that close:
//! - a piece that every face's leaf boxes keep `need` away (by the
//!   separating-axis test of [`crate::geometry::ProjectionIndex::leaf_near`])
//!   is clear as a whole;
//! - else its sample point is looked at (on the area's rim, where the
//!   probe comes closest, if the piece reaches it: the ball's path and the
//!   stylus at the start and at the end of the move; else its centre): the
//!   distance to the nearest leaf box, exact (a projection) once that is
//!   below `need`. A
//!   sample closer than `need` touches (so does a failed projection); one
//!   farther than `need` plus the piece's reach (sample to farthest corner)
//!   clears the piece (sphere tracing); a piece whose reach is at most
//!   `step_mm / sqrt(2)` is judged by its sample alone.
//!
//! A half's sample keeps at least its parent's distance less the distance
//! between the two samples, which often spares looking at it. So every
//! sample of a move called clear keeps `need`, and every point of the area
//! keeps `need - step_mm / sqrt(2)` at least: the move's ends lie outside
//! the material, so a surface crossing the area would come too close to a
//! sample. Only the design data's surfaces are obstacles: fixtures and
//! faces missing from the design data are not known to the software.
use crate::host::modes::FreeSpace;
use crate::math::{Point3, Vec3};
use crate::program::Pose;
use crate::seam::ProbePart;
use crate::workpiece::Workpiece;
use area::{AreaCheck, AreaPiece};

/// Smallest sampling step the check accepts, mm (a floor for a zero or
/// negative `step_mm`, which would never stop cutting).
const MIN_STEP_MM: f64 = 1e-3;

/// The distance an approach's ball centre keeps from the part (its
/// check with no margin), as a share of the ball radius.
const APPROACH_NEED_SHARE: f64 = 0.5;

/// The sampling step of an approach's check, as a share of the distance
/// it keeps.
const APPROACH_STEP_SHARE: f64 = 0.5;

/// Margins of the direct-move check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceOptions {
    /// Free distance kept between the ball (or stylus) and the nominal
    /// surfaces, mm. Covers the as-machined part's deviation from the
    /// design data (the trajectory tolerance and more).
    pub margin_mm: f64,
    /// Sampling step over the swept area, mm: the pieces that the surfaces'
    /// boxes do not clear are cut until all their points lie within
    /// `step_mm / sqrt(2)` of their samples (half the diagonal of a square
    /// of side `step_mm`), then judged by the samples, so that a point of a
    /// move called clear may come that much closer than the ball radius
    /// plus the margin (`step_mm` must stay below that distance).
    pub step_mm: f64,
    /// The smaller margin of routes that the full one leaves no way for
    /// (into narrow bores and pockets), mm: still above the as-machined
    /// part's deviation from the design that a program tolerates.
    pub tight_margin_mm: f64,
    /// Free distance the shaft (from where it leaves the ball) and the
    /// body keep from the part while the ball measures, mm. A ball touching
    /// a wall at its equator holds its shaft the ball radius less the
    /// shaft radius from the wall (a 0.3 mm ball's default shaft 0.075 mm):
    /// a margin above that calls every such touch a strike.
    pub posture_margin_mm: f64,
    /// Room a standoff where an approach starts keeps beyond the tight
    /// margin, mm: the route down to it is checked with the tight margin,
    /// and a start that met that margin exactly (a round-numbered bore
    /// whose far wall the full standoff just reaches) would be called clear
    /// or not by the rounding of the check.
    pub start_room_mm: f64,
}

impl Default for ClearanceOptions {
    fn default() -> Self {
        ClearanceOptions {
            margin_mm: 4.0,
            step_mm: 2.0,
            tight_margin_mm: 1.0,
            posture_margin_mm: 0.1,
            start_room_mm: 0.01,
        }
    }
}

/// The probe body above the stylus: a solid cylinder with flat ends from
/// the probe mount on, along the stylus (away from the ball). The check
/// covers all of it: the points within its radius of its axis from one
/// radius above the mount to its top (a capsule whose lower cap ends at
/// the mount) by the axis' swept area, and the flat end's region below
/// (the disc and the ring round the cap) by its boundary (see the `body`
/// module). Every point of the cylinder (swept along a move) keeps the
/// margin less `step_mm / sqrt(2)` (less `step_mm` on the flat end's rim);
/// the check reaches no farther below the flat end than the margin, so a
/// part more than the margin below it is clear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeBody {
    /// Radius, mm.
    pub radius_mm: f64,
    /// Length above the probe mount, mm.
    pub length_mm: f64,
}

/// The nominal part on the machine, with the probe's ball and stylus.
pub struct PartClearance<'w> {
    /// Design data.
    pub workpiece: &'w Workpiece,
    /// Part to machine.
    pub pose: Pose,
    /// Ball centre to probe mount along the stylus, machine coordinates, mm.
    pub stylus: Vec3,
    /// Ball radius, mm.
    pub tip_radius_mm: f64,
    /// Stylus shaft radius, mm.
    pub shaft_radius_mm: f64,
    /// The probe body (`None`: the stylus only).
    pub body: Option<ProbeBody>,
    /// Margins.
    pub opts: ClearanceOptions,
}

/// A piece of the area the stylus sweeps: the points `origin + s a + t b`
/// for `s, t` in `[0, 1]`, part coordinates, mm (`a` along the move, `b`
/// along the stylus).
#[derive(Debug, Clone, Copy)]
struct Piece {
    origin: Point3,
    a: Vec3,
    b: Vec3,
    /// Which of its sides lie on the area's sides where the probe comes
    /// closest.
    rim: Rim,
}

/// Sides of a piece that lie on the area's: the ball centre's path, and
/// the stylus where the move starts and where it ends. They are sampled
/// on themselves.
#[derive(Debug, Clone, Copy)]
struct Rim {
    /// The side `t = 0` lies on the path.
    path: bool,
    /// The side `s = 0` lies on the stylus at the start.
    start: bool,
    /// The side `s = 1` lies on the stylus at the end.
    end: bool,
}

impl Rim {
    /// Where the sample lies along the move (`s`): on the start's or the
    /// end's side, else (on neither or both) in the middle.
    fn s(&self) -> f64 {
        match (self.start, self.end) {
            (true, false) => 0.0,
            (false, true) => 1.0,
            _ => 0.5,
        }
    }

    /// Where the sample lies along the stylus (`t`).
    fn t(&self) -> f64 {
        if self.path {
            0.0
        } else {
            0.5
        }
    }

    /// How far the sample is from the farther end of a piece's side along
    /// the move and along the stylus, in side lengths.
    fn weights(&self) -> (f64, f64) {
        let weight = |on_rim: bool| if on_rim { 1.0 } else { 0.5 };
        (weight(self.start != self.end), weight(self.path))
    }
}

impl Piece {
    /// The four corners (the piece is their convex hull).
    fn corners(&self) -> [Point3; 4] {
        let o = self.origin;
        [o, o + self.a, o + self.b, o + self.a + self.b]
    }

    /// The point that stands for the piece: on its sides on the area's rim
    /// (where the probe comes closest), else in its middle.
    fn sample(&self) -> Point3 {
        self.origin + self.a * self.rim.s() + self.b * self.rim.t()
    }

    /// The distance from the sample to the farthest corner, mm.
    fn reach(&self) -> f64 {
        let s = self.sample();
        (self.corners().iter()).fold(0.0, |r, c| r.max((c - s).norm()))
    }

    /// The separating axes the piece offers (those of all pieces cut from
    /// it): its unit normal and its sides' unit directions, as far as it
    /// has them (a segment has no normal, a point nothing).
    fn axes(&self) -> Axes {
        let unit = |v: Vec3| v.try_normalize(0.0);
        Axes {
            normals: unit(self.a.cross(&self.b)).into_iter().collect(),
            edges: [self.a, self.b].into_iter().filter_map(unit).collect(),
        }
    }

    /// The two halves across the longer side, the one nearer the start or
    /// the path first. A side counts double when the sample lies on one of
    /// its ends (on the rim), so that the reach comes out shortest for a
    /// given area.
    fn halves(&self) -> [Piece; 2] {
        let (wa, wb) = self.rim.weights();
        let along = wa * self.a.norm() >= wb * self.b.norm();
        let (rim, half) = (self.rim, if along { self.a } else { self.b } * 0.5);
        let (a, b) = if along {
            (half, self.b)
        } else {
            (self.a, half)
        };
        let end = rim.end && !along;
        let first = Piece {
            a,
            b,
            rim: Rim { end, ..rim },
            ..*self
        };
        let (start, path) = (rim.start && !along, rim.path && along);
        let second = Piece {
            origin: self.origin + half,
            rim: Rim { start, path, ..rim },
            ..first
        };
        [first, second]
    }
}

/// Face normals and edge directions of a piece, unit vectors: the axes
/// along which it is tried against the faces' boxes.
struct Axes {
    normals: Vec<Vec3>,
    edges: Vec<Vec3>,
}

/// What is known of a piece's sample before looking at it.
#[derive(Debug, Clone, Copy)]
struct Known {
    /// A lower bound of its distance from the part, mm.
    floor: f64,
    /// Whether the sample is its parent's, so that `floor` is what a look
    /// would find.
    same: bool,
}

impl Known {
    /// What the look at a parent's sample `parent`, which keeps at least
    /// `d`, tells of its half's sample `half`: at least `d` less the
    /// distance between the two (the distance from the part changes no
    /// faster than the point).
    fn from(parent: Point3, d: f64, half: Point3) -> Known {
        let apart = (half - parent).norm();
        Known {
            floor: d - apart,
            same: apart == 0.0,
        }
    }
}

/// What one look at a piece decides.
enum Verdict {
    /// Every point keeps the required distance (to the sampling step).
    Clear,
    /// Some point comes too close, or a projection failed.
    Touches,
    /// Undecided: look at the halves. The sample keeps at least this
    /// distance, mm.
    Split(f64),
}

impl PartClearance<'_> {
    /// The area the stylus sweeps when the ball centre moves from `from`
    /// to `to` (machine), in part coordinates.
    fn swept(&self, from: Point3, to: Point3) -> Piece {
        let origin = self.pose.to_part(from);
        Piece {
            origin,
            a: self.pose.to_part(to) - origin,
            b: self.pose.to_part(from + self.stylus) - origin,
            rim: Rim {
                path: true,
                start: true,
                end: true,
            },
        }
    }

    /// Decides `piece` if it can, with what is `known` of its sample:
    /// clear when the boxes keep it far enough; else by its sample,
    /// touching when that comes too close, clear when it is far enough for
    /// the whole piece (sphere tracing) or when the piece is fine enough to
    /// be judged by its sample.
    fn verdict<P: AreaPiece>(&self, piece: &P, known: Known, check: &mut AreaCheck) -> Verdict {
        let (need, reach) = (check.need, piece.reach());
        let fine = reach <= check.fine_reach;
        // A fine piece is judged by its sample alone: its boxes could only
        // spare a look at the sample, which costs no more.
        let clear = if fine {
            known.floor >= need
        } else {
            let far = known.same && known.floor >= need + reach;
            far || !self.boxes_near(piece.hull().as_ref(), check)
        };
        if clear {
            return Verdict::Clear;
        }
        let d = if known.same {
            known.floor
        } else {
            self.distance_bound(piece.sample(), check)
        };
        if d < need {
            Verdict::Touches
        } else if fine || d >= need + reach {
            Verdict::Clear
        } else {
            Verdict::Split(d.max(known.floor))
        }
    }

    /// Whether every point of `area` keeps `need` from the part (to the
    /// sampling `step`), cutting it as far as that takes. The step is at
    /// most `need` itself, so a surface crossing the area always comes
    /// nearer than `need` to a sample (a thin shaft's posture, a small
    /// ball on a tight margin: a 2 mm step between samples that each keep
    /// 0.35 mm would let the shaft pass through a shoulder unseen).
    fn area_clear(&self, area: Piece, need: f64, step: f64) -> bool {
        let step = step.min(need).max(MIN_STEP_MM);
        let check = AreaCheck::new(need, step * std::f64::consts::FRAC_1_SQRT_2, area.axes());
        self.pieces_clear([area], check)
    }

    /// Whether every point of `pieces` keeps the distance `check`
    /// requires (to its sampling step), cutting them as far as that takes;
    /// the pieces are looked at in order.
    fn pieces_clear<P: AreaPiece>(
        &self,
        pieces: impl IntoIterator<Item = P>,
        mut check: AreaCheck,
    ) -> bool {
        let start = Known {
            floor: 0.0,
            same: false,
        };
        let mut pieces: Vec<(P, Known)> = pieces.into_iter().map(|p| (p, start)).collect();
        pieces.reverse();
        while let Some((piece, known)) = pieces.pop() {
            match self.verdict(&piece, known, &mut check) {
                Verdict::Clear => {}
                Verdict::Touches => return false,
                Verdict::Split(d) => {
                    // The first half is looked at first.
                    let ([first, second], s) = (piece.halves(), piece.sample());
                    pieces.extend([second, first].map(|h| {
                        let known = Known::from(s, d, h.sample());
                        (h, known)
                    }));
                }
            }
        }
        true
    }
}

impl PartClearance<'_> {
    /// Whether the ball, the stylus and the body keep `margin` (mm) from
    /// the part on the move from `from` to `to` (machine).
    fn probe_clear(&self, from: Point3, to: Point3, margin: f64) -> bool {
        let step = self.opts.step_mm.max(MIN_STEP_MM);
        let finite = |p: &Piece| p.corners().iter().all(|c| c.iter().all(|x| x.is_finite()));
        let stylus = self.swept(from, to);
        let stylus_clear =
            finite(&stylus) && self.area_clear(stylus, self.tip_radius_mm + margin, step);
        stylus_clear
            && (self.body).is_none_or(|body| self.body_clear((from, to), &body, margin, step))
    }
}

impl PartClearance<'_> {
    /// Whether the shaft (`body`: false) or the body standing with the
    /// ball centre at `ball` (machine) keeps the posture margin.
    fn standing_clear(&self, ball: Point3, body: bool) -> bool {
        let step = self.opts.step_mm.max(MIN_STEP_MM);
        let margin = self.opts.posture_margin_mm;
        let piece = |origin: Point3, b: Vec3| Piece {
            origin: self.pose.to_part(origin),
            a: Vec3::zeros(),
            b: self.pose.to_part(origin + b) - self.pose.to_part(origin),
            rim: Rim {
                path: true,
                start: true,
                end: true,
            },
        };
        let finite = ball.iter().all(|x| x.is_finite());
        match (body, self.body, self.stylus.try_normalize(1e-12)) {
            (false, _, Some(up)) => {
                // The shaft leaves the ball `lift` above its centre.
                let (r, rs) = (self.tip_radius_mm, self.shaft_radius_mm);
                let lift = (r * r - rs * rs).max(0.0).sqrt().min(self.stylus.norm());
                finite
                    && self.area_clear(
                        piece(ball + up * lift, self.stylus - up * lift),
                        rs + margin,
                        step,
                    )
            }
            (false, _, None) => finite,
            (true, Some(b), Some(_)) => finite && self.body_clear((ball, ball), &b, margin, step),
            (true, _, _) => true,
        }
    }
}

impl FreeSpace for PartClearance<'_> {
    fn segment_clear(&self, from: Point3, to: Point3) -> bool {
        self.probe_clear(from, to, self.opts.margin_mm)
    }

    fn margin_mm(&self) -> Option<f64> {
        Some(self.opts.margin_mm)
    }

    fn in_material(&self, p: Point3) -> bool {
        (self.workpiece.closest_point(self.pose.to_part(p)))
            .is_ok_and(|f| f.projection.signed_distance < 0.0)
    }

    fn design_foot(&self, p: Point3) -> Option<(f64, Vec3)> {
        let f = self.workpiece.closest_point(self.pose.to_part(p)).ok()?;
        let pr = f.projection;
        Some((pr.signed_distance, self.pose.dir_to_machine(pr.normal)))
    }

    fn body_clear(&self, ball: Point3) -> bool {
        self.standing_clear(ball, true)
    }

    fn posture(&self, ball: Point3) -> Option<ProbePart> {
        if !self.standing_clear(ball, false) {
            Some(ProbePart::Shaft)
        } else if !self.standing_clear(ball, true) {
            Some(ProbePart::Body)
        } else {
            None
        }
    }

    fn approach_clear(&self, from: Point3, to: Point3) -> bool {
        // The ball centre's path alone (the stylus over a surface that
        // leans over the ball comes nearer than the ball radius where it
        // touches; the posture checks hold it) keeping half the ball
        // radius, sampled at a quarter of it: a wall it would cross holds a
        // sample nearer than that, while the ball touching beside an edge
        // (the next face within the ball radius) passes.
        let r = APPROACH_NEED_SHARE * self.tip_radius_mm;
        let step = (APPROACH_STEP_SHARE * r).max(MIN_STEP_MM);
        let path = Piece {
            b: Vec3::zeros(),
            ..self.swept(from, to)
        };
        let finite = path
            .corners()
            .iter()
            .all(|c| c.iter().all(|x| x.is_finite()));
        finite && self.area_clear(path, r, step)
    }

    fn start_clear(&self, at: Point3) -> bool {
        let margin = self.opts.tight_margin_mm + self.opts.start_room_mm;
        self.probe_clear(at, at, margin)
    }

    fn segment_clear_with(&self, from: Point3, to: Point3, tight: bool) -> bool {
        let margin = if tight {
            self.opts.tight_margin_mm
        } else {
            self.opts.margin_mm
        };
        self.probe_clear(from, to, margin)
    }
}

mod area;
mod body;
pub mod memo;

#[cfg(test)]
mod tests;
