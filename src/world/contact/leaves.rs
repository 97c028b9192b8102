//! The contact search's leaves: every face's rational Bezier patches split
//! until near-flat, and along the trim boundary until small, each with
//! bounds on the true (as-machined) surface over it: an axis-aligned box
//! and a slab. Pieces outside a face's trim are left out, so the search
//! never sees the untrimmed surface beyond a face's boundary.
use super::mapped::ShapeCache;
use crate::geometry::nurbs::bezier::{decompose, BezierPatch};
use crate::geometry::projection::Bounds;
use crate::geometry::{NurbsSurface, Trim};
use crate::math::{Point3, Vec2, Vec3};
use crate::workpiece::{Face, Workpiece};
use crate::world::as_machined::AsMachined;

/// Sizes of the contact leaves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeafOptions {
    /// A piece is flat enough when its control points lie within this
    /// fraction of its box diagonal from the bilinear surface through its
    /// corner control points (dimensionless).
    pub flatness: f64,
    /// Most halvings of one Bezier patch for flatness.
    pub max_flat_depth: usize,
    /// A piece crossed by its face's trim boundary is halved until its box
    /// diagonal is at most this, mm (so that the boxes follow the trimmed
    /// face closely: no box over a pocket or hole).
    pub trim_leaf_mm: f64,
    /// Most halvings of one Bezier patch along a trim boundary.
    pub max_trim_depth: usize,
    /// The trimmed boxes of a piece the trim crosses (boxes holding its
    /// part inside the trim, which the shaft and body checks use) halve
    /// the piece's parts that the trim crosses until their boxes are at
    /// most this across, mm: they reach at most this far over a hole's
    /// edge, well below the 0.45 mm a 1.5 mm shaft keeps from the wall of
    /// a bore it scans with a 3 mm ball.
    pub trim_box_mm: f64,
    /// Most halvings of one piece for its trimmed box.
    pub max_trim_box_depth: usize,
    /// A face is split into leaves the first time a query's look comes
    /// within this (mm) of the face's box; a face farther away counts
    /// with its box (the answers are the same either way: this trades the
    /// time to split faces the probe never comes near against free-air
    /// bounds from looser boxes).
    pub split_within_mm: f64,
}

impl Default for LeafOptions {
    fn default() -> Self {
        LeafOptions {
            flatness: 0.05,
            max_flat_depth: 8,
            trim_leaf_mm: 8.0,
            max_trim_depth: 16,
            trim_box_mm: 0.15,
            max_trim_box_depth: 12,
            split_within_mm: 5.0,
        }
    }
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Aabb {
    pub(crate) min: Point3,
    pub(crate) max: Point3,
}

impl Aabb {
    /// The empty box.
    pub(crate) fn empty() -> Aabb {
        Aabb {
            min: Point3::from(Vec3::repeat(f64::INFINITY)),
            max: Point3::from(Vec3::repeat(f64::NEG_INFINITY)),
        }
    }

    /// The box of `points`.
    pub(super) fn of(points: impl Iterator<Item = Point3>) -> Aabb {
        points.fold(Aabb::empty(), |b, p| Aabb {
            min: b.min.inf(&p),
            max: b.max.sup(&p),
        })
    }

    /// The smallest box holding both.
    pub(crate) fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.inf(&o.min),
            max: self.max.sup(&o.max),
        }
    }

    /// Squared distance from `p` (zero inside).
    #[inline(always)]
    pub(crate) fn dist2(&self, p: Point3) -> f64 {
        let dx = (self.min.x - p.x).max(p.x - self.max.x).max(0.0);
        let dy = (self.min.y - p.y).max(p.y - self.max.y).max(0.0);
        let dz = (self.min.z - p.z).max(p.z - self.max.z).max(0.0);
        dx * dx + dy * dy + dz * dz
    }

    /// The centre.
    pub(crate) fn centre(&self) -> Point3 {
        nalgebra::center(&self.min, &self.max)
    }
}

/// The region `lo <= x . normal <= hi` (a unit normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Slab {
    pub(super) normal: Vec3,
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl Slab {
    /// Distance from `p` (zero inside).
    #[inline(always)]
    fn dist(&self, p: Point3) -> f64 {
        let s = p.coords.dot(&self.normal);
        (self.lo - s).max(s - self.hi).max(0.0)
    }

    /// Distance from the segment `a..b` (zero when it meets the slab).
    fn segment_dist(&self, a: Point3, b: Point3) -> f64 {
        let (sa, sb) = (a.coords.dot(&self.normal), b.coords.dot(&self.normal));
        (self.lo - sa.max(sb)).max(sa.min(sb) - self.hi).max(0.0)
    }
}

/// The box `lo[k] <= x . axes[k] <= hi[k]` of an orthonormal frame whose
/// first axis is a leaf's slab normal and whose second runs across it
/// along the diagonal of its control net: it holds the leaf as tightly
/// across as along the
/// normal, where the axis-aligned box of a tilted leaf reaches far past it
/// at its corners and the slab is unbounded across.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Obb {
    pub(super) axes: [Vec3; 3],
    pub(super) lo: Point3,
    pub(super) hi: Point3,
}

impl Obb {
    /// The distance from `p` to the box (zero inside), mm.
    #[inline(always)]
    fn dist(&self, p: Point3) -> f64 {
        let local = Point3::from(self.axes.map(|e| p.coords.dot(&e)));
        let bx = Aabb {
            min: self.lo,
            max: self.hi,
        };
        bx.dist2(local).sqrt()
    }

    /// The exact distance from the segment `a..b` to the box (zero when
    /// they meet), mm.
    fn segment_dist(&self, a: Point3, b: Point3) -> f64 {
        let local = |p: Point3| Point3::from(self.axes.map(|e| p.coords.dot(&e)));
        let bx = Aabb {
            min: self.lo,
            max: self.hi,
        };
        super::shapes::segment_box(local(a), local(b), &bx).0.sqrt()
    }
}

/// One piece of a face.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Leaf {
    /// The face.
    pub(crate) face: usize,
    /// Its nominal parameter rectangle.
    pub(crate) bounds: Bounds,
    /// The true surface over the rectangle lies in this box...
    pub(crate) aabb: Aabb,
    /// ... and in this slab ...
    slab: Slab,
    /// ... and in this oriented box (see [`Leaf::tight_segment_bound`]).
    obb: Option<Obb>,
    /// Whether the trim boundary crosses the rectangle (its piece has
    /// trim segments, see [`Leaves::trim_chords`]).
    crossed: bool,
    /// The form's bound over the leaf, stretched by `T`, mm: how far the
    /// true surface may lie from the image of the nominal one.
    inflate: f64,
}

impl Leaf {
    /// A lower bound of the distance from `p` to the true surface over the
    /// leaf, mm.
    #[inline(always)]
    pub(crate) fn lower_bound(&self, p: Point3) -> f64 {
        self.aabb.dist2(p).sqrt().max(self.slab.dist(p))
    }

    /// A lower bound of the distance from the segment `a..b` to the true
    /// surface over the leaf, mm.
    pub(crate) fn segment_lower_bound(&self, a: Point3, b: Point3) -> f64 {
        let d2 = super::shapes::segment_box(a, b, &self.aabb).0;
        self.segment_lower_bound_from(d2, a, b)
    }

    /// [`Self::segment_lower_bound`] with the squared segment-box distance
    /// `d2` known.
    #[inline(always)]
    pub(crate) fn segment_lower_bound_from(&self, d2: f64, a: Point3, b: Point3) -> f64 {
        d2.sqrt().max(self.slab.segment_dist(a, b))
    }

    /// A lower bound of the distance from the segment `a..b` to the true
    /// surface over the leaf at least `bound` (one of the cheaper bounds
    /// above), from its oriented box: dearer (a change of frame and an
    /// exact segment-box distance), kept for leaves whose cheaper bound
    /// does not settle a check, mm.
    pub(crate) fn tight_segment_bound(&self, a: Point3, b: Point3, bound: f64) -> f64 {
        self.obb.map_or(bound, |o| bound.max(o.segment_dist(a, b)))
    }

    /// A lower bound of the distance from `p` to the true surface over the
    /// leaf at least `bound` (its [`Self::lower_bound`]), from its oriented
    /// box: a little dearer, kept for a leaf the cheaper bound would send
    /// to a Newton iteration, mm.
    #[inline(always)]
    pub(crate) fn tight_bound(&self, p: Point3, bound: f64) -> f64 {
        self.obb.map_or(bound, |o| bound.max(o.dist(p)))
    }

    /// Whether the trim boundary crosses the leaf.
    pub(crate) fn crossed(&self) -> bool {
        self.crossed
    }

    /// The parameters of the sample nearest to `p` among `samples` (the
    /// leaf's 3 x 3 grid of approximate true points).
    pub(crate) fn start(&self, p: Point3, samples: &[Point3; 9]) -> Vec2 {
        let mut best = (f64::INFINITY, 4);
        for (k, s) in samples.iter().enumerate() {
            let d2 = (s - p).norm_squared();
            if d2 < best.0 {
                best = (d2, k);
            }
        }
        sample_uv(&self.bounds, best.1)
    }
}

/// Parameters of sample `k` of the 3 x 3 grid over `b`.
fn sample_uv(b: &Bounds, k: usize) -> Vec2 {
    let (i, j) = ((k / 3) as f64 * 0.5, (k % 3) as f64 * 0.5);
    Vec2::new(
        b.lo.x + (b.hi.x - b.lo.x) * i,
        b.lo.y + (b.hi.y - b.lo.y) * j,
    )
}

/// Every face's leaves.
///
/// A leaf holds only the bounds every query may look at; what a search
/// needs of the few leaves it comes near (start samples, trim chords) is
/// mapped from the shared nominal pieces when asked for, so a batch's
/// variants do not each copy the whole design.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Leaves {
    pub(crate) leaves: Vec<Leaf>,
    /// The factor by which `T` stretches lengths (at least 1).
    stretch: f64,
}

/// A trim segment's chord on the true part: the image of the segment lies
/// within `slack` (mm) of the straight line from `a` to `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Chord {
    pub(crate) a: Point3,
    pub(crate) b: Point3,
    pub(crate) slack: f64,
}

impl Chord {
    /// A lower bound of the distance from `p` to the segment's image, mm.
    pub(crate) fn lower_bound(&self, p: Point3) -> f64 {
        let d = self.b - self.a;
        let t = ((p - self.a).dot(&d) / d.norm_squared().max(1e-300)).clamp(0.0, 1.0);
        (p - (self.a + d * t)).norm() - self.slack
    }
}

/// How much farther than its sag at the middle a trim segment's nominal
/// image may lie from its chord (the sag of a parabola is its largest
/// deviation; the factor covers the change of curvature along a segment,
/// which is short against the surface's radii).
const SAG_FACTOR: f64 = 2.0;

/// Added to every chord's slack for the rounding of its points, mm.
const CHORD_ROUNDING_MM: f64 = 1e-9;

/// A finished piece of a face, nominal: what its leaf is made from.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Piece {
    pub(super) face: usize,
    rect: Bounds,
    pub(super) degree: [usize; 2],
    /// Its nominal control points (row-major), for a piece the trim does
    /// not cross ([`Piece::control_points`]: a crossed piece keeps them in
    /// its patch only).
    points: Vec<Point3>,
    /// Its trim segments, clipped to the rectangle.
    pub(super) segs: Vec<(Vec2, Vec2)>,
    /// For each segment: the nominal end points and a bound of the
    /// nominal image's distance from their chord, mm.
    chords: Vec<(Point3, Point3, f64)>,
    /// The nominal points of its 3 x 3 sample grid, made when first asked
    /// for ([`Piece::nominal_samples`]); boxed, as few pieces are ever
    /// searched cold (216 bytes a piece less to write).
    samples: std::sync::OnceLock<Box<[Point3; 9]>>,
    /// The box of its nominal control points (the nominal surface over
    /// the piece lies in their hull).
    nominal_box: (Point3, Point3),
    /// The Bezier patch of a piece the trim crosses, for its trimmed box.
    pub(super) crossed: Option<BezierPatch>,
    /// Boxes holding the nominal surface over the part of a crossed
    /// piece inside the trim, in their tree, made when first asked for
    /// ([`Pieces::trimmed_boxes`]).
    pub(super) trimmed: std::sync::OnceLock<super::box_tree::BoxTree>,
}

impl Piece {
    /// Its nominal control points (row-major) to `visit`.
    pub(super) fn control_points(&self, mut visit: impl FnMut(Point3)) {
        match &self.crossed {
            Some(patch) => patch.points().for_each(visit),
            None => self.points.iter().for_each(|&p| visit(p)),
        }
    }

    /// The nominal points of its 3 x 3 sample grid on `surface` (its
    /// face's), made on first use.
    pub(super) fn nominal_samples(&self, surface: &NurbsSurface) -> &[Point3; 9] {
        self.samples.get_or_init(|| {
            Box::new(std::array::from_fn(|k| {
                let uv = sample_uv(&self.rect, k);
                surface.point(uv.x, uv.y)
            }))
        })
    }
}

/// Every face of a workpiece split into pieces: the nominal design alone
/// decides the splits, so the pieces serve every as-machined part of it
/// (a batch's variants); each part only maps them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Pieces {
    pub(crate) opts: LeafOptions,
    pub(super) pieces: Vec<Piece>,
    /// The leaf tree over the pieces' nominal boxes: each part refits it
    /// to its own leaves ([`super::tree::LeafTree::refit`]).
    pub(crate) tree: super::tree::LeafTree,
    /// The pieces' bounds under the linear part of the transform last
    /// asked for ([`super::mapped`]).
    shapes: ShapeCache,
}

impl Pieces {
    /// The pieces of every face of `wp`.
    #[cfg(test)]
    pub(crate) fn new(wp: &Workpiece, opts: &LeafOptions) -> Pieces {
        Pieces::of_faces(wp, 0..wp.faces.len(), opts)
    }

    /// The pieces of the faces `faces` of `wp` (numbered as in `wp`).
    pub(crate) fn of_faces(
        wp: &Workpiece,
        faces: impl Iterator<Item = usize>,
        opts: &LeafOptions,
    ) -> Pieces {
        let mut out = Vec::new();
        for (i, f) in faces.filter_map(|i| wp.faces.get(i).map(|f| (i, f))) {
            let ctx = FaceContext {
                face: i,
                surface: &f.surface,
                trim: f.trim.as_ref(),
                opts: *opts,
            };
            let segs = boundary_segments(f);
            for patch in decompose(&f.surface) {
                let rect = rect_of(&patch);
                let mine = clip_all(&segs, &rect);
                ctx.split(patch, mine, 0, &mut out);
            }
        }
        Pieces::from_pieces(out, opts)
    }

    /// The pieces `pieces` with their tree.
    fn from_pieces(pieces: Vec<Piece>, opts: &LeafOptions) -> Pieces {
        let boxes: Vec<Aabb> = (pieces.iter())
            .map(|p| Aabb {
                min: p.nominal_box.0,
                max: p.nominal_box.1,
            })
            .collect();
        Pieces {
            opts: *opts,
            tree: super::tree::LeafTree::over(&boxes),
            pieces,
            shapes: ShapeCache::default(),
        }
    }

    /// Number of pieces.
    pub(crate) fn len(&self) -> usize {
        self.pieces.len()
    }

    /// The first `n` pieces only.
    pub(super) fn truncated(mut self, n: usize) -> Pieces {
        self.pieces.truncate(n);
        Pieces::from_pieces(self.pieces, &self.opts)
    }
}

/// What a face is split with.
pub(super) struct FaceContext<'a> {
    pub(super) face: usize,
    pub(super) surface: &'a NurbsSurface,
    pub(super) trim: Option<&'a Trim>,
    pub(super) opts: LeafOptions,
}

impl Leaves {
    /// The leaves of `pieces` (of a workpiece) as machined by `am`: the
    /// pieces' bounds under `am`'s linear map (shared by every part with
    /// that map), placed at its translation and widened by its form.
    pub(crate) fn of(pieces: &Pieces, am: &AsMachined) -> Leaves {
        let stretch = am.stretch_factor();
        let shapes = pieces.shapes.shapes(&pieces.pieces, am.linear_part());
        let t = am.translation();
        let leaves = (pieces.pieces.iter().zip(shapes.iter()))
            .map(|(piece, shape)| {
                let (lo, hi) = piece.nominal_box;
                let inflate = am.max_form_height_over(piece.face, lo, hi) * stretch;
                let (aabb, slab, obb) = shape.placed(t, inflate);
                Leaf {
                    face: piece.face,
                    bounds: piece.rect,
                    aabb,
                    slab,
                    obb,
                    crossed: !piece.segs.is_empty(),
                    inflate,
                }
            })
            .collect();
        Leaves { leaves, stretch }
    }

    /// The trim segments of leaf `id` (nominal parameters, clipped to its
    /// rectangle) with their chords on the true part `am` (the part the
    /// leaves were made for) and how far each segment's image can lie from
    /// its chord: a query farther than that from the chord needs no search
    /// along the segment.
    pub(crate) fn trim_chords<'a>(
        &'a self,
        pieces: &'a Pieces,
        id: usize,
        am: &'a AsMachined,
    ) -> impl Iterator<Item = ((Vec2, Vec2), Chord)> + 'a {
        let inflate = self.leaves.get(id).map_or(0.0, |l| l.inflate);
        let piece = pieces.pieces.get(id);
        let segs = piece.map_or(&[][..], |p| &p.segs[..]);
        let chords = piece.map_or(&[][..], |p| &p.chords[..]);
        // `T` is affine: it maps a chord to the chord of the mapped ends and
        // stretches the sag by at most its stretch; the form moves the
        // surface by at most `inflate`.
        segs.iter().zip(chords).map(move |(&seg, &(a, b, sag))| {
            let chord = Chord {
                a: am.transform_point(a),
                b: am.transform_point(b),
                slack: sag * self.stretch + inflate,
            };
            (seg, chord)
        })
    }
}

/// The trim segments of a face that do not lie on a side of its parameter
/// domain (those are the domain's own boundary, which Newton's bounds
/// hold), clamped to the domain.
fn boundary_segments(f: &Face) -> Vec<(Vec2, Vec2)> {
    let Some(t) = f.trim.as_ref() else {
        return Vec::new();
    };
    let ((u0, u1), (v0, v1)) = f.surface.domain();
    let eps = 1e-9 * (u1 - u0).abs().max(v1 - v0).max(1e-300);
    let on_side = |a: Vec2, b: Vec2| {
        let same = |x: f64, y: f64, s: f64| (x - s).abs() <= eps && (y - s).abs() <= eps;
        same(a.x, b.x, u0) || same(a.x, b.x, u1) || same(a.y, b.y, v0) || same(a.y, b.y, v1)
    };
    t.segments()
        .map(|(a, b)| (f.surface.clamp(a), f.surface.clamp(b)))
        .filter(|&(a, b)| !on_side(a, b) && (b - a).norm() > eps)
        .collect()
}

pub(super) fn rect_of(patch: &BezierPatch) -> Bounds {
    Bounds {
        lo: Vec2::new(patch.u.0, patch.v.0),
        hi: Vec2::new(patch.u.1, patch.v.1),
    }
}

/// The parts of `segs` inside `rect` (Liang-Barsky), leaving out points.
fn clip_all(segs: &[(Vec2, Vec2)], rect: &Bounds) -> Vec<(Vec2, Vec2)> {
    // Room for all the rest once one is inside: one allocation, none for
    // the many rectangles the trim misses (a finished piece shrinks it).
    let mut inside = segs.iter().filter_map(|&s| clip(s, rect));
    let Some(first) = inside.next() else {
        return Vec::new();
    };
    let mut out = Vec::with_capacity(1 + inside.size_hint().1.unwrap_or(0));
    out.push(first);
    out.extend(inside);
    out
}

fn clip((a, b): (Vec2, Vec2), r: &Bounds) -> Option<(Vec2, Vec2)> {
    // Both ends beyond one side: nothing inside (most segments of a long
    // trim, for a small rectangle), without the divisions below.
    let beyond = (a.x < r.lo.x && b.x < r.lo.x)
        || (a.x > r.hi.x && b.x > r.hi.x)
        || (a.y < r.lo.y && b.y < r.lo.y)
        || (a.y > r.hi.y && b.y > r.hi.y);
    if beyond {
        return None;
    }
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - r.lo.x),
        (d.x, r.hi.x - a.x),
        (-d.y, a.y - r.lo.y),
        (d.y, r.hi.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    (t0 < t1).then(|| (a + d * t0, a + d * t1))
}

impl FaceContext<'_> {
    /// The nominal chord of the trim segment `(a, b)` and its slack.
    fn chord(&self, (a, b): (Vec2, Vec2)) -> (Point3, Point3, f64) {
        let at = |uv: Vec2| self.surface.point(uv.x, uv.y);
        let (pa, pb, pm) = (at(a), at(b), at((a + b) * 0.5));
        let sag = (pm - Point3::from((pa.coords + pb.coords) * 0.5)).norm();
        (pa, pb, SAG_FACTOR * sag + CHORD_ROUNDING_MM)
    }

    /// Splits `patch` (crossed by the trim segments `segs`) until flat and,
    /// where the trim crosses it, small; pushes the pieces on the face.
    fn split(
        &self,
        patch: BezierPatch,
        mut segs: Vec<(Vec2, Vec2)>,
        depth: usize,
        out: &mut Vec<Piece>,
    ) {
        let rect = rect_of(&patch);
        if segs.is_empty() && self.trim.is_some_and(|t| !t.contains(centre(&rect))) {
            return;
        }
        // The control points are collected only for a finished piece (most
        // calls split further).
        let size = Aabb::of(patch.points());
        let diag = (size.max - size.min).norm();
        let flat = deviation(&patch) <= self.opts.flatness * diag;
        let refine_flat = !flat && depth < self.opts.max_flat_depth;
        let refine_trim =
            !segs.is_empty() && diag > self.opts.trim_leaf_mm && depth < self.opts.max_trim_depth;
        if !(refine_flat || refine_trim) {
            segs.shrink_to_fit();
            out.push(Piece {
                nominal_box: (size.min, size.max),
                trimmed: std::sync::OnceLock::new(),
                face: self.face,
                samples: std::sync::OnceLock::new(),
                rect,
                degree: patch.degree,
                points: match segs.is_empty() {
                    true => patch.points().collect(),
                    false => Vec::new(),
                },
                chords: segs.iter().map(|&seg| self.chord(seg)).collect(),
                crossed: (!segs.is_empty()).then_some(patch),
                segs,
            });
            return;
        }
        let ((a, sa), (b, sb)) = halves(&patch, &segs);
        self.split(a, sa, depth + 1, out);
        self.split(b, sb, depth + 1, out);
    }
}

/// The two halves of `patch` across its longer side, each with the trim
/// segments `segs` clipped to it.
type Half = (BezierPatch, Vec<(Vec2, Vec2)>);
pub(super) fn halves(patch: &BezierPatch, segs: &[(Vec2, Vec2)]) -> (Half, Half) {
    let (a, b) = if u_extent(patch) >= v_extent(patch) {
        patch.split_u()
    } else {
        patch.split_v()
    };
    let (sa, sb) = (clip_all(segs, &rect_of(&a)), clip_all(segs, &rect_of(&b)));
    ((a, sa), (b, sb))
}

pub(super) fn centre(r: &Bounds) -> Vec2 {
    (r.lo + r.hi) * 0.5
}

/// Largest distance of the control points from the bilinear surface
/// through the corner control points, at their uniform parameters.
fn deviation(patch: &BezierPatch) -> f64 {
    let [p, q] = patch.degree;
    let at = |i: usize, j: usize| {
        (patch.pw.get(i * (q + 1) + j)).map(|c| Point3::new(c.x / c.w, c.y / c.w, c.z / c.w))
    };
    let (Some(c00), Some(c10), Some(c01), Some(c11)) = (at(0, 0), at(p, 0), at(0, q), at(p, q))
    else {
        return 0.0;
    };
    let mut worst: f64 = 0.0;
    for i in 0..=p {
        for j in 0..=q {
            let (s, t) = (i as f64 / p.max(1) as f64, j as f64 / q.max(1) as f64);
            let b = c00.coords * ((1.0 - s) * (1.0 - t))
                + c10.coords * (s * (1.0 - t))
                + c01.coords * ((1.0 - s) * t)
                + c11.coords * (s * t);
            if let Some(c) = at(i, j) {
                worst = worst.max((c.coords - b).norm());
            }
        }
    }
    worst
}

/// Length of the control net along u (the longest row of differences).
fn u_extent(patch: &BezierPatch) -> f64 {
    let [p, q] = patch.degree;
    (0..=q)
        .map(|j| {
            (0..p)
                .map(|i| (patch.point(i + 1, j) - patch.point(i, j)).norm())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// Length of the control net along v.
fn v_extent(patch: &BezierPatch) -> f64 {
    let [p, q] = patch.degree;
    (0..=p)
        .map(|i| {
            (0..q)
                .map(|j| (patch.point(i, j + 1) - patch.point(i, j)).norm())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}
