"""`sds.log`, `sds.Tracker` and `sds.watch(on_round=...)` (issue 37): the report and each round
of a watch in Weights & Biases (offline mode: the run's files read back), TensorBoard (the event
files read back with tensorboard's reader) and MLflow (a local file store read back through
its client). Each skips, with the reason, where its package is not installed."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, Iterator, List

import pytest

import sds
from conftest import Demo


def _report(demo: Demo) -> Dict[str, Any]:
    return sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes, protocols=["all"])


def _watch(demo: Demo, tracker: "sds.Tracker") -> List[Dict[str, Any]]:
    """A watch of the finished demo run: every round goes to the tracker; the statuses seen."""
    seen: List[Dict[str, Any]] = []
    w = sds.watch(demo.results, telemetry=demo.telemetry, routes=demo.routes, interval=0.05, timeout=5,
                  protocols=["all"],
                  on_round=lambda status, report: (seen.append(status), tracker.on_round(status, report)))
    reports = list(w)
    assert len(reports) == len(seen) >= 1
    return seen


def _assert_settings(logged: Dict[str, Any], report: Dict[str, Any], as_text: bool = False) -> None:
    """The tracker's run holds the report's settings: the sds version, the settings' hash, the
    profile, the ability rule, the protocols and every value of ``config`` (issue 46 item 5c)."""
    provenance = report["inputs"]["provenance"]
    want: Dict[str, Any] = {
        "sds_version": provenance["sds_version"],
        "settings_sha256": provenance["settings_sha256"],
        "profile": report["profile"],
        "ability_rule": report["config"]["ability_rule"],
        "protocols": ",".join(report["config"]["protocols"]),
        "config/slack": report["config"]["slack"],
        "config/bounds/lat_acc": report["config"]["bounds"]["lat_acc"],
        "config/duplicates": report["config"]["duplicates"],
        "config/allow_missing_telemetry": report["config"]["allow_missing_telemetry"],
    }
    assert want["protocols"] and want["sds_version"] == sds.__version__
    for k, v in want.items():
        assert k in logged, (k, sorted(logged))
        if as_text:
            assert logged[k] == (str(v).lower() if isinstance(v, bool) else str(v)), k
        else:
            assert logged[k] == v, k
    assert sum(1 for k in logged if k.startswith("config/")) >= 30


def test_on_round_is_called_with_each_status_and_report(demo: Demo) -> None:
    calls: List[Any] = []
    w = sds.watch(demo.results, telemetry=demo.telemetry, routes=demo.routes, interval=0.05, timeout=5,
                  on_round=lambda status, report: calls.append((status, report)))
    reports = list(w)
    assert [r for _, r in calls] == reports
    assert calls[-1][0] == w.status
    assert calls[0][0]["round"] >= 1 and calls[0][0]["done"] == len(reports[0]["routes"])


def test_summary_scalars_name_the_headline_numbers(demo: Demo) -> None:
    from sds._trackers import summary_scalars

    report = _report(demo)
    s = summary_scalars(report)
    summary = report["summary"]
    assert s["sds/driving_score"] == summary["driving_score"]
    assert s["sds/success_rate"] == summary["success_rate"]
    assert s["sds/mean_ds_safe"] == summary["mean_ds_safe"]
    assert s["sds/mean_comfort"] == summary["mean_comfort"]
    assert s["sds/sds"] == summary["sds"]
    assert s["sds/protocols/lb2.1/driving_score"] == summary["protocols"]["lb2.1"]["driving_score"]
    assert any(k.startswith("sds/bench2drive/") for k in s)


def _wandb_records(path: Path) -> Iterator[Any]:
    """The records of an offline run's ``run-<id>.wandb`` file: a ``:W&B`` header (7 bytes),
    then LevelDB log blocks of 32 KiB, each record a checksum (4), a length (2), a type (1: whole,
    2/3/4: first/middle/last piece) and a protobuf ``Record`` (wandb's own ``wandb_internal``)."""
    from wandb.proto import wandb_internal_pb2

    data = path.read_bytes()
    assert data[:4] == b":W&B", path
    pos, block, buf = 7, 32768, b""
    while pos + 7 <= len(data):
        left = block - pos % block
        if left < 7:
            pos += left
            continue
        length = int.from_bytes(data[pos + 4:pos + 6], "little")
        kind = data[pos + 6]
        chunk = data[pos + 7:pos + 7 + length]
        pos += 7 + length
        if kind == 0:
            continue
        buf = chunk if kind in (1, 2) else buf + chunk
        if kind in (1, 4):
            record = wandb_internal_pb2.Record()
            record.ParseFromString(buf)
            yield record


def test_wandb_offline_run_files_hold_the_report(demo: Demo, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("wandb", reason="wandb is not installed (scripts/setup.sh downloads it)")
    for k, v in {"WANDB_MODE": "offline", "WANDB_SILENT": "true", "WANDB_DIR": str(tmp_path),
                 "WANDB_CACHE_DIR": str(tmp_path / "cache"), "WANDB_DATA_DIR": str(tmp_path / "data"),
                 "WANDB_CONFIG_DIR": str(tmp_path / "config")}.items():
        monkeypatch.setenv(k, v)
    report = _report(demo)
    tracker = sds.Tracker("wandb", project="sds-test", name="demo", log_dir=str(tmp_path))
    seen = _watch(demo, tracker)
    tracker.log(report)
    run_dir = Path(tracker.run.dir).parent
    tracker.close()
    history: Dict[str, Any] = {}
    summary: Dict[str, Any] = {}
    artifacts: Dict[str, List[str]] = {}
    config: Dict[str, Any] = {}
    for r in _wandb_records(next(run_dir.glob("run-*.wandb"))):
        kind = r.WhichOneof("record_type")
        if kind == "history":
            history.update({i.key or "/".join(i.nested_key): json.loads(i.value_json) for i in r.history.item})
        elif kind == "summary":
            summary.update({i.key or "/".join(i.nested_key): json.loads(i.value_json) for i in r.summary.update})
        elif kind == "artifact":
            artifacts[r.artifact.name] = [c.path for c in r.artifact.manifest.contents]
        elif kind == "config":
            config.update({i.key or "/".join(i.nested_key): json.loads(i.value_json) for i in r.config.update})
    assert history["sds/driving_score"] == report["summary"]["driving_score"]
    assert summary["sds/sds"] == report["summary"]["sds"]
    # Issue 46 item 5b: the route count stays a number; the routes table has a key of its own.
    assert summary["sds/routes"] == report["summary"]["routes"]
    assert summary["tables/routes/_type"] == "table-file"
    # Issue 46 item 5c: the settings are the run's config.
    _assert_settings(config, report)
    assert summary["sds/protocols/lb2.1/driving_score"] == report["summary"]["protocols"]["lb2.1"]["driving_score"]
    assert history["watch/ds_n"] == seen[-1]["ds_n"] and history["watch/crashes"] == 0
    assert history["_step"] == seen[-1]["round"]
    assert sorted(artifacts["demo-report"]) == ["decomposition.svg", "report.html", "report.json", "routes.svg"]
    tables = list((run_dir / "files" / "media" / "table").rglob("*.table.json"))
    assert tables, "no routes table in the run's files"
    table = json.loads(tables[0].read_text())
    assert len(table["data"]) == len(report["routes"])
    assert table["columns"][:2] == ["route_index", "route_id"]
    html = sorted(p.name.split("_")[0] for p in (run_dir / "files" / "media" / "html").rglob("*.html"))
    assert html == ["decomposition", "routes"]  # the two pictures as HTML panels
    assert summary["figures/routes/_type"] == "html-file"


def test_tensorboard_event_files_hold_the_report(demo: Demo, tmp_path: Path) -> None:
    pytest.importorskip("tensorboard", reason="tensorboard is not installed (scripts/setup.sh downloads it)")
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    report = _report(demo)
    with sds.Tracker("tensorboard", log_dir=str(tmp_path / "tb")) as tracker:
        seen = _watch(demo, tracker)
        tracker.log(report)
    acc = EventAccumulator(str(tmp_path / "tb"))
    acc.Reload()
    ds = acc.Scalars("sds/driving_score")
    assert ds[0].value == pytest.approx(report["summary"]["driving_score"], rel=1e-6)
    assert acc.Scalars("sds/sds")[0].value == pytest.approx(report["summary"]["sds"], rel=1e-6)
    rounds = acc.Scalars("watch/ds_done")
    assert [e.step for e in rounds] == [s["round"] for s in seen]
    assert rounds[-1].value == pytest.approx(seen[-1]["ds_done"], rel=1e-6)
    # Issue 46 item 5b: the route count is a scalar; the routes table a text under its own tag.
    assert acc.Scalars("sds/routes")[0].value == report["summary"]["routes"]
    assert "sds/routes" not in acc.Tags()["tensors"]
    text = acc.Tensors("tables/routes")[0]
    from tensorboard.util import tensor_util

    cells = tensor_util.make_ndarray(text.tensor_proto)
    assert cells.shape == (len(report["routes"]) + 1, len(sds.long_tables(report)["routes"][0]))
    assert cells[0][1] == b"route_id"
    assert (tmp_path / "tb" / "report.json").exists() and (tmp_path / "tb" / "report.html").exists()
    assert json.loads((tmp_path / "tb" / "report.json").read_text()) == report
    # Issue 46 item 5c: the settings as the run's hparams (the HParams dashboard's session).
    from tensorboard.plugins.hparams import plugin_data_pb2

    content = acc.PluginTagToContent("hparams")["_hparams_/session_start_info"]
    data = plugin_data_pb2.HParamsPluginData.FromString(content)
    hparams = {}
    for k, v in data.session_start_info.hparams.items():
        kind = v.WhichOneof("kind")
        hparams[k] = {"string_value": v.string_value, "bool_value": v.bool_value, "number_value": v.number_value}[kind]
    _assert_settings(hparams, report)


def test_mlflow_file_store_holds_the_report(demo: Demo, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    mlflow = pytest.importorskip("mlflow", reason="mlflow(-skinny) is not installed (scripts/setup.sh downloads it)")
    monkeypatch.setenv("MLFLOW_ALLOW_FILE_STORE", "true")  # MLflow 3 keeps the file store behind this
    report = _report(demo)
    tracker = sds.Tracker("mlflow", tracking_uri=f"file:{tmp_path / 'mlruns'}", experiment="sds-test", name="demo")
    seen = _watch(demo, tracker)
    tracker.log(report)
    tracker.close()
    client = mlflow.MlflowClient(tracking_uri=f"file:{tmp_path / 'mlruns'}")
    run = client.get_run(tracker.run_id)
    assert run.info.status == "FINISHED"
    metrics = run.data.metrics
    # Issue 46 item 5c: the settings as the run's params (MLflow keeps them as text).
    _assert_settings(run.data.params, report, as_text=True)
    assert metrics["sds/driving_score"] == report["summary"]["driving_score"]
    assert metrics["sds/protocols/lb2.1/driving_score"] == report["summary"]["protocols"]["lb2.1"]["driving_score"]
    history = client.get_metric_history(tracker.run_id, "watch/done")
    assert [m.step for m in history] == [s["round"] for s in seen]
    names = {f.path for f in client.list_artifacts(tracker.run_id, "sds")}
    assert {"sds/report.json", "sds/report.html", "sds/routes.svg", "sds/routes.json"} <= names
    local = client.download_artifacts(tracker.run_id, "sds/routes.json", str(tmp_path / "dl"))
    table = json.loads(Path(local).read_text())
    assert len(table["data"]) == len(report["routes"])
    # MLflow keeps a run's params once: a report of other settings into the same run is said,
    # and the params logged stay.
    other = sds.score(demo.results, telemetry=demo.telemetry, routes=demo.routes, profile="b2d-legacy")
    with pytest.warns(sds.SdsWarning, match="MLflow keeps a run's parameters once"):
        sds.log(other, to="mlflow", tracking_uri=f"file:{tmp_path / 'mlruns'}", run=tracker.run_id)
    _assert_settings(client.get_run(tracker.run_id).data.params, report, as_text=True)


def test_log_imports_no_backend_it_was_not_asked_for(demo: Demo, tmp_path: Path) -> None:
    import sys

    pytest.importorskip("tensorboard", reason="tensorboard is not installed")
    before = {m for m in ("wandb", "mlflow") if m in sys.modules}
    sds.log(_report(demo), to="tensorboard", log_dir=str(tmp_path / "tb"))
    assert {m for m in ("wandb", "mlflow") if m in sys.modules} == before
    with pytest.raises(ValueError, match="expected one of wandb, tensorboard, mlflow"):
        sds.log({}, to="neptune")


def test_r4_01_tensorboard_refuses_a_planted_link(demo: Demo, tmp_path: Path) -> None:
    """Issue 47 finding 1: sds.log(to="tensorboard") copied report.html through a link planted
    in the log folder (shutil.copy follows it). Now the link is refused, naming it; its target
    is untouched and no report file is left in the folder."""
    pytest.importorskip("tensorboard", reason="tensorboard is not installed (scripts/setup.sh downloads it)")
    victim = tmp_path / "victim"
    victim.write_text("secret")
    tb = tmp_path / "tb"
    tb.mkdir()
    (tb / "report.html").symlink_to(victim)
    with pytest.raises(sds.IoError, match=r"report\.html: a symbolic link"):
        sds.log(_report(demo), to="tensorboard", log_dir=str(tb))
    assert victim.read_text() == "secret"
    assert (tb / "report.html").is_symlink()
    assert not (tb / "report.json").exists()
