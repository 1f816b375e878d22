//! The command line's spelling of the options the library's messages name neutrally (by the
//! setting's or option's name: `expected_routes`, `route_subset = found`): `sds` appends its
//! flags to an error's or a warning's message, `(--expected-routes, --route-subset)`,
//! `(--set dt=SECONDS)`.

/// The flag of a neutral option name (`None`: the option has no flag of its own; it is then a
/// setting, given with `--set NAME=VALUE`).
pub fn flag(option: &str) -> Option<&'static str> {
    Some(match option {
        "set" => "--set",
        "jobs" => "--jobs",
        "duplicates" => "--duplicates",
        "expected_routes" => "--expected-routes",
        "route_subset" => "--route-subset",
        "telemetry" => "--telemetry",
        "maps" => "--maps",
        "routes" => "--routes",
        "labels" => "--labels",
        "families" => "--families",
        "weathers" => "--weathers",
        "group_by" => "--group-by",
        "seeds" => "--seeds",
        "baseline" => "--baseline",
        "protocols" => "--protocol",
        "bootstrap_samples" => "--bootstrap-samples",
        "repro.halfwidth" => "--repro-halfwidth",
        "common_routes" => "--common-routes",
        "sweep" => "--sweep",
        "allow_missing_telemetry" => "--allow-missing-telemetry",
        _ => return None,
    })
}

/// ` (--a, --b)`: the flags of the options an error names, or nothing.
pub fn suffix(e: &anyhow::Error) -> String {
    let options: &[&str] = if let Some(e) = e.downcast_ref::<monitor_host::Error>() {
        monitor_host::error_kind::options(e)
    } else if let Some(e) = e.downcast_ref::<monitor_host::merge::MergeError>() {
        monitor_host::error_kind::merge_options(e)
    } else if let Some(e) = e.downcast_ref::<monitor_host::SettingsError>() {
        monitor_host::error_kind::settings_options(e)
    } else if let Some(monitor_host::RequestError::Settings(e)) =
        e.downcast_ref::<monitor_host::RequestError>()
    {
        monitor_host::error_kind::settings_options(e)
    } else {
        &[]
    };
    flags(options)
}

/// ` (--a, --set b=VALUE)`: `options` as the command line spells them (a setting with its value
/// when the name carries one, `dt=SECONDS`), or nothing.
fn flags(options: &[&str]) -> String {
    let flags: Vec<String> = options
        .iter()
        .map(|o| match flag(o) {
            Some(f) => f.to_string(),
            None if o.contains('=') => format!("--set {o}"),
            None => format!("--set {o}=..."),
        })
        .collect();
    if flags.is_empty() {
        String::new()
    } else {
        format!(" ({})", flags.join(", "))
    }
}

/// A warning as `sds` prints it: the library's text, which names options neutrally (`the
/// setting dt=SECONDS`, `(maps)`), then the command line's flags for them, as errors get theirs
/// (`(--set dt=SECONDS)`, `(--maps)`).
pub fn warning(w: &monitor_host::warning::Warning) -> String {
    format!("{w}{}", flags(monitor_host::error_kind::warning_options(w)))
}

/// A report's warning or note as `sds` prints it after `sds: `: `warning: ...` or, for a note
/// ([`monitor_host::warning::Warning::is_note`]), `note: ...`.
pub fn line(w: &monitor_host::warning::Warning) -> String {
    let class = if w.is_note() { "note" } else { "warning" };
    format!("{class}: {}", warning(w))
}
