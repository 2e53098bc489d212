"""The path of a user who installs armlab with pip: the example arms by name, no graphviz, the wheel itself."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest
from helpers import armlab_main
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

import armlab
from armlab.models import examples
from armlab.presentation.graphviz import DotMissingWarning
from armlab.presentation.output import RUN_OUTPUTS

ROOT = Path(__file__).resolve().parents[1]
ARM3R = ROOT / "scripts" / "examples" / "arm3r.csv"
#: What a run without graphviz's dot leaves out, and the one warning that says so.
SVGS = {"diagram.svg", "diagram_full.svg"}
NO_DOT = ("graphviz's dot is not installed: diagram.svg, diagram_full.svg skipped; install graphviz "
          "(apt-get install graphviz) for them")


@pytest.fixture
def no_dot(tmp_path, monkeypatch):
    """PATH holds one empty folder: graphviz's ``dot`` (like every other program) is not found."""
    empty = tmp_path / "empty-path"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))


# --------------------------------------------------------------------------- the tested versions
def _pins() -> dict[str, str]:
    """constraints.txt's ``name==version`` lines, by normalised name."""
    lines = (ROOT / "constraints.txt").read_text().splitlines()
    pins = [line.split("==") for line in lines if line and not line.startswith("#")]
    assert all(len(pin) == 2 for pin in pins), "constraints.txt holds name==version lines only"
    return {canonicalize_name(name): version for name, version in pins}


def _installed(name: str) -> str | None:
    """The installed version of ``name``, ``None`` if it is not installed."""
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return None


def test_the_environment_has_the_versions_the_suite_last_passed_with():
    """make's set-up installs exactly constraints.txt's versions (pip's -c): every pin is what this environment runs,
    and every dependency pyproject.toml names (runtime and extras) is pinned."""
    pins = _pins()
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    # the bench extra's own packages (OMPL) are installed by make bench only, not by make setup (the tests')
    others = [*project["dependencies"], *(d for extra, deps in project["optional-dependencies"].items()
                                          if extra != "bench" for d in deps)]
    bench_only = ({canonicalize_name(Requirement(d).name) for d in project["optional-dependencies"]["bench"]}
                  - {canonicalize_name(Requirement(d).name) for d in others})
    wrong = {name: (version, _installed(name)) for name, version in pins.items()
             if _installed(name) != version and not (name in bench_only and _installed(name) is None)}
    assert not wrong, f"installed versions differ from constraints.txt (pinned, installed): {wrong}"
    named = [*project["dependencies"], *(d for extra in project["optional-dependencies"].values() for d in extra)]
    unpinned = {canonicalize_name(Requirement(d).name) for d in named} - set(pins) - {"armlab"}
    assert not unpinned, f"dependencies without a pinned version in constraints.txt: {sorted(unpinned)}"


# --------------------------------------------------------------------------- the example arms by name
def test_example_arms_are_the_shipped_files_by_name_from_any_folder(tmp_path, monkeypatch):
    assert examples() == {"arm3r": ARM3R}
    monkeypatch.chdir(tmp_path)  # no scripts/examples/ here
    by_name, by_path = armlab.load("example:arm3r"), armlab.load(ARM3R)
    q = np.radians([30.0, 45.0, -60.0])
    assert by_name.name == "arm3r" and by_name.n == 3
    np.testing.assert_array_equal(by_name.fk(q), by_path.fk(q))  # exact: one file read by the same code
    shown = armlab_main("show", "example:arm3r")
    assert shown.returncode == 0, shown.stderr
    assert shown.stdout == armlab_main("show", str(ARM3R)).stdout
    assert shown.stdout.startswith("arm3r: user DH table\n")


def test_an_unknown_example_is_a_one_line_error_naming_the_examples():
    with pytest.raises(ValueError, match=r"^unknown example arm 'example:arm9'; allowed: example:arm3r$"):
        armlab.load("example:arm9")
    out = armlab_main("fk", "example:arm9", "--q", "0,0,0")
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr == "armlab: error: unknown example arm 'example:arm9'; allowed: example:arm3r\n"
    with pytest.raises(ValueError, match=r"allowed: a paper arm \(rr, rrrr, arm4r, r2t, urm6\), a library arm "
                                         r"\(irb140, kr5, panda, puma560, stanford, ur10, ur5\), an example "
                                         r"\(example:arm3r\), or"):
        armlab.load("puma")


# --------------------------------------------------------------------------- without graphviz's dot
@pytest.mark.slow
def test_simulate_without_dot_writes_all_but_the_svgs_with_one_warning(tmp_path, monkeypatch, no_dot):
    monkeypatch.chdir(tmp_path)
    out = armlab_main("simulate", "example:arm3r", "--from", "0,0,0", "--to", "10,10,10", "--deg", "--tf", "0.2",
                      "--out", "runs/arm3r")
    assert out.returncode == 0, out.stderr
    assert out.stderr == f"armlab: warning: {NO_DOT}\n"
    written = out.stdout.splitlines()[-1].removeprefix("wrote runs/arm3r: ").split()
    # everything else, the DOT text included (no clearance.png: arm3r's table has no radius column, no collision pairs)
    assert set(written) == set(RUN_OUTPUTS) - SVGS - {"clearance.png", "servo.png", "bode.png"}
    assert sorted(p.name for p in (tmp_path / "runs" / "arm3r").iterdir()) == sorted(written)
    assert "digraph" in (tmp_path / "runs" / "arm3r" / "diagram.dot").read_text()


@pytest.mark.slow
def test_run_save_without_dot_warns_once_and_writes_the_rest(tmp_path, no_dot):
    arm = armlab.load("example:arm3r")
    run = armlab.simulate(arm, armlab.quintic(arm, np.zeros(3), np.radians([10.0, 10.0, 10.0]), tf=0.2))
    with pytest.warns(DotMissingWarning) as caught:
        written = run.save(tmp_path / "run")
    assert [str(w.message) for w in caught] == [NO_DOT]
    # arm3r has no collision geometry, and the run is not a servo run
    assert set(written) == set(RUN_OUTPUTS) - SVGS - {"clearance.png", "servo.png", "bode.png"}
    assert {p.name for p in (tmp_path / "run").iterdir()} == set(written)


def test_a_diagram_asked_for_as_svg_without_dot_is_a_one_line_error(tmp_path, no_dot):
    out = armlab_main("diagram", "rr", "--out", str(tmp_path / "fig6.svg"))
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr == ("armlab: error: graphviz's 'dot' program is needed for SVG/PNG/PDF diagrams and was not "
                          "found: install graphviz (apt-get install graphviz), or write a .dot file\n")
    assert not (tmp_path / "fig6.svg").exists()
    dot = armlab_main("diagram", "rr", "--out", str(tmp_path / "fig6.dot"))  # DOT text needs no graphviz
    assert dot.returncode == 0, dot.stderr
    assert (tmp_path / "fig6.dot").read_text().startswith("digraph fig6 {")


# --------------------------------------------------------------------------- the wheel, installed
def _run(argv: list[str], cwd: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    result = subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=600, check=False)
    assert result.returncode == 0, f"{' '.join(argv)}\n{result.stdout}\n{result.stderr}"
    return result


@pytest.mark.slow
def test_the_wheel_holds_the_examples_and_the_licence_and_works_outside_the_repository(tmp_path):
    """``pip wheel`` builds the wheel; it goes into a fresh venv, which runs armlab from a folder outside the
    repository. The venv reaches the dependencies (Drake …) through a ``.pth`` line naming this environment's
    site-packages, added after the install: ``venv --system-site-packages`` from a venv's python sees the base
    interpreter's packages, not the venv's, and a ``.pth`` line does not run that folder's own ``.pth`` files,
    so the editable armlab there stays out of the way."""
    source = tmp_path / "source"  # a copy: setuptools' build/ inside the repository could hold stale files
    shutil.copytree(ROOT, source, ignore=shutil.ignore_patterns(".*", "build", "*.egg-info", "__pycache__", "out",
                                                                "runs"))
    # verbose: the build backend's own warnings are shown (pip's --quiet hid setuptools' 50-line warning of a data
    # folder absent from `packages`, printed on every install)
    built = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-v", "-w", str(tmp_path / "dist"), str(source)],
                 tmp_path)
    assert "absent from the `packages` configuration" not in built.stdout + built.stderr
    (wheel,) = (tmp_path / "dist").glob("armlab-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    assert {"armlab/scripts/examples/arm3r.csv", "armlab/scripts/examples/size_drives.py",
            "armlab/scripts/examples/reachable.py", "armlab/scripts/examples/paper_figures.py",
            "armlab/analysis/studies/urm6_theta3_theta5.json", "armlab/models/urm6.urdf",
            "armlab/scripts/examples/catalogues/motors.csv",
            "armlab/scripts/examples/catalogues/gearboxes.csv",
            "armlab/scripts/examples/drives/rr_motors.csv"} <= names
    licence = [n for n in names if n.endswith(".dist-info/licenses/LICENSE")]
    assert len(licence) == 1
    # exact: the licence text, not numbers
    assert zipfile.ZipFile(wheel).read(licence[0]).decode() == (ROOT / "LICENSE").read_text()
    assert {n.split("/")[0] for n in names} == {"armlab", wheel.name.split("-py3")[0] + ".dist-info"}
    # the product, not the benchmarks: the reproduction and the pictures are in, scripts/bench/ is not
    assert {"armlab/papers/reproduce.py", "armlab/papers/errata.py", "armlab/presentation/replay.py"} <= names
    assert not [n for n in names if "bench" in n]

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)], tmp_path)
    _run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-deps", "--no-index", "--quiet", str(wheel)],
         tmp_path)
    site = _run([str(venv / "bin" / "python"), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                tmp_path).stdout.strip()
    (Path(site) / "armlab-test-dependencies.pth").write_text(sysconfig.get_path("purelib") + "\n")

    user = tmp_path / "elsewhere"
    user.mkdir()
    shown = _run([str(venv / "bin" / "armlab"), "show", "example:arm3r"], user).stdout
    assert shown == armlab_main("show", str(ARM3R)).stdout
    loaded = _run([str(venv / "bin" / "python"), "-c", "import armlab; arm = armlab.load('example:arm3r'); "
                   "print(armlab.__file__, arm.name, arm.n)"], user).stdout.split()
    assert Path(loaded[0]).is_relative_to(venv) and loaded[1:] == ["arm3r", "3"]  # the wheel's armlab, not ours
    reach = _run([str(venv / "bin" / "python"), "-m", "armlab.scripts.examples.reachable", "arm4r", "--position",
                  "1,1,1.4"], user).stdout
    assert "solution(s) reach" in reach
    sized = _run([str(venv / "bin" / "armlab"), "size", "rr", "--payload", "1"], user).stdout  # the example catalogues
    assert "mass iteration: converged" in sized
