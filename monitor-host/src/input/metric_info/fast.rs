//! The fast path of the `metric_info.json` parser: simd-json's tape, read by a walker that
//! accepts only what it is sure of.
//!
//! simd-json validates the whole input (syntax, UTF-8, control characters in strings) and parses
//! every number with correct rounding into a flat tape of nodes, each container knowing how many
//! nodes it spans; the walker below reads the five vectors of every frame off that tape. It never
//! produces an error: on anything it does not expect (a missing or repeated field, a short
//! vector, a non-number, a value that is not finite or does not fit f32, a step key that is not
//! decimal, deep nesting, `-0` written as an integer, a duplicate step) it returns `None`, and
//! the caller parses the same bytes with the serde_json visitor, which alone decides errors and
//! their messages. Where it returns frames they are the visitor's frames, bit for bit; the test
//! `metric_info_fast_path` checks that on the fuzz corpus and on generated and mutated files.
//!
//! Buffers (a mutable copy of the input, simd-json's buffers and the tape) are kept per thread
//! and reused from route to route: together about 4 bytes for every byte of the largest file
//! the thread has parsed.

use std::cell::RefCell;

use simd_json::{Buffers, Node, StaticNode};

use super::visitor::{field_index, frame_from, step_number};
use super::TelemetryFrame;

/// Deepest nesting inside an ignored value that the fast path reads; deeper goes to serde_json
/// (which has its own recursion rules).
const MAX_IGNORED_DEPTH: usize = 32;

/// Reused per thread: the tape keeps its allocation between routes (it holds no borrows while
/// stored: it is emptied before it is put back).
#[derive(Default)]
struct Scratch {
    input: Vec<u8>,
    buffers: Option<Buffers>,
    tape: Vec<Node<'static>>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The frames of `bytes` in file order and whether their steps increase, or `None` when the
/// serde_json path must decide.
pub(super) fn parse(bytes: &[u8]) -> Option<(Vec<TelemetryFrame>, bool)> {
    SCRATCH.with(|cell| {
        let Ok(mut guard) = cell.try_borrow_mut() else {
            return None; // re-entered (cannot happen): let serde decide
        };
        let scratch = &mut *guard;
        scratch.input.clear();
        scratch.input.extend_from_slice(bytes);
        let buffers = scratch
            .buffers
            .get_or_insert_with(|| Buffers::new(bytes.len()));
        // Reuse the stored tape's allocation for nodes borrowing this input (an in-place
        // collect of an empty vector: no element is ever mapped).
        let stored = std::mem::take(&mut scratch.tape);
        let mut tape: Vec<Node<'_>> = stored.into_iter().map(|_| unreachable!()).collect();
        let mut holder = simd_json::Tape(std::mem::take(&mut tape));
        let out = match simd_json::fill_tape(&mut scratch.input, buffers, &mut holder) {
            Ok(()) => walk(&holder.0),
            Err(_) => None,
        };
        let mut nodes = holder.0;
        nodes.clear();
        scratch.tape = nodes.into_iter().map(|_| unreachable!()).collect();
        out
    })
}

/// A number as serde_json hands it to `f64`'s `Deserialize`, or `None` if unsure.
fn number(node: &Node<'_>) -> Option<f64> {
    match node {
        Node::Static(StaticNode::F64(x)) if x.is_finite() => Some(*x),
        Node::Static(StaticNode::U64(n)) => Some(*n as f64),
        // simd-json reads `-0` as the integer 0; serde_json as the float -0.0.
        Node::Static(StaticNode::I64(n)) if *n != 0 => Some(*n as f64),
        _ => None,
    }
}

/// The index just past the value starting at `i`, or `None` if it nests too deeply.
fn skip(nodes: &[Node<'_>], i: usize) -> Option<usize> {
    let (len, count) = match nodes.get(i)? {
        Node::Object { len, count } => (*len, *count),
        Node::Array { len, count } => (*len, *count),
        _ => return Some(i + 1),
    };
    let end = i.checked_add(count)?.checked_add(1)?;
    if count != len {
        // Nested containers: bound the depth (ends of the open containers on a small stack).
        let mut open = [0usize; MAX_IGNORED_DEPTH];
        let mut depth = 1;
        open[0] = end;
        for (j, n) in nodes.get(i + 1..end)?.iter().enumerate() {
            let j = i + 1 + j;
            while depth > 0 && j >= open[depth - 1] {
                depth -= 1;
            }
            if let Node::Object { count, .. } | Node::Array { count, .. } = n {
                *open.get_mut(depth)? = j + count + 1;
                depth += 1;
            }
        }
    }
    Some(end)
}

/// Reads every frame off the tape, or `None` where the serde path must decide.
fn walk(nodes: &[Node<'_>]) -> Option<(Vec<TelemetryFrame>, bool)> {
    let Some(Node::Object { len, count }) = nodes.first() else {
        return None;
    };
    if *len == 0 || count.checked_add(1)? != nodes.len() {
        return None;
    }
    let mut frames = Vec::with_capacity(*len);
    let mut sorted = true;
    let mut i = 1;
    for _ in 0..*len {
        let Node::String(key) = nodes.get(i)? else {
            return None;
        };
        let step = step_number(key).ok()?;
        i += 1;
        let Node::Object { len: fields, .. } = nodes.get(i)? else {
            return None;
        };
        i += 1;
        let mut vals = [[0.0f64; 3]; 5];
        let mut seen = 0u8;
        for _ in 0..*fields {
            let Node::String(name) = nodes.get(i)? else {
                return None;
            };
            i += 1;
            let Some(idx) = field_index(name) else {
                i = skip(nodes, i)?;
                continue;
            };
            if seen & (1 << idx) != 0 {
                return None;
            }
            seen |= 1 << idx;
            let Node::Array { len: n, .. } = nodes.get(i)? else {
                return None;
            };
            if *n < 3 {
                return None;
            }
            for (k, slot) in vals[idx].iter_mut().enumerate() {
                *slot = number(nodes.get(i + 1 + k)?)?;
            }
            i = skip(nodes, i)?;
        }
        if seen != 0b1_1111 {
            return None;
        }
        let frame = frame_from(step, vals).ok()?;
        if frames.last().is_some_and(|p: &TelemetryFrame| step <= p.step) {
            sorted = false;
        }
        frames.push(frame);
    }
    (i == nodes.len()).then_some((frames, sorted))
}
