"""``python -m pim_cli ARGS``: the same as the ``pim`` console script."""

from pim_cli import run

run()
