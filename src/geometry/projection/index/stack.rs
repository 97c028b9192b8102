//! A depth-first stack that lives on the call stack: the trees are
//! shallow (median splits), so a search needs no heap allocation.

/// Entries held without allocating; a deeper search (not reached by a
/// median-split tree of fewer than 2^40 leaves) spills to the heap.
const INLINE: usize = 48;

/// A stack of `(squared box distance, node)` pairs.
pub(super) struct NodeStack {
    inline: [(f64, usize); INLINE],
    len: usize,
    spill: Vec<(f64, usize)>,
}

impl NodeStack {
    /// An empty stack.
    pub(super) fn new() -> NodeStack {
        NodeStack {
            inline: [(0.0, 0); INLINE],
            len: 0,
            spill: Vec::new(),
        }
    }

    /// Pushes an entry.
    #[inline]
    pub(super) fn push(&mut self, entry: (f64, usize)) {
        match self.inline.get_mut(self.len) {
            Some(slot) if self.spill.is_empty() => {
                *slot = entry;
                self.len += 1;
            }
            _ => self.spill.push(entry),
        }
    }

    /// Pops the last entry pushed.
    #[inline]
    pub(super) fn pop(&mut self) -> Option<(f64, usize)> {
        if let Some(e) = self.spill.pop() {
            return Some(e);
        }
        self.len = self.len.checked_sub(1)?;
        self.inline.get(self.len).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pushes past the inline part come back in reverse order.
    #[test]
    fn last_in_first_out_past_the_inline_part() {
        let mut s = NodeStack::new();
        for k in 0..3 * INLINE {
            s.push((k as f64, k));
        }
        for k in (0..3 * INLINE).rev() {
            assert_eq!(s.pop(), Some((k as f64, k)));
        }
        assert_eq!(s.pop(), None);
        s.push((1.0, 1));
        assert_eq!(s.pop(), Some((1.0, 1)));
    }
}
