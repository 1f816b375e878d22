//! Reading the run's files. Everything here turns bytes into typed values and names the file,
//! route and field of any problem.
//!
//! | what | module |
//! |---|---|
//! | a route record: infraction lists, scores, meta (§1.1) | [`record`] |
//! | results files: raw, merged, per-route (§1.1) | [`results_file`] |
//! | several inputs, duplicate routes (§1.5) | [`duplicates`] |
//! | the route set, missing and foreign routes, N (§1.5) | [`route_set`] |
//! | finding files: result trees, telemetry folders (§1.2) | [`discovery`] |
//! | a route's telemetry, whatever its format; the reader for a file (§1.2) | [`telemetry`] |
//! | `metric_info.json` telemetry (§1.2) | [`metric_info`] |
//! | LEAD's step-exact `infractions.json` (§5) | [`lead_infractions`] |
//! | vehicle logs: MCAP with ROS 2 messages (v1.4 §16) | [`mcap`](mod@mcap) |
//! | route XML: the lateral reference (§1.3) | [`route_xml`] |
//! | collision strings (§5, §7) | [`collision`] |
//! | what infraction messages carry: a position, a percentage | [`message`] |
//! | label maps for the breakdown (§8.3) | [`labels`] |
//! | duplicate JSON keys, refused | [`json_keys`] |
//! | the figures an input file stores, checked (§1.5) | [`stored`] |
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
