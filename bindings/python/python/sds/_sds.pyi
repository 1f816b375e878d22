"""Type stubs of the extension module ``sds._sds`` (Rust, PyO3)."""

import os
from typing import (
    Any,
    Callable,
    Dict,
    Iterable,
    Iterator,
    List,
    Literal,
    Mapping,
    Optional,
    Sequence,
    Tuple,
    Union,
)

__version__: str
FIELDS: List[str]
"""The fields of a ``get_metric_info()`` entry the monitor reads, in ``push_arrays`` order."""

class SdsError(Exception):
    """Base class of every error the sds package raises."""

class InputError(SdsError):
    """An input is invalid: a results file, route XML, labels file or telemetry frame."""

class ConfigError(SdsError):
    """An option or setting is invalid (also: a grouping without the label map it needs)."""

class NeedsLabelsError(ConfigError):
    """A grouping needs a label map that was not given (``group_by="family"`` or ``"route"``
    without ``labels``)."""

class IoError(SdsError):
    """A file or folder cannot be read."""

class SdsWarning(UserWarning):
    """A warning of the report (its ``warnings``): a problem that did not stop scoring, as the
    ``sds`` command prints it after ``sds: warning: ``. ``sds.score``, ``sds.frames``,
    ``sds.compare`` and ``sds.merge`` raise one per warning, at the caller's line."""

class FeatureUnavailableError(SdsError):
    """An option this build of sds does not have yet."""

class RefusedError(InputError, ConfigError):
    """The inputs do not fit the options (route ids given twice under ``duplicates="error"``,
    N smaller than the routes counted, a label map that matches no route, report parts that
    disagree): both an :class:`InputError` and a :class:`ConfigError`."""

def error_table() -> List[Tuple[str, int, type]]:
    """Every error kind of the library with the ``sds`` command's exit code and this package's
    exception class (the table docs/PYTHON.md documents)."""

def cli_main(argv: Sequence[str]) -> int:
    """Runs the ``sds`` command line with ``argv`` (program name first); returns its status."""

# The entry points: their types here, their docs once, in the Rust doc comments (pyo3 makes them
# `__doc__`; `help(sds.score)` shows them with the signature).

_Path = Union[str, "os.PathLike[str]"]
_Settings = Mapping[str, Union[str, int, float, bool]]

def score(
    results: Union[_Path, Sequence[_Path], None] = None,
    *,
    telemetry: Optional[_Path] = None,
    routes: Optional[_Path] = None,
    maps: Optional[_Path] = None,
    profile: str = "physical",
    duplicates: str = "error",
    expected_routes: Optional[int] = None,
    allow_missing_telemetry: bool = False,
    settings: Optional[_Settings] = None,
    group_by: Optional[str] = None,
    labels: Optional[_Path] = None,
    jobs: Optional[int] = None,
    progress: Union[bool, Callable[[int, int], Any], None] = None,
    protocols: Optional[Sequence[str]] = None,
    route_subset: Optional[Literal["all", "found"]] = None,
    lateral_reference: Optional[Literal["route", "lane"]] = None,
    mcap: Union[_Path, Sequence[_Path], None] = None,
    topics: Optional[Sequence[str]] = None,
) -> Dict[str, Any]: ...

def frames(
    results: Union[_Path, Sequence[_Path], None] = None,
    *,
    route_id: Optional[str] = None,
    mcap: Optional[_Path] = None,
    topics: Optional[Sequence[str]] = None,
    telemetry: Optional[_Path] = None,
    routes: Optional[_Path] = None,
    maps: Optional[_Path] = None,
    profile: str = "physical",
    duplicates: Optional[str] = None,
    settings: Optional[_Settings] = None,
) -> List[Dict[str, Any]]: ...

def compare(
    runs: Mapping[str, Union[_Path, Tuple[_Path, _Path]]],
    *,
    seeds: Optional[Mapping[str, Sequence[str]]] = None,
    baseline: Optional[str] = None,
    routes: Optional[_Path] = None,
    maps: Optional[_Path] = None,
    profile: str = "physical",
    expected_routes: Optional[int] = None,
    allow_missing_telemetry: bool = False,
    common_routes: bool = False,
    fail_if_worse: Optional[Sequence[str]] = None,
    bootstrap_samples: Optional[int] = None,
    bootstrap_seed: int = 0,
    settings: Optional[_Settings] = None,
    jobs: Optional[int] = None,
    protocols: Optional[Sequence[str]] = None,
    rank: bool = False,
    repro_halfwidth: float = 1.0,
    progress: Optional[Callable[[int, int], Any]] = None,
    route_subset: Optional[Literal["all", "found"]] = None,
    sweep: Optional[Mapping[str, Sequence[Union[str, int, float, bool]]]] = None,
) -> Dict[str, Any]: ...

def merge(
    parts: Union[_Path, Sequence[_Path]],
    *,
    duplicates: str = "error",
    host: bool = True,
) -> Dict[str, Any]: ...

def link(
    results: Union[_Path, Sequence[_Path], None] = None,
    *,
    to: str,
    telemetry: Optional[_Path] = None,
    routes: Optional[_Path] = None,
    maps: Optional[_Path] = None,
    mcap: Union[_Path, Sequence[_Path], None] = None,
    topics: Optional[Sequence[str]] = None,
    profile: str = "physical",
    duplicates: Optional[str] = None,
    expected_routes: Optional[int] = None,
    allow_missing_telemetry: bool = False,
    settings: Optional[_Settings] = None,
    jobs: Optional[int] = None,
    protocols: Optional[Sequence[str]] = None,
    route_subset: Optional[Literal["all", "found"]] = None,
    pace: Literal["fast", "realtime"] = "fast",
    inject: Optional[str] = None,
    tap: Optional[_Path] = None,
) -> Dict[str, Any]: ...

def long_tables(
    report_json: str,
) -> Dict[str, Tuple[List[str], Dict[str, List[Any]]]]:
    """The ``routes`` and ``events`` long tables of a JSON report's text, by the library's own
    builder: ``{name: (columns, {column: values})}`` (see ``sds.long_tables``)."""

def render(file: str, name: str) -> List[Tuple[str, str]]:
    """The HTML page and the figures of the ``sds score`` JSON report in ``file``:
    ``[(file name, text), ...]`` (``report.html``, ``decomposition.svg``, ``routes.svg``)."""

def refuse_unsafe(path: str) -> bool:
    """Raises ``IoError`` when ``path`` is a link or anything but a regular file; returns
    whether a regular file is there (the library's write rules)."""

class FileSet:
    """The library's all-or-nothing file set (``sds._files.FileSet`` wraps it)."""

    def __init__(self, folder: str) -> None: ...
    def place(self, path: str, write: Callable[[int], object]) -> None: ...
    def commit(self) -> None: ...
    def roll_back(self) -> None: ...

def watch(
    results: Union[_Path, Sequence[_Path]],
    *,
    telemetry: Optional[_Path] = None,
    routes: Optional[_Path] = None,
    maps: Optional[_Path] = None,
    interval: float = 10.0,
    timeout: Optional[float] = None,
    profile: str = "physical",
    duplicates: str = "error",
    expected_routes: Optional[int] = None,
    allow_missing_telemetry: bool = False,
    settings: Optional[_Settings] = None,
    group_by: Optional[str] = None,
    labels: Optional[_Path] = None,
    jobs: Optional[int] = None,
    protocols: Optional[Sequence[str]] = None,
    on_round: Optional[Callable[[Dict[str, Any], Dict[str, Any]], Any]] = None,
    route_subset: Optional[Literal["all", "found"]] = None,
    stall_factor: Optional[float] = None,
) -> "Watch": ...

class Watch(Iterator[Dict[str, Any]]):
    """The iterator of partial reports ``sds.watch`` returns: one round per ``next()``."""

    def __iter__(self) -> "Watch": ...
    def __next__(self) -> Dict[str, Any]:
        """Sleeps the interval (not before the first round), runs a round, returns its report
        (a half-written results file is retried after another interval); StopIteration once
        the route set is complete and a further round found nothing new, or after the
        timeout."""
    @property
    def status(self) -> Optional[Dict[str, Any]]:
        """The figures of the round that made the last report, with the fields of
        ``sds watch --status-json`` (``round``, ``time``, ``done``, ``n``, ``ds_done``,
        ``ds_n``, ``sds_done``, ``sds_n``, ``last_route``, ``last_state``, ``last_ds``,
        ``crashes``, ``seconds_left``, ``rescored``, ``reused``, ``rescored_routes``, ``changed``,
        ``complete``, ``retries``, ``round_ms``, ``stopped``); None before the first."""
    @property
    def finished(self) -> bool:
        """True once the iterator has stopped."""

class Monitor:
    """The streaming monitor of one route (see ``sds.Monitor``)."""

    def __new__(
        cls,
        profile: str = "physical",
        dt: float = 0.05,
        settings: Optional[Mapping[str, Union[str, int, float, bool]]] = None,
        *,
        route: Optional[Iterable[Any]] = None,
        maps: Optional[Union[str, "os.PathLike[str]"]] = None,
        town: Optional[str] = None,
        lateral_reference: Optional[str] = None,
    ) -> "Monitor": ...
    def push(
        self,
        entry: Mapping[str, Any],
        *,
        step: Optional[int] = None,
        collisions: Optional[Sequence[str]] = None,
        lat_err: Optional[float] = None,
    ) -> List[Dict[str, Any]]:
        """Pushes one tick (a ``get_metric_info()`` entry); returns that frame's events.

        ``collisions`` names this frame's collisions by kind (``pedestrian``, ``vehicle``,
        ``layout``, ``workzone``) or by the other actor's CARLA type id.
        """
    def _push_raw(
        self,
        n: int,
        data: bytes,
        steps: Optional[List[int]] = None,
        lat_err: Optional[bytes] = None,
        collisions: Optional[Dict[int, List[str]]] = None,
    ) -> List[Dict[str, Any]]: ...
    def finish(
        self,
        *,
        score_route: Optional[float] = None,
        score_penalty: Optional[float] = None,
        workzone: int = 0,
    ) -> Dict[str, Any]:
        """Ends the route: its last events, its summary, and DS_safe given the evaluator's
        ``score_route`` and ``score_penalty`` (and work-zone contacts)."""
    @property
    def frames(self) -> int:
        """Frames pushed so far."""
    @property
    def last_step(self) -> Optional[int]:
        """The step of the last frame pushed."""
    @property
    def last_frame(self) -> Optional[Dict[str, Any]]:
        """The last frame as the monitor saw it (``a_lon``, ``a_lat``, ``a_mag``, ``yaw_rate``,
        ``speed``, ``lat_err``, ``collisions``)."""
    @property
    def finished(self) -> bool:
        """True once ``finish`` has run."""
    @property
    def reference(self) -> str:
        """What the lateral error is measured against: ``map-route``, ``xml``, ``map-lane`` or
        ``none``."""
    @property
    def config(self) -> Dict[str, Any]:
        """The monitor's configuration."""
