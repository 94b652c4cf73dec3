"""The ``pim`` command line: the group and shared options (:mod:`pim.cli.main`) and pim's own
commands (``fit``, ``sensitivity``, ``plot`` in :mod:`pim.cli.fit`; ``uncertainty`` in
:mod:`pim.cli.uncertainty`).

Commands are registered under the ``pim.commands`` entry-point group in pyproject.toml and
loaded only when used, so ``pim --help`` stays fast; the layers above ``pim/`` (``sim``,
``comparisons``) add theirs the same way.
"""

from .main import (
    INADMISSIBLE_EXIT_CODE,
    NO_IMPACT_EXIT_CODE,
    FiniteFloat,
    allow_inadmissible_option,
    beta_option,
    cap_friction_option,
    case_argument,
    check_answer,
    cli,
    echo_json,
    eps_option,
    findings_json,
    finish_answer,
    friction_limit_option,
    json_option,
    law_options,
    main,
    require_brach,
    run,
    say_findings,
    solve_with_options,
    units_option,
    warnings_of,
)

__all__ = ["main", "run", "cli", "case_argument", "eps_option", "beta_option", "units_option",
           "json_option", "echo_json", "friction_limit_option", "cap_friction_option",
           "solve_with_options", "warnings_of", "NO_IMPACT_EXIT_CODE", "law_options",
           "require_brach", "FiniteFloat", "allow_inadmissible_option", "check_answer",
           "say_findings", "finish_answer", "findings_json", "INADMISSIBLE_EXIT_CODE"]
