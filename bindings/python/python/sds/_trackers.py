"""The report in experiment trackers (issue 37): Weights & Biases, TensorBoard, MLflow.

:func:`log` logs a scored run (the dict of :func:`sds.score`, :func:`sds.merge` or a round of
:func:`sds.watch`); :class:`Tracker` does the same and, live, logs each round of
:func:`sds.watch` through its :meth:`Tracker.on_round`. Each backend is imported only when
asked for (none is a dependency of the package): ``wandb``, ``tensorboard``, ``mlflow`` (or
``mlflow-skinny``).

What is logged:

- the summary's numbers as scalars, each named ``sds/<path in summary>``: ``sds/driving_score``
  (DS), ``sds/success_rate`` (SR), ``sds/mean_ds_safe`` (DS_safe), ``sds/mean_comfort``,
  ``sds/sds``, ``sds/protocols/<id>/<field>``, ``sds/bench2drive/<field>`` and the rest;
- the settings the report was scored with (:func:`settings_params`: ``sds_version``,
  ``settings_sha256``, ``profile``, ``ability_rule``, ``protocols`` and every value of
  ``config`` as ``config/<path>``) as the run's parameters: W&B config, TensorBoard hparams,
  MLflow params, so that runs can be filtered and grouped by them;
- the per-route rows (the long table ``routes``, :func:`sds.long_tables`) as a table under
  ``tables/routes`` (apart from the scalar ``sds/routes``, the route count): a W&B Table, a
  TensorBoard text table, an MLflow table artifact ``sds/routes.json``;
- the JSON and HTML reports as artifacts (TensorBoard has none: both files are written into
  its log folder, as ``sds score`` writes its own files), and the two pictures
  (``decomposition.svg``, ``routes.svg``) where the tracker shows them (W&B as HTML panels
  ``figures/decomposition`` and ``figures/routes``, MLflow as artifacts; TensorBoard shows no
  SVG);
- each round of a watch (:meth:`Tracker.on_round`): ``watch/ds_done``, ``watch/ds_n`` (the
  running DS over the routes done and over N), ``watch/sds_done``, ``watch/sds_n``,
  ``watch/done``, ``watch/n``, ``watch/crashes`` (the round's ``crashes``: routes whose
  record says the run broke, the rerun list's classes but ``missing`` and ``timeout``),
  ``watch/rescored``, at the round's number as step.
"""

from __future__ import annotations

import functools
import importlib
import json
import os
import shutil
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any, BinaryIO, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _sds
from ._files import FileSet, refuse_unsafe
from ._sds import SdsWarning
from ._tables import long_tables

BACKENDS = ("wandb", "tensorboard", "mlflow")
# The routes table's key (W&B) and tag (TensorBoard): apart from the scalars `sds/<path>`, one of
# which is the route count `sds/routes` (a table logged there replaced it in W&B).
TABLE_KEY = "tables/routes"
# The two pictures' keys in W&B (`figures/routes`, `figures/decomposition`), apart from the
# scalars for the same reason (`sds/routes` is the route count).
FIGURES_KEY = "figures"


def summary_scalars(report: Mapping[str, Any]) -> Dict[str, float]:
    """Every number of the report's ``summary`` (nested objects included, lists left out), as
    ``{"sds/<path>": value}`` with the path joined by ``/``.

    >>> summary_scalars({"summary": {"sds": 55.7, "protocols": {"b2d": {"driving_score": 71.3}}}})
    {'sds/sds': 55.7, 'sds/protocols/b2d/driving_score': 71.3}
    """
    out: Dict[str, float] = {}

    def walk(prefix: str, v: Any) -> None:
        if isinstance(v, Mapping):
            for k, x in v.items():
                walk(f"{prefix}/{k}", x)
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            out[prefix] = float(v)

    walk("sds", report.get("summary", {}))
    return out


Setting = Union[str, int, float, bool]


def settings_params(report: Mapping[str, Any]) -> Dict[str, Setting]:
    """The settings a report was scored with, flat, for a tracker's run parameters (MLflow
    params, W&B config, TensorBoard hparams), so that runs can be filtered and grouped by them:
    ``sds_version`` and ``settings_sha256`` (the report's ``inputs.provenance``; the version of
    this package when the report has none), ``profile``, ``ability_rule``, ``protocols`` (the
    ids joined with ``,``; empty for none) and every value of ``config`` as ``config/<path>``
    (a list as its JSON text, a null as ``"null"``).

    >>> p = settings_params({"profile": "physical", "config": {"ability_rule": "b2d-0.0.4",
    ...     "protocols": ["lb2.1"], "bounds": {"lat_acc": 4.89}, "expected_routes": None}})
    >>> p["protocols"], p["config/bounds/lat_acc"], p["config/expected_routes"]
    ('lb2.1', 4.89, 'null')
    """
    config = report.get("config") or {}
    provenance = (report.get("inputs") or {}).get("provenance") or {}
    out: Dict[str, Setting] = {"sds_version": str(provenance.get("sds_version") or _sds.__version__)}
    if provenance.get("settings_sha256"):
        out["settings_sha256"] = str(provenance["settings_sha256"])
    profile = report.get("profile", config.get("profile"))
    if profile is not None:
        out["profile"] = str(profile)
    if config.get("ability_rule") is not None:
        out["ability_rule"] = str(config["ability_rule"])
    if isinstance(config.get("protocols"), list):
        out["protocols"] = ",".join(str(p) for p in config["protocols"])

    def walk(prefix: str, v: Any) -> None:
        if isinstance(v, Mapping):
            for k, x in v.items():
                walk(f"{prefix}/{k}", x)
        elif v is None:
            out[prefix] = "null"
        elif isinstance(v, (str, int, float, bool)):
            out[prefix] = v
        else:
            out[prefix] = json.dumps(v, ensure_ascii=False)

    walk("config", config)
    return out


def _text(v: Setting) -> str:
    """A setting as MLflow keeps it (text; a bool as JSON writes it)."""
    return ("true" if v else "false") if isinstance(v, bool) else str(v)


def crashes(status: Mapping[str, Any]) -> int:
    """The round's crash figure, as the library classifies the routes (one rule with the
    rerun list: ``Failed - TickRuntime`` is the agent's outcome, not a crash)."""
    return int(status.get("crashes") or 0)


def round_scalars(status: Mapping[str, Any], report: Mapping[str, Any]) -> Dict[str, float]:
    """The figures :meth:`Tracker.on_round` logs for one round of :func:`sds.watch`."""
    out: Dict[str, float] = {}
    for key in ("ds_done", "ds_n", "sds_done", "sds_n", "done", "n", "rescored"):
        v = status.get(key)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out[f"watch/{key}"] = float(v)
    out["watch/crashes"] = float(crashes(status))
    return out


def report_files(report: Mapping[str, Any], folder: Path, name: str) -> List[Path]:
    """Writes ``report.json``, ``report.html`` and the figures of ``report`` into ``folder``
    (as ``sds score --format html`` and ``--figures`` render them); returns the paths."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "report.json"
    with open(path, "w", encoding="utf-8") as f:
        json.dump(report, f, ensure_ascii=False, allow_nan=False)
    written = [path]
    for file_name, text in _sds.render(str(path), name):
        p = folder / file_name
        p.write_text(text, encoding="utf-8")
        written.append(p)
    return written


def _routes(report: Mapping[str, Any]) -> Tuple[List[str], List[List[Any]]]:
    columns, rows = long_tables(report)["routes"]
    return columns, [[row[c] for c in columns] for row in rows]


def _write_bytes(data: bytes, f: BinaryIO) -> None:
    f.write(data)


class Tracker:
    """One run in a tracker: :meth:`log` logs a report, :meth:`on_round` one round of a watch
    (hand it to :func:`sds.watch` as ``on_round``), :meth:`close` ends the run this object
    started (a run handed in is left open).

    Args:
        to: ``"wandb"``, ``"tensorboard"`` or ``"mlflow"``.
        name: The run's name (and the report's name in its HTML page).
        run: A run already started (``wandb.init()``'s run; an MLflow run or its id); None:
            start one (W&B: ``wandb.init(project=project, name=name, dir=log_dir, **options)``;
            MLflow: ``start_run(run_name=name)`` in ``experiment``).
        project: The W&B project (default ``"sds"``).
        log_dir: TensorBoard's log folder (default ``runs/<name>``); W&B's ``dir``.
        tracking_uri: MLflow's tracking URI (e.g. ``file:/tmp/mlruns``); None: MLflow's own.
        experiment: MLflow's experiment name.
        options: More keyword arguments for ``wandb.init``.

    Example:
        >>> tracker = sds.Tracker("wandb", project="b2d-eval", name="tcp")  # doctest: +SKIP
        >>> for report in sds.watch("eval/results.json", telemetry="eval/",
        ...                         routes="bench2drive220.xml", on_round=tracker.on_round):
        ...     pass  # doctest: +SKIP
        >>> tracker.log(report)  # doctest: +SKIP
        >>> tracker.close()  # doctest: +SKIP
    """

    def __init__(
        self,
        to: str,
        *,
        name: str = "sds",
        run: Any = None,
        project: Optional[str] = None,
        log_dir: Optional[str] = None,
        tracking_uri: Optional[str] = None,
        experiment: Optional[str] = None,
        **options: Any,
    ) -> None:
        if to not in BACKENDS:
            raise ValueError(f"to={to!r}: expected one of {', '.join(BACKENDS)}")
        self.to = to
        self.name = name
        self.owns = run is None
        self._rounds = 0
        self._params: Optional[Dict[str, Setting]] = None
        self._logged: Dict[str, str] = {}
        self._tmp = Path(tempfile.mkdtemp(prefix="sds-log-"))
        if to == "wandb":
            wandb = importlib.import_module("wandb")
            self.wandb = wandb
            self.run = run if run is not None else wandb.init(project=project or "sds", name=name, dir=log_dir, **options)
        elif to == "tensorboard":
            writer = importlib.import_module("tensorboard.summary.writer.event_file_writer")
            self.log_dir = Path(log_dir or os.path.join("runs", name))
            self.log_dir.mkdir(parents=True, exist_ok=True)
            self.writer = writer.EventFileWriter(str(self.log_dir))
            self.run = self.log_dir
        else:
            mlflow = importlib.import_module("mlflow")
            self.client = mlflow.MlflowClient(tracking_uri=tracking_uri)
            if run is None:
                exp = self.client.get_experiment_by_name(experiment or "Default")
                exp_id = exp.experiment_id if exp is not None else self.client.create_experiment(experiment or "Default")
                run = self.client.create_run(exp_id, run_name=name)
            self.run_id: str = run if isinstance(run, str) else run.info.run_id
            self.run = run
            if not self.owns:  # a run handed in may hold params already
                self._logged = dict(self.client.get_run(self.run_id).data.params)

    # -- the backends' three primitives: scalars, a table, files ------------------------------
    def _scalars(self, values: Mapping[str, float], step: int) -> None:
        if self.to == "wandb":
            self.run.log(dict(values), step=step)
        elif self.to == "tensorboard":
            event_pb2 = importlib.import_module("tensorboard.compat.proto.event_pb2")
            summary_pb2 = importlib.import_module("tensorboard.compat.proto.summary_pb2")
            summary = summary_pb2.Summary(
                value=[summary_pb2.Summary.Value(tag=k, simple_value=v) for k, v in values.items()]
            )
            self.writer.add_event(event_pb2.Event(wall_time=time.time(), step=step, summary=summary))
        else:
            entities = importlib.import_module("mlflow.entities")
            now = int(time.time() * 1000)
            metrics = [entities.Metric(k, v, now, step) for k, v in values.items()]
            self.client.log_batch(self.run_id, metrics=metrics)

    def _settings(self, report: Mapping[str, Any]) -> None:
        """The report's settings as the run's parameters, once per run unless they change."""
        params = settings_params(report)
        if params == self._params:
            return
        self._params = params
        if self.to == "wandb":
            self.run.config.update(params, allow_val_change=True)
        elif self.to == "tensorboard":
            hparams = importlib.import_module("tensorboard.plugins.hparams.summary_v2")
            event_pb2 = importlib.import_module("tensorboard.compat.proto.event_pb2")
            summary = hparams.hparams_pb(params, trial_id=self.name)
            self.writer.add_event(event_pb2.Event(wall_time=time.time(), summary=summary))
        else:
            # MLflow keeps a run's params once: the new ones are logged, a changed one is said.
            entities = importlib.import_module("mlflow.entities")
            text = {k: _text(v) for k, v in params.items()}
            changed = [k for k, v in text.items() if self._logged.get(k, v) != v]
            if changed:
                k = changed[0]
                warnings.warn(
                    f"MLflow run {self.run_id}: this report's settings differ from those logged "
                    f"({len(changed)} parameter(s), first {k}: {self._logged[k]} kept, this report "
                    f"has {text[k]}); MLflow keeps a run's parameters once: log reports scored "
                    "with other settings to another run",
                    SdsWarning,
                    stacklevel=4,
                )
            items = [entities.Param(k, v) for k, v in text.items() if k not in self._logged]
            for i in range(0, len(items), 100):  # MLflow takes at most 100 params a batch
                self.client.log_batch(self.run_id, params=items[i : i + 100])
            self._logged.update({p.key: p.value for p in items})

    def _table(self, columns: Sequence[str], rows: Sequence[Sequence[Any]], step: int) -> None:
        if self.to == "wandb":
            table = self.wandb.Table(columns=list(columns), data=[list(r) for r in rows], allow_mixed_types=True)
            self.run.log({TABLE_KEY: table}, step=step)
        elif self.to == "tensorboard":
            text = importlib.import_module("tensorboard.plugins.text.summary_v2")
            event_pb2 = importlib.import_module("tensorboard.compat.proto.event_pb2")
            np = importlib.import_module("numpy")
            cells = [list(columns)] + [["" if v is None else str(v) for v in r] for r in rows]
            summary = text.text_pb(TABLE_KEY, np.array(cells, dtype=object))
            self.writer.add_event(event_pb2.Event(wall_time=time.time(), step=step, summary=summary))
        else:
            data = {c: [r[i] for r in rows] for i, c in enumerate(columns)}
            self.client.log_table(self.run_id, data=data, artifact_file="sds/routes.json")

    def _files(self, paths: Sequence[Path]) -> None:
        if self.to == "wandb":
            artifact = self.wandb.Artifact(f"{self.name}-report", type="sds-report")
            for p in paths:
                artifact.add_file(str(p))
            self.run.log_artifact(artifact)
            pictures = {f"{FIGURES_KEY}/{p.stem}": self.wandb.Html(p.read_text(encoding="utf-8"), inject=False) for p in paths if p.suffix == ".svg"}
            if pictures:
                self.run.log(pictures)
        elif self.to == "tensorboard":
            # Into a folder others may write to: as sds score writes its own files (a link at
            # a name refused, never followed; the set all or nothing).
            targets = [self.log_dir / p.name for p in paths]
            for t in targets:
                refuse_unsafe(t)
            with FileSet(self.log_dir) as out:
                for p, t in zip(paths, targets):
                    out.place(t, functools.partial(_write_bytes, p.read_bytes()))
        else:
            for p in paths:
                self.client.log_artifact(self.run_id, str(p), "sds")

    # -- what users call -----------------------------------------------------------------------
    def log(self, report: Mapping[str, Any], *, step: Optional[int] = None) -> None:
        """Logs a report: the summary's scalars, the per-route table, the JSON and HTML reports
        and the pictures (see the module's doc). ``step``: the tracker's step (default: after
        the last round logged)."""
        at = self._rounds if step is None else step
        self._settings(report)
        self._scalars(summary_scalars(report), at)
        columns, rows = _routes(report)
        self._table(columns, rows, at)
        self._files(report_files(report, self._tmp / f"report-{at}", self.name))
        self._flush()

    def on_round(self, status: Mapping[str, Any], report: Mapping[str, Any]) -> None:
        """Logs one round of :func:`sds.watch` (its ``status`` and report): the running DS over
        the routes done and over N, routes done, crashes (see the module's doc), at the round's
        number as step. Hand it to ``sds.watch(..., on_round=tracker.on_round)``."""
        step = int(status.get("round") or self._rounds + 1)
        self._rounds = max(self._rounds, step)
        self._settings(report)
        self._scalars(round_scalars(status, report), step)
        self._flush()

    def _flush(self) -> None:
        if self.to == "tensorboard":
            self.writer.flush()

    def close(self) -> None:
        """Ends the run this tracker started (W&B ``finish``, MLflow ``FINISHED``); closes the
        TensorBoard writer."""
        if self.to == "wandb" and self.owns:
            self.run.finish()
        elif self.to == "tensorboard":
            self.writer.close()
        elif self.to == "mlflow" and self.owns:
            self.client.set_terminated(self.run_id)
        shutil.rmtree(self._tmp, ignore_errors=True)

    def __enter__(self) -> "Tracker":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


def log(report: Mapping[str, Any], to: str, *, step: Optional[int] = None, **options: Any) -> Any:
    """Logs a report to a tracker in one call and returns the run (W&B's run, TensorBoard's log
    folder, MLflow's run id): :class:`Tracker` ``(to, **options)``, :meth:`Tracker.log`, then
    :meth:`Tracker.close` (a run handed in as ``run=`` stays open).

    Example:
        >>> report = sds.score("results/", telemetry="eval/", routes="bench2drive220.xml")  # doctest: +SKIP
        >>> sds.log(report, to="mlflow", tracking_uri="file:/tmp/mlruns", name="tcp")  # doctest: +SKIP
    """
    with Tracker(to, **options) as t:
        t.log(report, step=step)
        return t.run_id if to == "mlflow" else t.run
