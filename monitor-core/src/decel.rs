//! Pre-collision deceleration (spec section 5): the raw `a_lon` of the last frames in a fixed
//! ring.
//!
//! The ring is written and read through `get_mut` and slice iterators only, so no index can be
//! out of bounds and the optimiser leaves no panic path in the per-frame code (heapless'
//! `HistoryBuf` indexes its storage, and its bounds checks survive optimisation).

/// The `a_lon` of the last `N` frames.
#[derive(Clone, Debug)]
pub struct DecelWindow<const N: usize> {
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
    pub const fn len(&self) -> usize {
        self.len
    }

    /// True when no value is held.
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
