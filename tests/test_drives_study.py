"""Design studies ask for the drives: the lightest feasible drive set, whether there is one, and its margin."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import armlab
from armlab.analysis.study import evaluate, parse_study


def test_drive_objectives_are_the_sizings(tmp_path):
    study = parse_study({"arm": "rr", "vary": {"payload": {"values": [1, 50], "unit": "kg"}},
                         "evaluate": ["drive_mass", "drives_feasible", "drive_margin"], "safety_factor": 1.5},
                        tmp_path)
    light, heavy = (evaluate(study, values) for values in study.candidates)
    sizing = armlab.size_drives(armlab.load("rr"), payloads=1.0, safety_factor=1.5)
    np.testing.assert_allclose([light["drive_mass"], light["drive_margin"]], [sizing.drive_mass, sizing.margin],
                               rtol=1e-12)
    assert light["drives_feasible"] and not heavy["drives_feasible"]
    assert math.isnan(heavy["drive_mass"]) and math.isnan(heavy["drive_margin"])
    assert study.units()["drive_mass"] == "kg"
    np.testing.assert_allclose(study.to_json()["safety_factor"], 1.5, rtol=1e-15)


@pytest.mark.parametrize(("change", "message"), [
    ({"vary": {"L1": {"values": [0.4]}}, "evaluate": ["reach"], "safety_factor": 2},
     "safety_factor changes only the drive objectives"),
    ({"safety_factor": 0.5}, "safety factor 0.5 is not allowed"),
    ({"motors": "nowhere.csv"}, "nowhere.csv"),
])
def test_bad_drive_settings_of_a_study(tmp_path, change, message):
    data = {"arm": "rr", "vary": {"payload": {"values": [1]}}, "evaluate": ["drive_mass"], **change}
    with pytest.raises((ValueError, OSError), match=message):
        parse_study(json.loads(json.dumps(data)), tmp_path)


@pytest.mark.slow
def test_paper_000s_beyond_the_paper_drives_are_armlab_sizes(tmp_path):
    """The reproduction's table of paper 000's drives is what ``armlab size rr --payload … --safety-factor …`` (the
    API the CLI calls) chooses, and each joint's torque–speed figure is written."""
    import csv

    from armlab.papers.beyond import OVERSIZE, RR_PAYLOADS, rr_drives_chosen
    from armlab.papers.paper_output import PaperOutput

    out = PaperOutput("000", tmp_path, lambda *_: None)
    out.group("beyond")
    rr_drives_chosen(out, fast=True)
    rows = list(csv.DictReader((tmp_path / "beyond_drives.csv").open()))
    sizing = armlab.size_drives(armlab.load("rr"), None, RR_PAYLOADS[True], safety_factor=OVERSIZE)
    assert [r["motor + gearbox"] for r in rows] == [f"{j.chosen.motor_name} + {j.chosen.gearbox_name}"
                                                     for j in sizing.joints]
    np.testing.assert_allclose([float(r["mass [kg]"]) for r in rows], [j.chosen.mass for j in sizing.joints],
                               rtol=1e-15)
    assert {"beyond_drives_joint1.png", "beyond_drives_joint2.png"} <= {p.name for p in tmp_path.iterdir()}
