//! Every setting of a run (`SDS-SPEC.md` v1.2 §1.3, §2, §5, §8 and the core's §3-§7): the core's
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

use monitor_core::{Config, ConfigError, Profile};

use crate::input::duplicates::DuplicatePolicy;
use crate::input::route_set::RouteSubset;

/// Why a setting was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SettingsError {
    /// `--set` text without `=`.
    #[error("--set {0}: expected NAME=VALUE")]
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
        /// What it takes.
        expected: &'static str,
        /// The text given.
        value: String,
    },
    /// The core's configuration is inconsistent.
    #[error("invalid configuration: {0}")]
    Config(ConfigError),
    /// A host setting is out of its range.
    #[error("invalid configuration: {name} must be {rule}")]
    Range {
        /// The setting.
        name: &'static str,
        /// The rule it breaks.
        rule: &'static str,
    },
}

/// What the lateral error is measured against (`SDS-SPEC.md` v1.2 §2) **\[decision\]**.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LateralReference {
    /// The route polyline, its junction gaps filled by the map where the town has one (`route`).
    #[default]
    Route,
    /// The nearest driving lane of the map, whichever it is (`lane`); routes in towns without a
    /// map fall back to [`LateralReference::Route`] with a warning.
    Lane,
}

impl LateralReference {
    /// `route` or `lane`.
    pub fn name(self) -> &'static str {
        match self {
            LateralReference::Route => "route",
            LateralReference::Lane => "lane",
        }
    }

    /// The setting from its name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "route" => Some(LateralReference::Route),
            "lane" => Some(LateralReference::Lane),
            _ => None,
        }
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
    /// Re-acquisition of the lateral reference (§2, v1.4): at a frame whose step exceeds the
    /// previous frame's by more than this (and at a first frame whose step is not 0), the
    /// forward search looks at the whole rest of the route instead of `lookahead` (10)
    /// **\[decision\]**.
    pub reacquire_steps: u64,
    /// What the lateral error is measured against (§2): the route (`route`, default) or the
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
    /// Factors of the penalty re-check (§8).
    pub penalty_flavour: PenaltyFlavour,
    /// Benchmark size N: routes not found count as 0 / failed (§8.1).
    pub expected_routes: Option<usize>,
    /// Which copy of a duplicated route id is scored (§1.5) **\[decision\]**.
    pub duplicates: DuplicatePolicy,
    /// Which routes of `--routes` make the route set: `all` (default) or those `found` with a
    /// record **\[decision\]**.
    pub route_subset: RouteSubset,
    /// Infer each route's step period from its record (§1.2); `false` uses `dt` for every
    /// route. Setting `dt` turns it off.
    pub dt_inference: bool,
    /// Score routes without telemetry without telemetry terms instead of failing them.
    pub allow_missing_telemetry: bool,
    /// Worker threads (`None`: all cores). Not part of the report: it never changes a number.
    pub threads: Option<usize>,
    /// Thresholds of the distance and stationary figures (§8.5).
    pub motion: MotionSettings,
    /// How the route's `events` place the evaluator's other infractions and stationary
    /// stretches on the frame axis.
    pub events: EventSettings,
    /// Scoring protocols to add (§8.4; default none).
    pub protocols: Vec<Protocol>,
    /// Bench2Drive's Traffic_Signs counting rule (§8.2; default `b2d-0.0.4`).
    pub ability_rule: AbilityRule,
    /// Which min-speed checkpoint grid a record's entries are read on under the Leaderboard
    /// protocols (§8.4 v1.4; default `auto`) **\[decision\]**.
    pub min_speed_grid: MinSpeedGridSetting,
    /// Name the host in the report's `inputs.provenance` (§13; default true) **\[decision\]**.
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
            protocols: Vec::new(),
            ability_rule: AbilityRule::B2d004,
            min_speed_grid: MinSpeedGridSetting::Auto,
            provenance_host: true,
        }
    }
}

fn f32_of(name: &'static str, v: &str) -> Result<f32, SettingsError> {
    // Through f64, as a JSON reader does, so `--set` gives the value the report prints.
    Ok(f64_of(name, v)? as f32)
}

fn f64_of(name: &'static str, v: &str) -> Result<f64, SettingsError> {
    v.trim().parse().map_err(|_| SettingsError::Value {
        name,
        expected: "a number",
        value: v.to_string(),
    })
}

fn bool_of(name: &'static str, v: &str) -> Result<bool, SettingsError> {
    v.trim().parse().map_err(|_| SettingsError::Value {
        name,
        expected: "true or false",
        value: v.to_string(),
    })
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

fn u16_of(name: &'static str, v: &str) -> Result<u16, SettingsError> {
    v.trim().parse().map_err(|_| SettingsError::Value {
        name,
        expected: "an integer in 0..=65535",
        value: v.to_string(),
    })
}

impl Settings {
    /// Every settable name, in the order of the report's `config` block.
    pub const NAMES: [&'static str; 45] = [
        "ability_rule",
        "align_max_dist",
        "align_tie",
        "allow_missing_telemetry",
        "anomalous_excess",
        "bounds.lat_acc",
        "bounds.lon_acc_max",
        "bounds.lon_acc_min",
        "bounds.lon_jerk",
        "bounds.mag_jerk",
        "bounds.yaw_acc",
        "bounds.yaw_rate",
        "chunk_len",
        "critical_excess",
        "decel_threshold",
        "decel_window",
        "dt",
        "dt_inference",
        "duplicates",
        "ego_half_width",
        "events.min_standing",
        "events.signal_reach",
        "expected_routes",
        "factors.anomalous",
        "factors.critical",
        "factors.layout",
        "factors.nodecel",
        "factors.workzone",
        "gap_max",
        "lane_width",
        "lateral_reference",
        "legacy_jerk_spacing",
        "lookahead",
        "min_chunk",
        "min_speed_grid",
        "motion.moving_speed",
        "motion.stationary_speed",
        "penalty_flavour",
        "profile",
        "protocols",
        "provenance.host",
        "reacquire_steps",
        "route_subset",
        "slack",
        "stationary_speed",
    ];

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
        let c = &mut self.core;
        let b = &mut c.bounds;
        let f = &mut c.factors;
        let Some(&key) = Self::NAMES.iter().find(|n| **n == name) else {
            return Err(SettingsError::Unknown { name: name.into() });
        };
        match key {
            "ability_rule" => {
                self.ability_rule =
                    AbilityRule::from_name(v.trim()).ok_or(SettingsError::Value {
                        name: key,
                        expected: "b2d-0.0.4 or b2d-0.0.3",
                        value: v.into(),
                    })?
            }
            "min_speed_grid" => {
                self.min_speed_grid =
                    MinSpeedGridSetting::from_name(v.trim()).ok_or(SettingsError::Value {
                        name: key,
                        expected: "auto, b2d-20 or lb-4",
                        value: v.into(),
                    })?
            }
            "protocols" => {
                self.protocols = parse_protocols(v).map_err(|_| SettingsError::Value {
                    name: key,
                    expected:
                        "all, none, or comma-separated ids of b2d, lb2.0, lb2.1, lead-nds, f2d",
                    value: v.into(),
                })?
            }
            "align_max_dist" => self.align_max_dist = f64_of(key, v)?,
            "align_tie" => self.align_tie = f64_of(key, v)?,
            "gap_max" => self.gap_max = f64_of(key, v)?,
            "lookahead" => self.lookahead = f64_of(key, v)?,
            "reacquire_steps" => {
                self.reacquire_steps = v.trim().parse().map_err(|_| SettingsError::Value {
                    name: key,
                    expected: "a step count (an integer, 0 or more)",
                    value: v.into(),
                })?
            }
            "lateral_reference" => {
                self.lateral_reference =
                    LateralReference::from_name(v.trim()).ok_or(SettingsError::Value {
                        name: key,
                        expected: "route or lane",
                        value: v.into(),
                    })?
            }
            "lane_width" | "ego_half_width" => {
                let x = f64_of(key, v)?;
                if key == "lane_width" {
                    self.lane_width = x;
                } else {
                    self.ego_half_width = x;
                }
                // Without a map the core's slack is the default lane's (§2).
                self.core.slack = (self.lane_width / 2.0 - self.ego_half_width) as f32;
            }
            "allow_missing_telemetry" => self.allow_missing_telemetry = bool_of(key, v)?,
            "provenance.host" => self.provenance_host = bool_of(key, v)?,
            "dt_inference" => self.dt_inference = bool_of(key, v)?,
            "route_subset" => {
                self.route_subset =
                    RouteSubset::from_name(v.trim()).ok_or(SettingsError::Value {
                        name: key,
                        expected: "all or found",
                        value: v.into(),
                    })?
            }
            "duplicates" => {
                self.duplicates =
                    DuplicatePolicy::from_name(v.trim()).ok_or(SettingsError::Value {
                        name: key,
                        expected: "error, first, last, newest or all",
                        value: v.into(),
                    })?
            }
            "expected_routes" => {
                self.expected_routes = match v.trim() {
                    "null" | "" => None,
                    t => Some(t.parse().map_err(|_| SettingsError::Value {
                        name: key,
                        expected: "a route count or null",
                        value: v.into(),
                    })?),
                }
            }
            "penalty_flavour" => {
                self.penalty_flavour =
                    PenaltyFlavour::from_name(v.trim()).ok_or(SettingsError::Value {
                        name: key,
                        expected: "bench2drive or leaderboard20",
                        value: v.into(),
                    })?
            }
            "profile" => {
                c.profile = [Profile::Physical, Profile::B2dLegacy]
                    .into_iter()
                    .find(|p| p.name() == v.trim())
                    .ok_or(SettingsError::Value {
                        name: key,
                        expected: "physical or b2d-legacy",
                        value: v.into(),
                    })?
            }
            "anomalous_excess" => c.anomalous_excess = f32_of(key, v)?,
            "critical_excess" => c.critical_excess = f32_of(key, v)?,
            "decel_threshold" => c.decel_threshold = f32_of(key, v)?,
            "dt" => {
                // A fixed step period: every route uses it (spec section 1.2).
                c.dt = f32_of(key, v)?;
                self.dt_inference = false;
            }
            "legacy_jerk_spacing" => c.legacy_jerk_spacing = f32_of(key, v)?,
            "slack" => c.slack = f32_of(key, v)?,
            "stationary_speed" => c.stationary_speed = f32_of(key, v)?,
            "chunk_len" => c.chunk_len = u16_of(key, v)?,
            "min_chunk" => c.min_chunk = u16_of(key, v)?,
            "decel_window" => c.decel_window = u16_of(key, v)?,
            "bounds.lat_acc" => b.lat_acc = f32_of(key, v)?,
            "bounds.lon_acc_max" => b.lon_acc_max = f32_of(key, v)?,
            "bounds.lon_acc_min" => b.lon_acc_min = f32_of(key, v)?,
            "bounds.lon_jerk" => b.lon_jerk = f32_of(key, v)?,
            "bounds.mag_jerk" => b.mag_jerk = f32_of(key, v)?,
            "bounds.yaw_acc" => b.yaw_acc = f32_of(key, v)?,
            "bounds.yaw_rate" => b.yaw_rate = f32_of(key, v)?,
            "factors.anomalous" => f.anomalous = f64_of(key, v)?,
            "factors.critical" => f.critical = f64_of(key, v)?,
            "factors.layout" => f.layout = f64_of(key, v)?,
            "factors.nodecel" => f.nodecel = f64_of(key, v)?,
            "factors.workzone" => f.workzone = f64_of(key, v)?,
            "motion.moving_speed" => self.motion.moving_speed = f64_of(key, v)?,
            "events.min_standing" => self.events.min_standing = f64_of(key, v)?,
            "events.signal_reach" => self.events.signal_reach = f64_of(key, v)?,
            "motion.stationary_speed" => self.motion.stationary_speed = f64_of(key, v)?,
            _ => return Err(SettingsError::Unknown { name: name.into() }),
        }
        Ok(())
    }

    /// The value of a setting as a person writes it (`0.05`, not the f32's f64 widening), or
    /// `None` for an unknown name.
    pub fn get(&self, name: &str) -> Option<String> {
        let c = &self.core;
        let (b, f) = (&c.bounds, &c.factors);
        Some(match name {
            "ability_rule" => self.ability_rule.name().into(),
            "protocols" => protocols_text(&self.protocols),
            "min_speed_grid" => self.min_speed_grid.name().into(),
            "align_max_dist" => self.align_max_dist.to_string(),
            "align_tie" => self.align_tie.to_string(),
            "gap_max" => self.gap_max.to_string(),
            "lookahead" => self.lookahead.to_string(),
            "reacquire_steps" => self.reacquire_steps.to_string(),
            "lateral_reference" => self.lateral_reference.name().into(),
            "lane_width" => self.lane_width.to_string(),
            "ego_half_width" => self.ego_half_width.to_string(),
            "allow_missing_telemetry" => self.allow_missing_telemetry.to_string(),
            "provenance.host" => self.provenance_host.to_string(),
            "dt_inference" => self.dt_inference.to_string(),
            "duplicates" => self.duplicates.name().into(),
            "route_subset" => self.route_subset.name().into(),
            "expected_routes" => self
                .expected_routes
                .map_or_else(|| "null".into(), |n| n.to_string()),
            "penalty_flavour" => self.penalty_flavour.name().into(),
            "profile" => c.profile.name().into(),
            "anomalous_excess" => c.anomalous_excess.to_string(),
            "critical_excess" => c.critical_excess.to_string(),
            "decel_threshold" => c.decel_threshold.to_string(),
            "dt" => c.dt.to_string(),
            "legacy_jerk_spacing" => c.legacy_jerk_spacing.to_string(),
            "slack" => c.slack.to_string(),
            "stationary_speed" => c.stationary_speed.to_string(),
            "chunk_len" => c.chunk_len.to_string(),
            "min_chunk" => c.min_chunk.to_string(),
            "decel_window" => c.decel_window.to_string(),
            "bounds.lat_acc" => b.lat_acc.to_string(),
            "bounds.lon_acc_max" => b.lon_acc_max.to_string(),
            "bounds.lon_acc_min" => b.lon_acc_min.to_string(),
            "bounds.lon_jerk" => b.lon_jerk.to_string(),
            "bounds.mag_jerk" => b.mag_jerk.to_string(),
            "bounds.yaw_acc" => b.yaw_acc.to_string(),
            "bounds.yaw_rate" => b.yaw_rate.to_string(),
            "factors.anomalous" => f.anomalous.to_string(),
            "factors.critical" => f.critical.to_string(),
            "factors.layout" => f.layout.to_string(),
            "factors.nodecel" => f.nodecel.to_string(),
            "factors.workzone" => f.workzone.to_string(),
            "motion.moving_speed" => self.motion.moving_speed.to_string(),
            "events.min_standing" => self.events.min_standing.to_string(),
            "events.signal_reach" => self.events.signal_reach.to_string(),
            "motion.stationary_speed" => self.motion.stationary_speed.to_string(),
            _ => return None,
        })
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
        let checks = [
            (
                "gap_max",
                self.gap_max,
                "finite and positive",
                self.gap_max > 0.0,
            ),
            (
                "lookahead",
                self.lookahead,
                "finite and not negative",
                self.lookahead >= 0.0,
            ),
            (
                "lane_width",
                self.lane_width,
                "finite and positive",
                self.lane_width > 0.0,
            ),
            (
                "ego_half_width",
                self.ego_half_width,
                "finite and not negative",
                self.ego_half_width >= 0.0,
            ),
            (
                "align_max_dist",
                self.align_max_dist,
                "finite and not negative",
                self.align_max_dist >= 0.0,
            ),
            (
                "align_tie",
                self.align_tie,
                "finite and not negative",
                self.align_tie >= 0.0,
            ),
            (
                "events.min_standing",
                self.events.min_standing,
                "finite and not negative",
                self.events.min_standing >= 0.0,
            ),
            (
                "events.signal_reach",
                self.events.signal_reach,
                "finite and not negative",
                self.events.signal_reach >= 0.0,
            ),
            (
                "motion.moving_speed",
                self.motion.moving_speed,
                "finite and not negative",
                self.motion.moving_speed >= 0.0,
            ),
            (
                "motion.stationary_speed",
                self.motion.stationary_speed,
                "finite and not negative",
                self.motion.stationary_speed >= 0.0,
            ),
        ];
        for (name, x, rule, ok) in checks {
            if !(ok && x.is_finite()) {
                return Err(SettingsError::Range { name, rule });
            }
        }
        if self.threads == Some(0) {
            return Err(SettingsError::Range {
                name: "threads (--jobs)",
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

/// The report's `config` block: every setting by name, keys in alphabetical order, the groups
/// `bounds` and `factors` as objects, f32 values printed as the decimal a person writes
/// ([`decimal`]). `threads` and `provenance.host` are not part of it.
impl serde::Serialize for Settings {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let c = &self.core;
        let (b, f) = (&c.bounds, &c.factors);
        let w = decimal;
        let bounds: [(&str, f64); 7] = [
            ("lat_acc", w(b.lat_acc)),
            ("lon_acc_max", w(b.lon_acc_max)),
            ("lon_acc_min", w(b.lon_acc_min)),
            ("lon_jerk", w(b.lon_jerk)),
            ("mag_jerk", w(b.mag_jerk)),
            ("yaw_acc", w(b.yaw_acc)),
            ("yaw_rate", w(b.yaw_rate)),
        ];
        let factors: [(&str, f64); 5] = [
            ("anomalous", f.anomalous),
            ("critical", f.critical),
            ("layout", f.layout),
            ("nodecel", f.nodecel),
            ("workzone", f.workzone),
        ];
        let mut m = s.serialize_map(Some(30))?;
        m.serialize_entry("ability_rule", self.ability_rule.name())?;
        m.serialize_entry("align_max_dist", &self.align_max_dist)?;
        m.serialize_entry("align_tie", &self.align_tie)?;
        m.serialize_entry("allow_missing_telemetry", &self.allow_missing_telemetry)?;
        m.serialize_entry("anomalous_excess", &w(c.anomalous_excess))?;
        m.serialize_entry("bounds", &Group(&bounds))?;
        m.serialize_entry("chunk_len", &c.chunk_len)?;
        m.serialize_entry("critical_excess", &w(c.critical_excess))?;
        m.serialize_entry("decel_threshold", &w(c.decel_threshold))?;
        m.serialize_entry("decel_window", &c.decel_window)?;
        m.serialize_entry("dt", &w(c.dt))?;
        m.serialize_entry("dt_inference", &self.dt_inference)?;
        m.serialize_entry("duplicates", self.duplicates.name())?;
        m.serialize_entry("ego_half_width", &self.ego_half_width)?;
        let events = [
            ("min_standing", self.events.min_standing),
            ("signal_reach", self.events.signal_reach),
        ];
        m.serialize_entry("events", &Group(&events))?;
        m.serialize_entry("expected_routes", &self.expected_routes)?;
        m.serialize_entry("factors", &Group(&factors))?;
        m.serialize_entry("gap_max", &self.gap_max)?;
        m.serialize_entry("lane_width", &self.lane_width)?;
        m.serialize_entry("lateral_reference", self.lateral_reference.name())?;
        m.serialize_entry("legacy_jerk_spacing", &w(c.legacy_jerk_spacing))?;
        m.serialize_entry("lookahead", &self.lookahead)?;
        m.serialize_entry("min_chunk", &c.min_chunk)?;
        m.serialize_entry("min_speed_grid", self.min_speed_grid.name())?;
        let motion = [
            ("moving_speed", self.motion.moving_speed),
            ("stationary_speed", self.motion.stationary_speed),
        ];
        m.serialize_entry("motion", &Group(&motion))?;
        m.serialize_entry("penalty_flavour", self.penalty_flavour.name())?;
        m.serialize_entry("profile", c.profile.name())?;
        let ids: Vec<&str> = self.protocols.iter().map(|p| p.id()).collect();
        m.serialize_entry("protocols", &ids)?;
        m.serialize_entry("reacquire_steps", &self.reacquire_steps)?;
        m.serialize_entry("route_subset", self.route_subset.name())?;
        m.serialize_entry("slack", &w(c.slack))?;
        m.serialize_entry("stationary_speed", &w(c.stationary_speed))?;
        m.end()
    }
}

/// A settings group (`bounds`, `factors`) as a JSON object.
struct Group<'a>(&'a [(&'a str, f64)]);

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

/// One scoring protocol (§8.4).
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

/// The Traffic_Signs counting rule (§8.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AbilityRule {
    /// Bench2Drive release 0.0.4: counted once.
    #[default]
    B2d004,
    /// Bench2Drive release 0.0.3: counted twice.
    B2d003,
}

impl AbilityRule {
    /// `b2d-0.0.4` or `b2d-0.0.3`.
    pub fn name(self) -> &'static str {
        match self {
            AbilityRule::B2d004 => "b2d-0.0.4",
            AbilityRule::B2d003 => "b2d-0.0.3",
        }
    }

    /// The rule of a name.
    pub fn from_name(name: &str) -> Option<AbilityRule> {
        [AbilityRule::B2d004, AbilityRule::B2d003]
            .into_iter()
            .find(|r| r.name() == name)
    }
}

/// The `min_speed_grid` setting (§8.4 v1.4): on which checkpoint grid a record's min-speed
/// entries are read under `lb2.0`, `lb2.1` and `lead-nds`.
///
/// ```
/// use monitor_host::settings::MinSpeedGridSetting;
/// assert_eq!(MinSpeedGridSetting::from_name("b2d-20"), Some(MinSpeedGridSetting::B2d20));
/// assert_eq!(MinSpeedGridSetting::default().name(), "auto");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MinSpeedGridSetting {
    /// Per record: Bench2Drive's 20-checkpoint grid when it holds more than 5 min-speed
    /// entries with a number or any at 100 % or more, else the Leaderboard's (default).
    #[default]
    Auto,
    /// Every record on Bench2Drive's 20-checkpoint grid: entries regrouped by 5.
    B2d20,
    /// Every record on the Leaderboard's grid: every entry below 100 % is an event.
    Lb4,
}

impl MinSpeedGridSetting {
    /// `auto`, `b2d-20` or `lb-4`.
    pub fn name(self) -> &'static str {
        match self {
            MinSpeedGridSetting::Auto => "auto",
            MinSpeedGridSetting::B2d20 => "b2d-20",
            MinSpeedGridSetting::Lb4 => "lb-4",
        }
    }

    /// The setting of a name.
    pub fn from_name(name: &str) -> Option<MinSpeedGridSetting> {
        [
            MinSpeedGridSetting::Auto,
            MinSpeedGridSetting::B2d20,
            MinSpeedGridSetting::Lb4,
        ]
        .into_iter()
        .find(|g| g.name() == name)
    }
}

/// Which evaluator's penalty rules to re-check against (§8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PenaltyFlavour {
    /// Bench2Drive: min-speed infractions carry no factor.
    Bench2Drive,
    /// CARLA Leaderboard 2.0: each min-speed infraction multiplies by `1 - 0.3 (1 - pct/100)`.
    Leaderboard20,
}

impl PenaltyFlavour {
    /// `"bench2drive"` or `"leaderboard20"` (the name used in reports and on the command line).
    pub fn name(self) -> &'static str {
        match self {
            PenaltyFlavour::Bench2Drive => "bench2drive",
            PenaltyFlavour::Leaderboard20 => "leaderboard20",
        }
    }

    /// The flavour named `name` (see [`PenaltyFlavour::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        [PenaltyFlavour::Bench2Drive, PenaltyFlavour::Leaderboard20]
            .into_iter()
            .find(|f| f.name() == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        // `provenance.host` changes no figure: not in the config block (v1.4 §13).
        let names: Vec<&str> = Settings::NAMES
            .into_iter()
            .filter(|n| *n != "provenance.host")
            .collect();
        assert_eq!(keys, names);
        assert_eq!(s.get("dt").as_deref(), Some("0.05"));
        assert_eq!(s.get("nope"), None);
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

/// The options every front end of a scored run shares (`sds score`, `sds compare`, the Python
/// `sds.score`), before the overrides by name: one mapping to [`Settings`] for all of them.
///
/// ```
/// use monitor_core::Profile;
/// use monitor_host::settings::RunOptions;
///
/// let options = RunOptions {
///     profile: Profile::B2dLegacy,
///     expected_routes: Some(220),
///     overrides: vec![("slack".into(), "0.9".into())],
///     ..RunOptions::default()
/// };
/// let s = options.settings()?;
/// assert_eq!((s.core.profile, s.expected_routes), (Profile::B2dLegacy, Some(220)));
/// assert_eq!(s.get("slack").as_deref(), Some("0.9"));
/// # Ok::<(), monitor_host::SettingsError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunOptions {
    /// The comfort profile.
    pub profile: Profile,
    /// Benchmark size N.
    pub expected_routes: Option<usize>,
    /// The duplicate policy (`None`: the setting's default, or an override's).
    pub duplicates: Option<DuplicatePolicy>,
    /// Score routes without telemetry without telemetry terms.
    pub allow_missing_telemetry: bool,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Overrides by name, applied in order after the options above (`--set NAME=VALUE`).
    pub overrides: Vec<(String, String)>,
}

impl Default for RunOptions {
    /// The defaults: physical profile, no option given, no override.
    fn default() -> Self {
        RunOptions {
            profile: Profile::Physical,
            expected_routes: None,
            duplicates: None,
            allow_missing_telemetry: false,
            threads: None,
            overrides: Vec::new(),
        }
    }
}

impl RunOptions {
    /// The settings: the defaults, the options, then the overrides in order, validated.
    ///
    /// # Errors
    /// An override that names no setting or whose value does not parse, or settings that do
    /// not validate.
    pub fn settings(&self) -> Result<Settings, SettingsError> {
        let mut s = Settings::default();
        s.core.profile = self.profile;
        s.expected_routes = self.expected_routes;
        if let Some(d) = self.duplicates {
            s.duplicates = d;
        }
        s.allow_missing_telemetry = self.allow_missing_telemetry;
        s.threads = self.threads;
        s.apply_pairs(self.overrides.iter().map(|(n, v)| (n, v)))?;
        Ok(s)
    }
}
