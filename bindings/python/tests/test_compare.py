"""`sds.compare` against the `sds compare` binary: the same report, the errors' classes."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, List, Tuple

import pytest

import sds

from conftest import run_cli


def _demo(sds_bin: Path, tmp: Path) -> Path:
    code, _, err = run_cli(sds_bin, ["demo", str(tmp / "demo")])
    assert code == 0, err
    return tmp / "demo"


def test_compare_is_the_cli_report(sds_bin: Path, tmp_path: Path) -> None:
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    c = sds.compare(
        {"a": (res, tel), "b": (str(res), str(tel))}, bootstrap_samples=1500, bootstrap_seed=3
    )
    assert c["schema"] == "sds-compare/1"
    assert c["baseline"] == "a"
    out = tmp_path / "cli.json"
    code, _, err = run_cli(
        sds_bin,
        ["compare", f"a={res}:{tel}", f"b={res}:{tel}", "--bootstrap-samples", "1500",
         "--bootstrap-seed", "3", "--format", "json", "-o", str(out)],
    )
    assert code == 0, err
    cli: Dict[str, Any] = json.loads(out.read_text())
    assert c == cli
    ds = [p for p in c["paired"] if p["model"] == "b" and p["metric"] == "ds"][0]
    assert ds["delta"] == 0.0 and ds["verdict"] == "within noise"


def test_seeds_and_errors(sds_bin: Path, tmp_path: Path) -> None:
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    c = sds.compare(
        {"base": (res, tel), "s1": (res, tel), "s2": (res, tel)},
        seeds={"m": ["s1", "s2"]},
        bootstrap_samples=1000,
    )
    assert [m["name"] for m in c["models"]] == ["base", "m"]
    assert c["models"][1]["runs"] == ["s1", "s2"]
    with pytest.raises(sds.ConfigError, match="needs at least two models"):
        sds.compare({"a": (res, tel)})
    with pytest.raises(sds.ConfigError, match="unknown metric"):
        sds.compare({"a": (res, tel), "b": (res, tel)}, fail_if_worse=["nope"])
    with pytest.raises(sds.IoError, match="run b: .*absent.json"):
        sds.compare({"a": (res, tel), "b": (tmp_path / "absent.json", tel)})


def test_shared_options_are_the_cli_flags(sds_bin: Path, tmp_path: Path) -> None:
    """The keyword arguments sds.score shares (RunKwargs) map to the same settings as the flags
    `sds compare` shares with `sds score` (RunArgs)."""
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    c = sds.compare(
        {"a": (res, tel), "b": (res, tel)},
        routes=demo / "routes.xml",
        profile="b2d-legacy",
        allow_missing_telemetry=True,
        settings={"slack": 0.9},
        protocols=["lb2.1"],
        jobs=1,
        bootstrap_samples=1000,
    )
    out = tmp_path / "cli.json"
    code, _, err = run_cli(
        sds_bin,
        ["compare", f"a={res}:{tel}", f"b={res}:{tel}", "--routes", str(demo / "routes.xml"),
         "--profile", "b2d-legacy", "--allow-missing-telemetry", "--set", "slack=0.9",
         "--protocol", "lb2.1", "--jobs", "1", "--bootstrap-samples", "1000",
         "--format", "json", "-o", str(out)],
    )
    assert code == 0, err
    assert c == json.loads(out.read_text())
    with pytest.raises(sds.ConfigError, match="protocols"):
        sds.compare({"a": (res, tel), "b": (res, tel)}, protocols="lb2.1")
    with pytest.raises(sds.ConfigError, match="profile=\"fast\""):
        sds.compare({"a": (res, tel), "b": (res, tel)}, profile="fast")


def test_bootstrap_samples_are_bounded(sds_bin: Path, tmp_path: Path) -> None:
    """Issue 34, finding 6: B = 10**12 aborted the process (and the kernel), 2**64 - 1
    panicked, 1 gave a one-point interval. Out of range is a ConfigError with the CLI's text,
    raised before any run is scored."""
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    runs = {"a": (res, tel), "b": (res, tel)}
    for bad in (0, 1, 999, 1_000_001, 10**12, 2**64 - 1, 2**64, -1):
        with pytest.raises(sds.ConfigError, match=r"between 1000 and 1000000") as e:
            sds.compare(runs, bootstrap_samples=bad)
        assert f"= {bad}:" in str(e.value)
    c = sds.compare(runs, bootstrap_samples=1000)
    assert c["config"]["bootstrap_samples"] == 1000


def test_no_data_is_a_verdict(sds_bin: Path, tmp_path: Path) -> None:
    """Spec v1.4: n = 0 (comfort without telemetry) is the verdict "no data", not null."""
    demo = _demo(sds_bin, tmp_path)
    res = demo / "results.json"
    c = sds.compare({"a": (res, tmp_path), "b": (res, tmp_path)}, allow_missing_telemetry=True)
    comfort = [p for p in c["paired"] if p["metric"] == "comfort"][0]
    assert comfort["n"] == 0 and comfort["verdict"] == "no data" and comfort["ci95"] is None


def test_ctrl_c_stops_compare_between_routes(sds_bin: Path, tmp_path: Path) -> None:
    """Issue 34, finding 6: Ctrl-C in `sds.compare` was honoured only at the end; it now takes
    `sds.score`'s cancel path (between routes, runs and bootstrap blocks).

    Issue 47 item 13: no clock decides it. The SIGINT is sent from the `progress` callable
    after the first route of the first run, which returns only once the signal was handled:
    the comparison must stop before the next route (one worker)."""
    import os
    import signal
    import threading

    run = tmp_path / "large"
    code, _, err = run_cli(sds_bin, ["demo", str(run), "--large", "--large-routes", "20", "--large-frames", "400"])
    assert code == 0, err
    r, t = run / "results.json", run / "telemetry"
    handled = threading.Event()
    calls: List[Tuple[int, int]] = []

    def on_sigint(signum: int, frame: Any) -> None:
        handled.set()
        raise KeyboardInterrupt

    def progress(done: int, total: int) -> None:
        calls.append((done, total))
        if done == 1 and len(calls) == 1:
            os.kill(os.getpid(), signal.SIGINT)
            assert handled.wait(600), "the SIGINT was never handled"  # a guard, not a decision

    previous = signal.signal(signal.SIGINT, on_sigint)
    try:
        with pytest.raises(KeyboardInterrupt):
            sds.compare({"a": (r, t), "b": (r, t)}, jobs=1, progress=progress)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert calls == [(1, 20)], calls
    # Uninterrupted, the callable hears every route of each run, the count restarting per run.
    calls.clear()
    c = sds.compare({"a": (r, t), "b": (r, t)}, jobs=1, bootstrap_samples=1000,
                    progress=lambda d, n: calls.append((d, n)))
    assert c["baseline"] == "a"
    assert calls == [(k, 20) for k in range(1, 21)] * 2
    with pytest.raises(sds.ConfigError, match="progress=True"):
        sds.compare({"a": (r, t), "b": (r, t)}, progress=True)  # type: ignore[arg-type]


def test_rank_and_seeds_are_the_cli_report(sds_bin: Path, tmp_path: Path) -> None:
    """Issue 38: ``rank=True`` and ``repro_halfwidth`` give the report ``sds compare --rank
    --repro-halfwidth`` writes: the ranking listed by rank, each model's seed figures."""
    demo = _demo(sds_bin, tmp_path)
    res, tel = demo / "results.json", demo / "telemetry"
    runs = {"base": (res, tel), "s1": (res, tel), "s2": (res, tel)}
    c = sds.compare(
        runs, seeds={"m": ["s1", "s2"]}, rank=True, repro_halfwidth=2.5, bootstrap_samples=1000
    )
    out = tmp_path / "cli.json"
    code, _, err = run_cli(
        sds_bin,
        ["compare", f"base={res}:{tel}", f"s1={res}:{tel}", f"s2={res}:{tel}",
         "--seeds", "m=s1,s2", "--rank", "--repro-halfwidth", "2.5",
         "--bootstrap-samples", "1000", "--format", "json", "-o", str(out)],
    )
    assert code == 0, err
    assert c == json.loads(out.read_text())
    ranking = c["ranking"]
    # The same run everywhere: every model ties at rank 1 in every resample, sharing the first
    # place (p_best 1/2 each); listed by name.
    assert [r["model"] for r in ranking] == ["base", "m"]
    assert all(r["rank"] == 1 and r["rank_ci95"] == [1, 1] and r["p_best"] == 0.5
               for r in ranking)
    m = c["models"][1]
    assert m["seed_std"] == 0.0 and m["seeds_needed"] == 0 and m["flaky_routes"] == []
    assert c["config"]["repro.halfwidth"] == 2.5
    # Without rank there is no ranking; a half-width that sizes nothing is refused.
    assert sds.compare(runs, bootstrap_samples=1000).get("ranking") is None
    with pytest.raises(sds.ConfigError, match="repro.halfwidth"):
        sds.compare(runs, repro_halfwidth=0.0)


def test_i46_6_route_subset_like_the_cli(sds_bin: Path, tmp_path: Path) -> None:
    """Issue 46 item 6: ``sds.compare(route_subset=...)`` as ``sds compare --route-subset``: a
    run of 3 of the demo's routes compared over those 3 (``"found"``) or over the route XML's
    every route (``"all"``, the default)."""
    demo = _demo(sds_bin, tmp_path)
    data = json.loads((demo / "results.json").read_text())
    total = len(data["_checkpoint"]["records"])
    data["_checkpoint"]["records"] = data["_checkpoint"]["records"][:3]
    part = tmp_path / "part.json"
    part.write_text(json.dumps(data))
    tel, routes = demo / "telemetry", demo / "routes.xml"
    runs = {"a": (part, tel), "b": (part, tel)}
    for subset, n in (("found", 3), ("all", total)):
        c = sds.compare(runs, routes=routes, route_subset=subset, bootstrap_samples=1000)
        assert c["scope"]["routes"] == n, subset
        out = tmp_path / f"cli-{subset}.json"
        code, _, err = run_cli(
            sds_bin,
            ["compare", f"a={part}:{tel}", f"b={part}:{tel}", "--routes", str(routes),
             "--route-subset", subset, "--bootstrap-samples", "1000", "--format", "json",
             "-o", str(out)],
        )
        assert code == 0, err
        assert c == json.loads(out.read_text())
    assert sds.compare(runs, routes=routes, bootstrap_samples=1000)["scope"]["routes"] == total
    with pytest.raises(sds.ConfigError, match="route_subset"):
        sds.compare(runs, routes=routes, route_subset="some")  # type: ignore[arg-type]
def test_sweep_is_the_cli_report(sds_bin: Path, tmp_path: Path) -> None:
    """Issue 50: sds.compare(sweep=...) is `sds compare --sweep`'s report; refusals are
    ConfigError naming the settings a sweep takes."""
    demo = _demo(sds_bin, tmp_path)
    res, tel, routes = demo / "results.json", demo / "telemetry", demo / "routes.xml"
    c = sds.compare(
        {"a": (res, tel), "b": (res, tel)},
        routes=routes,
        bootstrap_samples=1000,
        sweep={"factors.critical": [0.8, 0.9], "bounds.lat_acc": ["0.5", 4.89]},
    )
    out = tmp_path / "cli.json"
    code, _, err = run_cli(
        sds_bin,
        ["compare", f"a={res}:{tel}", f"b={res}:{tel}", "--routes", str(routes),
         "--bootstrap-samples", "1000", "--sweep", "factors.critical=0.8,0.9",
         "--sweep", "bounds.lat_acc=0.5,4.89", "--format", "json", "-o", str(out)],
    )
    assert code == 0, err
    assert c == json.loads(out.read_text())
    assert c["sweep"]["settings"] == ["factors.critical", "bounds.lat_acc"]
    assert len(c["sweep"]["points"]) == 4
    assert c["sweep"]["pairs"] == [{"a": "a", "b": "b", "order_stable": True, "flips": []}]
    with pytest.raises(sds.ConfigError, match="changes no route's figures.*critical_excess"):
        sds.compare({"a": (res, tel), "b": (res, tel)}, sweep={"protocols": ["all", "none"]})
    with pytest.raises(sds.ConfigError, match="the grid has 65 points"):
        sds.compare(
            {"a": (res, tel), "b": (res, tel)},
            sweep={"slack": [0.1 * k for k in range(1, 14)], "factors.critical": [0.5, 0.6, 0.7, 0.8, 0.9]},
        )
    with pytest.raises(sds.ConfigError, match="expected a list of values"):
        sds.compare({"a": (res, tel), "b": (res, tel)}, sweep={"slack": "0.5"})
    # Issue 48 item 1: each axis is checked by `--sweep`'s own parser.
    for bad in ({"slack": []}, {"slack": [" "]}, {"": [0.5]}, {"slack": ["0.5,0.9"]}):
        with pytest.raises(sds.ConfigError, match="expected NAME=V1,V2"):
            sds.compare({"a": (res, tel), "b": (res, tel)}, sweep=bad)
