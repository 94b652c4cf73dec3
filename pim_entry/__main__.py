"""``python -m pim_entry ARGS``: the same as the ``pim`` console script."""

from pim_entry import run

run()
