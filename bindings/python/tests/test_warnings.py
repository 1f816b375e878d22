"""Issue 46 item 6: the report's warnings as Python warnings. ``sds.score``, ``sds.compare`` and
``sds.merge`` call ``warnings.warn(text, sds.SdsWarning)`` for each warning the ``sds`` command
prints (``sds: warning: ...``), pointing at the caller's line, so that notebooks show them,
``warnings.simplefilter("error", sds.SdsWarning)`` makes them fatal and
``warnings.simplefilter("ignore", sds.SdsWarning)`` silences them. On the real files: VAD's
merged file says ``eval num 214`` over 213 records."""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import Any, Callable, Dict, List, Tuple

import pytest

import sds
from conftest import run_cli


def _caught(call: Callable[[], Dict[str, Any]]) -> Tuple[Dict[str, Any], List[warnings.WarningMessage]]:
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        report = call()
    return report, [w for w in seen if issubclass(w.category, sds.SdsWarning)]


def _cli_warnings(stderr: str) -> List[str]:
    return [line[len("sds: warning: "):] for line in stderr.splitlines() if line.startswith("sds: warning: ")]


def test_i46_6_sds_warning_is_a_user_warning() -> None:
    assert issubclass(sds.SdsWarning, UserWarning)
    assert not issubclass(sds.SdsWarning, sds.SdsError)
    assert "SdsWarning" in sds.__all__


def test_i46_6_score_warns_each_report_warning(b2d: Path, sds_bin: Path) -> None:
    vad = b2d / "b2dzoo_VAD_merged.json"
    report, seen = _caught(lambda: sds.score(vad, allow_missing_telemetry=True))
    assert report["warnings"], "VAD's file has warnings"
    assert [str(w.message) for w in seen] == report["warnings"]
    assert any("eval num 214" in str(w.message) for w in seen)
    assert all(w.filename == __file__ for w in seen), "the warning points at the caller"
    code, _, err = run_cli(sds_bin, ["score", "--results", str(vad), "--allow-missing-telemetry", "--format", "json"])
    assert code in (0, 3), err
    assert len(_cli_warnings(err)) == len(seen)
    with warnings.catch_warnings():
        warnings.simplefilter("error", sds.SdsWarning)
        with pytest.raises(sds.SdsWarning, match=r"b2dzoo_VAD_merged\.json: "):
            sds.score(vad, allow_missing_telemetry=True)
    demo_free, none = _caught(lambda: sds.score(b2d / "carla_garage_tfpp_b2d_traj_merged.json", allow_missing_telemetry=True))
    assert demo_free["warnings"] == [] and none == []


def test_i46_6_compare_warns_each_runs_warnings_and_its_own(b2d: Path, sds_bin: Path) -> None:
    runs = {"tfpp": b2d / "carla_garage_tfpp_b2d_traj_merged.json", "vad": b2d / "b2dzoo_VAD_merged.json"}
    report, seen = _caught(
        lambda: sds.compare(runs, common_routes=True, allow_missing_telemetry=True, bootstrap_samples=1000)
    )
    messages = [str(w.message) for w in seen]
    assert any(m.startswith("vad: ") and "eval num 214" in m for m in messages), messages
    for w in report["warnings"]:
        assert w in messages
    assert all(w.filename == __file__ for w in seen)
    code, _, err = run_cli(
        sds_bin,
        ["compare", f"tfpp={runs['tfpp']}", f"vad={runs['vad']}", "--common-routes", "--allow-missing-telemetry",
         "--bootstrap-samples", "1000", "--format", "json"],
    )
    assert code in (0, 3), err
    assert len(_cli_warnings(err)) == len(messages)


def test_i46_6_merge_warns_the_merged_reports_warnings(b2d: Path, tmp_path: Path) -> None:
    part = tmp_path / "vad.json"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sds.SdsWarning)
        part.write_text(json.dumps(sds.score(b2d / "b2dzoo_VAD_merged.json", allow_missing_telemetry=True)))
    merged, seen = _caught(lambda: sds.merge([part]))
    assert merged["warnings"] and [str(w.message) for w in seen] == merged["warnings"]
    assert any("eval num 214" in str(w.message) for w in seen)
    assert all(w.filename == __file__ for w in seen)


def test_i48_2_notes_are_report_warnings_as_the_cli_says_them(demo: Any, sds_bin: Path) -> None:
    """The inferred-period note was printed by the command only: it is now in the report, so
    Python warns it too, with the command's text (`sds: note: ...`)."""
    report, seen = _caught(lambda: sds.score(demo.results, telemetry=demo.telemetry))
    notes = [str(w.message) for w in seen if str(w.message).startswith("step period inferred as 0.1 s")]
    assert len(notes) == 1 and "RouteScenario_900008_rep0" in notes[0], notes
    assert notes[0] in report["warnings"]
    code, _, err = run_cli(sds_bin, ["score", "--results", str(demo.results), "--telemetry", str(demo.telemetry)])
    assert code == 0, err
    said = [line for line in err.splitlines() if line.startswith("sds: note: step period inferred")]
    assert said == ["sds: note: " + notes[0]], said
