"""Command-line commands of the ``pim`` tool that live outside :mod:`pim.cli`.

Each is registered under the ``pim.commands`` entry-point group in pyproject.toml and loaded
only when used, so ``pim --help`` stays fast.
"""
