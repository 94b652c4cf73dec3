"""Regression tooling: baselines (record, check), the sections they record, and the pytest
plugin (``pim_check``, ``assert_agrees``)."""
