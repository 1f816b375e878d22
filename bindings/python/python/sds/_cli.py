"""The ``sds`` command installed with the package: the Rust command line, run in-process."""

from __future__ import annotations

import signal
import sys
from typing import List, NoReturn, Optional

from . import _sds


def main(argv: Optional[List[str]] = None) -> NoReturn:
    """Runs ``sds`` with ``argv`` (default: ``sys.argv``) and exits with its status."""
    # Ctrl-C stops the command at once, as it stops the binary (the scoring runs in Rust).
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    args = list(sys.argv if argv is None else argv)
    if args:
        args[0] = "sds"
    sys.stdout.flush()
    code = _sds.cli_main(args)
    raise SystemExit(code)


if __name__ == "__main__":
    main()
