"""The package's `sds` command is the Rust command line: same output, same exit codes."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from conftest import Demo, run_cli


def py_sds(*args: str) -> "subprocess.CompletedProcess[str]":
    exe = shutil.which("sds", path=str(Path(sys.executable).parent))
    assert exe, "the package installs an `sds` command beside the interpreter"
    return subprocess.run([exe, *args], capture_output=True, text=True)


def test_score_output_is_the_binarys(demo: Demo, sds_bin: Path) -> None:
    for fmt in ("json", "csv", "table"):
        args = ["score", "--results", str(demo.results), "--telemetry", str(demo.telemetry),
                "--routes", str(demo.routes), "--format", fmt]
        ours = py_sds(*args)
        code, out, _ = run_cli(sds_bin, args)
        assert (ours.returncode, ours.stdout) == (code, out)
        assert ours.stdout


def test_exit_codes_and_messages(demo: Demo, sds_bin: Path, tmp_path: Path) -> None:
    for args in (["score", "--results", str(tmp_path / "nope")], ["score"], ["--version"],
                 ["score", "--results", str(demo.results)]):
        ours = py_sds(*args)
        code, out, err = run_cli(sds_bin, args)
        assert (ours.returncode, ours.stdout, ours.stderr) == (code, out, err), args
    assert py_sds("score").returncode == 2
    assert py_sds("score", "--results", str(demo.results)).returncode == 3  # telemetry missing
    module = subprocess.run([sys.executable, "-m", "sds", "--version"], capture_output=True, text=True)
    assert module.returncode == 0 and module.stdout.startswith("sds ")
