"""Every cell of every REBA and RULA table against a separate transcription of the sources."""

import importlib

import numpy as np
import pytest
from tables_text import parse_tables

from ergohandover.ergonomics.bands import lookup

REBA = importlib.import_module("ergohandover.ergonomics.reba")
RULA = importlib.import_module("ergohandover.ergonomics.rula")
REF = parse_tables()


@pytest.mark.parametrize(("name", "table", "shape"), [
    ("reba_a", REBA.TABLE_A, (5, 3, 4)),
    ("reba_b", REBA.TABLE_B, (6, 2, 3)),
    ("reba_c", REBA.TABLE_C, (12, 12)),
    # RULA Table A is stored as [upper][lower][wrist][twist]; the source flattens wrist/twist.
    ("rula_a", RULA.TABLE_A.reshape(6, 3, 8), (6, 3, 8)),
    ("rula_b", RULA.TABLE_B, (6, 6, 2)),
    ("rula_c", RULA.TABLE_C, (8, 7)),
])
def test_every_cell_matches_the_reference(name, table, shape):
    expected = np.array(REF[name])
    assert expected.shape == shape == table.shape
    mismatches = np.argwhere(table != expected)
    assert mismatches.size == 0, f"{name} differs at 0-based cells {mismatches.tolist()}"


def test_rula_table_a_is_indexed_by_wrist_then_twist():
    # Source column (wrist - 1) * 2 + (twist - 1): wrist 3, twist 2 is column 5.
    assert RULA.TABLE_A[0, 0, 2, 1] == REF["rula_a"][0][0][5]


@pytest.mark.parametrize("table", [REBA.TABLE_A, REBA.TABLE_B, REBA.TABLE_C, RULA.TABLE_A,
                                   RULA.TABLE_B, RULA.TABLE_C])
def test_lookup_reads_every_cell_through_one_based_indices(table):
    grids = np.meshgrid(*[np.arange(1, n + 1) for n in table.shape], indexing="ij")
    flat = [g.ravel().astype(np.int8) for g in grids]
    np.testing.assert_array_equal(lookup(table, *flat), table.ravel())
