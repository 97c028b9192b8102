//! Evaluation behind measurement: while the machine measures, a second
//! thread turns the points already measured into point reports (nominal
//! and true deviations, which need global closest-point searches and cost
//! about a third of the measuring itself).
//!
//! Points come in *streams*: a design-value scan hands over its points
//! while it runs ([`super::live`]), and whatever else a feature measured
//! comes as one stream when the feature ends. A stream is cut into fixed
//! chunks ([`CHUNK_POINTS`]) in the order its points were taken; each
//! chunk is evaluated on its own (its searches start cold, then follow its
//! points) and the chunks are put back in order, so the reports depend
//! neither on which thread evaluated what nor on timing: the same inputs
//! give the same bytes. A failed attempt's stream is discarded. When the
//! measuring ends, the measuring thread helps evaluate what is left.
//! Without a second thread (it cannot be started) the measuring thread
//! evaluates everything at the end.
use std::borrow::Cow;
use std::collections::{BTreeMap, VecDeque};
use std::sync::{Barrier, Condvar, Mutex, MutexGuard, OnceLock};
use std::time::Instant;

use super::evaluate::point_reports;
use super::LivePoints;
use crate::host::modes::Measured;
use crate::program::Program;
use crate::report::PointReport;
use crate::workpiece::as_machined::AsMachined;

/// Measured points per evaluation job: small enough that both threads
/// share the last points, large enough that the cold start of each
/// chunk's first search costs little.
pub const CHUNK_POINTS: usize = 32;

/// The program whose points the evaluation evaluates, set once the
/// measuring knows it (an alignment moves its placement), before the
/// first points are handed over.
pub(super) type ProgramSlot<'p> = OnceLock<Cow<'p, Program>>;

/// Runs `measure` (which hands over points with [`Queue::submit`] and
/// the [`LivePoints`] streams) while evaluating them behind it; returns
/// `measure`'s result and the point reports of every stream.
#[cfg(test)]
pub(super) fn measure_and_evaluate<T>(
    program: &Program,
    truth: &AsMachined,
    measure: impl FnOnce(&Queue) -> T,
) -> (T, Streams) {
    let slot = ProgramSlot::from(Cow::Borrowed(program));
    let (out, streams, _) = evaluate_behind(&slot, truth, measure);
    (out, streams)
}

/// [`measure_and_evaluate`] for the program that `measure` sets in `slot`
/// before it hands over points. The evaluation thread is running before
/// `measure` is called, so a clock `measure` starts leaves out the
/// thread's start. Points handed over while `slot` is empty get no
/// reports. Also returns when the last report was in, before the
/// evaluation thread is joined (its exit is no part of the evaluation).
pub(super) fn evaluate_behind<'p, T>(
    slot: &ProgramSlot<'p>,
    truth: &AsMachined,
    measure: impl FnOnce(&Queue) -> T,
) -> (T, Streams, Instant) {
    let queue = Queue::new(slot, truth);
    let started = Barrier::new(2);
    let out = std::thread::scope(|s| {
        let worker = std::thread::Builder::new()
            .name("cmm-evaluate".into())
            .spawn_scoped(s, || {
                started.wait();
                queue.work();
            });
        if worker.is_ok() {
            started.wait();
        }
        // Closed even if `measure` panics, so the worker cannot wait for
        // jobs forever while the scope waits for the worker.
        let closing = CloseOnDrop(&queue);
        let out = measure(&queue);
        drop(closing);
        queue.work();
        let done_at = queue.all_done();
        if let Ok(Err(panic)) = worker.map(|w| w.join()) {
            std::panic::resume_unwind(panic);
        }
        (out, done_at)
    });
    (out.0, queue.into_streams(), out.1)
}

/// The point reports of each kept stream, by stream id.
#[derive(Debug, Default)]
pub(super) struct Streams(BTreeMap<usize, Vec<PointReport>>);

impl Streams {
    /// The reports of `streams` one after the other.
    pub(super) fn concat(&mut self, streams: &[usize]) -> Vec<PointReport> {
        (streams.iter())
            .flat_map(|s| self.0.remove(s).unwrap_or_default())
            .collect()
    }
}

/// Closes the queue when dropped.
struct CloseOnDrop<'q, 'a, 'p>(&'q Queue<'a, 'p>);

impl Drop for CloseOnDrop<'_, '_, '_> {
    fn drop(&mut self) {
        self.0.close();
    }
}

/// Evaluation jobs and their results, shared by the two threads.
pub(super) struct Queue<'a, 'p> {
    program: &'a ProgramSlot<'p>,
    truth: &'a AsMachined,
    state: Mutex<State>,
    wake: Condvar,
}

#[derive(Default)]
struct State {
    jobs: VecDeque<Job>,
    /// Nominal faces of each stream opened so far (index = stream id).
    faces: Vec<Vec<usize>>,
    /// Streams whose points are not wanted.
    discarded: Vec<usize>,
    done: Vec<(usize, usize, Vec<PointReport>)>,
    /// Jobs taken and not yet done.
    busy: usize,
    closed: bool,
}

/// A job being evaluated: counted in [`State::busy`] until dropped (also
/// when the evaluation panics, so that [`Queue::all_done`] cannot wait
/// for it forever).
struct Busy<'q, 'a, 'p>(&'q Queue<'a, 'p>);

impl Drop for Busy<'_, '_, '_> {
    fn drop(&mut self) {
        let mut state = self.0.lock();
        state.busy = state.busy.saturating_sub(1);
        let idle = state.closed && state.busy == 0;
        drop(state);
        if idle {
            self.0.wake.notify_all();
        }
    }
}

/// One chunk of one stream.
struct Job {
    stream: usize,
    chunk: usize,
    faces: Vec<usize>,
    points: Vec<Measured>,
}

impl<'a, 'p> Queue<'a, 'p> {
    fn new(program: &'a ProgramSlot<'p>, truth: &'a AsMachined) -> Queue<'a, 'p> {
        Queue {
            program,
            truth,
            state: Mutex::new(State::default()),
            wake: Condvar::new(),
        }
    }

    /// Hands over `points` (machine frame) as one new stream evaluated
    /// against the nominal faces `faces`; returns its id.
    pub(super) fn submit(&self, faces: &[usize], points: &[Measured]) -> usize {
        let stream = self.open(faces);
        for (chunk, c) in points.chunks(CHUNK_POINTS).enumerate() {
            self.push(stream, chunk, c.to_vec());
        }
        stream
    }

    /// No more jobs will come.
    fn close(&self) {
        self.lock().closed = true;
        self.wake.notify_all();
    }

    /// Evaluates jobs until the queue is closed and empty.
    fn work(&self) {
        while let Some(job) = self.next_job() {
            let _busy = Busy(self);
            let reports = self.program.get().map_or(Vec::new(), |program| {
                point_reports(program, self.truth, &job.faces, &job.points)
            });
            self.lock().done.push((job.stream, job.chunk, reports));
        }
    }

    /// The next job, waiting for one while the queue is open.
    fn next_job(&self) -> Option<Job> {
        let mut state = self.lock();
        loop {
            if let Some(job) = state.jobs.pop_front() {
                state.busy += 1;
                return Some(job);
            }
            if state.closed {
                return None;
            }
            state = self.wake.wait(state).unwrap_or_else(|p| p.into_inner());
        }
    }

    /// Waits until no job is being evaluated (once the queue is closed
    /// and empty, every report is then in); returns when.
    fn all_done(&self) -> Instant {
        let mut state = self.lock();
        while state.busy > 0 {
            state = self.wake.wait(state).unwrap_or_else(|p| p.into_inner());
        }
        Instant::now()
    }

    /// The state; a thread that panicked while holding the lock leaves it
    /// consistent (every update is a single push, retain or flag), so a
    /// poisoned lock is used as it is.
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The reports of every stream not discarded, chunks put back in order.
    fn into_streams(self) -> Streams {
        let state = self.state.into_inner().unwrap_or_else(|p| p.into_inner());
        let mut done = state.done;
        done.sort_by_key(|d| (d.0, d.1));
        let mut out = Streams::default();
        for (stream, _, reports) in done {
            if !state.discarded.contains(&stream) {
                out.0.entry(stream).or_default().extend(reports);
            }
        }
        out
    }
}

impl LivePoints for Queue<'_, '_> {
    fn open(&self, faces: &[usize]) -> usize {
        let mut state = self.lock();
        state.faces.push(faces.to_vec());
        state.faces.len() - 1
    }

    fn push(&self, stream: usize, chunk: usize, points: Vec<Measured>) {
        // Without a program there is nothing to evaluate against (and
        // whether a job would find one later depends on timing).
        if self.program.get().is_none() {
            return;
        }
        let mut state = self.lock();
        let faces = state.faces.get(stream).cloned().unwrap_or_default();
        state.jobs.push_back(Job {
            stream,
            chunk,
            faces,
            points,
        });
        drop(state);
        self.wake.notify_all();
    }

    fn discard(&self, stream: usize) {
        let mut state = self.lock();
        state.jobs.retain(|j| j.stream != stream);
        state.discarded.push(stream);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Point3, Vec3};
    use crate::program::Pose;
    use std::path::Path;

    fn blade_z60() -> Program {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("part-programs/blade-z60.json");
        match crate::program::load(&file) {
            Ok(p) => p,
            Err(e) => panic!("{e}"),
        }
    }

    /// Points off the blade's surfaces (machine frame) along a line over
    /// each face, as a feature's measured points come.
    fn measured_points(program: &Program, n: usize) -> Vec<Measured> {
        let face = |k: usize| &program.workpiece.faces[k % program.workpiece.faces.len()];
        (0..n)
            .map(|k| {
                let s = &face(k).surface;
                let ((u0, u1), (v0, v1)) = s.domain();
                let t = (k as f64 + 0.5) / n as f64;
                let (u, v) = (u0 + (u1 - u0) * t, 0.5 * (v0 + v1));
                let off = 0.01 * ((k % 7) as f64 - 3.0);
                let p = program
                    .placement
                    .to_machine(s.point(u, v) + s.normal(u, v) * off);
                Measured {
                    point: p,
                    normal: Vec3::z(),
                    ball: p,
                    scales: p,
                    reading: Vec3::zeros(),
                    motion: Vec3::zeros(),
                }
            })
            .collect()
    }

    /// A measurement that panics after handing over points ends the
    /// evaluation thread too: the panic comes through instead of a hang.
    #[test]
    fn a_panicking_measurement_does_not_hang() {
        let program = blade_z60();
        let truth = program.as_machined.clone();
        let points = measured_points(&program, 40);
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            measure_and_evaluate(&program, &truth, |queue| {
                queue.submit(&[0, 1], &points);
                panic!("measuring failed");
            })
        }));
        assert!(result.is_err());
    }

    /// Streams of 0, 70 and 45 points, evaluated behind a slow
    /// "measurement", the second one pushed live chunk by chunk, and a
    /// discarded stream between them: each kept stream's reports come back
    /// in measuring order, each equal to the report of its point evaluated
    /// alone (the chunks only change where the searches start), and the
    /// discarded one's do not come back.
    #[test]
    fn reports_come_back_in_order_and_equal_lone_evaluations() {
        let program = blade_z60();
        let truth = program.as_machined.clone().without_roughness();
        let faces: Vec<usize> = (0..program.workpiece.faces.len()).collect();
        let sets = [
            Vec::new(),
            measured_points(&program, 70),
            measured_points(&program, 45),
        ];
        let (ids, mut streams) = measure_and_evaluate(&program, &truth, |queue| {
            let first = queue.submit(&faces, &sets[0]);
            let live = queue.open(&faces);
            let dropped = queue.submit(&faces, &sets[2]);
            queue.discard(dropped);
            for (k, chunk) in sets[1].chunks(CHUNK_POINTS).enumerate() {
                std::thread::sleep(std::time::Duration::from_millis(2));
                queue.push(live, k, chunk.to_vec());
            }
            let last = queue.submit(&faces, &sets[2]);
            [first, live, dropped, last]
        });
        assert!(streams.concat(&[ids[2]]).is_empty(), "discarded stream");
        for (set, id) in sets.iter().zip([ids[0], ids[1], ids[3]]) {
            let got = streams.concat(&[id]);
            assert_eq!(set.len(), got.len());
            for (m, r) in set.iter().zip(&got) {
                let want = point_reports(&program, &truth, &faces, std::slice::from_ref(m));
                let want = &want[0];
                let part = program.placement.to_part(m.point);
                assert!((Point3::from(r.measured) - part).norm() < 1e-12);
                assert!((r.deviation_mm - want.deviation_mm).abs() < 1e-10);
                assert!((r.true_deviation_mm - want.true_deviation_mm).abs() < 1e-10);
            }
        }
    }

    /// The program evaluated is the one the measuring sets in the slot
    /// (as an alignment does, with a moved placement), not one known at
    /// the start: the reports are those of the moved program, each equal
    /// to its point evaluated alone against it; points handed over
    /// before it is set get no reports.
    #[test]
    fn points_are_evaluated_against_the_program_set_while_measuring() {
        let nominal = blade_z60();
        let truth = nominal.as_machined.clone().without_roughness();
        let moved = Program {
            placement: Pose {
                translation: nominal.placement.translation + Vec3::new(0.3, -0.2, 0.1),
                ..nominal.placement
            },
            ..nominal.clone()
        };
        let faces: Vec<usize> = (0..nominal.workpiece.faces.len()).collect();
        let points = measured_points(&moved, 40);
        let slot = ProgramSlot::new();
        let (ids, mut streams, _) = evaluate_behind(&slot, &truth, |queue| {
            let early = queue.submit(&faces, &points[..3]);
            let _ = slot.set(Cow::Borrowed(&moved));
            [early, queue.submit(&faces, &points)]
        });
        assert!(streams.concat(&[ids[0]]).is_empty(), "before the program");
        let got = streams.concat(&[ids[1]]);
        let want = point_reports(&moved, &truth, &faces, &points);
        assert_eq!(got.len(), points.len());
        for (m, (r, w)) in points.iter().zip(got.iter().zip(&want)) {
            let part = moved.placement.to_part(m.point);
            assert!((Point3::from(r.measured) - part).norm() < 1e-12);
            assert!((r.deviation_mm - w.deviation_mm).abs() < 1e-10);
            assert!((r.deviation_mm.abs()) < 0.05, "{}", r.deviation_mm);
        }
    }
}
