//! What the evaluator's infraction messages carry besides their text: the position some end
//! with (`... at (x=<x>, y=<y>, z=<z>)`) and the percentage of the outside-lanes and min-speed
//! entries.
//!
//! CARLA's criteria write a position into red-light, stop-sign, blocked and route-deviation messages as
//! well as collisions. What the position is differs by list: the ego's location for a blocked
//! agent or a route deviation, the traffic light's or the stop sign's own location for a
//! signal (the actor's transform, not the ego's), so the callers decide how near a frame must be.

use crate::input::collision::parse_python_float;

/// The percentage of `Agent went outside its route lanes for about <m> meters (<pct>% of the
/// completed route)`.
pub fn outside_lanes_percent(s: &str) -> Option<f64> {
    parse_python_float(outside_lanes_percent_text(s)?)
}

/// The text where [`outside_lanes_percent`] reads its number.
pub fn outside_lanes_percent_text(s: &str) -> Option<&str> {
    let open = s.rfind('(')?;
    let inner = &s[open + 1..];
    let end = inner.find("% of the completed route)")?;
    Some(&inner[..end])
}

/// The percentage of `Average speed is <pct>% of the surrounding traffic's one`.
pub fn min_speed_percent(s: &str) -> Option<f64> {
    parse_python_float(min_speed_percent_text(s)?)
}

/// The text where [`min_speed_percent`] reads its number.
pub fn min_speed_percent_text(s: &str) -> Option<&str> {
    let rest = s.strip_prefix("Average speed is ")?;
    let end = rest.find('%')?;
    Some(&rest[..end])
}

/// What a message's percentage is, as the scoring protocols read it (docs/PROTOCOLS.md): a possible
/// percentage (finite, not negative), an impossible one (negative or beyond f64's range: the
/// entry is refused), or no number at all.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Percent {
    /// A finite percentage `>= 0`.
    Possible(f64),
    /// A number no evaluator writes: negative, or not finite.
    Impossible,
    /// No number where the message holds its percentage.
    Unreadable,
}

/// Classifies the percentage text found by `find` in `s` ([`min_speed_percent_text`],
/// [`outside_lanes_percent_text`]).
///
/// ```
/// use monitor_host::input::message::{min_speed_percent_text, percent_of, Percent};
/// let p = |s| percent_of(s, min_speed_percent_text);
/// assert_eq!(p("Average speed is 80.5% of it"), Percent::Possible(80.5));
/// assert_eq!(p("Average speed is -300% of it"), Percent::Impossible);
/// assert_eq!(p("Average speed is 1e999% of it"), Percent::Impossible);
/// assert_eq!(p("Average speed is slow"), Percent::Unreadable);
/// ```
pub fn percent_of(s: &str, find: impl Fn(&str) -> Option<&str>) -> Percent {
    let Some(text) = find(s) else {
        return Percent::Unreadable;
    };
    match parse_python_float(text) {
        Some(v) if v >= 0.0 => Percent::Possible(v),
        Some(_) => Percent::Impossible,
        // Digits that overflow to infinity: a number, but none an evaluator writes.
        None if text.trim().parse::<f64>().is_ok_and(|v| !v.is_finite())
            && text.bytes().any(|b| b.is_ascii_digit()) =>
        {
            Percent::Impossible
        }
        None => Percent::Unreadable,
    }
}

/// The (x, y, z) of a message ending in ` at (x=<x>, y=<y>, z=<z>)`, or `None` when it has no
/// such ending or a coordinate is not a finite number.
///
/// ```
/// use monitor_host::input::message::message_position;
/// let m = "Agent ran a red light 90776 at (x=1638.825, y=4406.786, z=364.036)";
/// assert_eq!(message_position(m), Some([1638.825, 4406.786, 364.036]));
/// assert_eq!(message_position("Agent timed out a scenario"), None);
/// assert_eq!(message_position("at (x=nan, y=0.0, z=0.0)"), None);
/// ```
pub fn message_position(message: &str) -> Option<[f64; 3]> {
    let open = message.rfind(" at (")?;
    let inner = message[open + 5..].strip_suffix(')')?;
    let mut xyz = [0.0f64; 3];
    let mut parts = inner.split(", ");
    for (slot, axis) in xyz.iter_mut().zip(["x=", "y=", "z="]) {
        *slot = parse_python_float(parts.next()?.strip_prefix(axis)?)?;
    }
    parts.next().is_none().then_some(xyz)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_messages() {
        assert_eq!(
            message_position("Agent ran a stop with id=5593 at (x=189.933, y=-169.668, z=0.196)"),
            Some([189.933, -169.668, 0.196])
        );
        assert_eq!(
            message_position("Agent got blocked at (x=508.959, y=6000.96, z=165.532)"),
            Some([508.959, 6000.96, 165.532])
        );
        assert_eq!(
            message_position("Agent went outside its route lanes for about 2.0 meters (1.64% of the completed route)"),
            None
        );
    }

    #[test]
    fn malformed_endings_have_no_position() {
        for m in [
            "at (x=1.0, y=2.0)",
            " at (x=1.0, y=2.0, z=3.0, w=4.0)",
            " at (x=1.0, y=2.0, z=3.0",
            " at (y=1.0, x=2.0, z=3.0)",
            " at (x=1.0, y=inf, z=3.0)",
            "",
        ] {
            assert_eq!(message_position(m), None, "{m:?}");
        }
    }
}
