//! Chunked reductions over large point sets on all cores. Chunks have a
//! fixed size and partial results come back in chunk order, so sums do not
//! depend on the number of threads (results are reproducible everywhere).

use std::sync::OnceLock;

/// Items per chunk.
const CHUNK: usize = 1 << 14;
/// Below this many items everything runs on the calling thread.
const PARALLEL_MIN: usize = 1 << 16;

/// Worker threads for large sets, asked once per process:
/// `available_parallelism` reads the affinity mask and the cgroup quota
/// files (several system calls, tens of microseconds), far more than a
/// small fit's reduction takes.
fn threads() -> usize {
    static THREADS: OnceLock<usize> = OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get().min(16)))
}

/// `f` applied to consecutive chunks of `items`, results in chunk order.
pub(crate) fn map_chunks<T, R, F>(items: &[T], f: F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&[T]) -> R + Sync,
{
    let chunks: Vec<&[T]> = items.chunks(CHUNK).collect();
    if items.len() < PARALLEL_MIN || threads() < 2 {
        return chunks.into_iter().map(&f).collect();
    }
    let workers = threads();
    let per = chunks.len().div_ceil(workers).max(1);
    let f = &f;
    std::thread::scope(|s| {
        let handles: Vec<_> = chunks
            .chunks(per)
            .map(|group| s.spawn(move || group.iter().map(|c| f(c)).collect::<Vec<R>>()))
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    })
}
