"""``armlab size`` as a user runs it: the outputs, a duty-cycle file, exit 3 without a feasible drive, bad input."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest
from helpers import DATA, armlab_main

import armlab
from armlab.sizing.duty import read_duty_cycle, read_load_cases


def _cycle_file(tmp_path: Path) -> Path:
    """rr: pick at A, carry it to B in 1 s, place it (0.3 s held), come back empty in 0.8 s, wait 0.5 s."""
    path = tmp_path / "cycle.json"
    path.write_text(json.dumps({"deg": True, "steps": [
        {"segments": [{"from": [-38, 98], "to": [62, 68], "tf": 1.0}], "payload": True},
        {"dwell": 0.3, "payload": True},
        {"segments": [{"to": [-38, 98], "tf": 0.8}]},
        {"dwell": 0.5}]}))
    return path


@pytest.mark.slow
def test_size_writes_the_sizing_and_prints_one_line_per_joint(tmp_path):
    out = tmp_path / "sizing"
    done = armlab_main("size", "rr", "--duty-cycle", str(_cycle_file(tmp_path)), "--payload", "0,1.5",
                       "--safety-factor", "1.5", "--out", str(out))
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0].startswith("rr: duty cycle cycle.json (2.6 s), load cases 0 kg, 1.5 kg, safety factor 1.5")
    assert lines[1].startswith("joint1: ") and lines[2].startswith("joint2: ") and "converged after" in lines[-2]
    assert all("binds: " in line for line in lines[1:3])
    assert sorted(p.name for p in out.iterdir()) == ["sizing.csv", "sizing.md", "torque_speed_joint1.png",
                                                     "torque_speed_joint2.png"]
    rows = list(csv.DictReader((out / "sizing.csv").open()))
    assert [(r["joint"], r["load_case"]) for r in rows] == [("joint1", "0 kg"), ("joint1", "1.5 kg"),
                                                            ("joint2", "0 kg"), ("joint2", "1.5 kg")]
    # the CLI's numbers are the API's
    api = armlab.size_drives(armlab.load("rr"), _cycle_file(tmp_path), [0, 1.5], safety_factor=1.5)
    chosen = api.joints[0].chosen
    assert rows[1]["motor"] == chosen.motor_name and rows[1]["gearbox"] == chosen.gearbox_name
    np.testing.assert_allclose(float(rows[1]["motor_rms_torque_Nm"]), chosen.stats["rms_torque"][1], rtol=1e-15)
    assert rows[1]["binding_check"] == chosen.binding.name
    np.testing.assert_allclose(float(rows[1]["winding_peak_C"]), chosen.stats["winding_peak_C"][1], rtol=1e-15)
    md = (out / "sizing.md").read_text()
    assert "Nearest infeasible" in md and "| winding temperature |" in md and "duty S" in md
    assert "e+" not in md.split("## ")[1].split("Per load case")[0] or "≫" in md  # readable numbers


def test_the_payload_is_carried_one_way_only(tmp_path):
    """The duty cycle's empty return needs less than carrying the load both ways."""
    arm = armlab.load("rr")
    one_way = armlab.size_drives(arm, read_duty_cycle(arm, _cycle_file(tmp_path)), 3.0, mass_iteration=False)
    both = json.loads(_cycle_file(tmp_path).read_text())
    for step in both["steps"]:
        step["payload"] = True
    (tmp_path / "both.json").write_text(json.dumps(both))
    both_ways = armlab.size_drives(arm, tmp_path / "both.json", 3.0, mass_iteration=False)
    for j_one, j_both in zip(one_way.joints, both_ways.joints, strict=True):
        if (j_one.chosen.motor, j_one.chosen.gearbox) == (j_both.chosen.motor, j_both.chosen.gearbox):
            assert j_one.chosen.stats["rms_torque"][0] < j_both.chosen.stats["rms_torque"][0]


def test_no_feasible_drive_exits_3_with_the_nearest_candidates(tmp_path):
    done = armlab_main("size", "rr", "--payload", "50", "--out", str(tmp_path / "s"))
    assert done.returncode == 3
    assert "joint1: no feasible motor and gearbox among" in done.stdout
    assert "> gearbox rated" in done.stdout or "> rated" in done.stdout
    assert sorted(p.name for p in (tmp_path / "s").iterdir()) == ["sizing.csv", "sizing.md"]


def test_size_reads_a_urdf_with_its_tool_option(tmp_path):
    """``armlab size`` takes the URDF options of every arm command: --tool moves the payload to the elbow."""
    peaks = []
    for tool in ([], ["--tool", "fore"]):
        done = armlab_main("size", str(DATA / "two_link.urdf"), *tool, "--package-path", str(tmp_path), "--payload",
                           "5", "--from", "0,0", "--to", "0.5,0.5", "--out", str(tmp_path / f"s{len(tool)}"))
        assert done.returncode == 0, done.stderr
        elbow = next(line for line in done.stdout.splitlines() if line.startswith("elbow:"))
        peaks.append(float(re.search(r"joint peak ([0-9.e+-]+) N·m", elbow)[1]))  # joint side: any gearbox
    assert peaks[1] < 0.5 * peaks[0]  # 5 kg at the elbow axis, not 0.4 m beyond it


def test_a_lower_bus_voltage_can_change_the_choice(tmp_path):
    """The voltage check at the bus voltage: the example drives' 325/560 V make rr's joints feasible; at 60 V DC the
    voltage binds (or fails) where it did not."""
    done = armlab_main("size", "rr", "--payload", "1", "--bus-voltage", "60")
    assert "voltage" in done.stdout, done.stdout + done.stderr
    assert done.returncode in (0, 3)


def test_load_cases_from_a_file(tmp_path):
    path = tmp_path / "cases.json"
    path.write_text(json.dumps([{"name": "box", "mass": 2.0, "offset": [0.05, 0, 0],
                                 "inertia": [[0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.01]]}, {"mass": 0.5}]))
    cases = read_load_cases(path)
    assert [c.label for c in cases] == ["box", "0.5 kg"]
    done = armlab_main("size", "rr", "--load-cases", str(path))
    assert done.returncode == 0 and "load cases box, 0.5 kg" in done.stdout


@pytest.mark.parametrize(("argv", "message"), [
    (["--safety-factor", "0.5"], "safety factor 0.5 is not allowed"),
    (["--payload", "-1"], "--payload -1 is out of range: allowed 0 ≤ payload ≤ 1000 kg"),  # the option, issue 36
    (["--motors", "missing.csv"], "missing.csv"),
    (["--duty-cycle", "CYCLE", "--tf", "2"], "--duty-cycle gives the whole cycle"),
    (["--rank", "price"], "invalid choice: 'price'"),
    (["--bus-voltage", "0"], "bus voltage 0.0 V is not allowed"),
    (["--ambient", "400"], "ambient 400.0 °C is not allowed"),
    (["--brake-factor", "0.2"], "brake_factor 0.2 is not allowed"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, argv, message):
    argv = [str(_cycle_file(tmp_path)) if a == "CYCLE" else a for a in argv]
    done = armlab_main("size", "rr", *argv)
    assert done.returncode == 2 and message in done.stderr and len(done.stderr.splitlines()) == 1


@pytest.mark.parametrize(("steps", "message"), [
    ([{"dwell": -1}], "dwell -1.0 s is not allowed"),
    ([{"dwell": 1}], "a cycle that begins with a dwell needs \"start\""),
    ([{"segments": [{"from": [0, 0], "to": [1, 1], "tf": 1}], "payload": "yes"}], "\"payload\" = \"yes\" must be"),
    ([{"segments": [{"from": [0, 0], "to": [1, 1], "tf": 1}], "weight": 1}], "unknown key(s) weight"),
    ([{"move": 1}], "expected an object with \"segments\" (a move) or \"dwell\" (s)"),
])
def test_bad_duty_cycle_files(tmp_path, steps, message):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"steps": steps}))
    done = armlab_main("size", "rr", "--duty-cycle", str(path))
    assert done.returncode == 2 and message in done.stderr, done.stderr
