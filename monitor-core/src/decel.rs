//! Pre-collision deceleration (spec section 5): the raw `a_lon` of the last frames in a
//! `heapless` ring.

use heapless::HistoryBuf;

/// The `a_lon` of the last `N` frames, newest last.
#[derive(Clone, Debug)]
pub struct DecelWindow<const N: usize> {
    history: HistoryBuf<f32, N>,
}

impl<const N: usize> DecelWindow<N> {
    /// An empty window.
    pub const fn new() -> Self {
        DecelWindow {
            history: HistoryBuf::new(),
        }
    }

    /// Records the `a_lon` of the frame just seen.
    pub fn push(&mut self, a_lon: f32) {
        self.history.write(a_lon);
    }

    /// True iff one of the last `window` recorded frames has `a_lon <= threshold`.
    /// Empty (the route's first frame): false.
    pub fn decelerated(&self, window: usize, threshold: f32) -> bool {
        let skip = self.history.len().saturating_sub(window);
        self.history
            .oldest_ordered()
            .skip(skip)
            .any(|&a| a <= threshold)
    }

    /// Forgets every frame.
    pub fn clear(&mut self) {
        self.history.clear();
    }
}

impl<const N: usize> Default for DecelWindow<N> {
    fn default() -> Self {
        Self::new()
    }
}
