"""The ``pim`` command line: the group and shared options (:mod:`pim.cli.main`) and pim's own
commands (``fit``, ``sensitivity``, ``plot`` in :mod:`pim.cli.fit`; ``uncertainty`` in
:mod:`pim.cli.uncertainty`).

Commands are registered under the ``pim.commands`` entry-point group in pyproject.toml and
loaded only when used, so ``pim --help`` stays fast; the layers above ``pim/`` (``sim``,
``comparisons``) add theirs the same way.
"""

from .main import (
    NO_IMPACT_EXIT_CODE,
    FiniteFloat,
    beta_option,
    cap_friction_option,
    case_argument,
    cli,
    echo_json,
    eps_option,
    friction_limit_option,
    json_option,
    law_options,
    main,
    require_brach,
    run,
    solve_with_options,
    units_option,
    warnings_of,
)

__all__ = ["main", "run", "cli", "case_argument", "eps_option", "beta_option", "units_option",
           "json_option", "echo_json", "friction_limit_option", "cap_friction_option",
           "solve_with_options", "warnings_of", "NO_IMPACT_EXIT_CODE", "law_options",
           "require_brach", "FiniteFloat"]
