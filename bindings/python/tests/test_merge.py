"""`sds.merge`: reports scored where the files are, merged into `sds.score` over all of them
(issue 36, docs/SCORE.md §13.2)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, List

import pytest

import sds
from conftest import Demo, run_cli, same


def _split(demo: Demo, tmp: Path, cut: int) -> List[Path]:
    """The demo's results as two results files: records ``..cut`` and ``cut..``."""
    data: Dict[str, Any] = json.loads(demo.results.read_text())
    records = data["_checkpoint"]["records"]
    out = []
    for name, recs in (("a.json", records[:cut]), ("b.json", records[cut:])):
        d = json.loads(json.dumps(data))
        d["_checkpoint"]["records"] = recs
        d["_checkpoint"]["progress"] = [len(recs), len(recs)]
        p = tmp / name
        p.write_text(json.dumps(d))
        out.append(p)
    return out


def _without_inputs(report: Dict[str, Any]) -> Dict[str, Any]:
    return {k: v for k, v in report.items() if k not in ("inputs", "warnings")}


def test_merge_of_parts_equals_score_over_all(demo: Demo, tmp_path: Path, sds_bin: Path) -> None:
    a, b = _split(demo, tmp_path, 4)
    kw: Dict[str, Any] = {"telemetry": demo.telemetry, "routes": demo.routes}
    parts = []
    for i, results in enumerate((a, b)):
        part = tmp_path / f"part{i}.json"
        part.write_text(json.dumps(sds.score(results, **kw)))
        parts.append(part)
    whole = sds.score([a, b], **kw)
    merged = sds.merge(parts)
    assert merged["summary"]["missing"] == 0
    assert same(_without_inputs(merged), _without_inputs(whole))
    assert [p["file"] for p in merged["inputs"]["parts"]] == [str(p) for p in parts]
    assert merged["inputs"]["provenance"]["host"] is not None
    assert sds.merge(parts, host=False)["inputs"]["provenance"]["host"] is None
    # The command gives the same report.
    out = tmp_path / "cli.json"
    code, _, err = run_cli(sds_bin, ["merge", *map(str, parts), "-o", str(out)])
    assert code == 0, err
    assert same(_without_inputs(json.loads(out.read_text())), _without_inputs(merged))


def test_merge_refusals_raise(demo: Demo, tmp_path: Path) -> None:
    part = tmp_path / "part.json"
    part.write_text(json.dumps(sds.score(demo.results, telemetry=demo.telemetry)))
    with pytest.raises(sds.InputError, match="has a record in"):
        sds.merge([part, part])
    first = sds.merge([part, part], duplicates="first")
    assert len(first["dropped"]) == len(demo.records())
    with pytest.raises(sds.InputError, match="not an sds report"):
        sds.merge([demo.results])
    with pytest.raises(sds.IoError):
        sds.merge([tmp_path / "absent.json"])
    # `newest` works across parts (each row keeps its record's stamp): one copy of each route.
    newest = sds.merge([part, part], duplicates="newest")
    assert len(newest["dropped"]) == len(demo.records())
    with pytest.raises(sds.ConfigError):
        sds.merge([part], duplicates="sometimes")
