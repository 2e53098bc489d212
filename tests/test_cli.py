"""The ``armlab`` command line as a user runs it: output contract, errors, exit codes."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import ARM_NAMES
from helpers import armlab_main as armlab

from armlab.models import get_arm


def test_list_names_every_arm_with_paper_and_dof():
    out = armlab("list")
    assert out.returncode == 0
    lines = out.stdout.split("library arms")[0].strip().splitlines()  # the paper arms, then the library's
    assert [line.split()[0] for line in lines] == ARM_NAMES
    for line, name in zip(lines, ARM_NAMES, strict=True):
        assert f"{get_arm(name).n} DOF" in line and "paper" in line


@pytest.mark.parametrize("name", ARM_NAMES)
def test_show_json(name):
    out = armlab("show", name, "--json")
    assert out.returncode == 0, out.stderr
    info = json.loads(out.stdout)
    assert set(info) == {"name", "paper", "dof", "joints", "units", "has_dynamics", "links", "dh", "gravity",
                         "parameters", "urdf", "tool_frame", "drive_train", "tool_source", "dh_links"}
    arm = get_arm(name)
    assert info["drive_train"] is None  # a paper arm's drives are ideal
    assert info["name"] == name and info["tool_frame"] == arm.tool_name and info["dof"] == arm.n
    assert [j["name"] for j in info["joints"]] == arm.joint_names
    assert all(set(j) == {"name", "type", "lower", "upper", "effort", "velocity"} for j in info["joints"])
    assert [(j["effort"], j["velocity"]) for j in info["joints"]] == [(lim.effort, lim.velocity) for lim in arm.limits]
    assert info["has_dynamics"] and [link["mass"] for link in info["links"]] == [b.mass for b in arm.bodies]
    assert info["gravity"] == list(arm.gravity) and info["dh"] is None and info["dh_links"] is None
    assert info["parameters"] == dict(arm.parameters)
    assert info["urdf"].endswith(f"{name}.urdf")


def test_show_prints_a_dh_tables_rows_masses_and_limits_with_units():
    out = armlab("show", str(Path(__file__).resolve().parents[1] / "scripts" / "examples" / "arm3r.csv"))
    assert out.returncode == 0, out.stderr
    text = out.stdout
    assert "DH table (standard; a, d in m, alpha, theta in rad):" in text
    assert "+1.5708" in text  # alpha1 = 90° given in degrees (# units: deg), shown in rad
    assert "150 rad/s" not in text and "2.61799 rad/s" in text and "60 N·m" in text
    assert "link1" in text and "com (+0, +0, +0.2)" in text  # DH frame 1's (0, -0.2, 0) in link frame {1}


@pytest.mark.parametrize("name", ARM_NAMES)
def test_fk_json_matches_the_library(name):
    arm = get_arm(name)
    q = np.array([0.3, -0.2, 0.25, 0.1, -0.4, 0.5][: arm.n])
    q = np.where(arm.revolute, q, 0.1)  # prismatic joints: 0.1 m, inside the strokes
    out = armlab("fk", name, "--q", ",".join(map(repr, q.tolist())), "--json")
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    fk = arm.forward(q)
    assert result["arm"] == name and result["q"] == q.tolist()
    np.testing.assert_allclose(result["tool"]["position"], fk.tool[:3, 3], atol=1e-15)
    np.testing.assert_allclose(result["tool"]["rotation"], fk.tool[:3, :3], atol=1e-15)
    assert list(result["points"]) == list(fk.points)


def test_fk_deg_converts_revolute_only():
    out = armlab("fk", "r2t", "--q", "90,0.1,0.2", "--deg", "--json")
    assert json.loads(out.stdout)["q"] == pytest.approx([np.pi / 2, 0.1, 0.2], abs=1e-15)


def test_fk_urm6_table1_human_output():
    out = armlab("fk", "urm6", "--q", "15,30,50,130,230,340", "--deg")
    assert out.returncode == 0
    assert "p7" in out.stdout and "+0.797180" in out.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("fk", "puma", "--q", "1"), "unknown arm 'puma'"),
        (("fk", "rr", "--q", "1,2,3"), "rr has 2 joints, got 3"),
        (("fk", "rr", "--q", "1,nan"), "'nan' is not a finite number"),
        (("fk", "rr", "--q", "1,inf"), "'inf' is not a finite number"),
        (("fk", "rr", "--q", "1,abc"), "'abc' is not a number"),
        (("fk", "arm4r", "--q", "170,0,0,0", "--deg"), "joint1 = 170 deg is outside its limits [-160, 160] deg"),
        (("fk", "arm4r", "--q", "2.9,0,0,0"), "joint1 = 2.9 rad is outside its limits [-2.79253, 2.79253] rad"),
        (("fk", "r2t", "--q", "10,0.5,0", "--deg"), "joint2 = 0.5 m is outside its limits [0, 0.3] m"),
        (("fk", "rr"), "required: --q"),
        (("show", "/no/such/arm.urdf"), "cannot read URDF"),
        (("ik", "rr", "--target", "2,0"), "2"),
        (("ik", "rr", "--target", "0.5,nan"), "nan"),
        (("ik", "arm4r", "--target", "1,1,1.4", "--pitch", "1,2"), "--pitch 1,2: give one angle"),
        (("ik", "rr", "--target", "0.5,0.2", "--pitch", "0.1"), "pitch = 0.1 is not an option of rr's"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, message):
    out = armlab(*args)
    assert out.returncode == 2
    assert out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("armlab: error:"), out.stderr
    assert message in lines[0]


def test_negative_values_need_no_equals_sign():
    out = armlab("fk", "rr", "--q", "-38,98", "--deg", "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["tool"]["position"][:2] == pytest.approx([0.4652, 0.0135], abs=5e-5)


def test_help_does_not_import_drake():
    code = "import sys; from armlab.cli import build_parser; build_parser(); print('pydrake' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# ---- closed streams: a file descriptor closed before armlab starts (``>&-``, ``2>&-``), subprocesses --------------
def _with_closed(fd: int, cwd: Path, *argv: str) -> subprocess.CompletedProcess:
    """``python -m armlab ARGV`` started with file descriptor ``fd`` closed (the shell's ``>&-`` or ``2>&-``);
    the stream left open is captured."""
    return subprocess.run(["sh", "-c", f'"$@" {fd}>&-', "sh", sys.executable, "-m", "armlab", *argv],
                          capture_output=True, text=True, cwd=cwd, timeout=120)


@pytest.mark.parametrize("argv", [("list",), ("--help",), ("fk", "rr", "--q", "9,9"),
                                  ("simulate", "rr", "--tf", "0.5", "--out", "run")], ids=" ".join)
def test_a_closed_stdout_is_one_line_and_exit_2_before_any_work(tmp_path, argv):
    out = _with_closed(1, tmp_path, *argv)
    assert (out.returncode, out.stderr) == (2, "armlab: error: standard output is closed\n")
    assert list(tmp_path.iterdir()) == []  # simulate did not run: no run/, no temporary


@pytest.mark.parametrize(("argv", "code"), [(("fk", "rr", "--q", "9,9"), 2), (("fk", "rr", "--q", "x"), 2),
                                            (("fk", "rr"), 2), (("list",), 0), ((), 2)], ids=str)
def test_a_closed_stderr_changes_no_exit_code(tmp_path, argv, code):
    out = _with_closed(2, tmp_path, *argv)
    assert out.returncode == code
    assert (out.stdout != "") == (code == 0 or not argv)  # list's lines; no command: the help


def test_a_reader_gone_before_the_first_line_ends_it_quietly():
    """``armlab list | head -0``: stdout a pipe without a reader from the start; exit 141 like the shell's tools,
    and nothing on stderr (no ``Exception ignored … BrokenPipeError`` from the interpreter's last flush)."""
    read, write = os.pipe()
    os.close(read)
    try:
        out = subprocess.run([sys.executable, "-m", "armlab", "list"], stdout=write, stderr=subprocess.PIPE,
                             text=True, timeout=120)
    finally:
        os.close(write)
    assert (out.returncode, out.stderr) == (141, "")
