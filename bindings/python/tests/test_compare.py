"""`sds.compare` against the `sds compare` binary: the same report, the errors' classes."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict

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
    `sds.score`'s cancel path (between routes, runs and bootstrap blocks)."""
    import signal
    import subprocess
    import sys
    import time

    run = tmp_path / "large"
    code, _, err = run_cli(sds_bin, ["demo", str(run), "--large", "--large-routes", "60", "--large-frames", "4000"])
    assert code == 0, err
    r, t = str(run / "results.json"), str(run / "telemetry")
    script = (
        "import sds, sys\n"
        "print('start', flush=True)\n"
        f"sds.compare({{'a': ({r!r}, {t!r}), 'b': ({r!r}, {t!r})}}, jobs=1)\n"
        "print('done', flush=True)\n"
    )

    def launch() -> "subprocess.Popen[str]":
        p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert p.stdout is not None and p.stdout.readline() == "start\n"
        return p

    t0 = time.monotonic()
    p = launch()
    out, err = p.communicate(timeout=600)
    whole = time.monotonic() - t0
    assert p.returncode == 0 and "done" in out, err
    # Interrupted a fifth into the comparison (in the first run), it must stop long before the end.
    t0 = time.monotonic()
    p = launch()
    time.sleep(whole / 5)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=600)
    interrupted = time.monotonic() - t0
    assert "KeyboardInterrupt" in err and "done" not in out, (out, err)
    assert interrupted < whole * 0.7, f"stopped after {interrupted:.2f} s of a {whole:.2f} s comparison"


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
    # The same run everywhere: every model ties at rank 1 in every resample; listed by name.
    assert [r["model"] for r in ranking] == ["base", "m"]
    assert all(r["rank"] == 1 and r["rank_ci95"] == [1, 1] and r["p_best"] == 1.0
               for r in ranking)
    m = c["models"][1]
    assert m["seed_std"] == 0.0 and m["seeds_needed"] == 0 and m["flaky_routes"] == []
    assert c["config"]["repro.halfwidth"] == 2.5
    # Without rank there is no ranking; a half-width that sizes nothing is refused.
    assert sds.compare(runs, bootstrap_samples=1000).get("ranking") is None
    with pytest.raises(sds.ConfigError, match="repro.halfwidth"):
        sds.compare(runs, repro_halfwidth=0.0)


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
