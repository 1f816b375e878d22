//! One test binary for monitor-core's integration tests, one module per feature (ripgrep's
//! `tests/` shape): each module tests one part of docs/SCORE.md through the public API, on the
//! host (std), and `common` holds the helpers they share. The core itself stays `no_std`.

mod common;

mod chunks;
mod comfort;
mod decel;
#[cfg(feature = "serde")] // monitor_core::json exists only with serde (a default feature)
mod json;
mod lateral;
mod legacy;
mod robustness;
mod score;
mod sg;
mod signal;
