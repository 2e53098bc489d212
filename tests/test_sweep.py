"""Design studies: checked before any work, objectives two ways, resumable results.csv, failures reported."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
from helpers import armlab_main, assert_same_objectives, objectives, rows, write_study

from armlab.analysis.study import evaluate, load_study, parse_study
from armlab.analysis.sweep import EXIT_FAILED, RESULTS, STUDY, run_sweep
from armlab.analysis.workspace import workspace
from armlab.models import get_arm

ARMLAB = str(Path(__file__).resolve().parents[1] / ".venv" / "bin" / "armlab")
RR_LENGTHS = {"arm": "rr",
              "vary": {"L2": {"from": 0.2, "to": 0.3, "steps": 2}, "L1": {"values": [30, 40], "unit": "cm"}},
              "evaluate": ["workspace_volume", "reach"], "samples": 20000}


@pytest.mark.parametrize(("change", "message"), [
    ({"arm": "nope"}, "unknown arm 'nope'"),
    ({"vary": {"L9": {"values": [1]}}}, "unknown parameter 'L9'"),
    ({"vary": {"L1": {"values": []}}}, "the range is empty"),
    ({"vary": {"L1": {"from": 0.1, "to": 0.2, "steps": 0}}}, "the range is empty"),
    ({"vary": {"L1": {"from": 0.1, "to": 0.2}}}, "missing 'steps'"),
    ({"vary": {"L1": {"values": [1], "unit": "furlong"}}}, "unit \"furlong\" is not allowed"),
    ({"vary": {}}, "vary must be a non-empty object"),
    ({"evaluate": ["beauty"]}, "unknown objective 'beauty'"),
    ({"evaluate": []}, "non-empty list"),
    ({"samples": 10}, "samples 10 is not allowed"),
    ({"samples": 10**11}, "samples 1e11 is not allowed: give a whole number 1000 … 1e9"),
    ({"seed": -1}, "seed -1 is not allowed"),
    ({"resolution": 1e308}, "resolution 1e308 is out of range"),
    ({"vary": {"L1": {"from": 0.1, "to": 0.5, "steps": 10**9}}}, "steps = 1,000,000,000 is more than the 10,000"),
    ({"vary": {"L1": {"from": 0.1, "to": 0.5, "steps": 200}, "L2": {"from": 0.1, "to": 0.5, "steps": 200}}},
     r"vary makes 40,000 candidates \(200 × 200\), more than the 10,000"),
    ({"vary": {"L1": {"values": [0.3, 1e308]}}}, r"vary.L1: 1e\+308 is out of range"),
    ({"vary": {"tf": {"values": [1, 1e308]}}, "evaluate": ["peak_torque"]}, "tf 1e308 is out of range"),
    ({"vary": {"tf": {"values": [1, 1e5]}}, "evaluate": ["peak_torque"]}, "100,000,001 log samples"),
    ({"vary": {"tf": {"values": [1, 2]}}}, "changes only the torque objectives"),
    ({"colour": "red"}, "unknown key 'colour'"),
    ({"vary": {"payload": {"values": [-1]}}, "evaluate": ["peak_torque"]}, "payload"),
    ({"vary": {"tf": {"values": [0]}}, "evaluate": ["peak_torque"]}, "tf = 0"),
])
def test_bad_studies_are_one_line_errors(change: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message) as error:
        parse_study(RR_LENGTHS | change)
    assert "\n" not in str(error.value)


def test_bad_study_from_the_cli_does_no_work(tmp_path: Path) -> None:
    """``armlab sweep`` run in this process (:func:`conftest.armlab_main`)."""
    (tmp_path / "broken.json").write_text("{\"arm\": ")
    for study, message in ((tmp_path / "broken.json", "not valid JSON"),
                           (write_study(tmp_path, RR_LENGTHS | {"evaluate": ["x"]}), "unknown objective 'x'"),
                           (tmp_path / "missing.json", "cannot read it")):
        run = armlab_main("sweep", str(study), "--out", str(tmp_path / "out"))
        assert run.returncode == 2 and run.stderr.startswith("armlab: error:") and message in run.stderr
        assert len(run.stderr.strip().splitlines()) == 1
        assert not (tmp_path / "out").exists()


def test_candidates_and_units() -> None:
    study = parse_study(RR_LENGTHS)
    assert study.candidates == [(0.2, 30.0), (0.2, 40.0), (0.3, 30.0), (0.3, 40.0)]  # exact: the study's values
    # exact: 40 cm / 100, correctly rounded like 0.4
    assert study.settings((0.3, 40.0)) == ({"L2": 0.3, "L1": 0.4}, 0.0, None)
    assert study.units()["workspace_volume"] == "m²" and study.columns[0] == "candidate"


def test_workspace_objectives_equal_a_direct_workspace() -> None:
    study = parse_study(RR_LENGTHS)
    got = evaluate(study, (0.3, 40.0))
    ws = workspace(get_arm("rr", L1=0.4, L2=0.3), 20000, study.resolution, 0, jacobians=False)
    assert got == {"workspace_volume": ws.volume, "reach": ws.reach}  # exact: the same code and input, this process


def test_torques_by_inverse_dynamics_equal_the_simulation() -> None:
    """Batch inverse dynamics along the motion every 1 ms against paper 000's Fig. 6 simulation."""
    base = {"arm": "rr", "vary": {"payload": {"values": [1.5]}}, "tf": 1.0,
            "evaluate": ["peak_torque", "rms_torque", "peak_power"]}
    by_rnea = evaluate(parse_study(base), (1.5,))
    by_simulation = evaluate(parse_study(base | {"simulate": True}), (1.5,))
    assert by_rnea.keys() == by_simulation.keys() == {"peak_torque_1", "peak_torque_2", "rms_torque_1",
                                                      "rms_torque_2", "peak_power"}
    for key, value in by_rnea.items():
        assert abs(value - by_simulation[key]) < 1e-6 * max(1.0, abs(value)), key


def test_peak_torque_grows_with_payload_and_shrinks_with_time() -> None:
    study = parse_study({"arm": "rr", "vary": {"tf": {"values": [1, 2]}, "payload": {"values": [0, 2]}},
                         "evaluate": ["peak_torque"]})
    peaks = {values: evaluate(study, values)["peak_torque_1"] for values in study.candidates}
    assert peaks[(1.0, 2.0)] > peaks[(1.0, 0.0)] and peaks[(1.0, 0.0)] > peaks[(2.0, 0.0)]


def test_sweep_resumes_and_never_keeps_half_a_row(tmp_path: Path) -> None:
    study = write_study(tmp_path, RR_LENGTHS)
    out = tmp_path / "out"
    first = run_sweep(study, out, workers=2)
    assert (first.total, first.done_before, first.computed, first.failed) == (4, 0, 4, [])
    columns = ["workspace_volume", "reach"]
    complete = objectives(out, columns)
    assert sorted(complete) == [0, 1, 2, 3]
    for i, values in enumerate(load_study(study).candidates):  # each row is its candidate's
        # computed by the sweep's worker processes: up to another process's rounding (helpers.RECOMPUTED_RTOL)
        assert_same_objectives({i: complete[i]}, {i: [evaluate(load_study(study), values)[c] for c in columns]})
    assert {"workspace_volume.png", "workspace_volume_map.png", "reach.png", "reach_map.png"} <= {
        p.name for p in out.iterdir()}
    record = json.loads((out / STUDY).read_text())
    assert {"armlab", "drake", "numpy", "dask"} <= set(record["versions"])
    assert record["study"]["vary"]["L1"] == {"values": [30.0, 40.0], "unit": "cm"}  # exact: the study's values

    lines = (out / RESULTS).read_text().splitlines(keepends=True)
    (out / RESULTS).write_text("".join(lines[:3]) + lines[3][:17])  # two rows kept, the third cut mid-line
    again = run_sweep(study, out, workers=1)
    assert (again.done_before, again.computed) == (2, 2)
    assert_same_objectives(objectives(out, columns), complete)  # two rows recomputed by another process
    assert (out / RESULTS).read_text().count("\n") == 5 and (out / RESULTS).read_text().endswith("\n")
    assert run_sweep(study, out, workers=1).computed == 0
    assert len(json.loads((out / STUDY).read_text())["runs"]) == 3


def test_a_stopped_sweep_resumes(tmp_path: Path) -> None:
    """Ctrl-C (SIGINT to the process group) after the first rows: exit 130, and a rerun computes only the rest."""
    study = write_study(tmp_path, RR_LENGTHS | {"samples": 400000})
    out = tmp_path / "out"
    process = subprocess.Popen([ARMLAB, "sweep", str(study), "--out", str(out), "--workers", "1"],
                               stderr=subprocess.PIPE, text=True, start_new_session=True)
    began = time.monotonic()
    while not ((out / RESULTS).exists() and (out / RESULTS).read_text().count("\n") >= 2):
        assert process.poll() is None and time.monotonic() - began < 120, "no row written"
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 130 and "Traceback" not in err, err
    kept = rows(out)
    assert 1 <= len(kept) < 4 and {p.name for p in out.iterdir()} == {RESULTS, STUDY}
    again = run_sweep(study, out, workers=1)
    assert (again.done_before, again.computed, again.failed) == (len(kept), 4 - len(kept), [])
    assert {i: r for i, r in rows(out).items() if i in kept} == kept  # exact: the kept rows' own text, not recomputed


def test_another_study_into_the_same_folder_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "out"
    run_sweep(write_study(tmp_path, RR_LENGTHS), out, workers=1)
    other = write_study(tmp_path, RR_LENGTHS | {"samples": 30000}, "other.json")
    with pytest.raises(ValueError, match="holds a different study"):
        run_sweep(other, out, workers=1)
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep")
    with pytest.raises(ValueError, match="not an armlab sweep folder"):
        run_sweep(other, tmp_path / "mine", workers=1)


def test_a_failing_candidate_is_reported_and_the_rest_go_on(tmp_path: Path) -> None:
    """r1 = 100 m makes the fixed voxel grid too large: that candidate raises on its worker."""
    study = write_study(tmp_path, {"arm": "urm6", "vary": {"r1": {"values": [0.3, 100.0, 0.4], "unit": "m"}},
                                   "evaluate": ["workspace_volume"], "samples": 5000, "resolution": 0.05})
    run = subprocess.run([ARMLAB, "sweep", str(study), "--out", str(tmp_path / "out"), "--workers", "2"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == EXIT_FAILED + 1, run.stderr
    assert "candidate 1 (r1 = 100 m) failed" in run.stderr and "too fine" in run.stderr
    assert "Traceback" not in run.stderr
    assert sorted(rows(tmp_path / "out")) == [0, 2]
    assert "1 failed" in run.stdout


@pytest.mark.slow
def test_shipped_studies_are_valid() -> None:
    folder = Path(__file__).resolve().parents[1] / "analysis" / "studies"
    studies = {p.name: load_study(p) for p in sorted(folder.glob("*.json"))}
    assert set(studies) == {"rr_drive_sizing.json", "rr_drives_payload.json", "rr_servo_rate_encoder.json",
                            "urm6_bend_angles.json", "urm6_theta3_theta5.json"}
    assert len(studies["rr_servo_rate_encoder.json"].candidates) == 15
    assert len(studies["urm6_bend_angles.json"].candidates) == 4**6
    assert len(studies["urm6_theta3_theta5.json"].candidates) == 21
    assert studies["rr_drive_sizing.json"].objective_columns[:2] == ["peak_torque_1", "peak_torque_2"]


def test_a_given_motion_instead_of_the_paper_motion(tmp_path: Path) -> None:
    """``segments``: a motion file (relative to the study) replaces the paper motion; tf cannot be given."""
    (tmp_path / "move.json").write_text(json.dumps({"deg": True, "segments": [
        {"tf": 1.0, "from": [-38, 98], "to": [62, 68]}, {"tf": 1.0, "to": [-38, 98]}]}))
    base = {"arm": "rr", "vary": {"payload": {"values": [0, 1]}}, "evaluate": ["peak_torque"], "segments": "move.json"}
    study = load_study(write_study(tmp_path, base))
    there_and_back = evaluate(study, (1.0,))
    one_way = evaluate(parse_study({"arm": "rr", "vary": {"payload": {"values": [1]}}, "tf": 1.0,
                                    "evaluate": ["peak_torque"]}), (1.0,))
    assert there_and_back["peak_torque_1"] >= one_way["peak_torque_1"] - 1e-9
    with pytest.raises(ValueError, match="do not give or vary tf"):
        load_study(write_study(tmp_path, base | {"tf": 2.0}, "bad.json"))


def test_a_study_takes_any_arm_get_arm_takes(tmp_path: Path) -> None:
    """A library arm by name (get_arm decides, not the study): its torques along a given motion."""
    (tmp_path / "move.json").write_text(json.dumps({"segments": [
        {"tf": 1.0, "from": [0, -1, 1, 0, 0, 0], "to": [0.5, -0.5, 0.5, 0, 0, 0]}]}))
    study = load_study(write_study(tmp_path, {"arm": "ur5", "vary": {"payload": {"values": [0, 2]}},
                                              "evaluate": ["peak_torque"], "segments": "move.json"}))
    assert study.arm == "ur5"
    light, heavy = (evaluate(study, values) for values in study.candidates)
    assert sorted(light) == [f"peak_torque_{i}" for i in range(1, 7)]
    assert heavy["peak_torque_2"] > light["peak_torque_2"]  # the payload weighs on the shoulder


def test_a_sweep_refuses_a_folder_another_sweep_is_writing(tmp_path: Path) -> None:
    """Two sweeps into one folder: the second is refused while the first runs (SIGINT ends it: the lock goes with
    it), and a third resumes; every candidate is in results.csv once."""
    study = write_study(tmp_path, RR_LENGTHS | {"samples": 400000})
    out = tmp_path / "out"
    first = subprocess.Popen([ARMLAB, "sweep", str(study), "--out", str(out), "--workers", "1"],
                             stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        began = time.monotonic()
        while not (out / RESULTS).exists():
            assert first.poll() is None and time.monotonic() - began < 120, "the first sweep did not start"
            time.sleep(0.05)
        with pytest.raises(ValueError, match="another armlab sweep is writing into it"):
            run_sweep(study, out, workers=1)
        assert first.poll() is None, "the first sweep ended before the second was refused: no overlap tested"
    finally:
        os.killpg(first.pid, signal.SIGINT)
        first.communicate(timeout=60)
    assert first.returncode == 130
    again = run_sweep(study, out, workers=1)  # the lock went with the stopped sweep
    assert again.done_before + again.computed == 4
    indices = [line.split(",")[0] for line in (out / RESULTS).read_text().splitlines()[1:]]
    assert sorted(indices) == ["0", "1", "2", "3"]
