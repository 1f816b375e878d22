//! Pre-collision deceleration (docs/SCORE.md §6): the raw `a_lon` of the last frames in a fixed
//! ring.
//!
//! The ring is written and read through `get_mut` and slice iterators only, so no index can be
//! out of bounds and the optimiser leaves no panic path in the per-frame code (heapless'
//! `HistoryBuf` indexes its storage, and its bounds checks survive optimisation).

/// The `a_lon` of the last `N` frames.
#[derive(Clone, Debug)]
pub(crate) struct DecelWindow<const N: usize> {
    /// Ring storage: `data[..next]` holds the newest values (newest last), `data[next..]` the
    /// older ones once the ring has wrapped.
    data: [f32; N],
    /// Slot written next, in `0..N` (0 when `N` is 0).
    next: usize,
    /// Values held, at most `N`.
    len: usize,
}

impl<const N: usize> DecelWindow<N> {
    /// An empty window.
    pub const fn new() -> Self {
        DecelWindow {
            data: [0.0; N],
            next: 0,
            len: 0,
        }
    }

    /// Records the `a_lon` of the frame just seen (the oldest value drops out when full).
    pub fn push(&mut self, a_lon: f32) {
        if let Some(slot) = self.data.get_mut(self.next) {
            *slot = a_lon;
            let n = self.next.wrapping_add(1);
            self.next = if n >= N { 0 } else { n };
            if self.len < N {
                self.len = self.len.wrapping_add(1);
            }
        }
    }

    /// Values held (at most `N`).
    #[cfg(test)]
    pub const fn len(&self) -> usize {
        self.len
    }

    /// True when no value is held.
    #[cfg(test)]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// True iff one of the last `window` recorded frames has `a_lon <= threshold`.
    /// Empty (the route's first frame): false.
    pub fn decelerated(&self, window: usize, threshold: f32) -> bool {
        let k = if window < self.len { window } else { self.len };
        let (newer, older) = match self.data.split_at_checked(self.next) {
            Some((head, tail)) => (head, tail),
            None => (&[][..], &[][..]),
        };
        // Newest first: the `k` newest are the end of `newer`, then (if the ring has wrapped)
        // the end of `older`. Before the first wrap `len == next`, so `k <= newer.len()` and
        // the unwritten slots of `older` are never read.
        let rest = k.saturating_sub(newer.len());
        newer
            .iter()
            .rev()
            .take(k)
            .chain(older.iter().rev().take(rest))
            .any(|&a| a <= threshold)
    }

    /// Forgets every frame.
    pub fn clear(&mut self) {
        self.next = 0;
        self.len = 0;
    }
}

impl<const N: usize> Default for DecelWindow<N> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ring_by_hand() {
        // Capacity 4; threshold +1.0 so that the ring's unwritten zeros would count if read.
        let mut w: DecelWindow<4> = DecelWindow::new();
        assert!(w.is_empty());
        assert!(!w.decelerated(4, 1.0));
        // Push 5, 6, 0.5: values (oldest..newest) [5, 6, 0.5]; 0.5 <= 1 is the newest.
        for a in [5.0, 6.0, 0.5] {
            w.push(a);
        }
        assert_eq!(w.len(), 3);
        assert!(w.decelerated(1, 1.0));
        assert!(!w.decelerated(0, 1.0));
        // Push 7, 8: the ring wraps; values [6, 0.5, 7, 8]: 0.5 is the 3rd newest.
        w.push(7.0);
        w.push(8.0);
        assert_eq!(w.len(), 4);
        assert!(!w.decelerated(2, 1.0));
        assert!(w.decelerated(3, 1.0));
        assert!(w.decelerated(100, 1.0)); // a window beyond the capacity is the whole ring
                                          // Push 9, 9, 9: 0.5 drops out ([8, 9, 9, 9]).
        for _ in 0..3 {
            w.push(9.0);
        }
        assert!(!w.decelerated(4, 1.0));
        assert!(w.decelerated(4, 8.0)); // 8 is the oldest, 4th newest
        assert!(!w.decelerated(3, 8.0));
        w.clear();
        assert!(w.is_empty() && !w.decelerated(4, 100.0));
        // Capacity 0: pushing is a no-op, never decelerated.
        let mut z: DecelWindow<0> = DecelWindow::new();
        z.push(-5.0);
        assert!(z.is_empty() && !z.decelerated(1, 0.0));
    }
}
