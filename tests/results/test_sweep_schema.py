"""A sweep's two forms from its one schema (results.sweep.SWEEP_SCHEMA): every column of the table
(``SweepResult.rows()``, speed_sweep.csv) is a value of the labelled form (``to_xarray()``) over
speed, quantity or criterion, and nothing else is there.

The problem: the two-speed synthetic sweep of test_sweep_report.py (no solver run; its second speed
lacks some criterion columns the first has). The labelled form is flattened back here by its dims
(``<quantity>_<name>``, ``<criterion>_<name>``), independently of the table's code; values must be
equal (the same floats and texts, no tolerance); a column missing at a speed is NaN or "".
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from .test_sweep_report import _sweep

xr = pytest.importorskip("xarray")


def _flattened(ds) -> list[dict]:
    rows = []
    for i, speed in enumerate(ds.speed.values):
        row = {"speed_kmh": float(speed)}
        for name, var in ds.data_vars.items():
            if var.dims == ("speed",):
                row[name] = var.values[i]
            else:
                dim = var.dims[1]
                for j, label in enumerate(ds[dim].values):
                    row[f"{label}_{name.removeprefix(dim + '_')}"] = var.values[i, j]
        rows.append(row)
    return rows


def _same(a, b) -> bool:
    if isinstance(a, str) or isinstance(b, str):
        return str(a) == str(b)
    return (math.isnan(a) and math.isnan(b)) or float(a) == float(b)


def test_every_column_of_the_table_is_in_the_labelled_form():
    sweep = _sweep()
    ds = sweep.to_xarray()
    assert list(ds.speed.values) == [200.0, 300.0] and list(ds.quantity.values) == ["deck_acc_z", "wheel_force_z"]
    assert list(ds.criterion.values) == ["deck/acc_z", "force/y"]
    assert list(ds.unit.values) == ["m/s^2", "N"] and ds.speed.attrs["units"] == "km/h"
    for row, flat in zip(sweep.rows(), _flattened(ds)):
        assert set(row) <= set(flat), sorted(set(row) - set(flat))
        for key, value in row.items():
            assert _same(value, flat[key]), (key, value, flat[key])
        for key in set(flat) - set(row):  # a criterion column this speed has not: empty
            assert flat[key] == "" or (not isinstance(flat[key], str) and np.isnan(flat[key])), key
    assert ds.attrs["kind"] == "speed_sweep" and "resonances_json" in ds.attrs


def test_a_criterions_values_are_the_schemas_criterion_variables():
    """CriterionValues (a speed's checks, labelled) has one field per variable over ``criterion``, in the
    schema's order: the table's ``<criterion>_<name>`` columns are composed from them in one place."""
    import dataclasses

    from tb_exudyn.results.sweep import SWEEP_SCHEMA, CriterionValues, checks_text, read_checks

    assert [f.name for f in dataclasses.fields(CriterionValues)] == [
        v.name for v in SWEEP_SCHEMA if v.dims == ("speed", "criterion")]
    values = {"a/b": CriterionValues(0.5, math.nan, 1.0, 2.0, "m", "ch", "OK", reason="r")}
    back = read_checks({"checks": np.array(checks_text(values))})
    assert list(back) == ["a/b"] and back["a/b"].reason == "r" and math.isnan(back["a/b"].probability)
