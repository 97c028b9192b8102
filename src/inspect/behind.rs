//! Evaluation behind measurement: while the machine measures the next
//! feature, a second thread turns the points already measured into point
//! reports (nominal and true deviations, which need global closest-point
//! searches and cost about as much as the measuring itself).
//!
//! The points are cut into fixed chunks ([`CHUNK_POINTS`]), evaluated
//! independently (each chunk's searches start cold and then follow its
//! points) and put back in order, so the reports do not depend on which
//! thread evaluated what, nor on timing: the same inputs give the same
//! bytes. When the measuring ends, the measuring thread helps evaluate
//! what is left. Without a second thread (it cannot be started) the
//! measuring thread evaluates everything at the end.
use std::collections::VecDeque;
use std::sync::{Condvar, Mutex, MutexGuard};

use super::evaluate::point_reports;
use crate::host::modes::Measured;
use crate::program::Program;
use crate::report::PointReport;
use crate::workpiece::as_machined::AsMachined;

/// Measured points per evaluation job: small enough that both threads
/// share the last feature's points, large enough that the cold start of
/// each chunk's first search costs little.
pub const CHUNK_POINTS: usize = 32;

/// Runs `measure` (which hands over each feature's points with
/// [`Queue::submit`]) while evaluating the submitted points behind it;
/// returns `measure`'s result and the point reports of features `0..n`.
pub(super) fn measure_and_evaluate<T>(
    program: &Program,
    truth: &AsMachined,
    features: usize,
    measure: impl FnOnce(&Queue) -> T,
) -> (T, Vec<Vec<PointReport>>) {
    let queue = Queue::new(program, truth);
    let out = std::thread::scope(|s| {
        let worker = std::thread::Builder::new()
            .name("cmm-evaluate".into())
            .spawn_scoped(s, || queue.work());
        // Closed even if `measure` panics, so the worker cannot wait for
        // jobs forever while the scope waits for the worker.
        let closing = CloseOnDrop(&queue);
        let out = measure(&queue);
        drop(closing);
        queue.work();
        if let Ok(Err(panic)) = worker.map(|w| w.join()) {
            std::panic::resume_unwind(panic);
        }
        out
    });
    (out, queue.into_reports(features))
}

/// Closes the queue when dropped.
struct CloseOnDrop<'q, 'a>(&'q Queue<'a>);

impl Drop for CloseOnDrop<'_, '_> {
    fn drop(&mut self) {
        self.0.close();
    }
}

/// Evaluation jobs and their results, shared by the two threads.
pub(super) struct Queue<'a> {
    program: &'a Program,
    truth: &'a AsMachined,
    state: Mutex<State>,
    wake: Condvar,
}

#[derive(Default)]
struct State {
    jobs: VecDeque<Job>,
    done: Vec<(usize, usize, Vec<PointReport>)>,
    closed: bool,
}

/// One chunk of one feature's measured points.
struct Job {
    feature: usize,
    chunk: usize,
    faces: Vec<usize>,
    points: Vec<Measured>,
}

impl<'a> Queue<'a> {
    fn new(program: &'a Program, truth: &'a AsMachined) -> Queue<'a> {
        Queue {
            program,
            truth,
            state: Mutex::new(State::default()),
            wake: Condvar::new(),
        }
    }

    /// Hands over feature `feature`'s measured points (machine frame), to
    /// be evaluated against the nominal surfaces `faces`.
    pub(super) fn submit(&self, feature: usize, faces: &[usize], points: &[Measured]) {
        let jobs = points
            .chunks(CHUNK_POINTS)
            .enumerate()
            .map(|(chunk, c)| Job {
                feature,
                chunk,
                faces: faces.to_vec(),
                points: c.to_vec(),
            });
        self.lock().jobs.extend(jobs);
        self.wake.notify_all();
    }

    /// No more jobs will come.
    fn close(&self) {
        self.lock().closed = true;
        self.wake.notify_all();
    }

    /// Evaluates jobs until the queue is closed and empty.
    fn work(&self) {
        while let Some(job) = self.next_job() {
            let reports = point_reports(self.program, self.truth, &job.faces, &job.points);
            self.lock().done.push((job.feature, job.chunk, reports));
        }
    }

    /// The next job, waiting for one while the queue is open.
    fn next_job(&self) -> Option<Job> {
        let mut state = self.lock();
        loop {
            if let Some(job) = state.jobs.pop_front() {
                return Some(job);
            }
            if state.closed {
                return None;
            }
            state = self.wake.wait(state).unwrap_or_else(|p| p.into_inner());
        }
    }

    /// The state; a thread that panicked while holding the lock leaves it
    /// consistent (every update is a single push or flag), so a poisoned
    /// lock is used as it is.
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The reports of features `0..n`, chunks put back in order.
    fn into_reports(self, n: usize) -> Vec<Vec<PointReport>> {
        let mut done = self
            .state
            .into_inner()
            .unwrap_or_else(|p| p.into_inner())
            .done;
        done.sort_by_key(|d| (d.0, d.1));
        let mut out: Vec<Vec<PointReport>> = (0..n).map(|_| Vec::new()).collect();
        for (feature, _, reports) in done {
            if let Some(slot) = out.get_mut(feature) {
                slot.extend(reports);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Point3, Vec3};
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
            measure_and_evaluate(&program, &truth, 1, |queue| {
                queue.submit(0, &[0, 1], &points);
                panic!("measuring failed");
            })
        }));
        assert!(result.is_err());
    }

    /// Three features of 0, 70 and 45 points, evaluated behind a slow
    /// "measurement": the reports come back per feature in submission
    /// order, each equal to the report of its point evaluated alone (the
    /// chunks only change where the searches start).
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
        let (count, reports) = measure_and_evaluate(&program, &truth, 3, |queue| {
            for (i, set) in sets.iter().enumerate() {
                std::thread::sleep(std::time::Duration::from_millis(2));
                queue.submit(i, &faces, set);
            }
            sets.len()
        });
        assert_eq!(count, 3);
        assert_eq!(reports.len(), 3);
        for (set, got) in sets.iter().zip(&reports) {
            assert_eq!(set.len(), got.len());
            for (m, r) in set.iter().zip(got) {
                let want = point_reports(&program, &truth, &faces, std::slice::from_ref(m));
                let want = &want[0];
                let part = program.placement.to_part(m.point);
                assert!((Point3::from(r.measured) - part).norm() < 1e-12);
                assert!((r.deviation_mm - want.deviation_mm).abs() < 1e-10);
                assert!((r.true_deviation_mm - want.true_deviation_mm).abs() < 1e-10);
            }
        }
    }
}
