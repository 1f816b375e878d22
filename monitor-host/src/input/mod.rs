//! Reading the run's files. Everything here turns bytes into typed values and names the file,
//! route and field of any problem.
//!
//! | what | module |
//! |---|---|
//! | a route record: infraction lists, scores, meta (docs/SCORE.md §2.1) | [`record`] |
//! | results files: raw, merged, per-route (docs/SCORE.md §2.1) | [`results_file`] |
//! | several inputs, duplicate routes (docs/SCORE.md §14.1) | [`duplicates`] |
//! | the route set, missing and foreign routes, N (docs/SCORE.md §14.1) | [`route_set`] |
//! | finding files: result trees, telemetry folders (docs/SCORE.md §2.2) | [`discovery`] |
//! | a route's telemetry, whatever its format; the reader for a file (docs/SCORE.md §2.2) | [`telemetry`] |
//! | `metric_info.json` telemetry (docs/SCORE.md §2.2) | [`metric_info`] |
//! | LEAD's step-exact `infractions.json` (docs/SCORE.md §6) | [`lead_infractions`] |
//! | vehicle logs: MCAP with ROS 2 messages (docs/SCORE.md §2.4) | [`mcap`](mod@mcap) |
//! | route XML: the lateral reference (docs/SCORE.md §2.3) | [`route_xml`] |
//! | collision strings (docs/SCORE.md §6, docs/SCORE.md §8) | [`collision`] |
//! | what infraction messages carry: a position, a percentage | [`message`] |
//! | label maps for the breakdown (docs/SCORE.md §10.2) | [`labels`] |
//! | duplicate JSON keys, refused | [`json_keys`] |
//! | the figures an input file stores, checked (docs/SCORE.md §14.1) | [`stored`] |
//! | the one guarded file reader: regular files, bounded size | [`read`] |

pub mod collision;
pub mod discovery;
pub mod duplicates;
pub mod json_keys;
pub mod labels;
pub mod lead_infractions;
pub mod mcap;
pub mod message;
pub mod metric_info;
pub mod read;
pub mod record;
pub mod results_file;
pub mod route_set;
pub mod route_xml;
pub mod source;
pub mod stored;
pub mod telemetry;
pub mod warning;
