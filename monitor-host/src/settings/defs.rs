//! Every setting, defined once: one row ([`SettingDef`]) per setting with its name, group, unit,
//! meaning, how it parses and how it reads (ripgrep's `flags/defs.rs` shape). [`Settings::NAMES`],
//! [`Settings::set`], [`Settings::get`], the report's `config` block and the settings table of
//! docs/SCORE.md (a test keeps it in step) all come from [`SETTINGS`]; adding a setting is adding
//! a row here (and its field with its default).

use monitor_core::Profile;

use super::{
    decimal, parse_protocols, AbilityRule, LateralReference, MinSpeedGridSetting, PenaltyFlavour,
    Protocol, Settings, SettingsError,
};
use crate::input::duplicates::DuplicatePolicy;
use crate::input::route_set::RouteSubset;

/// One setting: its name, where it acts, and how it is parsed and read.
pub struct SettingDef {
    /// The name (`group.field` for a member of a `config` group: `bounds.yaw_rate`).
    pub name: &'static str,
    /// Where it acts (the docs table's second column): `reference`, `comfort`, `collisions`,
    /// `penalty`, `aggregates`, `protocols`, `run`, `events`.
    pub group: &'static str,
    /// The unit the docs print after the default (`m`, `s`, `m/s²`, or empty).
    pub unit: &'static str,
    /// What it does (the docs table's meaning column; Markdown).
    pub doc: &'static str,
    /// Why the default is what it is (the docs table's last column; Markdown, may be empty).
    pub decision: &'static str,
    /// Sets the value from its text (not validated; [`Settings::set`] validates the whole).
    pub(super) set: fn(&mut Settings, &'static str, &str) -> Result<(), SettingsError>,
    /// The value.
    pub(super) get: fn(&Settings) -> Value,
    /// What the value must be beyond its type ([`Settings::validate`] checks every row's).
    pub check: Check,
    /// Part of the report's `config` block (`false`: a setting that never changes a number).
    pub in_config: bool,
    /// What `sds compare --sweep` redoes when only this setting moves ([`Sweep`]); by default
    /// from the group ([`Sweep::of_group`]).
    pub sweep: Sweep,
}

/// What a point of `sds compare --sweep` must redo when a setting moves: the deepest stage of
/// the replay that reads it. A sweep re-uses every stage above it (docs/SCORE.md, "The sweep").
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Sweep {
    /// Changes no route's DS_safe, comfort or SDS (protocols, aggregates, events, run
    /// handling): refused as a sweep setting.
    No,
    /// A penalty factor: each route's monitor counts stay; only DS_safe is computed again.
    Factors,
    /// Read by the monitor alone (comfort bounds, the lateral bands, the deceleration rule):
    /// the prepared frames stay; they are streamed through the monitor again.
    Monitor,
    /// Read when the telemetry is prepared (lateral reference, slack, alignment, chunking of
    /// the motion figures, step period): the telemetry is read and replayed again.
    Replay,
}

impl Sweep {
    /// The default of a group: `penalty` → [`Sweep::Factors`]; `reference`, `comfort`,
    /// `collisions` → [`Sweep::Replay`] (a row read by the monitor alone says
    /// [`Sweep::Monitor`]); every other group → [`Sweep::No`].
    pub const fn of_group(group: &str) -> Sweep {
        match group.as_bytes() {
            b"penalty" => Sweep::Factors,
            b"reference" | b"comfort" | b"collisions" => Sweep::Replay,
            _ => Sweep::No,
        }
    }
}

/// What a setting's value must be beyond its type: checked by [`Settings::validate`] from the
/// row, so that a setting's name, parsing, check and writing live in one place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Check {
    /// Nothing beyond its type (or the core checks it: `monitor_core::Config::validate`).
    Any,
    /// Finite and positive.
    Positive,
    /// Finite and not negative.
    NotNegative,
    /// Finite and within `lo..=hi`, with the rule as an error states it.
    Within(f64, f64, &'static str),
}

impl Check {
    /// Whether `value` passes.
    pub fn holds(self, value: &Value) -> bool {
        let x = match *value {
            Value::F64(x) => x,
            Value::F32(x) => f64::from(x),
            _ => return true,
        };
        match self {
            Check::Any => true,
            Check::Positive => x.is_finite() && x > 0.0,
            Check::NotNegative => x.is_finite() && x >= 0.0,
            Check::Within(lo, hi, _) => x.is_finite() && (lo..=hi).contains(&x),
        }
    }

    /// The rule as an error states it (`finite and positive`).
    pub fn rule(self) -> &'static str {
        match self {
            Check::Any => "anything of its type",
            Check::Positive => "finite and positive",
            Check::NotNegative => "finite and not negative",
            Check::Within(_, _, rule) => rule,
        }
    }
}

/// A row whose value is checked by `check`.
const fn checked(check: Check, d: SettingDef) -> SettingDef {
    SettingDef { check, ..d }
}

/// A row whose setting only the monitor reads (a sweep streams the prepared frames again).
const fn monitor_only(d: SettingDef) -> SettingDef {
    SettingDef {
        sweep: Sweep::Monitor,
        ..d
    }
}

/// A row whose setting changes the figures although its group does not say so (the step period).
const fn replayed(d: SettingDef) -> SettingDef {
    SettingDef {
        sweep: Sweep::Replay,
        ..d
    }
}

/// The settings `sds compare --sweep` takes, in the table's order: those that change a route's
/// figures ([`SettingDef::sweep`] not [`Sweep::No`]).
///
/// ```
/// use monitor_host::settings::defs::sweep_names;
/// assert!(sweep_names().contains(&"critical_excess"));
/// assert!(!sweep_names().contains(&"protocols"));
/// ```
pub fn sweep_names() -> Vec<&'static str> {
    SETTINGS
        .iter()
        .filter(|d| d.sweep != Sweep::No)
        .map(|d| d.name)
        .collect()
}

/// A setting's value, typed: [`Settings::get`] prints it as a person writes it, the `config`
/// block as JSON.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// An f32 of the core: printed as the shortest decimal that reads back as it.
    F32(f32),
    /// An f64 of the host.
    F64(f64),
    /// A frame count of the core.
    U16(u16),
    /// A step count.
    U64(u64),
    /// A switch.
    Bool(bool),
    /// A named choice.
    Name(&'static str),
    /// A route count, or none (`null`).
    Count(Option<usize>),
    /// The protocols' ids (`none` as text when empty).
    Protocols(Vec<Protocol>),
}

impl Value {
    /// As a person writes it (`0.05`, not the f32's f64 widening; `null`; `b2d,lb2.1`).
    pub fn text(&self) -> String {
        match self {
            Value::F32(x) => x.to_string(),
            Value::F64(x) => x.to_string(),
            Value::U16(n) => n.to_string(),
            Value::U64(n) => n.to_string(),
            Value::Bool(b) => b.to_string(),
            Value::Name(n) => (*n).to_string(),
            Value::Count(n) => n.map_or_else(|| "null".into(), |n| n.to_string()),
            Value::Protocols(p) => super::protocols_text(p),
        }
    }
}

impl Value {
    /// The text [`SettingDef`]'s parser reads from a `config` block's JSON value of a setting
    /// whose value is of this kind (the inverse of [`serde::Serialize`] below), or what the
    /// kind takes.
    pub(super) fn text_of_json(&self, json: &serde_json::Value) -> Result<String, &'static str> {
        use serde_json::Value as J;
        match (self, json) {
            (Value::F32(_) | Value::F64(_), J::Number(n)) if n.as_f64().is_some() => {
                Ok(n.to_string())
            }
            (Value::F32(_) | Value::F64(_), _) => Err("a number"),
            (Value::U16(_) | Value::U64(_), J::Number(n)) if n.as_u64().is_some() => {
                Ok(n.to_string())
            }
            (Value::U16(_) | Value::U64(_), _) => Err("a whole number"),
            (Value::Bool(_), J::Bool(b)) => Ok(b.to_string()),
            (Value::Bool(_), _) => Err("true or false"),
            (Value::Name(_), J::String(s)) => Ok(s.clone()),
            (Value::Name(_), _) => Err("a name (a string)"),
            (Value::Count(_), J::Null) => Ok("null".into()),
            (Value::Count(_), J::Number(n)) if n.as_u64().is_some() => Ok(n.to_string()),
            (Value::Count(_), _) => Err("a route count or null"),
            (Value::Protocols(_), J::Array(ids)) => {
                let ids: Option<Vec<&str>> = ids.iter().map(J::as_str).collect();
                match ids {
                    Some(ids) if ids.is_empty() => Ok("none".into()),
                    Some(ids) => Ok(ids.join(",")),
                    None => Err("a list of protocol ids"),
                }
            }
            (Value::Protocols(_), _) => Err("a list of protocol ids"),
        }
    }
}

impl serde::Serialize for Value {
    /// As the `config` block writes it: an f32 as the decimal a person writes ([`decimal`]).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Value::F32(x) => s.serialize_f64(decimal(*x)),
            Value::F64(x) => s.serialize_f64(*x),
            Value::U16(n) => s.serialize_u16(*n),
            Value::U64(n) => s.serialize_u64(*n),
            Value::Bool(b) => s.serialize_bool(*b),
            Value::Name(n) => s.serialize_str(n),
            Value::Count(n) => n.serialize(s),
            Value::Protocols(p) => s.collect_seq(p.iter().map(|p| p.id())),
        }
    }
}

fn f32_of(name: &'static str, v: &str) -> Result<f32, SettingsError> {
    // Through f64, as a JSON reader does, so `NAME=VALUE` gives the value the report prints.
    Ok(f64_of(name, v)? as f32)
}

fn f64_of(name: &'static str, v: &str) -> Result<f64, SettingsError> {
    v.trim().parse().map_err(|_| bad(name, "a number", v))
}

fn bool_of(name: &'static str, v: &str) -> Result<bool, SettingsError> {
    v.trim().parse().map_err(|_| bad(name, "true or false", v))
}

fn u16_of(name: &'static str, v: &str) -> Result<u16, SettingsError> {
    v.trim()
        .parse()
        .map_err(|_| bad(name, "an integer in 0..=65535", v))
}

fn bad(name: &'static str, expected: impl Into<String>, v: &str) -> SettingsError {
    SettingsError::Value {
        name,
        expected: expected.into(),
        value: v.to_string(),
    }
}

/// A row whose value is a field of [`Settings`] of a plain type (`f32`, `f64`, `u16`, `bool`),
/// or of a [`named_enum!`] type (`named Type`).
macro_rules! row {
    (@ $name:literal, $group:literal, $unit:literal, $doc:literal, $decision:literal,
     $set:expr, $get:expr) => {
        SettingDef {
            name: $name,
            group: $group,
            unit: $unit,
            doc: $doc,
            decision: $decision,
            set: $set,
            get: $get,
            check: Check::Any,
            in_config: true,
            sweep: Sweep::of_group($group),
        }
    };
    ($name:literal, $group:literal, $unit:literal, $doc:literal, $decision:literal,
     f32 $($f:ident).+) => {
        row!(@ $name, $group, $unit, $doc, $decision,
             |s, k, v| { s.$($f).+ = f32_of(k, v)?; Ok(()) }, |s| Value::F32(s.$($f).+))
    };
    ($name:literal, $group:literal, $unit:literal, $doc:literal, $decision:literal,
     f64 $($f:ident).+) => {
        row!(@ $name, $group, $unit, $doc, $decision,
             |s, k, v| { s.$($f).+ = f64_of(k, v)?; Ok(()) }, |s| Value::F64(s.$($f).+))
    };
    ($name:literal, $group:literal, $unit:literal, $doc:literal, $decision:literal,
     u16 $($f:ident).+) => {
        row!(@ $name, $group, $unit, $doc, $decision,
             |s, k, v| { s.$($f).+ = u16_of(k, v)?; Ok(()) }, |s| Value::U16(s.$($f).+))
    };
    ($name:literal, $group:literal, $unit:literal, $doc:literal, $decision:literal,
     bool $($f:ident).+) => {
        row!(@ $name, $group, $unit, $doc, $decision,
             |s, k, v| { s.$($f).+ = bool_of(k, v)?; Ok(()) }, |s| Value::Bool(s.$($f).+))
    };
    ($name:literal, $group:literal, $unit:literal, $doc:literal, $decision:literal,
     named $ty:ident $($f:ident).+) => {
        row!(@ $name, $group, $unit, $doc, $decision,
             |s, k, v| {
                 s.$($f).+ = $ty::from_name(v.trim()).ok_or_else(|| bad(k, $ty::choices(), v))?;
                 Ok(())
             },
             |s| Value::Name(s.$($f).+.name()))
    };
}

/// Every setting, in the order of the report's `config` block (alphabetical, a group's members
/// under the group's name).
pub const SETTINGS: &[SettingDef] = &[
    row!("ability_rule", "protocols", "",
        "Bench2Drive's Traffic_Signs counting rule (section 10.1, \"Rule versions\"): `b2d-0.0.4` or `b2d-0.0.3`",
        "**[decision]**", named AbilityRule ability_rule),
    checked(
        Check::NotNegative,
        row!("align_max_dist", "collisions", "m",
        "farthest a collision may be from its frame, inclusive (section 6.1)",
        "**decision**", f64 align_max_dist),
    ),
    checked(
        Check::NotNegative,
        row!("align_tie", "collisions", "m",
        "frames this close to the smallest distance tie; the earliest wins",
        "**decision**", f64 align_tie),
    ),
    replayed(row!("allow_missing_telemetry", "run", "",
        "score routes without telemetry without telemetry terms",
        "", bool allow_missing_telemetry)),
    monitor_only(row!("anomalous_excess", "reference", "m",
        "anomalous band's lower edge, exclusive (section 7)",
        "**decision**: exclusive bands", f32 core.anomalous_excess)),
    monitor_only(
        row!("bounds.lat_acc", "comfort", "m/s²", "comfort bound `\\|lat\\| < lat_acc` (section 5.4)", "",
        f32 core.bounds.lat_acc),
    ),
    monitor_only(
        row!("bounds.lon_acc_max", "comfort", "m/s²", "comfort bound `lon < lon_acc_max` (section 5.4)", "",
        f32 core.bounds.lon_acc_max),
    ),
    monitor_only(
        row!("bounds.lon_acc_min", "comfort", "m/s²", "comfort bound `lon_acc_min < lon` (section 5.4)", "",
        f32 core.bounds.lon_acc_min),
    ),
    monitor_only(
        row!("bounds.lon_jerk", "comfort", "m/s³", "comfort bound `\\|longitudinal jerk\\| < lon_jerk` (section 5.4)", "",
        f32 core.bounds.lon_jerk),
    ),
    monitor_only(
        row!("bounds.mag_jerk", "comfort", "m/s³", "comfort bound `\\|jerk magnitude\\| < mag_jerk` (section 5.4)", "",
        f32 core.bounds.mag_jerk),
    ),
    monitor_only(
        row!("bounds.yaw_acc", "comfort", "rad/s²", "comfort bound `\\|yaw acceleration\\| < yaw_acc` (section 5.4)", "",
        f32 core.bounds.yaw_acc),
    ),
    monitor_only(
        row!("bounds.yaw_rate", "comfort", "rad/s", "comfort bound `\\|yaw rate\\| < yaw_rate` (section 5.4)", "",
        f32 core.bounds.yaw_rate),
    ),
    row!("chunk_len", "comfort", "frames", "chunk length (section 4); at most 20", "",
        u16 core.chunk_len),
    monitor_only(
        row!("critical_excess", "reference", "m", "critical above this (section 7)",
        "**decision**: exclusive bands", f32 core.critical_excess),
    ),
    monitor_only(
        row!("decel_threshold", "collisions", "m/s²", "`a_lon` at or below this is deceleration",
        "**decision**", f32 core.decel_threshold),
    ),
    monitor_only(
        row!("decel_window", "collisions", "frames", "frames before a collision searched (section 6.2); at most 20", "",
        u16 core.decel_window),
    ),
    replayed(row!(@ "dt", "run", "s",
        "step period where none is inferred; setting it fixes the period of every route (and turns `dt_inference` off)",
        "(20 Hz CARLA ticks; section 14.2)",
        |s, k, v| {
            // A fixed step period: every route uses it (docs/SCORE.md §2.2).
            s.core.dt = f32_of(k, v)?;
            s.dt_inference = false;
            Ok(())
        },
        |s| Value::F32(s.core.dt))),
    replayed(row!("dt_inference", "run", "",
        "infer each route's step period from its record (section 14.2); setting `dt` turns it off",
        "**decision**", bool dt_inference)),
    row!("duplicates", "run", "",
        "which copy of a duplicated route id is scored: `error`, `first`, `last`, `newest`, `all` (section 14.1)",
        "**decision**", named DuplicatePolicy duplicates),
    checked(
        Check::NotNegative,
        row!(@ "ego_half_width", "reference", "m",
        "half the ego's width: the slack is `lane_width / 2 − ego_half_width`; setting it sets `slack` (section 14.3)",
        "**decision**",
        |s, k, v| {
            s.ego_half_width = f64_of(k, v)?;
            s.core.slack = default_lane_slack(s);
            Ok(())
        },
        |s| Value::F64(s.ego_half_width)),
    ),
    checked(
        Check::NotNegative,
        row!("events.min_standing", "events", "s",
        "a stationary stretch at least this long is an event (section 13.1); changes no score",
        "**decision**", f64 events.min_standing),
    ),
    checked(
        Check::NotNegative,
        row!("events.signal_reach", "events", "m",
        "a red light or stop sign is placed at the ego's closest approach to its position if that frame is this near (section 13.1); changes no score",
        "**decision**", f64 events.signal_reach),
    ),
    row!(@ "expected_routes", "aggregates", "",
        "`N` (section 10); `null`: the route set's size, or the routes found",
        "",
        |s, k, v| {
            s.expected_routes = match v.trim() {
                "null" | "" => None,
                t => Some(t.parse().map_err(|_| bad(k, "a route count or null", v))?),
            };
            Ok(())
        },
        |s| Value::Count(s.expected_routes)),
    row!("factors.anomalous", "penalty", "", "factor per anomalous chunk (section 8)", "",
        f64 core.factors.anomalous),
    row!("factors.critical", "penalty", "", "factor per critical chunk (section 8)", "",
        f64 core.factors.critical),
    row!("factors.layout", "penalty", "",
        "Bench2Drive's layout factor, which a work-zone contact replaces", "",
        f64 core.factors.layout),
    row!("factors.nodecel", "penalty", "", "factor per collision without deceleration", "",
        f64 core.factors.nodecel),
    row!("factors.workzone", "penalty", "", "factor of a work-zone contact (section 8)",
        "**decision**", f64 core.factors.workzone),
    checked(
        Check::Positive,
        row!("gap_max", "reference", "m",
        "longer reference segments are junction gaps (section 2.3)",
        "**decision**", f64 gap_max),
    ),
    checked(
        Check::Positive,
        row!(@ "lane_width", "reference", "m",
        "lane width where no map gives one: the slack is `lane_width / 2 − ego_half_width`; setting it sets `slack` (section 14.3)",
        "**decision**",
        |s, k, v| {
            s.lane_width = f64_of(k, v)?;
            s.core.slack = default_lane_slack(s);
            Ok(())
        },
        |s| Value::F64(s.lane_width)),
    ),
    row!("lateral_reference", "reference", "",
        "`route` (junction gaps filled by the map) or `lane` (nearest lane; needs a map) (section 14.3)",
        "**decision**", named LateralReference lateral_reference),
    monitor_only(
        row!("legacy_jerk_spacing", "comfort", "s", "jerk spacing of `b2d-legacy`",
        "reproduces Bench2Drive", f32 core.legacy_jerk_spacing),
    ),
    checked(
        Check::NotNegative,
        row!("lookahead", "reference", "m", "forward-search window of `lat_err` (section 3)",
        "**decision**: bounded forward search", f64 lookahead),
    ),
    checked(
        Check::Within(1e-3, 60.0, "in 0.001..=60 s"),
        row!("mcap.max_hold", "run", "s",
        "vehicle logs: pose messages further apart than this make a gap; the log is cut into segments there, each monitored as a fresh start (section 16)",
        "**decision**", f64 mcap.max_hold),
    ),
    row!("min_chunk", "comfort", "frames", "fewest frames with a comfort chunk; at least 7",
        "**decision**: shorter routes have undefined comfort", u16 core.min_chunk),
    row!("min_speed_grid", "protocols", "",
        "the checkpoint grid of a record's min-speed entries under `lb2.0`, `lb2.1`, `lead-nds`: `auto`, `b2d-20` (regrouped by 5 at their harmonic mean) or `lb-4` ([PROTOCOLS.md](PROTOCOLS.md), \"The min-speed grid\")",
        "**[decision]**", named MinSpeedGridSetting min_speed_grid),
    checked(
        Check::NotNegative,
        row!("motion.moving_speed", "aggregates", "m/s",
        "a comfort chunk at least this fast on average moved (`comfort.moving_*`, section 10.0)",
        "**decision**", f64 motion.moving_speed),
    ),
    checked(
        Check::NotNegative,
        row!("motion.stationary_speed", "aggregates", "m/s",
        "a frame slower than this stands still (`stationary_share`, section 10.0)",
        "**decision**", f64 motion.stationary_speed),
    ),
    SettingDef {
        // The penalty check only reports; it never changes a score.
        sweep: Sweep::No,
        ..row!("penalty_flavour", "penalty", "",
            "factors of the penalty check (section 9.2): `bench2drive` or `leaderboard20`", "",
            named PenaltyFlavour penalty_flavour)
    },
    monitor_only(row!(@ "profile", "comfort", "",
        "comfort profile (section 5): `physical`, `b2d-legacy` or `autoware` (section 5.3a)",
        "**decision**: physical units by default",
        |s, k, v| {
            let profiles = Profile::ALL;
            let profile = profiles
                .into_iter()
                .find(|p| p.name() == v.trim())
                .ok_or_else(|| bad(k, crate::named::choices(&profiles.map(Profile::name)), v))?;
            // The profile brings its own bounds (autoware: docs/SCORE.md §2.4), unless they were set
            // one by one.
            let c = &mut s.core;
            if c.bounds == monitor_core::Bounds::of(c.profile) {
                c.bounds = monitor_core::Bounds::of(profile);
            }
            c.profile = profile;
            Ok(())
        },
        |s| Value::Name(s.core.profile.name()))),
    row!(@ "protocols", "protocols", "",
        "scoring protocols added to the report: `all`, `none`, or ids of `b2d`, `lb2.0`, `lb2.1`, `lead-nds`, `f2d` ([PROTOCOLS.md](PROTOCOLS.md))",
        "",
        |s, k, v| {
            s.protocols = parse_protocols(v).map_err(|_| bad(k, PROTOCOLS_EXPECTED, v))?;
            Ok(())
        },
        |s| Value::Protocols(s.protocols.clone())),
    SettingDef {
        in_config: false,
        ..row!("provenance.host", "run", "",
            "name the host in the report's `inputs.provenance` (section 13); not in `config`: it never changes a number, so parts scored with and without it still merge",
            "**decision**", bool provenance_host)
    },
    row!(@ "reacquire_steps", "reference", "steps",
        "a frame more than this many steps after the previous one, or a first frame whose step is not 0, searches the whole rest of the route (section 3)",
        "**decision**: re-acquisition after a gap or a late start",
        |s, k, v| {
            s.reacquire_steps = v
                .trim()
                .parse()
                .map_err(|_| bad(k, "a step count (an integer, 0 or more)", v))?;
            Ok(())
        },
        |s| Value::U64(s.reacquire_steps)),
    row!("route_subset", "run", "",
        "which routes of the route XML make the route set: `all`, or those `found` with a record (section 14.1)",
        "**decision**", named RouteSubset route_subset),
    row!("slack", "reference", "m",
        "lane half width − ego half width (section 3) where no map gives the lane",
        "**decision**: \"excess\" = how far the ego's side left its lane", f32 core.slack),
    monitor_only(
        row!("stationary_speed", "collisions", "m/s", "a collision below this speed is exempt",
        "**decision**", f32 core.stationary_speed),
    ),
];

/// What the `protocols` setting takes.
pub const PROTOCOLS_EXPECTED: &str =
    "all, none, or comma-separated ids of b2d, lb2.0, lb2.1, lead-nds, f2d";

/// The core's slack without a map: the default lane's (docs/SCORE.md §3).
fn default_lane_slack(s: &Settings) -> f32 {
    (s.lane_width / 2.0 - s.ego_half_width) as f32
}

/// [`SETTINGS`]' names, in order (what [`Settings::NAMES`] is).
pub(super) const NAMES: [&str; SETTINGS.len()] = {
    let mut names = [""; SETTINGS.len()];
    let mut i = 0;
    while i < SETTINGS.len() {
        names[i] = SETTINGS[i].name;
        i += 1;
    }
    names
};

/// The row of a setting.
pub fn def(name: &str) -> Option<&'static SettingDef> {
    SETTINGS.iter().find(|d| d.name == name)
}

/// The sweep's list of docs/SCORE.md: per stage a sweep redoes ([`Sweep`]), the settings of
/// that stage, from the rows.
pub fn sweep_markdown() -> String {
    let stage = |s: Sweep| -> String {
        SETTINGS
            .iter()
            .filter(|d| d.sweep == s)
            .map(|d| format!("`{}`", d.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "- penalty factors, each route's counts re-used and DS_safe computed again: {}\n\
         - read by the monitor alone, the prepared frames streamed again: {}\n\
         - read when the telemetry is prepared, the telemetry read and replayed again: {}\n",
        stage(Sweep::Factors),
        stage(Sweep::Monitor),
        stage(Sweep::Replay)
    )
}

/// The settings table of docs/SCORE.md: one row per setting, its default read from
/// [`Settings::default`].
pub fn markdown_table() -> String {
    let defaults = Settings::default();
    let mut out =
        String::from("| setting | group | default | meaning | decision |\n|---|---|---|---|---|\n");
    for d in SETTINGS {
        let value = (d.get)(&defaults).text();
        let default = match d.unit {
            "" => format!("`{value}`"),
            unit => format!("{value} {unit}"),
        };
        out.push_str(&format!(
            "| `{}` | {} | {default} | {} | {} |\n",
            d.name, d.group, d.doc, d.decision
        ));
    }
    out
}
