//! Every setting of a run (docs/SCORE.md §2.3, docs/SCORE.md §3, docs/SCORE.md §6, docs/SCORE.md §9 and the core's §3-§7): the core's
//! [`Config`] plus the host's own, with the spec's defaults, validation, and `NAME=VALUE` parsing.
//!
//! Names are those of the report's `config` block; a group member is written `group.field`
//! (`bounds.yaw_rate`, `factors.workzone`).
//!
//! ```
//! use monitor_host::Settings;
//!
//! let mut s = Settings::default();
//! s.set("slack", "0.9")?;
//! s.set("bounds.yaw_rate", "1.0")?;
//! s.set("penalty_flavour", "leaderboard20")?;
//! s.set("profile", "b2d-legacy")?;
//! assert_eq!(s.get("slack").as_deref(), Some("0.9"));
//! assert!(s.set("nope", "1").unwrap_err().to_string().contains("gap_max"));
//! assert!(s.set("chunk_len", "99").is_err()); // validated: beyond the monitor's capacity
//! # Ok::<(), monitor_host::SettingsError>(())
//! ```

pub mod defs;

use monitor_core::{Config, ConfigError, Profile};

use crate::input::duplicates::DuplicatePolicy;
use crate::input::route_set::RouteSubset;

/// Why a setting was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SettingsError {
    /// `--set` text without `=`.
    #[error("setting {0}: expected NAME=VALUE")]
    Syntax(String),
    /// No setting has this name.
    #[error("unknown setting {name}; known settings: {}", Settings::NAMES.join(", "))]
    Unknown {
        /// The name given.
        name: String,
    },
    /// The value does not parse as the setting's type.
    #[error("setting {name}: expected {expected}, got {value:?}")]
    Value {
        /// The setting.
        name: &'static str,
        /// What it takes (for a named choice: its names, `a, b or c`).
        expected: String,
        /// The text given.
        value: String,
    },
    /// The core's configuration is inconsistent.
    #[error("invalid configuration: {0}")]
    Config(ConfigError),
    /// A report's `config` block states no settings this version writes
    /// ([`Settings::from_config`]): the message names the key (`config.slack: ...`).
    #[error("{0}")]
    ConfigBlock(String),
    /// A host setting is out of its range.
    #[error("invalid configuration: {name} must be {rule}")]
    Range {
        /// The setting.
        name: &'static str,
        /// The rule it breaks.
        rule: &'static str,
    },
}

named_enum! {
    /// What the lateral error is measured against (docs/SCORE.md §3) **\[decision\]**.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum LateralReference {
        /// The route polyline, its junction gaps filled by the map where the town has one
        /// (`route`).
        #[default]
        Route = "route",
        /// The nearest driving lane of the map, whichever it is (`lane`); routes in towns
        /// without a map fall back to [`LateralReference::Route`] with a warning.
        Lane = "lane",
    }
}

/// All settings of a run. Build from [`Settings::default`] (the spec's defaults), change fields
/// or call [`Settings::set`], then [`Settings::validate`] (done again by [`crate::score_run`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// The monitor's configuration (profile, bounds, windows, slack, factors).
    pub core: Config,
    /// A reference segment strictly longer than this is a junction gap, m (8.0) **\[decision\]**.
    pub gap_max: f64,
    /// Forward-search window of the lateral error, m of route length (10.0) **\[decision\]**.
    pub lookahead: f64,
    /// Re-acquisition of the lateral reference (docs/SCORE.md §3, v1.4): at a frame whose step exceeds the
    /// previous frame's by more than this (and at a first frame whose step is not 0), the
    /// forward search looks at the whole rest of the route instead of `lookahead` (10)
    /// **\[decision\]**.
    pub reacquire_steps: u64,
    /// What the lateral error is measured against (docs/SCORE.md §3): the route (`route`, default) or the
    /// nearest driving lane of the map (`lane`) **\[decision\]**.
    pub lateral_reference: LateralReference,
    /// Lane width where no map gives one, m (3.5) **\[decision\]**. Setting it (or
    /// `ego_half_width`) sets `slack` to `lane_width / 2 - ego_half_width`.
    pub lane_width: f64,
    /// Half the ego's width, m (0.93): a frame's slack is `w_i / 2 - ego_half_width`.
    pub ego_half_width: f64,
    /// Farthest a collision may be from its frame to be aligned, m, inclusive (1.0) **\[decision\]**.
    pub align_max_dist: f64,
    /// Frames within this of the smallest distance tie; ties go to the earliest, m (1e-3).
    pub align_tie: f64,
    /// Factors of the penalty re-check (docs/SCORE.md §9).
    pub penalty_flavour: PenaltyFlavour,
    /// Benchmark size N: routes not found count as 0 / failed (docs/SCORE.md §10).
    pub expected_routes: Option<usize>,
    /// Which copy of a duplicated route id is scored (docs/SCORE.md §14.1) **\[decision\]**.
    pub duplicates: DuplicatePolicy,
    /// Which routes of `--routes` make the route set: `all` (default) or those `found` with a
    /// record **\[decision\]**.
    pub route_subset: RouteSubset,
    /// Infer each route's step period from its record (docs/SCORE.md §2.2); `false` uses `dt` for every
    /// route. Setting `dt` turns it off.
    pub dt_inference: bool,
    /// Score routes without telemetry without telemetry terms instead of failing them.
    pub allow_missing_telemetry: bool,
    /// Worker threads (`None`: all cores). Not part of the report: it never changes a number.
    pub threads: Option<usize>,
    /// Thresholds of the distance and stationary figures (docs/SCORE.md §10.0).
    pub motion: MotionSettings,
    /// How the route's `events` place the evaluator's other infractions and stationary
    /// stretches on the frame axis.
    pub events: EventSettings,
    /// How vehicle logs are cut at their gaps (docs/SCORE.md §2.4).
    pub mcap: McapSettings,
    /// Scoring protocols to add (docs/PROTOCOLS.md; default none).
    pub protocols: Vec<Protocol>,
    /// Bench2Drive's Traffic_Signs counting rule (docs/SCORE.md §10.1; default `b2d-0.0.4`).
    pub ability_rule: AbilityRule,
    /// Which min-speed checkpoint grid a record's entries are read on under the Leaderboard
    /// protocols (docs/PROTOCOLS.md v1.4; default `auto`) **\[decision\]**.
    pub min_speed_grid: MinSpeedGridSetting,
    /// Name the host in the report's `inputs.provenance` (docs/SCORE.md §13.2; default true) **\[decision\]**.
    /// Not part of `config`: it never changes a number, so parts scored with and without it
    /// still merge.
    pub provenance_host: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            core: Config::DEFAULT,
            gap_max: 8.0,
            lookahead: 10.0,
            reacquire_steps: 10,
            lateral_reference: LateralReference::Route,
            lane_width: 3.5,
            ego_half_width: 0.93,
            align_max_dist: 1.0,
            align_tie: 1e-3,
            penalty_flavour: PenaltyFlavour::Bench2Drive,
            expected_routes: None,
            duplicates: DuplicatePolicy::Error,
            route_subset: RouteSubset::All,
            dt_inference: true,
            allow_missing_telemetry: false,
            threads: None,
            motion: MotionSettings::default(),
            events: EventSettings::default(),
            mcap: McapSettings::default(),
            protocols: Vec::new(),
            ability_rule: AbilityRule::B2d004,
            min_speed_grid: MinSpeedGridSetting::Auto,
            provenance_host: true,
        }
    }
}

/// An f32 setting as the decimal a person writes: the shortest text that reads back as the same
/// f32 (`0.05`, not its f64 widening `0.05000000074505806`), as an f64.
///
/// ```
/// use monitor_host::settings::decimal;
/// assert_eq!(decimal(0.05), 0.05);
/// assert_ne!(f64::from(0.05f32), 0.05);
/// ```
pub fn decimal(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}

impl Settings {
    /// Every settable name, in the order of the report's `config` block (the names of
    /// [`defs::SETTINGS`]).
    pub const NAMES: [&'static str; defs::SETTINGS.len()] = defs::NAMES;

    /// Sets one setting from its text (`"0.9"`, `"b2d-legacy"`, `"true"`, `"220"`, `"null"` for
    /// no `expected_routes`) and validates the whole.
    ///
    /// # Errors
    /// [`SettingsError::Unknown`] (listing the known names), [`SettingsError::Value`], or a
    /// validation error; the settings are unchanged then.
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), SettingsError> {
        let mut next = self.clone();
        next.set_unchecked(name, value)?;
        next.validate()?;
        *self = next;
        Ok(())
    }

    /// Applies `NAME=VALUE` overrides in order (the command line's `--set`), then validates.
    ///
    /// # Errors
    /// As [`Settings::set`], or [`SettingsError::Syntax`] for text without `=`.
    pub fn apply(&mut self, overrides: &[String]) -> Result<(), SettingsError> {
        let pairs = overrides
            .iter()
            .map(|s| {
                s.split_once('=')
                    .ok_or_else(|| SettingsError::Syntax(s.clone()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        self.apply_pairs(pairs)
    }

    /// Applies `(NAME, VALUE)` overrides in order, then validates once (so a pair may pass
    /// through a state that only a later pair makes valid); nothing changes on an error. What
    /// [`Settings::apply`] does after splitting `NAME=VALUE`, for front ends that hold names and
    /// values apart (the Python `settings={...}` mapping).
    ///
    /// ```
    /// use monitor_host::Settings;
    /// let mut s = Settings::default();
    /// s.apply_pairs([("slack", "0.9"), ("bounds.yaw_rate", "1.0")])?;
    /// assert_eq!(s.get("slack").as_deref(), Some("0.9"));
    /// assert!(s.apply_pairs([("slack", "1.0"), ("nope", "1")]).is_err());
    /// assert_eq!(s.get("slack").as_deref(), Some("0.9"));
    /// # Ok::<(), monitor_host::SettingsError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Settings::set`].
    pub fn apply_pairs<N: AsRef<str>, V: AsRef<str>>(
        &mut self,
        pairs: impl IntoIterator<Item = (N, V)>,
    ) -> Result<(), SettingsError> {
        let mut next = self.clone();
        for (name, value) in pairs {
            next.set_unchecked(name.as_ref(), value.as_ref())?;
        }
        next.validate()?;
        *self = next;
        Ok(())
    }

    fn set_unchecked(&mut self, name: &str, v: &str) -> Result<(), SettingsError> {
        let def = defs::def(name).ok_or_else(|| SettingsError::Unknown { name: name.into() })?;
        (def.set)(self, def.name, v)
    }

    /// The value of a setting as a person writes it (`0.05`, not the f32's f64 widening), or
    /// `None` for an unknown name.
    pub fn get(&self, name: &str) -> Option<String> {
        defs::def(name).map(|d| (d.get)(self).text())
    }

    /// The deepest stage of a route's replay that differs between `self` and `other`
    /// ([`defs::Sweep`], from each row's `sweep`): [`defs::Sweep::No`] when no setting differs;
    /// a differing setting that changes no figure counts as [`defs::Sweep::Replay`] (nothing is
    /// re-used across it).
    ///
    /// ```
    /// use monitor_host::settings::defs::Sweep;
    /// use monitor_host::Settings;
    /// let a = Settings::default();
    /// let mut b = a.clone();
    /// b.set("factors.critical", "0.8")?;
    /// assert_eq!(a.sweep_stage(&b), Sweep::Factors);
    /// b.set("critical_excess", "0.5")?;
    /// assert_eq!(a.sweep_stage(&b), Sweep::Monitor);
    /// b.set("gap_max", "6")?;
    /// assert_eq!(a.sweep_stage(&b), Sweep::Replay);
    /// # Ok::<(), monitor_host::SettingsError>(())
    /// ```
    pub fn sweep_stage(&self, other: &Settings) -> defs::Sweep {
        let rows = defs::SETTINGS
            .iter()
            .filter(|d| (d.get)(self) != (d.get)(other))
            .map(|d| match d.sweep {
                defs::Sweep::No => defs::Sweep::Replay,
                s => s,
            });
        // The worker threads are no row: they never change a number.
        rows.max().unwrap_or(defs::Sweep::No)
    }

    /// The value of a setting, typed (as the report's `config` block writes it), or `None` for
    /// an unknown name.
    pub fn value(&self, name: &str) -> Option<defs::Value> {
        defs::def(name).map(|d| (d.get)(self))
    }

    /// Checks the whole: the core's [`Config::validate`] for the default monitor capacity, and
    /// the host's distances.
    ///
    /// # Errors
    /// The first problem found.
    pub fn validate(&self) -> Result<(), SettingsError> {
        self.core
            .validate(monitor_core::DEFAULT_CAPACITY)
            .map_err(SettingsError::Config)?;
        // Each row's own check (defs.rs): the rule lives beside the setting it bounds.
        for d in defs::SETTINGS {
            if !d.check.holds(&(d.get)(self)) {
                return Err(SettingsError::Range {
                    name: d.name,
                    rule: d.check.rule(),
                });
            }
        }
        if self.threads == Some(0) {
            return Err(SettingsError::Range {
                name: "threads",
                rule: "at least 1",
            });
        }
        Ok(())
    }

    /// The most worker threads a run starts, whatever [`Settings::threads`] asks.
    pub const MAX_THREADS: usize = 256;

    /// The worker threads for `routes` routes: [`Settings::threads`] (default: the cores),
    /// never more than the routes (at least 1) nor [`Settings::MAX_THREADS`].
    ///
    /// ```
    /// let mut s = monitor_host::Settings::default();
    /// s.threads = Some(100_000);
    /// assert_eq!(s.worker_threads(7), 7);
    /// assert_eq!(s.worker_threads(10_000), monitor_host::Settings::MAX_THREADS);
    /// assert_eq!(s.worker_threads(0), 1);
    /// ```
    pub fn worker_threads(&self, routes: usize) -> usize {
        let wanted = self.threads.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
        });
        wanted.min(routes).clamp(1, Self::MAX_THREADS)
    }
}

impl std::fmt::Display for Settings {
    /// One `name = value` line per setting, in [`Settings::NAMES`] order.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for name in Self::NAMES {
            writeln!(f, "{name} = {}", self.get(name).unwrap_or_default())?;
        }
        Ok(())
    }
}

/// The report's `config` block: every setting of [`defs::SETTINGS`] that is part of it, by name,
/// keys in alphabetical order, the members of a group (`bounds.yaw_rate`) in an object of the
/// group's name, f32 values printed as the decimal a person writes ([`decimal`]). `threads` and
/// `provenance.host` are not part of it.
impl serde::Serialize for Settings {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let rows: Vec<&defs::SettingDef> = defs::SETTINGS.iter().filter(|d| d.in_config).collect();
        // Top-level entries: a plain setting, or a group of consecutive `group.member` rows.
        let mut entries: Vec<(&str, Entry)> = Vec::new();
        for d in rows {
            let value = (d.get)(self);
            match d.name.split_once('.') {
                None => entries.push((d.name, Entry::Value(value))),
                Some((group, member)) => match entries.last_mut() {
                    Some((g, Entry::Group(members))) if *g == group => {
                        members.push((member, value));
                    }
                    _ => entries.push((group, Entry::Group(vec![(member, value)]))),
                },
            }
        }
        let mut m = s.serialize_map(Some(entries.len()))?;
        for (key, entry) in &entries {
            match entry {
                Entry::Value(v) => m.serialize_entry(key, v)?,
                Entry::Group(members) => m.serialize_entry(key, &Group(members))?,
            }
        }
        m.end()
    }
}

impl<'de> serde::Deserialize<'de> for Settings {
    /// A report's `config` block, read back ([`Settings::from_config`]).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let config = <serde_json::Value as serde::Deserialize>::deserialize(d)?;
        Settings::from_config(&config).map_err(serde::de::Error::custom)
    }
}

impl Settings {
    /// The settings a report's `config` block states: the inverse of `Serialize for Settings`,
    /// through the same rows of [`defs::SETTINGS`] (each value read as its row's kind, parsed
    /// and checked as `--set` parses and checks it), then written back to check that it is the
    /// block this version writes. Settings outside the block (`threads`, `provenance.host`)
    /// keep their defaults.
    ///
    /// ```
    /// use monitor_host::Settings;
    /// let mut s = Settings::default();
    /// s.apply_pairs([("slack", "0.7"), ("protocols", "all"), ("bounds.yaw_rate", "1.1")])?;
    /// let config = serde_json::to_value(&s)?;
    /// assert_eq!(Settings::from_config(&config)?, s);
    /// let mut edited = config.clone();
    /// edited["slack"] = "wide".into();
    /// let e = Settings::from_config(&edited).unwrap_err().to_string();
    /// assert!(e.contains("config.slack: expected a number"), "{e}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`SettingsError::ConfigBlock`] naming the first key that is absent, not a setting of
    /// this version, of the wrong kind, refused by its row, or not written back as given.
    pub fn from_config(config: &serde_json::Value) -> Result<Settings, SettingsError> {
        let err = |why: String| SettingsError::ConfigBlock(why);
        let other = "(a report of another sds version?)";
        let Some(block) = config.as_object() else {
            return Err(err(format!(
                "config: expected an object of settings, got {config}"
            )));
        };
        let rows = || defs::SETTINGS.iter().filter(|d| d.in_config);
        let known = |name: &str| rows().any(|d| d.name == name);
        for (key, value) in block {
            match value.as_object() {
                Some(members) if !known(key) => {
                    if let Some(m) = members.keys().find(|m| !known(&format!("{key}.{m}"))) {
                        return Err(err(format!("config.{key}.{m}: not a setting {other}")));
                    }
                }
                _ if !known(key) => {
                    return Err(err(format!("config.{key}: not a setting {other}")));
                }
                _ => {}
            }
        }
        let at = |name: &str| match name.split_once('.') {
            Some((group, member)) => block.get(group).and_then(|g| g.get(member)),
            None => block.get(name),
        };
        // The profile first: it brings its own bounds, which the block then states one by one.
        let (profile, rest): (Vec<_>, Vec<_>) = rows().partition(|d| d.name == "profile");
        let defaults = Settings::default();
        let mut s = Settings::default();
        for d in profile.iter().chain(&rest) {
            let Some(json) = at(d.name) else {
                return Err(err(format!("config.{}: absent {other}", d.name)));
            };
            let text = (d.get)(&defaults).text_of_json(json).map_err(|expected| {
                err(format!(
                    "config.{}: expected {expected}, got {json}",
                    d.name
                ))
            })?;
            (d.set)(&mut s, d.name, &text).map_err(|e| err(format!("config.{}: {e}", d.name)))?;
        }
        s.validate().map_err(|e| err(format!("config: {e}")))?;
        for d in rows() {
            let back = serde_json::to_value((d.get)(&s)).unwrap_or_default();
            if let Some(json) = at(d.name).filter(|j| **j != back) {
                return Err(err(format!(
                    "config.{}: {json} is not a value sds writes (it reads as {back}) {other}",
                    d.name
                )));
            }
        }
        Ok(s)
    }
}

/// One top-level entry of the `config` block.
enum Entry {
    Value(defs::Value),
    Group(Vec<(&'static str, defs::Value)>),
}

/// A settings group (`bounds`, `factors`) as a JSON object.
struct Group<'a>(&'a [(&'static str, defs::Value)]);

impl serde::Serialize for Group<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

/// The thresholds of §8.5 (settings `motion.stationary_speed`, `motion.moving_speed`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionSettings {
    /// A frame whose speed is below this is stationary, m/s (0.1) **\[decision\]**. (The
    /// setting `stationary_speed` is §5's collision exemption, 0.5 m/s: another threshold.)
    pub stationary_speed: f64,
    /// A chunk whose mean speed (path length over its duration) is at least this is moving,
    /// m/s (1.0) **\[decision\]**.
    pub moving_speed: f64,
}

impl Default for MotionSettings {
    fn default() -> Self {
        MotionSettings {
            stationary_speed: 0.1,
            moving_speed: 1.0,
        }
    }
}

/// How a route's `events` place what the evaluator reports on the frame axis (settings
/// `events.signal_reach`, `events.min_standing`; none of them changes a score).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventSettings {
    /// A red-light or stop-sign event is placed at the frame of the ego's closest approach to
    /// the position in its message (the light's or the sign's own location, not the ego's) if
    /// that frame is at most this far from it, m (30.0) **\[decision\]**: on the project's real
    /// results files, the 49 red lights stand a median 15.7 m (at most 28.3 m) from their
    /// route's waypoints, the 50 stop signs 5.5 m (at most 9.2 m).
    pub signal_reach: f64,
    /// A stationary stretch (frames slower than `motion.stationary_speed`) is an event when it
    /// lasts at least this long, s (2.0) **\[decision\]**.
    pub min_standing: f64,
}

impl Default for EventSettings {
    fn default() -> Self {
        EventSettings {
            signal_reach: 30.0,
            min_standing: 2.0,
        }
    }
}

/// How vehicle logs are framed (docs/SCORE.md §2.4; setting `mcap.max_hold`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct McapSettings {
    /// Two consecutive pose messages further apart than this make a gap, s (0.25)
    /// **\[decision\]**: no tick is made inside it, nothing is held across it, and the log is
    /// cut into segments there, each monitored as a fresh start. A 10 Hz log's poses are 0.1 s
    /// apart; a pause of a recorder, seconds.
    pub max_hold: f64,
}

impl Default for McapSettings {
    fn default() -> Self {
        McapSettings { max_hold: 0.25 }
    }
}

/// One scoring protocol (docs/PROTOCOLS.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Protocol {
    /// Bench2Drive's evaluator: the recorded penalty and score.
    B2d,
    /// CARLA Leaderboard 2.0 (`master`): a product of per-event factors.
    Lb20,
    /// CARLA Leaderboard 2.1 (`leaderboard-2.1`): `f_out / (1 + sum of per-event costs)`.
    Lb21,
    /// LEAD's "Normalized DS": per-event factors normalised by the driven kilometres.
    LeadNds,
    /// Fail2Drive: DS as `b2d`, its own success rule, and the harmonic mean of DS and SR.
    F2d,
}

impl Protocol {
    /// Every protocol, in the order reports and tables list them.
    pub const ALL: [Protocol; 5] = [
        Protocol::B2d,
        Protocol::Lb20,
        Protocol::Lb21,
        Protocol::LeadNds,
        Protocol::F2d,
    ];

    /// The id used on the command line and as the report's key (`lb2.1`, ...).
    pub fn id(self) -> &'static str {
        match self {
            Protocol::B2d => "b2d",
            Protocol::Lb20 => "lb2.0",
            Protocol::Lb21 => "lb2.1",
            Protocol::LeadNds => "lead-nds",
            Protocol::F2d => "f2d",
        }
    }

    /// The protocol of an id.
    pub fn from_id(id: &str) -> Option<Protocol> {
        Protocol::ALL.into_iter().find(|p| p.id() == id)
    }

    /// The protocol of a report's key (a `protocols` object read back), or an error naming it.
    pub(crate) fn of_key<E: serde::de::Error>(id: &str) -> Result<Protocol, E> {
        Protocol::from_id(id).ok_or_else(|| {
            E::custom(format!(
                "unknown protocol {id:?}; expected {}",
                crate::named::choices(&Protocol::ALL.map(Protocol::id))
            ))
        })
    }

    /// A name for the tables (`CARLA Leaderboard 2.1`, ...).
    pub fn title(self) -> &'static str {
        match self {
            Protocol::B2d => "Bench2Drive (recorded)",
            Protocol::Lb20 => "CARLA Leaderboard 2.0",
            Protocol::Lb21 => "CARLA Leaderboard 2.1",
            Protocol::LeadNds => "LEAD normalized DS",
            Protocol::F2d => "Fail2Drive",
        }
    }
}

/// Parses the `protocols` setting: `all`, `none` (or empty), or comma-separated ids. The result
/// is in [`Protocol::ALL`] order without repeats.
///
/// # Errors
/// The text naming the unknown id and the known ones.
pub fn parse_protocols(text: &str) -> Result<Vec<Protocol>, String> {
    let text = text.trim();
    if text == "all" {
        return Ok(Protocol::ALL.to_vec());
    }
    if text.is_empty() || text == "none" {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for id in text.split(',').map(str::trim) {
        let p = Protocol::from_id(id).ok_or_else(|| {
            format!(
                "unknown protocol {id:?}; known: {}, or all",
                Protocol::ALL.map(Protocol::id).join(", ")
            )
        })?;
        out.push(p);
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// What a list holding `all` or `none` beside other items is told.
const PROTOCOLS_ALONE: &str =
    "all or none alone, or comma-separated ids of b2d, lb2.0, lb2.1, lead-nds, f2d";

/// The `protocols` setting from a list of ids (a front end's typed list, never joined into
/// text): each item an id, or `all` or `none` alone. In [`Protocol::ALL`] order without repeats.
///
/// ```
/// use monitor_host::settings::{protocols_of, Protocol};
/// assert_eq!(protocols_of(&["lb2.1", "b2d"])?, [Protocol::B2d, Protocol::Lb21]);
/// assert_eq!(protocols_of(&["all"])?, Protocol::ALL);
/// assert!(protocols_of(&["lb3"]).unwrap_err().to_string().contains("\"lb3\""));
/// assert!(protocols_of(&["all", "none"]).unwrap_err().to_string().contains("alone"));
/// # Ok::<(), monitor_host::SettingsError>(())
/// ```
///
/// # Errors
/// [`SettingsError::Value`] naming the item that is no id.
pub fn protocols_of<S: AsRef<str>>(ids: &[S]) -> Result<Vec<Protocol>, SettingsError> {
    // `all` and `none` stand alone: `all,none` or `none,lb2.1` says two things at once (the
    // text setting refuses them too).
    if ids.len() > 1
        && ids
            .iter()
            .any(|id| matches!(id.as_ref().trim(), "all" | "none"))
    {
        return Err(SettingsError::Value {
            name: "protocols",
            expected: PROTOCOLS_ALONE.into(),
            value: ids.iter().map(AsRef::as_ref).collect::<Vec<_>>().join(","),
        });
    }
    let mut out = Vec::new();
    for id in ids {
        let id = id.as_ref();
        match id.trim() {
            "all" => out.extend(Protocol::ALL),
            "none" => {}
            t => out.push(Protocol::from_id(t).ok_or_else(|| SettingsError::Value {
                name: "protocols",
                expected: defs::PROTOCOLS_EXPECTED.into(),
                value: id.to_string(),
            })?),
        }
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// The `protocols` setting as text: `none`, or the ids joined by commas.
pub fn protocols_text(protocols: &[Protocol]) -> String {
    if protocols.is_empty() {
        return "none".into();
    }
    protocols
        .iter()
        .map(|p| p.id())
        .collect::<Vec<_>>()
        .join(",")
}

named_enum! {
    /// The Traffic_Signs counting rule (docs/SCORE.md §10.1): `b2d-0.0.4` or `b2d-0.0.3`.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum AbilityRule {
        /// Bench2Drive release 0.0.4: counted once.
        #[default]
        B2d004 = "b2d-0.0.4",
        /// Bench2Drive release 0.0.3: counted twice.
        B2d003 = "b2d-0.0.3",
    }
}

named_enum! {
    /// The `min_speed_grid` setting (docs/PROTOCOLS.md v1.4): on which checkpoint grid a record's min-speed
    /// entries are read under `lb2.0`, `lb2.1` and `lead-nds`: `auto`, `b2d-20` or `lb-4`.
    ///
    /// ```
    /// use monitor_host::settings::MinSpeedGridSetting;
    /// assert_eq!(MinSpeedGridSetting::from_name("b2d-20"), Some(MinSpeedGridSetting::B2d20));
    /// assert_eq!(MinSpeedGridSetting::default().name(), "auto");
    /// assert_eq!(MinSpeedGridSetting::choices(), "auto, b2d-20 or lb-4");
    /// ```
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
    pub enum MinSpeedGridSetting {
        /// Per record: Bench2Drive's 20-checkpoint grid when it holds more than 5 min-speed
        /// entries with a number or any at 100 % or more, else the Leaderboard's (default).
        #[default]
        Auto = "auto",
        /// Every record on Bench2Drive's 20-checkpoint grid: entries regrouped by 5.
        B2d20 = "b2d-20",
        /// Every record on the Leaderboard's grid: every entry below 100 % is an event.
        Lb4 = "lb-4",
    }
}

named_enum! {
    /// Which evaluator's penalty rules to re-check against (docs/SCORE.md §9): `bench2drive` or
    /// `leaderboard20` (the name used in reports and settings).
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum PenaltyFlavour {
        /// Bench2Drive: min-speed infractions carry no factor.
        Bench2Drive = "bench2drive",
        /// CARLA Leaderboard 2.0: each min-speed infraction multiplies by
        /// `1 - 0.3 (1 - pct/100)`.
        Leaderboard20 = "leaderboard20",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn i48_4_settings_read_back_from_config_are_the_settings() {
        let mut s = Settings::default();
        s.apply_pairs([
            ("protocols", "all"),
            ("dt", "0.1"),
            ("lane_width", "3.2"),
            ("slack", "0.7"),
            ("bounds.yaw_rate", "1.1"),
            ("expected_routes", "220"),
            ("duplicates", "last"),
            ("profile", "autoware"),
        ])
        .unwrap();
        for s in [Settings::default(), s] {
            let config = serde_json::to_value(&s).unwrap();
            let back = Settings::from_config(&config).unwrap();
            assert_eq!(back, s);
            assert_eq!(serde_json::to_value(&back).unwrap(), config);
        }
        // What sds never writes is named, with its JSON path.
        let config = serde_json::to_value(Settings::default()).unwrap();
        let refused = |edit: &dyn Fn(&mut serde_json::Value)| {
            let mut c = config.clone();
            edit(&mut c);
            Settings::from_config(&c).unwrap_err().to_string()
        };
        assert!(refused(&|c| c["bounds"]["nope"] = 1.into())
            .contains("config.bounds.nope: not a setting"));
        assert!(refused(&|c| c["nope"] = 1.into()).contains("config.nope: not a setting"));
        assert!(refused(&|c| {
            c.as_object_mut().unwrap().remove("gap_max");
        })
        .contains("config.gap_max: absent"));
        assert!(refused(&|c| c["gap_max"] = "wide".into())
            .contains("config.gap_max: expected a number"));
        assert!(refused(&|c| c["gap_max"] = (-1.0).into())
            .contains("gap_max must be finite and positive"));
        assert!(refused(&|c| c["duplicates"] = "twice".into()).contains(
            "config.duplicates: setting duplicates: expected error, first, last, newest or all"
        ));
        assert!(refused(&|c| c["slack"] = 0.123_456_789_123.into())
            .contains("config.slack: 0.123456789123 is not a value sds writes"));
        assert!(refused(&|c| *c = serde_json::json!([1])).contains("config: expected an object"));
    }

    #[test]
    fn every_name_round_trips() {
        let s = Settings::default();
        for name in Settings::NAMES {
            let v = s.get(name).expect(name);
            let mut t = Settings::default();
            t.set(name, &v)
                .unwrap_or_else(|e| panic!("{name}={v}: {e}"));
            if name == "dt" {
                // A fixed dt turns the per-route inference off.
                assert!(!t.dt_inference);
                t.dt_inference = true;
            }
            assert_eq!(t, s, "{name}");
        }
        let json = serde_json::to_value(&s).unwrap();
        assert_eq!(json["dt"], serde_json::json!(0.05));
        assert_eq!(
            json["bounds"]["yaw_rate"].to_string(),
            s.get("bounds.yaw_rate").unwrap()
        );
        assert_eq!(json["duplicates"], "error");
        // Every name of the config block can be set.
        let mut keys = Vec::new();
        for (k, v) in json.as_object().unwrap() {
            match v.as_object() {
                Some(group) => keys.extend(group.keys().map(|g| format!("{k}.{g}"))),
                None => keys.push(k.clone()),
            }
        }
        // `provenance.host` changes no figure: not in the config block (docs/SCORE.md §13.2).
        let names: Vec<&str> = Settings::NAMES
            .into_iter()
            .filter(|n| *n != "provenance.host")
            .collect();
        assert_eq!(keys, names);
        assert_eq!(s.get("dt").as_deref(), Some("0.05"));
        assert_eq!(s.get("nope"), None);
    }

    /// Checks that the block of docs/SCORE.md between `start` and `end` is `generated`
    /// (`SDS_BLESS=1` rewrites it); skips, saying so, outside the repository.
    fn check_generated_block(start: &str, end: &str, generated: &str, what: &str) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/SCORE.md");
        let Ok(doc) = std::fs::read_to_string(&path) else {
            eprintln!(
                "skipped: {} not found (the crate outside its repository)",
                path.display()
            );
            return;
        };
        let a = doc.find(start).expect("the block's start marker") + start.len();
        let b = a + doc[a..].find(end).expect("the block's end marker");
        if std::env::var_os("SDS_BLESS").is_some() {
            std::fs::write(&path, format!("{}{generated}{}", &doc[..a], &doc[b..])).unwrap();
            return;
        }
        assert_eq!(
            doc[a..b],
            *generated,
            "docs/SCORE.md's {what}: rerun with SDS_BLESS=1"
        );
    }

    /// docs/SCORE.md's settings table is [`defs::markdown_table`]: a setting added, renamed or
    /// re-documented in the table of settings changes the docs with it (`SDS_BLESS=1` rewrites).
    #[test]
    fn score_md_settings_table_is_generated_from_the_table() {
        check_generated_block(
            "<!-- settings table: generated from monitor-host/src/settings/defs.rs; a test checks it (SDS_BLESS=1 rewrites it) -->\n",
            "<!-- end of settings table -->",
            &defs::markdown_table(),
            "settings table",
        );
        assert_eq!(defs::SETTINGS.len(), Settings::NAMES.len());
    }

    /// docs/SCORE.md's list of the settings a sweep takes is [`defs::sweep_markdown`], from the
    /// rows' `sweep` column (`SDS_BLESS=1` rewrites).
    #[test]
    fn score_md_sweep_list_is_generated_from_the_table() {
        check_generated_block(
            "<!-- sweep settings: generated from monitor-host/src/settings/defs.rs; a test checks it (SDS_BLESS=1 rewrites it) -->\n",
            "<!-- end of sweep settings -->",
            &defs::sweep_markdown(),
            "sweep list",
        );
    }

    #[test]
    fn set_parses_and_validates() {
        let mut s = Settings::default();
        s.apply(&["gap_max=6".into(), "factors.workzone=0.4".into()])
            .unwrap();
        assert_eq!((s.gap_max, s.core.factors.workzone), (6.0, 0.4));
        s.set("expected_routes", "220").unwrap();
        assert_eq!(s.expected_routes, Some(220));
        s.set("allow_missing_telemetry", "true").unwrap();
        assert!(s.allow_missing_telemetry);
        s.set("duplicates", "last").unwrap();
        assert_eq!(s.duplicates, DuplicatePolicy::Last);
        s.set("penalty_flavour", "leaderboard20").unwrap();
        assert_eq!(s.penalty_flavour, PenaltyFlavour::Leaderboard20);
        s.set("protocols", "lb2.1, b2d").unwrap();
        assert_eq!(s.protocols, [Protocol::B2d, Protocol::Lb21]);
        assert_eq!(s.get("protocols").as_deref(), Some("b2d,lb2.1"));
        s.set("protocols", "all").unwrap();
        assert_eq!(s.protocols, Protocol::ALL);
        assert!(s.set("protocols", "lb3").is_err());
        s.set("ability_rule", "b2d-0.0.3").unwrap();
        assert_eq!(s.ability_rule, AbilityRule::B2d003);
        assert!(s.set("ability_rule", "0.0.3").is_err());
        s.set("min_speed_grid", "lb-4").unwrap();
        assert_eq!(s.min_speed_grid, MinSpeedGridSetting::Lb4);
        assert!(s.set("min_speed_grid", "20").is_err());
        s.set("dt", "0.1").unwrap();
        assert_eq!(
            (s.core.dt, s.dt_inference, s.get("dt").as_deref()),
            (0.1, false, Some("0.1"))
        );
        let before = s.clone();
        let e = s.set("slack", "-1").unwrap_err();
        assert!(e.to_string().contains("slack"), "{e}");
        assert_eq!(s, before, "a refused setting changes nothing");
        assert!(matches!(
            s.set("gap_max", "x"),
            Err(SettingsError::Value {
                name: "gap_max",
                ..
            })
        ));
        assert!(s.set("gap_max", "NaN").is_err());
        assert!(matches!(
            s.apply(&["slack".into()]),
            Err(SettingsError::Syntax(_))
        ));
        let e = s.set("bounds", "1").unwrap_err().to_string();
        assert!(
            e.contains("bounds.yaw_rate") && e.contains("penalty_flavour"),
            "{e}"
        );
    }
}

/// The options every scored run takes (`sds score`, `sds compare`, `sds watch`, `sds frames`,
/// `sds link` and their Python functions), mapped to [`Settings`] once ([`RunSettings::settings`]).
/// The named options come first, as settings of their names, then `overrides` in order (which can
/// override them).
///
/// ```
/// use monitor_core::Profile;
/// use monitor_host::RunSettings;
///
/// let options = RunSettings {
///     profile: Profile::B2dLegacy,
///     expected_routes: Some(220),
///     protocols: Some(vec!["lb2.1".into()]),
///     overrides: vec![("slack".into(), "0.9".into())],
///     ..RunSettings::default()
/// };
/// let s = options.settings()?;
/// assert_eq!((s.core.profile, s.expected_routes), (Profile::B2dLegacy, Some(220)));
/// assert_eq!(s.get("slack").as_deref(), Some("0.9"));
/// # Ok::<(), monitor_host::SettingsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RunSettings {
    /// The comfort profile.
    pub profile: Profile,
    /// Benchmark size N.
    pub expected_routes: Option<usize>,
    /// The duplicate policy (`None`: the setting's default, or an override's).
    pub duplicates: Option<DuplicatePolicy>,
    /// Score routes without telemetry without telemetry terms.
    pub allow_missing_telemetry: bool,
    /// Worker threads (`None`: all cores).
    pub jobs: Option<usize>,
    /// Which routes of the route XML make the route set (setting `route_subset`).
    pub route_subset: Option<RouteSubset>,
    /// Scoring protocols to add, ids or `all` (setting `protocols`; an item may hold ids joined
    /// by commas).
    pub protocols: Option<Vec<String>>,
    /// Bench2Drive's Traffic_Signs counting rule, one of [`AbilityRule::NAMES`] (setting
    /// `ability_rule`).
    pub ability_rule: Option<String>,
    /// What the lateral error is measured against (setting `lateral_reference`, docs/SCORE.md §3).
    pub lateral_reference: Option<LateralReference>,
    /// Settings by name, applied in order after the options above (`--set NAME=VALUE`).
    pub overrides: Vec<(String, String)>,
}

impl Default for RunSettings {
    /// The physical profile, no option given, no override.
    fn default() -> Self {
        RunSettings {
            profile: Profile::Physical,
            expected_routes: None,
            duplicates: None,
            allow_missing_telemetry: false,
            jobs: None,
            route_subset: None,
            protocols: None,
            ability_rule: None,
            lateral_reference: None,
            overrides: Vec::new(),
        }
    }
}

impl RunSettings {
    /// The settings: the defaults, the options, then the overrides in order, validated.
    ///
    /// # Errors
    /// A setting that names no setting, or whose value does not parse or validate.
    pub fn settings(&self) -> Result<Settings, SettingsError> {
        let mut s = Settings::default();
        s.core.profile = self.profile;
        s.core.bounds = monitor_core::Bounds::of(self.profile);
        s.expected_routes = self.expected_routes;
        if let Some(d) = self.duplicates {
            s.duplicates = d;
        }
        s.allow_missing_telemetry = self.allow_missing_telemetry;
        s.threads = self.jobs;
        if let Some(p) = &self.protocols {
            // A typed list, not text parsed back.
            let ids: Vec<&str> = p.iter().flat_map(|x| x.split(',')).collect();
            s.protocols = protocols_of(&ids)?;
        }
        // The named options as settings of their names, before the overrides (which win).
        let named = self
            .route_subset
            .map(|r| ("route_subset".to_string(), r.name().to_string()))
            .into_iter()
            .chain(
                self.ability_rule
                    .iter()
                    .map(|r| ("ability_rule".to_string(), r.clone())),
            )
            .chain(
                self.lateral_reference
                    .map(|r| ("lateral_reference".to_string(), r.name().to_string())),
            );
        let pairs: Vec<(String, String)> = named.chain(self.overrides.iter().cloned()).collect();
        s.apply_pairs(pairs.iter().map(|(n, v)| (n, v)))?;
        Ok(s)
    }
}
