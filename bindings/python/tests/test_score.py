"""`sds.score` returns the report of `sds score --format json`, the same numbers to the bit."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, List, Tuple

import pytest

import sds
from conftest import Demo, cli_report, run_cli, same


def test_demo_report_equals_cli(demo: Demo, demo_report: Dict[str, Any]) -> None:
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes)
    assert report["summary"]["sds"] is not None
    assert len(report["routes"]) == len(demo.records()) >= 7
    assert same(report, demo_report)
    # The same dict, keys in the JSON report's order too (what json.dumps(report) shows).
    assert json.dumps(report) == json.dumps(demo_report)


def test_decomposition_and_events_explain_the_score(demo: Demo) -> None:
    """Issue 28 from Python: the steps from DS to SDS sum back, and each route's events put
    its infractions on its frames (the demo's junction route runs a red light)."""
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes)
    d = report["summary"]["decomposition"]
    losses = d["rounding"] + d["workzone"] + d["nodecel"] + d["anomalous"] + d["critical"]
    assert abs(d["ds"] - losses - d["ds_safe"]) < 1e-9
    assert abs(d["ds_safe"] - d["comfort"] - d["sds"]) < 1e-9
    assert abs(d["sds"] - report["summary"]["sds"]) < 1e-9
    junction = next(r for r in report["routes"] if r["route_id"] == "RouteScenario_900009_rep0")
    red = [e for e in junction["events"] if e["kind"] == "red_light"]
    assert len(red) == 1 and red[0]["placed_by"] == "closest_approach"
    assert 0 <= red[0]["frame"] < junction["frames"]
    frames = [e["frame"] for e in junction["events"] if e["frame"] is not None]
    assert frames == sorted(frames)


def test_no_command_line_in_between() -> None:
    """`sds.score` calls the library: the binding builds no argument list and calls no CLI code
    for it (the `sds-cli` crate serves only the `sds` command and the error table)."""
    src = Path(__file__).resolve().parents[1] / "src"
    uses = [
        (p.name, line.strip())
        for p in sorted(src.glob("*.rs"))
        for line in p.read_text().splitlines()
        if "cli::" in line and not line.lstrip().startswith("//")
    ]
    assert uses == [
        ("errors.rs", ".map(|k| Ok((k.name(), sds_cli::exit::code(*k), class(py, *k)?)))"),
        ("lib.rs", "py.detach(|| sds_cli::main(argv))"),
    ], uses
    assert not hasattr(sds._sds, "score_json")


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        ({"profile": "b2d-legacy"}, ["--profile", "b2d-legacy"]),
        (
            {"settings": {"slack": 0.9, "bounds.yaw_rate": 1.0, "gap_max": 6}},
            ["--set", "slack=0.9", "--set", "bounds.yaw_rate=1.0", "--set", "gap_max=6"],
        ),
        ({"expected_routes": 10, "jobs": 1}, ["--expected-routes", "10", "--jobs", "1"]),
        # Issue 39: Autoware's planning envelope as the comfort bounds.
        ({"profile": "autoware"}, ["--profile", "autoware"]),
        ({"protocols": ["lb2.1", "f2d"]}, ["--protocol", "lb2.1,f2d"]),
        ({"protocols": ["all"], "settings": {"ability_rule": "b2d-0.0.3"}},
         ["--protocol", "all", "--set", "ability_rule=b2d-0.0.3"]),
    ],
)
def test_options_equal_cli_flags(
    demo: Demo, sds_bin: Path, tmp_path: Path, kwargs: Dict[str, Any], flags: List[str]
) -> None:
    base = ["--results", str(demo.results), "--telemetry", str(demo.telemetry), "--routes", str(demo.routes)]
    expected = cli_report(sds_bin, base + flags, tmp_path)
    report = sds.score([demo.results], telemetry=str(demo.telemetry), routes=demo.routes, **kwargs)
    assert same(report, expected)
    # The options changed something (the test would not see a dropped option otherwise).
    default = cli_report(sds_bin, base, tmp_path)
    assert not same(report, default)


def test_missing_telemetry_allowed(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    for allow in (False, True):
        flags = ["--allow-missing-telemetry"] if allow else []
        expected = cli_report(sds_bin, ["--results", str(demo.results), *flags], tmp_path)
        report = sds.score(demo.results, allow_missing_telemetry=allow)
        assert same(report, expected)
        assert all(r["telemetry"] == "missing" for r in report["routes"])
        assert (report["summary"]["mean_ds_safe"] is not None) == allow


def test_real_fixtures_equal_cli(b2d: Path, sds_bin: Path, tmp_path: Path) -> None:
    routes = b2d / "routes" / "bench2drive220.xml"
    runs = sorted(b2d.glob("*.json")) + [b2d / "lead_tfv6_per_route", b2d / "tfpp_raw_shards"]
    assert len(runs) >= 5
    scored = refused = 0
    for run in runs:
        for allow in (False, True):
            flags = ["--allow-missing-telemetry"] if allow else []
            args = ["--results", str(run), "--routes", str(routes), "--expected-routes", "220", *flags]
            out = tmp_path / "cli-report.json"
            code, _, err = run_cli(sds_bin, ["score", *args, "--format", "json", "-o", str(out)])
            if code in (1, 2, 4):
                # No report: the same error, as an exception.
                with pytest.raises(sds.SdsError) as e:
                    sds.score(run, routes=routes, expected_routes=220, allow_missing_telemetry=allow)
                # The command's message is the exception's, its flags appended (` (--flag)`).
                assert any(line.startswith(f"sds: error: {e.value}") for line in err.splitlines()), run
                refused += 1
                continue
            expected = json.loads(out.read_text())
            report = sds.score(run, routes=routes, expected_routes=220, allow_missing_telemetry=allow)
            assert same(report, expected), run
            scored += 1
    assert scored >= 10 and refused >= 1


def test_progress_bar_same_report(demo: Demo, demo_report: Dict[str, Any]) -> None:
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes, progress=True)
    assert same(report, demo_report)


def test_labels_are_checked_like_the_cli(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    labels = tmp_path / "families.csv"
    labels.write_text("DemoCruising,calm\nDemoHardBraking,braking\n")
    base = ["--results", str(demo.results), "--telemetry", str(demo.telemetry)]
    expected = cli_report(sds_bin, base + ["--group-by", "family", "--families", str(labels)], tmp_path)
    report = sds.score(demo.results, telemetry=demo.telemetry, group_by="family", labels=labels)
    assert same(report, expected)
    assert report["routes"]
    bad = tmp_path / "bad.csv"
    bad.write_text("no comma here\n")
    with pytest.raises(sds.InputError) as e:
        sds.score(demo.results, group_by="family", labels=bad)
    code, _, err = run_cli(sds_bin, ["score", *base, "--group-by", "family", "--families", str(bad)])
    assert code in (1, 2) and any(line.startswith(f"sds: error: {e.value}") for line in err.splitlines())
    with pytest.raises(sds.ConfigError):
        sds.score(demo.results, group_by="nope")
    with pytest.raises(sds.ConfigError):
        sds.score(demo.results, labels=labels)


def test_group_by_route_labels_like_the_cli(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    ids = [r["route_id"] for r in demo.records()]
    labels = tmp_path / "split.json"
    # The first two routes by XML id, the others by full route id: two groups.
    split = {i.split("_")[1] if n < 2 else i: "train" if n < 2 else "test" for n, i in enumerate(ids)}
    labels.write_text(json.dumps(split))
    base = ["--results", str(demo.results), "--telemetry", str(demo.telemetry), "--routes", str(demo.routes)]
    expected = cli_report(sds_bin, base + ["--group-by", "route", "--labels", str(labels)], tmp_path)
    report = sds.score(
        demo.results, telemetry=demo.telemetry, routes=demo.routes, group_by="route", labels=labels
    )
    assert same(report, expected)
    rows = {g["label"]: g for g in report["groups"]["rows"]}
    assert sorted(rows) == ["test", "train"]
    assert rows["train"]["routes"] == 2 and rows["test"]["routes"] == len(ids) - 2
    first = [r for r in report["routes"] if r["route_id"] in ids[:2]]
    assert rows["train"]["driving_score"] == (first[0]["score_composed"] + first[1]["score_composed"]) / 2
    # Without its label map: a ConfigError with the command's message.
    with pytest.raises(sds.ConfigError) as e:
        sds.score(demo.results, telemetry=demo.telemetry, group_by="route")
    assert "(labels)" in str(e.value) and "--" not in str(e.value)


def test_duplicates_like_the_cli(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    twice = ["--results", str(demo.results), "--results", str(demo.results), "--telemetry", str(demo.telemetry)]
    with pytest.raises(sds.InputError) as e:
        sds.score([demo.results, demo.results], telemetry=demo.telemetry)
    code, _, err = run_cli(sds_bin, ["score", *twice])
    # A multi-line message; the command appends its flag.
    assert code == 2 and f"sds: error: {e.value} (--duplicates)\n" in err
    for policy in ("first", "last", "all"):
        expected = cli_report(sds_bin, twice + ["--duplicates", policy], tmp_path)
        report = sds.score([demo.results, demo.results], telemetry=demo.telemetry, duplicates=policy)
        assert same(report, expected), policy
    assert len(report["routes"]) == 2 * len(demo.records())  # "all" scores every copy


def test_protocols_reach_the_report(demo: Demo) -> None:
    report = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes, protocols=["all"])
    assert list(report["summary"]["protocols"]) == ["b2d", "lb2.0", "lb2.1", "lead-nds", "f2d"]
    assert report["summary"]["protocols"]["b2d"]["driving_score"] == report["summary"]["driving_score"]
    assert all(set(r["protocols"]) == set(report["summary"]["protocols"]) for r in report["routes"])
    with pytest.raises(sds.ConfigError):
        sds.score(demo.results, telemetry=demo.telemetry, protocols=["lb3"])
    with pytest.raises(sds.ConfigError):
        sds.score(demo.results, telemetry=demo.telemetry, protocols="all")  # type: ignore[arg-type]
    # Issue 47 item 12: "all" and "none" stand alone.
    for both in (["all", "none"], ["all", "all"], ["none", "lb2.1"]):
        with pytest.raises(sds.ConfigError, match="alone"):
            sds.score(demo.results, telemetry=demo.telemetry, protocols=both)


def test_ctrl_c_stops_the_run_between_routes(sds_bin: Path, tmp_path: Path) -> None:
    """Issue 29, finding 17: Ctrl-C in `sds.score` took effect only when the run ended.

    Issue 47 item 13: no clock decides it. The SIGINT is sent from the `progress` callable after
    the first route, and the callable returns only once the signal was handled on the main
    thread: the run is still under way when Ctrl-C arrives and must stop before the next route
    (one worker)."""
    import os
    import signal
    import threading

    run = tmp_path / "large"
    code, _, err = run_cli(sds_bin, ["demo", str(run), "--large", "--large-routes", "20", "--large-frames", "400"])
    assert code == 0, err
    handled = threading.Event()
    calls: List[Tuple[int, int]] = []

    def on_sigint(signum: int, frame: Any) -> None:
        handled.set()
        raise KeyboardInterrupt

    def progress(done: int, total: int) -> None:
        calls.append((done, total))
        if done == 1:
            os.kill(os.getpid(), signal.SIGINT)
            assert handled.wait(600), "the SIGINT was never handled"  # a guard, not a decision

    previous = signal.signal(signal.SIGINT, on_sigint)
    try:
        with pytest.raises(KeyboardInterrupt):
            sds.score(run / "results.json", telemetry=run / "telemetry", jobs=1, progress=progress)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert handled.is_set()
    assert calls == [(1, 20)], calls  # stopped at the next route: 19 never scored
    # Without Ctrl-C the same call scores every route, the callable hearing each one.
    calls.clear()
    report = sds.score(run / "results.json", telemetry=run / "telemetry", jobs=1, progress=progress_quiet(calls))
    assert len(report["routes"]) == 20 and calls == [(k, 20) for k in range(1, 21)]


def progress_quiet(calls: List[Tuple[int, int]]) -> Any:
    """A `progress` callable that records its calls."""
    return lambda done, total: calls.append((done, total))


def test_progress_callable_stops_the_run_with_its_exception(demo: Demo) -> None:
    """An exception raised by the `progress` callable stops the run and comes out of
    `sds.score`; a value that is neither a bool nor a callable is a ConfigError."""

    class Stop(Exception):
        pass

    seen: List[int] = []

    def progress(done: int, total: int) -> None:
        seen.append(done)
        raise Stop(f"{done}/{total}")

    with pytest.raises(Stop, match=f"1/{len(demo.records())}"):
        sds.score(demo.results, telemetry=demo.telemetry, jobs=1, progress=progress)
    assert seen == [1]
    with pytest.raises(sds.ConfigError, match="progress=3"):
        sds.score(demo.results, telemetry=demo.telemetry, progress=3)  # type: ignore[arg-type]


def test_route_subset_like_the_cli(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    """Issue 33, item 8: `sds.score(route_subset=...)` as `--route-subset`."""
    data = json.loads(demo.results.read_text())
    data["_checkpoint"]["records"] = data["_checkpoint"]["records"][:3]
    part = tmp_path / "part.json"
    part.write_text(json.dumps(data))
    base = ["--results", str(part), "--telemetry", str(demo.telemetry), "--routes", str(demo.routes)]
    found = sds.score(part, telemetry=demo.telemetry, routes=demo.routes, route_subset="found")
    assert same(found, cli_report(sds_bin, base + ["--route-subset", "found"], tmp_path))
    assert found["config"]["route_subset"] == "found"
    assert found["summary"]["missing"] == 0 and len(found["routes"]) == 3
    every = sds.score(part, telemetry=demo.telemetry, routes=demo.routes, route_subset="all")
    assert same(every, cli_report(sds_bin, base, tmp_path))
    assert every["summary"]["missing"] == len(demo.records()) - 3
    # A `settings` override wins, as `--set` after `--route-subset` does.
    over = sds.score(part, telemetry=demo.telemetry, routes=demo.routes, route_subset="all",
                     settings={"route_subset": "found"})
    assert same(over, found)
    with pytest.raises(sds.ConfigError) as e:
        sds.score(part, telemetry=demo.telemetry, routes=demo.routes,
                  route_subset="some")  # type: ignore[arg-type]
    assert "route_subset" in str(e.value) and "found" in str(e.value)
