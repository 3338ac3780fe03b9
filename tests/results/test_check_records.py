"""The check's records and their two forms from the one schema (results.schema.CHECK_RECORD).

Records are built here by hand (no integration): two trains on a two-span bridge, one record with the
stochastic values. The CSV's columns must be the schema's in order (acc_z_mid_span one per span), every
cell the record's value (floats by repr, so bit for bit), empty where not computed; the labelled form
holds every variable with the same values (no tolerance: the values are copied, not computed).
"""

from __future__ import annotations

import csv
import dataclasses
import io
import math
import types

import numpy as np
import pytest

from tb_exudyn.results.check_records import CheckRecord, StochasticValues, check_dataset, record_columns, records_csv
from tb_exudyn.results.schema import CHECK_CRITERIA, CHECK_RECORD


def _record(train: str, speed: float, value: float, stochastic: StochasticValues | None = None) -> CheckRecord:
    return CheckRecord(criterion="en1990_deck/deck_acc_ballasted", load_model="HSLM-A as moving forces", train=train,
                       speed_kmh=speed, case="nominal", track="ballasted", location="span1.x4/8 (16 m)", value=value,
                       limit=3.5, damping_ratio=0.01, cutoff_hz=30.0, acc_z_mid_span=(value, 0.5 * value),
                       disp_z_mid=1e-3, phi_dyn=0.1, phi_irregularity=0.05, enhancement=1.125,
                       value_with_phi2=value * 1.025, stochastic=stochastic)


RECORDS = (_record("HSLM-A1", 144.0, 1.0), _record("HSLM-A1", 150.0, 4.0),
           _record("ice_mttm", 144.0, 0.25, StochasticValues(1e-7, 0.9, "bridge.span1.mid.acc_z_en1990", 0.2, "OK",
                                                             "", 64)))


def test_every_record_field_is_a_variable_of_the_schema():
    """Each field (and the utilisation and verdict it implies) is read by exactly one variable, so a field
    added to CheckRecord without its variable fails here."""
    read = {(v.attribute or v.name).split(".")[0] for v in CHECK_RECORD}
    fields = {f.name for f in dataclasses.fields(CheckRecord)}
    assert read == fields | {"utilisation", "verdict"}
    stochastic = {v.attribute.split(".")[1] for v in CHECK_RECORD if v.attribute.startswith("stochastic.")}
    assert stochastic == {f.name for f in dataclasses.fields(StochasticValues)}


def test_csv_columns_and_cells_from_the_records():
    text = records_csv(RECORDS)
    rows = list(csv.DictReader(io.StringIO(text)))
    assert tuple(rows[0]) == record_columns(2)
    assert record_columns(2)[5:7] == ("acc_z_mid_span1", "acc_z_mid_span2")
    assert "criterion" not in rows[0] and "utilisation" not in rows[0]  # the labelled form's only
    assert [float(r["max_deck_acc_z"]) for r in rows] == [r.value for r in RECORDS]
    assert [r["verdict"] for r in rows] == ["ok", "exceeds", "ok"]
    assert rows[0]["p_exceed"] == "" and float(rows[2]["p_exceed"]) == 1e-7 and rows[2]["stochastic_n_freq"] == "64"
    assert float(rows[1]["acc_z_mid_span2"]) == 2.0 and rows[0]["max_deck_acc_z_location"] == "span1.x4/8 (16 m)"


def test_a_record_read_by_column_is_its_cell():
    r = RECORDS[2]
    assert dict(r) == dict(zip(record_columns(2), [r[c] for c in record_columns(2)]))
    assert r["max_deck_acc_z"] == r.value and r["acc_z_mid_span2"] == 0.125 and r["level_at_target"] == 0.9
    assert RECORDS[0].get("p_exceed") is None and RECORDS[1].utilisation == pytest.approx(4.0 / 3.5)
    for bad in ("acc_z_mid_span3", "acc_z_mid_span", "criterion", "value"):
        with pytest.raises(KeyError):
            r[bad]


def test_labelled_form_holds_every_variable():
    pytest.importorskip("xarray")
    verdict = types.SimpleNamespace(criterion="deflection", title="t", clause="A2.4.4.2.3", load_model="LM71",
                                    value=0.01, limit=0.05, unit="m", bound="upper", utilisation=0.2, verdict="ok",
                                    case="nominal", location="span 1", caveats="")
    result = types.SimpleNamespace(rows=RECORDS, criteria=(verdict,), bridge="b", line_speed_kmh=200.0,
                                   track="ballasted", construction="prestressed_concrete", damping_basis="d",
                                   cutoff_hz=30.0, cutoff_basis="c", mode_frequencies=(3.0, 9.0), cases=("nominal",),
                                   stochastic_basis="", target_probability=None)
    ds = check_dataset(result)
    assert ds.sizes["row"] == 3 and ds.sizes["span"] == 2 and ds.sizes["criterion"] == 1
    assert list(ds["train"].values) == ["HSLM-A1", "HSLM-A1", "ice_mttm"]
    np.testing.assert_array_equal(ds["acc_z_mid_span"].values, [r.acc_z_mid_span for r in RECORDS])
    assert list(ds["utilisation"].values) == [r.value / 3.5 for r in RECORDS]
    assert math.isnan(ds["p_exceed"].values[0]) and ds["p_exceed"].values[2] == 1e-7
    assert ds["stochastic_location"].values[0] == "" and ds["criterion_verdict"].values[0] == "ok"
    labelled = {v.labelled_name for v in (*CHECK_RECORD, *CHECK_CRITERIA)}
    assert labelled == set(ds.data_vars) | set(ds.coords) - {"row", "span", "criterion"}
    assert ds["max_deck_acc_z"].attrs["units"] == "m/s^2" and math.isnan(ds.attrs["target_probability"])
