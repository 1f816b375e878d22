"""Issue 48 item 1 (the Python half): the package's entry points are the extension's typed
functions (``#[pyo3(signature = ...)]`` in Rust, the types in ``_sds.pyi``), not Python functions
packing their keyword arguments into a dict; names are read with the library's ``from_name``
and refused with its ``choices()``; the report's warnings are raised from Rust at the caller's
line."""

from __future__ import annotations

import ast
import inspect
import json
import re
import warnings
from pathlib import Path
from typing import Any, Callable, Dict, List, Tuple

import pytest

import sds
from conftest import Demo, run_cli

ENTRY_POINTS = ["score", "frames", "compare", "watch", "merge", "link"]
STUB = Path(sds.__file__).with_name("_sds.pyi")


def stub_signature(name: str) -> List[Tuple[str, str, Any]]:
    """(name, kind, default) of each parameter of `def name` in `_sds.pyi`."""
    tree = ast.parse(STUB.read_text())
    fn = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == name)
    a = fn.args
    out: List[Tuple[str, str, Any]] = []
    plain = a.posonlyargs + a.args
    defaults = [inspect.Parameter.empty] * (len(plain) - len(a.defaults)) + [
        ast.literal_eval(d) for d in a.defaults
    ]
    for p, d in zip(plain, defaults):
        out.append((p.arg, "POSITIONAL_OR_KEYWORD", d))
    for p, kd in zip(a.kwonlyargs, a.kw_defaults):
        out.append((p.arg, "KEYWORD_ONLY", inspect.Parameter.empty if kd is None else ast.literal_eval(kd)))
    return out


def runtime_signature(name: str) -> List[Tuple[str, str, Any]]:
    sig = inspect.signature(getattr(sds, name))
    return [(p.name, p.kind.name, p.default) for p in sig.parameters.values()]


@pytest.mark.parametrize("name", ENTRY_POINTS)
def test_i48_1_entry_points_are_the_typed_rust_functions(name: str) -> None:
    """`sds.score` is `sds._sds.score` (no Python wrapper), its signature (Rust's
    `#[pyo3(signature)]`) is the stub's, name for name and default for default, and `help()`
    shows the signature and the docs, written once in the Rust doc comment."""
    fn = getattr(sds, name)
    assert fn is getattr(sds._sds, name)
    assert runtime_signature(name) == stub_signature(name)
    doc = fn.__doc__ or ""
    assert "Args:" in doc and "Returns:" in doc and "Example:" in doc, doc[:200]
    text = pydoc_text(fn)
    assert f"{name}(" in text and "Args:" in text


def pydoc_text(fn: Callable[..., Any]) -> str:
    import pydoc

    return pydoc.render_doc(fn, renderer=pydoc.plaintext)


def test_i48_1_no_dict_packing_left() -> None:
    """The keyword arguments are no longer packed into a dict for Rust to read back."""
    import sds._options as options

    assert not hasattr(options, "run_options")
    for module in ("sds._compare", "sds._watch", "sds._warn"):
        with pytest.raises(ImportError):
            __import__(module)
    # A keyword an entry point does not take is refused by the signature itself.
    with pytest.raises(TypeError, match="no_such_option"):
        sds.score("x.json", no_such_option=1)  # type: ignore[call-arg]


def cli_choices(sds_bin: Path, args: List[str]) -> List[str]:
    """The names clap lists for a bad value (`[possible values: a, b]`): the library's names."""
    code, _, err = run_cli(sds_bin, args)
    assert code == 2, err
    m = re.search(r"\[possible values: ([^\]]+)\]", err)
    assert m, err
    return [v.strip() for v in m.group(1).split(",")]


def said_choices(e: BaseException) -> List[str]:
    """The names of `OPTION="value": expected a, b or c`."""
    listed = str(e).split(": expected ", 1)[1]
    return re.split(r", | or ", listed)


def test_i48_1_choices_are_the_librarys(demo: Demo, sds_bin: Path) -> None:
    """Every refusal of a name lists the library's choices (the command's `possible values`),
    named as Python spells the option, before anything is read."""
    base = ["--results", str(demo.results)]
    cases: List[Tuple[Callable[[], Any], str, List[str]]] = [
        (lambda: sds.score(demo.results, profile="fast"), 'profile="fast"', ["score", *base, "--profile", "fast"]),
        (lambda: sds.score(demo.results, duplicates="one"), 'duplicates="one"', ["score", *base, "--duplicates", "one"]),
        (lambda: sds.score(demo.results, route_subset="some"),  # type: ignore[arg-type]
         'route_subset="some"', ["score", *base, "--route-subset", "some"]),
        (lambda: sds.score(demo.results, lateral_reference="road"),  # type: ignore[arg-type]
         'lateral_reference="road"', ["score", *base, "--lateral-reference", "road"]),
        (lambda: sds.score(demo.results, group_by="colour"), 'group_by="colour"', ["score", *base, "--group-by", "colour"]),
        (lambda: sds.watch(demo.results, profile="fast"), 'profile="fast"', ["score", *base, "--profile", "fast"]),
        (lambda: sds.merge([demo.results], duplicates="one"), 'duplicates="one"', ["merge", str(demo.results), "--duplicates", "one"]),
        (lambda: sds.link(demo.results, to="exec:true", pace="slow"),  # type: ignore[arg-type]
         'pace="slow"', ["link", *base, "--to", "exec:true", "--pace", "slow"]),
        (lambda: sds.frames(demo.results, duplicates="one"), 'duplicates="one"', ["score", *base, "--duplicates", "one"]),
    ]
    for call, head, cli in cases:
        with pytest.raises(sds.ConfigError) as e:
            call()
        assert str(e.value).startswith(head + ": expected "), str(e.value)
        assert sorted(said_choices(e.value)) == sorted(cli_choices(sds_bin, cli)), (head, str(e.value))


def caught(call: Callable[[], Any]) -> List[warnings.WarningMessage]:
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        call()
    return [w for w in seen if issubclass(w.category, sds.SdsWarning)]


def test_i48_2_warnings_are_raised_at_the_callers_line(demo: Demo, tmp_path: Path) -> None:
    """Raised from Rust (`PyErr::warn`, stack level 1: the extension's function has no frame of
    its own), each warning points at the file and line that called the entry point."""
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1  # type: ignore[union-attr]
        report = sds.score(demo.results, telemetry=demo.telemetry)
    ours = [w for w in seen if issubclass(w.category, sds.SdsWarning)]
    assert ours and [str(w.message) for w in ours] == report["warnings"]
    assert {(w.filename, w.lineno) for w in ours} == {(__file__, line)}

    part = tmp_path / "part.json"
    part.write_text(json.dumps(report))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1  # type: ignore[union-attr]
        merged = sds.merge([part])
    ours = [w for w in seen if issubclass(w.category, sds.SdsWarning)]
    assert ours and [str(w.message) for w in ours] == merged["warnings"]
    assert {(w.filename, w.lineno) for w in ours} == {(__file__, line)}

    runs = {"a": (demo.results, demo.telemetry), "b": (demo.results, demo.telemetry)}
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1  # type: ignore[union-attr]
        sds.compare(runs, bootstrap_samples=1000)  # type: ignore[arg-type]
    ours = [w for w in seen if issubclass(w.category, sds.SdsWarning)]
    assert any("runs a and b are the same results" in str(w.message) for w in ours), ours
    assert {(w.filename, w.lineno) for w in ours} == {(__file__, line)}

    # A filter that makes them errors raises the first from the call, as before.
    with warnings.catch_warnings():
        warnings.simplefilter("error", sds.SdsWarning)
        with pytest.raises(sds.SdsWarning, match="step period inferred"):
            sds.score(demo.results, telemetry=demo.telemetry)


def test_i48_1_one_string_for_a_list_is_refused_by_name(demo: Demo) -> None:
    """A list option given one string would read as its characters: refused, naming it."""
    for call, name in [
        (lambda: sds.score(demo.results, protocols="all"), "protocols"),
        (lambda: sds.score(demo.results, topics="pose=/odom"), "topics"),
        (lambda: sds.compare({"a": demo.results, "b": demo.results}, fail_if_worse="ds"), "fail_if_worse"),
        (lambda: sds.compare({"a": demo.results, "b": demo.results}, seeds={"m": "ab"}), "seeds"),
        (lambda: sds.link(demo.results, to="exec:true", topics="pose=/odom"), "topics"),
    ]:
        with pytest.raises(sds.ConfigError, match=f"^{name}.*expected a list"):
            call()


def test_i48_1_paths_take_one_or_many(demo: Demo) -> None:
    """`results` (and `mcap`, `parts`) take one path, str or `os.PathLike`, or a list of them."""
    one: Dict[str, Any] = sds.score(demo.results, telemetry=demo.telemetry)
    for given in (str(demo.results), [demo.results], (str(demo.results),)):
        again = sds.score(given, telemetry=str(demo.telemetry))  # type: ignore[arg-type]
        assert again["summary"] == one["summary"]


def test_i48_1_lateral_reference_is_a_named_option(demo: Demo) -> None:
    """`lateral_reference=` (added in the four places docs/DESIGN.md lists): the report of
    `settings={"lateral_reference": ...}`, given before the overrides (a later setting wins)."""
    kw: Dict[str, Any] = dict(telemetry=demo.telemetry, routes=demo.routes, maps=demo.root / "maps")
    route = sds.score(demo.results, **kw)
    lane = sds.score(demo.results, lateral_reference="lane", **kw)
    assert route["config"]["lateral_reference"] == "route"
    assert lane["config"]["lateral_reference"] == "lane"
    assert lane == sds.score(demo.results, settings={"lateral_reference": "lane"}, **kw)
    assert lane["routes"] != route["routes"]
    again = sds.score(demo.results, lateral_reference="lane", settings={"lateral_reference": "route"}, **kw)
    assert again == route
