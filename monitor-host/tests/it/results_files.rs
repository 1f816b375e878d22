//! Reads the real Bench2Drive result fixtures in `shared/fixtures/b2d/` (SOURCES.md describes
//! each) through `results_file::read_results` and checks them against their own stored totals and the
//! docs/SCORE.md §8/§8 rules. Skips (passes with a printed reason) when the shared folder is absent.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use monitor_host::input::collision::{count_workzone, is_workzone, parse_collision, CollisionList};
use monitor_host::input::record::Record;
use monitor_host::input::results_file::{self as results, ResultSet};
use monitor_host::route::penalty::check_penalty;
use monitor_host::settings::PenaltyFlavour;

const B2D: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/fixtures/b2d");

const TFPP: &str = "carla_garage_tfpp_b2d_traj_merged.json";
const PDM: &str = "carla_garage_pdm_lite_b2d_traj_merged.json";
const UNIAD: &str = "b2dzoo_UniAD-Base_merged.json";
const SIMLINGO: &str = "simlingo_bench2drive220_targetpoint_checkpoint.json";
const R3564: &str = "pdmlite_route3564_endpoint_tickruntime_mesh_collisions.json";
const CRASHED: &str = "pdmlite_route24206_endpoint_crashed_empty.json";

/// The fixture's path, or `None` (after printing why) when the shared fixtures are absent.
fn fixture(name: &str) -> Option<PathBuf> {
    let p = Path::new(B2D).join(name);
    if p.is_file() {
        Some(p)
    } else {
        eprintln!("skipped: fixture {} not found", p.display());
        None
    }
}

fn valid(set: &ResultSet) -> Vec<&Record> {
    set.records
        .iter()
        .map(|r| match &r.entry {
            Ok(rec) => rec,
            Err(e) => panic!("{}#{}: invalid record: {e}", r.source.display(), r.index),
        })
        .collect()
}

#[test]
fn every_record_of_every_fixture_loads() {
    let expected = [
        (TFPP, 220),
        (PDM, 220),
        (UNIAD, 218),
        (SIMLINGO, 220),
        (R3564, 1),
        (CRASHED, 0),
    ];
    for (name, n) in expected {
        let Some(path) = fixture(name) else { return };
        let set = results::read_results(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(set.records.len(), n, "{name}");
        let recs = valid(&set);
        assert!(set.broken_files.is_empty());
        for (i, lr) in set.records.iter().enumerate() {
            assert_eq!((lr.index, lr.records_in_file), (i, n), "{name}");
            assert_eq!(lr.source, path);
        }
        for r in &recs {
            assert!(r.xml_id().is_some(), "{name}: {}", r.route_id);
            assert!(r.weather_id.is_some() && r.save_name.is_some() && r.town_name.is_some());
            assert!(r.meta.route_length.is_some());
            // every scenario name in these files is `<type>_1` (T_Junction_1, MergerIntoSlowTrafficV2_1)
            assert_eq!(r.scenario_name, format!("{}_1", r.scenario_type()));
            // score_composed is computed from the unrounded penalty, score_penalty is stored
            // rounded to 6 decimals: they agree within score_route * 5e-7 (+ the composed
            // value's own 6-decimal rounding), not exactly
            let bound = r.score_route * 5e-7 + 5e-7 + 1e-12;
            let diff = (r.score_composed - r.score_route * r.score_penalty).abs();
            assert!(diff <= bound, "{name}: {} off by {diff}", r.route_id);
        }
        if n == 220 {
            // 44 scenario types with 5 routes each
            let mut types: BTreeMap<&str, usize> = BTreeMap::new();
            for r in &recs {
                *types.entry(r.scenario_type()).or_default() += 1;
            }
            assert_eq!(types.len(), 44, "{name}");
            assert!(types.values().all(|&c| c == 5), "{name}: {types:?}");
            assert_eq!(types.get("T_Junction"), Some(&5));
        }
        if name == CRASHED {
            assert_eq!(set.warnings.len(), 1, "{:?}", set.warnings);
            let w = &set.warnings[0].to_string();
            assert!(w.contains(CRASHED), "{w}");
            assert!(
                w.ends_with(
                    "no records (entry_status Started, progress [0, 1]): the run crashed before any route finished"
                ),
                "{w}"
            );
        } else {
            // route ids are unique within each fixture and every status is a known one
            assert!(set.warnings.is_empty(), "{name}: {:?}", set.warnings);
        }
        let merged = [TFPP, PDM, UNIAD].contains(&name);
        assert_eq!(set.merged_totals.len(), usize::from(merged), "{name}");
    }
}

/// (Σ score_composed / 220, 100 × successes / 220) as Bench2Drive's merge computes them.
fn totals_220(set: &ResultSet) -> (f64, f64) {
    let recs = valid(set);
    let ds: f64 = recs.iter().map(|r| r.score_composed).sum::<f64>() / 220.0;
    let successes = recs.iter().filter(|r| r.is_success()).count();
    (ds, 100.0 * successes as f64 / 220.0)
}

#[test]
fn driving_score_and_success_rate_match_stored_totals() {
    for (name, successes) in [(TFPP, 148), (PDM, 203), (UNIAD, 36)] {
        let Some(path) = fixture(name) else { return };
        let set = results::read_results(&path).unwrap();
        let stored = &set.merged_totals[0];
        assert_eq!(stored.source, path);
        let (ds, sr) = totals_220(&set);
        assert!(
            (ds - stored.driving_score).abs() <= 1e-9,
            "{name}: DS {ds} vs stored {}",
            stored.driving_score
        );
        assert!(
            (sr - 100.0 * stored.success_rate).abs() <= 1e-9,
            "{name}: SR {sr} vs stored {}",
            stored.success_rate
        );
        let n = valid(&set).iter().filter(|r| r.is_success()).count();
        assert_eq!(n, successes, "{name}");
    }
    // UniAD-Base holds 218 records and says "eval num": 218, yet its stored totals divide by 220:
    // the two missing routes count as 0 / failed (a denominator of 218 would not match).
    let Some(path) = fixture(UNIAD) else { return };
    let set = results::read_results(&path).unwrap();
    let stored = &set.merged_totals[0];
    assert_eq!(stored.eval_num, Some(218));
    let sum: f64 = valid(&set).iter().map(|r| r.score_composed).sum();
    assert!((sum / 218.0 - stored.driving_score).abs() > 0.1);
}

#[test]
fn penalty_recheck_flags_only_the_hand_edited_record() {
    let flagged = |name: &str| -> Option<Vec<String>> {
        let set = results::read_results(&fixture(name)?).unwrap();
        Some(
            valid(&set)
                .into_iter()
                .filter(|r| !check_penalty(r, PenaltyFlavour::Bench2Drive).agrees)
                .map(|r| r.route_id.clone())
                .collect(),
        )
    };
    let Some(pdm) = flagged(PDM) else { return };
    assert_eq!(pdm, ["RouteScenario_11755_rep0"]);
    let Some(tfpp) = flagged(TFPP) else { return };
    assert!(tfpp.is_empty(), "{tfpp:?}");
    let Some(simlingo) = flagged(SIMLINGO) else {
        return;
    };
    assert!(simlingo.is_empty(), "{simlingo:?}");
    let Some(uniad) = flagged(UNIAD) else { return };
    assert!(uniad.is_empty(), "{uniad:?}");

    // the Leaderboard 2.0 flavour charges min-speed entries, which Bench2Drive records do not
    let set = results::read_results(&fixture(PDM).unwrap()).unwrap();
    let lb20 = valid(&set)
        .into_iter()
        .filter(|r| !check_penalty(r, PenaltyFlavour::Leaderboard20).agrees)
        .count();
    assert!(lb20 > 1, "{lb20}");
}

#[test]
fn route3564_mesh_collisions() {
    let Some(path) = fixture(R3564) else { return };
    let set = results::read_results(&path).unwrap();
    let recs = valid(&set);
    let r = recs[0];
    assert_eq!(r.route_id, "RouteScenario_3564_rep0");
    assert_eq!(r.xml_id(), Some("3564"));
    assert_eq!(r.scenario_type(), "InvadingTurn");
    assert_eq!(r.weather_id.as_deref(), Some("23"));
    assert_eq!(r.status, "Failed - TickRuntime");
    assert!(!r.is_success());
    assert_eq!(r.meta.duration_game, Some(200.05));
    let layout = r.infractions.list(CollisionList::Layout.name());
    assert_eq!(layout.len(), 3);
    let parsed: Vec<_> = layout.iter().map(|s| parse_collision(s).unwrap()).collect();
    assert!(parsed.iter().all(|c| c.type_id == "static.prop.mesh"));
    assert!(parsed.iter().all(|c| !is_workzone(&c.type_id)));
    assert_eq!(parsed[0].actor_id, Some(325426));
    assert_eq!(parsed[2].location, Some([6316.032, 5011.3, 172.629]));
    assert_eq!(count_workzone(&r.infractions), 0);
    let check = check_penalty(r, PenaltyFlavour::Bench2Drive);
    assert!(check.agrees);
    assert!(
        (check.recomputed - 0.274625).abs() < 1e-12,
        "{}",
        check.recomputed
    );
    assert_eq!(check.recorded, 0.274625);
}

#[test]
fn collision_strings_parse_and_workzones_count() {
    for name in [TFPP, PDM, UNIAD, SIMLINGO, R3564] {
        let Some(path) = fixture(name) else { return };
        let set = results::read_results(&path).unwrap();
        for r in valid(&set) {
            for list in CollisionList::ALL {
                for s in r.infractions.list(list.name()) {
                    let c = parse_collision(s).unwrap_or_else(|e| panic!("{name}: {e}"));
                    assert!(c.actor_id.is_some() && c.location.is_some(), "{s}");
                }
            }
        }
    }
    let Some(path) = fixture(UNIAD) else { return };
    let set = results::read_results(&path).unwrap();
    let mut by_type: BTreeMap<String, usize> = BTreeMap::new();
    let mut total = 0;
    for r in valid(&set) {
        total += count_workzone(&r.infractions);
        for s in r.infractions.list("collisions_layout") {
            let c = parse_collision(s).unwrap();
            if is_workzone(&c.type_id) {
                *by_type.entry(c.type_id).or_default() += 1;
            }
        }
    }
    let expected: BTreeMap<String, usize> = [
        ("static.prop.constructioncone".to_string(), 3),
        ("static.prop.trafficwarning".to_string(), 7),
    ]
    .into();
    assert_eq!(by_type, expected);
    assert_eq!(total, 10);
}

#[test]
fn directory_tree_with_broken_merged_and_duplicate_files() {
    let (Some(r3564), Some(crashed), Some(tfpp)) =
        (fixture(R3564), fixture(CRASHED), fixture(TFPP))
    else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let copy = |from: &Path, to: &str| {
        let to = root.join(to);
        fs::create_dir_all(to.parent().unwrap()).unwrap();
        fs::copy(from, &to).unwrap();
        to
    };
    let a = copy(&r3564, "per_route/3564/endpoint.json");
    let b = copy(&r3564, "rerun/3564/endpoint.json");
    let c = copy(&crashed, "per_route/24206/endpoint.json");
    // a merge output beside a raw file in its own folder: made from it, skipped
    let merged = copy(&tfpp, "per_route/3564/merged.json");
    // files that must be ignored: telemetry names and JSON without _checkpoint
    copy(&r3564, "per_route/3564/metric_info.json");
    copy(&r3564, "per_route/3564/infractions.json");
    fs::write(root.join("per_route/3564/notes.json"), "{\"x\": 1}").unwrap();
    fs::write(root.join("per_route/readme.txt"), "{").unwrap();
    // a truncated copy of a raw file
    let text = fs::read_to_string(&r3564).unwrap();
    let broken = root.join("per_route/9999/endpoint.json");
    fs::create_dir_all(broken.parent().unwrap()).unwrap();
    fs::write(&broken, &text[..text.len() / 2]).unwrap();

    let set = results::read_results(root).unwrap();
    // sorted by path: per_route/24206 (0 records), per_route/3564, rerun/3564
    let sources: Vec<_> = set.records.iter().map(|r| r.source.clone()).collect();
    assert_eq!(sources, [a.clone(), b.clone()]);
    assert!(set.records.iter().all(|r| r.records_in_file == 1));
    assert!(set.records.iter().all(|r| r.entry.is_ok()));
    assert!(set.merged_totals.is_empty());

    assert_eq!(set.broken_files.len(), 1);
    assert_eq!(set.broken_files[0].0, broken);
    assert!(
        set.broken_files[0].1.contains("truncated JSON"),
        "{}",
        set.broken_files[0].1
    );

    let has = |pred: &dyn Fn(&str) -> bool| set.warnings.iter().any(|w| pred(&w.to_string()));
    let m = merged.display().to_string();
    assert!(
        has(&|w| w.starts_with(&m) && w.contains("skipped")),
        "{:?}",
        set.warnings
    );
    let c = c.display().to_string();
    // Duplicates (a and b) are the run's business (the `duplicates` policy), not the reader's;
    // the files read are in byte-wise path order.
    let files: Vec<_> = set.files.iter().map(|f| f.path.clone()).collect();
    assert_eq!(
        files,
        [root.join("per_route/24206/endpoint.json"), a, b],
        "the crashed file, a and b: {:?}",
        set.files
    );
    assert!(
        has(&|w| w.starts_with(&c) && w.contains("crashed")),
        "{:?}",
        set.warnings
    );
    assert!(has(&|w| w.contains("truncated JSON")), "{:?}", set.warnings);
    assert_eq!(set.warnings.len(), 3, "{:?}", set.warnings);

    // a merge output elsewhere in the tree (no raw file in its folder) is read
    copy(&tfpp, "merged_elsewhere/merged.json");
    let set = results::read_results(root).unwrap();
    assert_eq!(set.records.len(), 2 + 220);
    assert_eq!(set.merged_totals.len(), 1);

    // without raw files, the merged file is read with its stored totals
    let only = tempfile::tempdir().unwrap();
    fs::create_dir_all(only.path().join("m")).unwrap();
    fs::copy(&tfpp, only.path().join("m/merged.json")).unwrap();
    let set = results::read_results(only.path()).unwrap();
    assert_eq!(set.records.len(), 220);
    assert_eq!(set.merged_totals.len(), 1);
    assert!(set.warnings.is_empty(), "{:?}", set.warnings);
}

#[test]
fn truncated_single_file_is_an_error_with_position() {
    let Some(r3564) = fixture(R3564) else { return };
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.json");
    let text = fs::read_to_string(&r3564).unwrap();
    fs::write(&p, &text[..100]).unwrap();
    let e = results::read_results(&p).unwrap_err().to_string();
    assert!(e.starts_with(&p.display().to_string()), "{e}");
    assert!(
        e.contains("truncated JSON: unexpected end of input at line"),
        "{e}"
    );
}
