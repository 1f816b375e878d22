//! Frames read by their layout: the bytes of a frame around its numbers, learned from a frame
//! the scanner read token by token, and compared (not scanned) in the frames after it.
//!
//! Bench2Drive writes every frame with the same keys in the same order and the same
//! indentation (`json.dump(indent=4)`), so a frame is `seps[0] num seps[1] num ... seps[n]`
//! with the same separators each time: the next frame is read by comparing its bytes between
//! numbers with the learned ones, eight at a time, and reading only its numbers (`number.rs`;
//! the reading itself is `Cursor::frame_by` in `scan.rs`, this file the layout).
//!
//! Why that gives what token-by-token reading gives: token by token, what the scanner does with
//! the bytes between two numbers depends only on those bytes and on where it is in the frame,
//! and a number token ends at the first byte that cannot continue it (every separator starts
//! with such a byte: `,`, `]`, `}` or whitespace). So a frame whose numbers are number tokens
//! and whose bytes between them equal the learned ones is read by the token-by-token scanner
//! in the same steps, into the same roles. Anything else (another key, order, indentation,
//! count of numbers, a token that is not a number) fails a comparison; that frame is read
//! token by token, and its layout learned in turn.

/// What a number in a frame is for.
#[derive(Clone, Copy)]
pub(super) enum Role {
    /// Component `comp` of required vector `field`, converted.
    Keep {
        /// Index in `TelemetryFrame::FIELDS` (< 5).
        field: u8,
        /// Component (< 3).
        comp: u8,
    },
    /// A required vector's component that is only checked to be finite.
    Finite,
    /// A number of another field, checked only.
    Other,
}

/// One number token of a frame read token by token: its extent and its role.
#[derive(Clone, Copy)]
pub(super) struct Mark {
    pub(super) start: usize,
    pub(super) end: usize,
    pub(super) role: Role,
}

/// A learned layout: the separators and the role of each number between them.
#[derive(Default)]
pub(super) struct Layout {
    /// The separators one after another.
    bytes: Vec<u8>,
    /// Each number: the separator before it, and its role.
    pub(super) steps: Vec<(Sep, Role)>,
    /// The separator after the last number (`None` until a layout is learned).
    pub(super) last: Option<Sep>,
}

/// Where a separator lies in [`Layout::bytes`].
#[derive(Clone, Copy)]
pub(super) struct Sep {
    /// Offset in `bytes`.
    at: usize,
    /// Its length.
    pub(super) len: usize,
}

impl Layout {
    /// The layout of the frame at `b[start..end]` whose numbers are `marks`.
    pub(super) fn learn(&mut self, b: &[u8], start: usize, end: usize, marks: &[Mark]) {
        self.bytes.clear();
        self.steps.clear();
        let mut at = start;
        for m in marks {
            let sep = self.push(&b[at..m.start]);
            self.steps.push((sep, m.role));
            at = m.end;
        }
        self.last = Some(self.push(&b[at..end]));
    }

    fn push(&mut self, sep: &[u8]) -> Sep {
        let at = self.bytes.len();
        self.bytes.extend_from_slice(sep);
        Sep { at, len: sep.len() }
    }

    /// Whether `b[i..]` starts with separator `s`.
    #[inline(always)]
    pub(super) fn matches(&self, b: &[u8], i: usize, s: Sep) -> bool {
        match (b.get(i..i + s.len), self.bytes.get(s.at..s.at + s.len)) {
            (Some(got), Some(want)) => same(got, want),
            _ => false,
        }
    }
}

/// `got == want` (equal lengths), eight bytes at a time: the words from the start and one
/// ending at the end (overlapping the one before it), their differences or-ed, one branch in
/// all. The separators are 14-60 bytes: a call to `memcmp` for each costs more.
#[inline(always)]
pub(super) fn same(got: &[u8], want: &[u8]) -> bool {
    let n = got.len();
    if n < 8 || want.len() != n {
        return got == want;
    }
    let word = |s: &[u8], j: usize| -> u64 {
        let mut w = [0u8; 8];
        w.copy_from_slice(&s[j..j + 8]);
        u64::from_le_bytes(w)
    };
    let mut diff = word(got, n - 8) ^ word(want, n - 8);
    let mut j = 0;
    while j + 8 < n {
        diff |= word(got, j) ^ word(want, j);
        j += 8;
    }
    diff == 0
}
