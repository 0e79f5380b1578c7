"""What a practitioner must not miss in a row of workload figures: an action limit exceeded, and
a figure that sits on a knife edge of a cut-off (a centimetre moves it between a value and 0).

The revised NIOSH equation sets a multiplier to 0 past its reach (H beyond 63 cm, V or D beyond
175 cm, A beyond 135°), so a location a fraction of a centimetre past H's reach gets a
recommended weight limit of 0 and one just inside gets a small positive one: both are flagged
when within :data:`KNIFE_EDGE_CM` of the cut-off. Its lifting index depends on the hands'
location and the task, not on the body: four manikins at one location share it
(:data:`LIFTING_INDEX_SCOPE`)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from .back import COMPRESSION_LIMITS_N
from .lifting import A_MAX_DEG, UNITS

KNIFE_EDGE_CM = 1.0
"""How close to a cut-off [cm] a distance is flagged as a knife edge."""
KNIFE_EDGE_DEG = 5.0
"""How close to the asymmetry's cut-off [deg] an angle is flagged as a knife edge."""
LIFTING_INDEX_SCOPE = ("the lifting index depends on the location and the lifting task only "
                       "(the equation has no body term)")
"""How a lifting index is labelled wherever bodies are compared."""


CUT_OFFS = (("niosh_h_cm", "H", UNITS["metric"].h_max), ("niosh_v_cm", "V", UNITS["metric"].v_max),
            ("niosh_d_cm", "D", UNITS["metric"].d_max))
"""The distances of the equation whose multiplier is 0 past a reach [cm]: column, name, reach."""


def flags(row: Mapping) -> list[str]:
    """Every flag of one row of workload columns (those it has), in words."""
    found = []
    for column, name, reach in CUT_OFFS:
        value = row.get(column)
        if value is None or pd.isna(value):
            continue
        if abs(value - reach) <= KNIFE_EDGE_CM:
            side = "past" if value > reach else "inside"
            found.append(f"knife edge: {name} {value:.2f} cm is {abs(value - reach):.2f} cm "
                         f"{side} the {reach:g} cm reach (RWL 0 beyond it)")
    asymmetry = row.get("niosh_a_deg")
    if asymmetry is not None and not pd.isna(asymmetry) and \
            abs(asymmetry - A_MAX_DEG) <= KNIFE_EDGE_DEG:
        found.append(f"knife edge: A {asymmetry:.1f}° is near the {A_MAX_DEG:g}° "
                     "limit (AM 0 beyond it)")
    li = row.get("niosh_li")
    if li is not None and not pd.isna(li) and li > 1:
        found.append(f"lifting index {'inf' if np.isinf(li) else f'{li:.2f}'} over 1"
                     + (f": {zero_limit(row)}" if np.isinf(li) else ""))
    failed = row.get("shift_failure_min")
    if failed is not None and not pd.isna(failed) and np.isfinite(failed):
        found.append(f"over the shift a joint fails its hold after {failed:.0f} min")
    compression = row.get("back_compression_n")
    if compression is not None and not pd.isna(compression):
        action, upper = COMPRESSION_LIMITS_N
        if compression > upper:
            found.append(f"L5/S1 compression {compression:,.0f} N over NIOSH's "
                         f"{upper:,.0f} N upper limit")
        elif compression > action:
            found.append(f"L5/S1 compression {compression:,.0f} N over NIOSH's "
                         f"{action:,.0f} N action limit")
    return found


def zero_limit(row: Mapping) -> str:
    """Why the recommended weight limit is 0 (a lifting index of inf): the distances and the
    angle past the equation's reach."""
    past = [f"{name} {row[column]:.1f} cm is beyond its {reach:g} cm reach"
            for column, name, reach in CUT_OFFS
            if row.get(column) is not None and not pd.isna(row[column]) and row[column] > reach]
    asymmetry = row.get("niosh_a_deg")
    if asymmetry is not None and not pd.isna(asymmetry) and asymmetry > A_MAX_DEG:
        past.append(f"A {asymmetry:.1f}° is beyond its {A_MAX_DEG:g}° reach")
    return ("the recommended weight limit is 0 because " + " and ".join(past) if past else
            "the recommended weight limit is 0")


def flag_column(table: pd.DataFrame) -> pd.Series:
    """Each row's flags joined by "; " ("" where none), for tables and CSVs."""
    return pd.Series(["; ".join(flags(row)) for row in table.to_dict("records")],
                     index=table.index, dtype=object)
