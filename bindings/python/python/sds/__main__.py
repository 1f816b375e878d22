"""``python -m sds``: the ``sds`` command."""

from ._cli import main

main()
