//! The per-route pipeline: [`prepare`] (record + telemetry → frames built by [`frame`], with
//! [`align`]ed collision events) → [`replay`] (frames → `Monitor` → summary, checked against the
//! batch reference) → [`outcome`] (what became of the route, with its [`timeline`]);
//! [`live`] builds the same frames one tick at a time for the live front ends;
//! [`step_period`] gives each route's `dt`; [`motion`] its distance, stationary share and
//! moving chunks; [`placement`] puts its other infractions and stationary stretches on its frames.

pub mod align;
pub mod drive;
pub mod frame;
pub mod live;
pub mod motion;
pub mod outcome;
pub mod placement;
pub mod prepare;
pub mod replay;
pub mod step_period;
pub mod timeline;
