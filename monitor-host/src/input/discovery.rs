//! Finding the run's files (docs/SCORE.md §2.2): the results files of a directory tree,
//! and the telemetry (`metric_info.json`) and LEAD `infractions.json` of a record.

use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

use walkdir::WalkDir;

use crate::input::warning::Warning;

/// What [`json_files`] found under a results root.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Found {
    /// The candidate results files, sorted by path.
    pub files: Vec<PathBuf>,
    /// Entries whose results cannot be known, with the reason: a folder that cannot be listed or
    /// searched, a `*.json` link that is dangling or loops, a `*.json` that is not a regular
    /// file. Each becomes an invalid entry of the report: its routes are lost, and it says so.
    pub broken: Vec<(PathBuf, String)>,
}

/// The candidate results files under `root`: every `*.json` except `metric_info.json` and
/// `infractions.json`, in byte-wise order of their paths (docs/SCORE.md §14.1's input order).
///
/// Symbolic links are followed inside `root` only: a folder link that leads out of it (`up ->
/// ../..`, which would pull in another run's results) is not followed, with a warning. A folder
/// reached twice (a link loop or a second link) is read once.
pub fn json_files(root: &Path, warnings: &mut Vec<Warning>) -> Found {
    let mut found = Found::default();
    let mut visited = HashSet::new();
    let canon_root = fs::canonicalize(root).unwrap_or_else(|_| root.to_path_buf());
    let is_json = |p: &Path| {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
        p.extension().is_some_and(|e| e == "json")
            && !matches!(
                name.as_deref(),
                Some("metric_info.json" | "infractions.json")
            )
    };
    let mut walk = WalkDir::new(root)
        .follow_links(true)
        .sort_by_file_name()
        .into_iter();
    while let Some(entry) = walk.next() {
        let entry = match entry {
            Ok(e) => e,
            Err(e) => {
                if e.loop_ancestor().is_some() {
                    continue; // a folder link loop: the folder is being read already
                }
                let path = e.path().unwrap_or(root).to_path_buf();
                let reason = e
                    .io_error()
                    .map_or_else(|| e.to_string(), ToString::to_string);
                if fs::metadata(&path).is_ok_and(|m| m.is_dir()) {
                    warnings.push(Warning::CannotList {
                        dir: path.clone(),
                        reason: reason.clone(),
                    });
                    found.broken.push((
                        path,
                        format!(
                            "cannot list this folder ({reason}): the results in it are unknown"
                        ),
                    ));
                } else if is_json(&path) {
                    warnings.push(Warning::CannotRead {
                        path: path.clone(),
                        reason: reason.clone(),
                    });
                    let why = if fs::symlink_metadata(&path).is_ok_and(|m| m.is_symlink()) {
                        format!("a symbolic link that cannot be followed ({reason})")
                    } else {
                        reason
                    };
                    found.broken.push((path, why));
                } else if fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
                    // A plain file that is not a results file: nothing is lost.
                    warnings.push(Warning::CannotRead { path, reason });
                } else {
                    // Cannot even tell what it is (its folder is not searchable): it may hold
                    // results.
                    warnings.push(Warning::CannotRead {
                        path: path.clone(),
                        reason: reason.clone(),
                    });
                    found.broken.push((
                        path,
                        format!("cannot inspect this entry ({reason}): it may hold results"),
                    ));
                }
                continue;
            }
        };
        let path = entry.path();
        if entry.file_type().is_dir() {
            let canon = fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
            if entry.path_is_symlink() && !canon.starts_with(&canon_root) {
                warnings.push(Warning::LinkLeavesRoot {
                    link: path.to_path_buf(),
                    target: canon,
                });
                walk.skip_current_dir();
            } else if !visited.insert(canon) {
                walk.skip_current_dir(); // a second link to a folder already read
            }
        } else if is_json(path) {
            if entry.file_type().is_file() {
                found.files.push(path.to_path_buf());
            } else {
                found.broken.push((
                    path.to_path_buf(),
                    "not a regular file (sds reads only regular files)".to_string(),
                ));
            }
        }
    }
    let bytewise = |a: &PathBuf, b: &PathBuf| {
        a.as_os_str()
            .as_encoded_bytes()
            .cmp(b.as_os_str().as_encoded_bytes())
    };
    found.files.sort_by(bytewise);
    found.broken.sort_by(|a, b| bytewise(&a.0, &b.0));
    found
}

/// Locates a record's `metric_info.json` (docs/SCORE.md §2.2): first
/// `<telemetry_root>/<save_name>/metric_info.json`, then `metric_info.json` in the folder of the
/// result file if that file holds this one record. Returns the first that is a file.
///
/// A `save_name` that is empty, `.`/`..` or contains a path separator is not used as a folder
/// name.
pub fn locate_metric_info(
    telemetry_root: Option<&Path>,
    save_name: &str,
    result_file: &Path,
    file_holds_one_record: bool,
) -> Option<PathBuf> {
    let safe_name = !save_name.is_empty()
        && save_name != "."
        && save_name != ".."
        && !save_name.contains(['/', '\\']);
    if let Some(root) = telemetry_root {
        if safe_name {
            let p = root.join(save_name).join("metric_info.json");
            // `exists`, not `is_file`: a directory or an unreadable file in its place is found
            // here and reported as invalid by the reader, not silently called missing.
            if p.exists() {
                return Some(p);
            }
        }
    }
    if file_holds_one_record {
        let dir = result_file.parent().unwrap_or_else(|| Path::new(""));
        let p = dir.join("metric_info.json");
        if p.exists() {
            return Some(p);
        }
    }
    None
}

/// The route id a `save_name` belongs to: its `RouteScenario_<id>_rep<k>` prefix (the evaluator
/// names telemetry folders `<route_id>_<Town>_<scenario>_<weather>_<timestamp>`). `None` for a
/// name of another form.
///
/// ```
/// use monitor_host::input::discovery::save_name_route;
/// let s = "RouteScenario_24206_rep3_Town12_ConstructionObstacle_12_7_06_17_06_49_04";
/// assert_eq!(save_name_route(s), Some("RouteScenario_24206_rep3"));
/// assert_eq!(save_name_route("RouteScenario_1_rep0"), Some("RouteScenario_1_rep0"));
/// assert_eq!(save_name_route("my_run_3"), None);
/// ```
pub fn save_name_route(save_name: &str) -> Option<&str> {
    let rest = save_name.strip_prefix("RouteScenario_")?;
    let id_len = rest.bytes().take_while(u8::is_ascii_digit).count();
    let rest = rest[id_len..].strip_prefix("_rep")?;
    let rep_len = rest.bytes().take_while(u8::is_ascii_digit).count();
    if id_len == 0 || rep_len == 0 {
        return None;
    }
    let end = "RouteScenario_".len() + id_len + "_rep".len() + rep_len;
    match save_name.as_bytes().get(end) {
        None | Some(b'_') => Some(&save_name[..end]),
        _ => None,
    }
}

/// Why a record's `metric_info.json` was not found (docs/SCORE.md §2.2): what was looked for —
/// the root and the `<save_name>` folder tried, the result file's folder when it holds one
/// record — and, when the root exists but has no such folder, the closest folder name for the
/// same route id (e.g. the run's other timestamp).
pub fn missing_reason(
    telemetry_root: Option<&Path>,
    save_name: Option<&str>,
    route_id: &str,
    result_file: &Path,
    file_holds_one_record: bool,
) -> String {
    let mut parts = Vec::new();
    match (telemetry_root, save_name) {
        (_, None) => parts.push("the record has no save_name (the telemetry folder name)".into()),
        (None, Some(_)) => parts.push("no telemetry root given".into()),
        (Some(root), Some(save)) => {
            let folder = root.join(save);
            if folder.is_dir() {
                parts.push(format!("{} holds no metric_info.json", folder.display()));
            } else {
                let mut text = format!(
                    "no folder {save} under the telemetry root {}",
                    root.display()
                );
                if let Some(near) = closest_folder(root, save, route_id) {
                    text.push_str(&format!(
                        " (the closest folder for {route_id} is {near}: another run of the \
                         route?)"
                    ));
                }
                parts.push(text);
            }
        }
    }
    if file_holds_one_record {
        let dir = result_file.parent().unwrap_or_else(|| Path::new(""));
        parts.push(format!(
            "no metric_info.json beside the results file in {}",
            if dir.as_os_str().is_empty() {
                Path::new(".").display()
            } else {
                dir.display()
            }
        ));
    }
    parts.join("; ")
}

/// The folders whose listing decides that a record's `metric_info.json` is missing, and the
/// reason given ([`locate_metric_info`], [`missing_reason`]): the telemetry root (its folders,
/// the closest one named), `<root>/<save_name>`, and the results file's folder when the file
/// holds this one record. While none of them changes (a folder's size and modification time
/// change when an entry is added, removed or renamed in it), the telemetry is still missing for
/// the same reason. Empty without a `save_name` (nothing is looked for).
///
/// ```
/// use monitor_host::input::discovery::looked_in;
/// use std::path::Path;
/// let at = looked_in(Some(Path::new("tel")), Some("R_1"), Path::new("run/r.json"), true);
/// assert_eq!(at, [Path::new("tel"), Path::new("tel/R_1"), Path::new("run")]);
/// assert!(looked_in(Some(Path::new("tel")), None, Path::new("r.json"), false).is_empty());
/// ```
pub fn looked_in(
    telemetry_root: Option<&Path>,
    save_name: Option<&str>,
    result_file: &Path,
    file_holds_one_record: bool,
) -> Vec<PathBuf> {
    let Some(save) = save_name else {
        return Vec::new();
    };
    let mut at = Vec::new();
    if let Some(root) = telemetry_root {
        at.push(root.to_path_buf());
        let safe = !save.is_empty() && save != "." && save != ".." && !save.contains(['/', '\\']);
        if safe {
            at.push(root.join(save));
        }
    }
    if file_holds_one_record {
        let dir = result_file.parent().unwrap_or_else(|| Path::new(""));
        at.push(if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir.to_path_buf()
        });
    }
    at
}

/// The folder under `root` whose name starts with `<route_id>_` and shares the longest prefix
/// with `save_name` (ties: the smallest name).
fn closest_folder(root: &Path, save_name: &str, route_id: &str) -> Option<String> {
    let prefix = format!("{route_id}_");
    let common = |a: &str| {
        a.bytes()
            .zip(save_name.bytes())
            .take_while(|(x, y)| x == y)
            .count()
    };
    fs::read_dir(root)
        .ok()?
        .filter_map(Result::ok)
        .filter(|e| e.path().is_dir())
        .filter_map(|e| e.file_name().into_string().ok())
        .filter(|n| n.starts_with(&prefix))
        .min_by(|a, b| common(b).cmp(&common(a)).then_with(|| a.cmp(b)))
}

/// The `infractions.json` beside a located `metric_info.json`, if it exists.
pub fn lead_infractions_beside(metric_info: &Path) -> Option<PathBuf> {
    let p = metric_info
        .parent()
        .unwrap_or_else(|| Path::new(""))
        .join("infractions.json");
    p.is_file().then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_prefers_root_then_result_folder() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("telemetry");
        let save = "RouteScenario_1_rep0_Town01_X_1_1_01_01_00_00_00";
        std::fs::create_dir_all(root.join(save)).unwrap();
        let results = dir.path().join("res");
        std::fs::create_dir_all(&results).unwrap();
        let result_file = results.join("r.json");
        std::fs::write(&result_file, "{}").unwrap();

        assert_eq!(
            locate_metric_info(Some(&root), save, &result_file, true),
            None
        );
        std::fs::write(results.join("metric_info.json"), "{}").unwrap();
        assert_eq!(
            locate_metric_info(Some(&root), save, &result_file, true),
            Some(results.join("metric_info.json"))
        );
        // A merged file (many records) never uses its folder.
        assert_eq!(
            locate_metric_info(Some(&root), save, &result_file, false),
            None
        );
        let mi = root.join(save).join("metric_info.json");
        std::fs::write(&mi, "{}").unwrap();
        assert_eq!(
            locate_metric_info(Some(&root), save, &result_file, true),
            Some(mi.clone())
        );
        assert_eq!(locate_metric_info(None, save, &result_file, false), None);
        assert_eq!(
            locate_metric_info(Some(&root), "../telemetry", &result_file, false),
            None
        );
        assert_eq!(lead_infractions_beside(&mi), None);
        let other = "RouteScenario_1_rep0_Town01_X_1_1_02_02_00_00_00";
        std::fs::create_dir_all(root.join(other)).unwrap();
        let why = missing_reason(
            Some(&root),
            Some("RouteScenario_1_rep0_Town01_X_1_1_09_09"),
            "RouteScenario_1_rep0",
            &result_file,
            false,
        );
        assert!(
            why.contains(&format!(
                "the closest folder for RouteScenario_1_rep0 is {save}"
            )),
            "{why}"
        );
        assert!(why.contains(&root.display().to_string()), "{why}");
        let why = missing_reason(None, Some(save), "RouteScenario_1_rep0", &result_file, true);
        assert!(
            why.contains("no telemetry root") && why.contains("beside the results file"),
            "{why}"
        );
        std::fs::write(root.join(save).join("infractions.json"), "{}").unwrap();
        assert_eq!(
            lead_infractions_beside(&mi),
            Some(root.join(save).join("infractions.json"))
        );
    }
}
