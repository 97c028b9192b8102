//! Free-space answers remembered across the runs of one program: a
//! batch measures many as-machined variants of one design with the same
//! probe, and the routes and postures it checks against the design data
//! are mostly the same from part to part. An answer is a pure function of
//! the design, the placement, the probe and the query, so a remembered
//! answer is the one the check would give (bit for bit: the keys are the
//! inputs' bits), and reports do not depend on what was remembered.
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::PartClearance;
use crate::host::modes::FreeSpace;
use crate::math::{Point3, Vec3};
use crate::seam::ProbePart;

/// One question to the free-space check, by the bits of its inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Query {
    /// A straight move of the ball centre, with the full or tight margin.
    Segment {
        from: [u64; 3],
        to: [u64; 3],
        tight: bool,
    },
    /// The probe standing with its ball centre here.
    Posture([u64; 3]),
    /// The probe body alone standing with the ball centre here.
    Body([u64; 3]),
    /// An approach starting with the ball centre here.
    Start([u64; 3]),
    /// An approach's measuring move of the ball centre (no margin).
    Approach { from: [u64; 3], to: [u64; 3] },
}

/// A remembered answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Answer {
    Clear(bool),
    Strikes(Option<ProbePart>),
}

/// Answers by the setting's bits, then by the query.
type Table = HashMap<Vec<u64>, HashMap<Query, Answer>>;

/// The answers of each free-space setting (placement, probe and margins,
/// by their bits), shared between threads.
#[derive(Debug, Clone, Default)]
pub struct FreeSpaceMemo {
    table: Arc<Mutex<Table>>,
}

impl FreeSpaceMemo {
    /// Number of answers remembered.
    pub fn len(&self) -> usize {
        (self.table.lock()).map_or(0, |t| t.values().map(HashMap::len).sum())
    }

    /// Whether nothing is remembered yet.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A free-space check that asks `inner` only what `memo` does not know,
/// and that keeps the way its part's probe came in
/// ([`FreeSpace::way_in`]).
pub struct Remembering<'a> {
    inner: &'a PartClearance<'a>,
    setting: Vec<u64>,
    memo: &'a FreeSpaceMemo,
    way: RefCell<Vec<Point3>>,
}

/// Ball centres of the way in that are kept (the latest).
const WAY_POINTS: usize = 32;

impl<'a> Remembering<'a> {
    /// `inner`, remembering its answers in `memo`.
    pub fn new(inner: &'a PartClearance<'a>, memo: &'a FreeSpaceMemo) -> Remembering<'a> {
        Remembering {
            setting: setting_bits(inner),
            inner,
            memo,
            way: RefCell::new(Vec::new()),
        }
    }

    /// The remembered answer to `q`, else `ask`'s (then remembered).
    fn answer(&self, q: Query, ask: impl FnOnce() -> Answer) -> Answer {
        let setting = self.setting.as_slice();
        let known = |t: &Table| t.get(setting).and_then(|m| m.get(&q)).copied();
        if let Some(a) = self.memo.table.lock().ok().and_then(|t| known(&t)) {
            return a;
        }
        let a = ask();
        if let Ok(mut t) = self.memo.table.lock() {
            match t.get_mut(setting) {
                Some(m) => {
                    m.insert(q, a);
                }
                None => {
                    t.insert(self.setting.clone(), HashMap::from([(q, a)]));
                }
            }
        }
        a
    }
}

fn bits(p: Point3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

impl FreeSpace for Remembering<'_> {
    fn segment_clear(&self, from: Point3, to: Point3) -> bool {
        self.segment_clear_with(from, to, false)
    }

    fn margin_mm(&self) -> Option<f64> {
        self.inner.margin_mm()
    }

    fn approach_clear(&self, from: Point3, to: Point3) -> bool {
        let q = Query::Approach {
            from: bits(from),
            to: bits(to),
        };
        let a = self.answer(q, || Answer::Clear(self.inner.approach_clear(from, to)));
        a == Answer::Clear(true)
    }

    fn segment_clear_with(&self, from: Point3, to: Point3, tight: bool) -> bool {
        let q = Query::Segment {
            from: bits(from),
            to: bits(to),
            tight,
        };
        let a = self.answer(q, || {
            Answer::Clear(self.inner.segment_clear_with(from, to, tight))
        });
        a == Answer::Clear(true)
    }

    fn start_clear(&self, at: Point3) -> bool {
        let a = self.answer(Query::Start(bits(at)), || {
            Answer::Clear(self.inner.start_clear(at))
        });
        a == Answer::Clear(true)
    }

    fn in_material(&self, p: Point3) -> bool {
        self.inner.in_material(p)
    }

    fn design_foot(&self, p: Point3) -> Option<(f64, Vec3)> {
        self.inner.design_foot(p)
    }

    fn note_way(&self, from: Point3, waypoints: &[Point3]) {
        let mut way = self.way.borrow_mut();
        for &p in std::iter::once(&from).chain(waypoints) {
            if way.last().is_none_or(|&l| (l - p).norm() > 1e-9) {
                way.push(p);
            }
        }
        let extra = way.len().saturating_sub(WAY_POINTS);
        way.drain(..extra);
    }

    fn way_in(&self) -> Vec<Point3> {
        self.way.borrow().clone()
    }

    fn body_clear(&self, ball: Point3) -> bool {
        let a = self.answer(Query::Body(bits(ball)), || {
            Answer::Clear(FreeSpace::body_clear(self.inner, ball))
        });
        a == Answer::Clear(true)
    }

    fn posture(&self, ball: Point3) -> Option<ProbePart> {
        let a = self.answer(Query::Posture(bits(ball)), || {
            Answer::Strikes(self.inner.posture(ball))
        });
        match a {
            Answer::Strikes(s) => s,
            Answer::Clear(_) => None,
        }
    }
}

/// The bits of everything but the design data that `c`'s answers depend
/// on: placement, probe and margins.
fn setting_bits(c: &PartClearance<'_>) -> Vec<u64> {
    let (r, t) = (c.pose.rotation, c.pose.translation);
    let body = c.body.map_or([f64::NAN; 2], |b| [b.radius_mm, b.length_mm]);
    let o = &c.opts;
    (r.iter().chain(t.iter()).chain(c.stylus.iter()))
        .copied()
        .chain([c.tip_radius_mm, c.shaft_radius_mm])
        .chain(body)
        .chain([
            o.margin_mm,
            o.step_mm,
            o.tight_margin_mm,
            o.posture_margin_mm,
            o.start_room_mm,
        ])
        .map(f64::to_bits)
        .collect()
}
