//! A design-value scan's points handed over for evaluation while the scan
//! runs: the machine seen through [`LiveCmm`] passes every point the scan
//! takes ([`Cmm::note_point`]) on to a [`LivePoints`] stream in chunks of
//! [`CHUNK_POINTS`].
use super::behind::CHUNK_POINTS;
use super::LivePoints;
use crate::host::machine::{Cmm, HeadCommandError, Phase, Readings};
use crate::host::modes::Measured;
use crate::math::Vec3;

/// The machine, with the points noted on it streamed to `live`.
pub(super) struct LiveCmm<'c> {
    inner: &'c mut dyn Cmm,
    live: &'c dyn LivePoints,
    stream: usize,
    /// Points noted and not yet handed over (less than a chunk).
    pending: Vec<Measured>,
    /// Every point noted, in order.
    noted: Vec<Measured>,
    /// Chunks handed over.
    chunks: usize,
}

impl<'c> LiveCmm<'c> {
    /// Opens a stream evaluated against `faces` on `live`.
    pub(super) fn new(
        inner: &'c mut dyn Cmm,
        live: &'c dyn LivePoints,
        faces: &[usize],
    ) -> LiveCmm<'c> {
        LiveCmm {
            stream: live.open(faces),
            inner,
            live,
            pending: Vec::with_capacity(CHUNK_POINTS),
            noted: Vec::new(),
            chunks: 0,
        }
    }

    /// Ends the stream: its id when `result` (the attempt's points, `None`
    /// when the attempt failed) are exactly the points streamed, else the
    /// stream is discarded.
    pub(super) fn finish(mut self, result: Option<&[Measured]>) -> Option<usize> {
        if result.is_some_and(|r| r == self.noted.as_slice()) {
            self.hand_over();
            return Some(self.stream);
        }
        self.live.discard(self.stream);
        None
    }

    fn hand_over(&mut self) {
        if !self.pending.is_empty() {
            let chunk = std::mem::replace(&mut self.pending, Vec::with_capacity(CHUNK_POINTS));
            self.live.push(self.stream, self.chunks, chunk);
            self.chunks += 1;
        }
    }
}

impl Cmm for LiveCmm<'_> {
    fn cycle_s(&self) -> f64 {
        self.inner.cycle_s()
    }

    fn readings(&self) -> Readings {
        self.inner.readings()
    }

    fn step(&mut self, velocity: Vec3) -> Readings {
        self.inner.step(velocity)
    }

    fn note_trajectory_error(&mut self, dl_mm: f64) {
        self.inner.note_trajectory_error(dl_mm);
    }

    fn note_phase(&mut self, phase: Phase) {
        self.inner.note_phase(phase);
    }

    fn note_point(&mut self, point: &Measured) {
        self.inner.note_point(point);
        self.noted.push(*point);
        self.pending.push(*point);
        if self.pending.len() >= CHUNK_POINTS {
            self.hand_over();
        }
    }

    fn head_axes(&self) -> usize {
        self.inner.head_axes()
    }

    fn index_head(&mut self, angles_rad: &[f64]) -> Result<Vec<f64>, HeadCommandError> {
        self.inner.index_head(angles_rad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::host::machine::MachineStatus;
    use crate::math::Point3;
    use std::sync::Mutex;

    /// A machine that stands still.
    struct Still;

    impl Cmm for Still {
        fn cycle_s(&self) -> f64 {
            0.001
        }
        fn readings(&self) -> Readings {
            Readings {
                time_s: 0.0,
                scales: Point3::origin(),
                deflection: Vec3::zeros(),
                status: MachineStatus::Ok,
            }
        }
        fn step(&mut self, _velocity: Vec3) -> Readings {
            self.readings()
        }
    }

    /// Records what it is handed.
    #[derive(Default)]
    struct Recorder {
        opened: Mutex<Vec<Vec<usize>>>,
        chunks: Mutex<Vec<(usize, usize, Vec<Measured>)>>,
        discarded: Mutex<Vec<usize>>,
    }

    impl LivePoints for Recorder {
        fn open(&self, faces: &[usize]) -> usize {
            let mut o = self.opened.lock().unwrap_or_else(|p| p.into_inner());
            o.push(faces.to_vec());
            o.len() - 1
        }
        fn push(&self, stream: usize, chunk: usize, points: Vec<Measured>) {
            let mut c = self.chunks.lock().unwrap_or_else(|p| p.into_inner());
            c.push((stream, chunk, points));
        }
        fn discard(&self, stream: usize) {
            let mut d = self.discarded.lock().unwrap_or_else(|p| p.into_inner());
            d.push(stream);
        }
    }

    fn point(k: usize) -> Measured {
        let p = Point3::new(k as f64, 0.0, 0.0);
        Measured {
            point: p,
            normal: Vec3::z(),
            ball: p,
            scales: p,
            reading: Vec3::zeros(),
            motion: Vec3::zeros(),
        }
    }

    /// Notes `n` points on a fresh stream and finishes it with `result`.
    fn stream(rec: &Recorder, n: usize, result: Option<&[Measured]>) -> Option<usize> {
        let mut machine = Still;
        let mut live = LiveCmm::new(&mut machine, rec, &[1, 2]);
        for k in 0..n {
            live.note_point(&point(k));
        }
        live.finish(result)
    }

    #[test]
    fn chunks_go_out_while_noting_and_the_rest_when_kept() {
        let rec = Recorder::default();
        let points: Vec<Measured> = (0..70).map(point).collect();
        assert_eq!(stream(&rec, 70, Some(&points)), Some(0));
        let chunks = rec.chunks.lock().unwrap_or_else(|p| p.into_inner());
        let sizes: Vec<(usize, usize, usize)> =
            chunks.iter().map(|c| (c.0, c.1, c.2.len())).collect();
        assert_eq!(sizes, [(0, 0, 32), (0, 1, 32), (0, 2, 6)]);
        let streamed: Vec<Measured> = chunks.iter().flat_map(|c| c.2.clone()).collect();
        assert_eq!(streamed, points);
        assert_eq!(
            *rec.opened.lock().unwrap_or_else(|p| p.into_inner()),
            [vec![1, 2]]
        );
        assert!(rec
            .discarded
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .is_empty());
    }

    #[test]
    fn a_failed_or_different_result_discards_the_stream() {
        let rec = Recorder::default();
        let points: Vec<Measured> = (0..40).map(point).collect();
        assert_eq!(stream(&rec, 40, None), None);
        assert_eq!(stream(&rec, 40, Some(&points[1..])), None);
        assert_eq!(stream(&rec, 40, Some(&points)), Some(2));
        assert_eq!(
            *rec.discarded.lock().unwrap_or_else(|p| p.into_inner()),
            [0, 1]
        );
    }
}
