"""The error table (issue 35): each library error kind's exit code in the ``sds`` command and
exception class in this package come from one classification, ``ErrorKind``; this pins it."""

import sds
from sds import _sds


def test_i35_error_kind_table_pins_exit_codes_and_classes() -> None:
    table = [(kind, code, cls.__name__) for kind, code, cls in _sds.error_table()]
    assert table == [
        ("io", 1, "IoError"),
        ("input", 1, "InputError"),
        ("option", 2, "ConfigError"),
        ("needs-labels", 2, "NeedsLabelsError"),
        ("missing-folder", 2, "IoError"),
        ("refused", 2, "RefusedError"),
        ("empty-run", 4, "InputError"),
        ("cancelled", 1, "KeyboardInterrupt"),
        ("internal", 1, "SdsError"),
    ]


def test_i35_refused_is_an_input_and_a_config_error() -> None:
    assert issubclass(sds.RefusedError, sds.InputError)
    assert issubclass(sds.RefusedError, sds.ConfigError)
    assert sds.RefusedError.__module__ == "sds"
