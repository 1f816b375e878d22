//! The doer's side of the live link (docs/SCORE.md, "Live link"; `sds link`, `sds checker`):
//! plays routes to a checker over a byte stream and checks that the checker's events are those
//! of the replay of the frames it accepted, cut into the segments it started.
//!
//! | file | what |
//! |---|---|
//! | [`transport`] | `serial:`, `tcp:`, `exec:` byte streams |
//! | [`inject`] | deterministic fault injection on the encoded bytes |
//! | [`doer`] | one route played, the replay, the route's `link` figures |
//! | [`host_checker`] | the checker on the host (`sds checker`): stdin to stdout |

pub mod doer;
pub mod host_checker;
pub mod inject;
pub mod transport;

pub use doer::{LinkFigures, Pace, Player, RouteLink};
pub use inject::Inject;
pub use transport::Target;
