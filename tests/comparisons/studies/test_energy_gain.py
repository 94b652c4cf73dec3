"""Where PIM gains energy the compliant contact loses it (it is passive)."""

import math

from comparisons.studies.energy_gain import energy_gain_study


def test_compliant_contact_loses_energy_where_pim_gains_it():
    table = energy_gain_study(count=4, seed=1)
    pim_change = table.column("PIM energy change [-]")
    sim_change = table.column("compliant energy change [-]")
    assert len(pim_change) == 4
    assert all(g > 0 for g in pim_change)
    assert all(math.isfinite(c) and c <= 1e-9 for c in sim_change)
    assert "%" in table.title
