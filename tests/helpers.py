"""Helpers the test modules share (test modules never import each other; conftest.py holds only fixtures).

The paper arms and their Drake plants, random configurations, the CLI run in this process, the files under
tests/data/, and comparisons of numbers that reach a test by two different paths (a batch and a single call,
another process, a file written by a worker): equal up to rounding, with the tolerance stated.
"""

from __future__ import annotations

import contextlib
import csv
import functools
import importlib.util
import io
import json
import pkgutil
import re
import subprocess
import tomllib
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from armlab.models import ARMS, get_arm
from armlab.models.arm import Arm

ARM_NAMES = list(ARMS)
#: The repository.
ROOT = Path(__file__).resolve().parents[1]
#: tests/data/: the test URDFs and DH tables, named for what they are.
DATA = Path(__file__).resolve().parent / "data"
EPS = np.finfo(float).eps
#: Numbers that another process (a reproduction's or a sweep's worker) wrote and this one recomputed: the same
#: code on the same input, so equal in practice to the last digit; a different CPU's vectorised numpy paths may
#: round a few ulps apart (≈ 1e-15 relative each), which 1e-12 relative / absolute covers many times over while
#: staying far tighter than any number the tests check (1e-9 and looser).
RECOMPUTED_RTOL = RECOMPUTED_ATOL = 1e-12
_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|[-+]?\b(?:nan|inf)\b")


def package_modules() -> dict[str, Path]:
    """Every module of the packages pyproject.toml installs: dotted name → source file (found without importing
    the modules; tests/test_layers.py and tests/test_bounds.py read them with ast)."""
    modules = {}
    for package in tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]:
        spec = importlib.util.find_spec(package)
        assert spec is not None and spec.submodule_search_locations, package
        if spec.origin is None:  # a data-only package (e.g. armlab.analysis.studies): no code to read
            continue
        modules[package] = Path(spec.origin)
        for info in pkgutil.iter_modules(spec.submodule_search_locations):
            if not info.ispkg:
                modules[f"{package}.{info.name}"] = Path(info.module_finder.path) / f"{info.name}.py"
    return modules


def is_program(module: str) -> bool:
    """A developer benchmark (``scripts/bench/bench_*.py``, read as ``bench.NAME``) or an example script for users
    (``armlab.scripts.examples.*``, run as ``python -m``): programs with command lines of their own."""
    return module.startswith(("bench.", "armlab.scripts.examples."))


@functools.cache
def arm_and_plant(name: str):
    """(arm, plant, context) for a paper arm with default parameters, built once per session."""
    arm = get_arm(name)
    plant = arm.make_plant()
    return arm, plant, plant.CreateDefaultContext()


def random_q(arm: Arm, rng: np.random.Generator, size: int) -> np.ndarray:
    """``size`` random configurations within the joint limits (unlimited joints: ±2π)."""
    return rng.uniform(*arm.limit_arrays(unlimited=2 * np.pi), size=(size, arm.n))


def armlab_main(*argv: str) -> subprocess.CompletedProcess:
    """``armlab ARGV`` run in this process: ``armlab.cli.main`` (what the console script and ``python -m armlab``
    call), its exit code, stdout and stderr (the real process's start and exit: test_cli_usage.py, test_signals.py).
    A Dask cluster's or a reproduction's worker processes are real all the same."""
    from armlab.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return subprocess.CompletedProcess(["armlab", *argv], code, out.getvalue(), err.getvalue())


def data(name: str) -> str:
    """The text of ``tests/data/NAME`` (a test URDF or DH table)."""
    return (DATA / name).read_text()


def two_link_urdf(mass2: float = 0.5, mesh: str | None = None) -> str:
    """A planar two-link arm as users write them: no <transmission>, optionally a mesh on link 2."""
    visual = f'<visual><geometry><mesh filename="{mesh}"/></geometry></visual>' if mesh else ""
    inertial = ("" if mass2 == 0 else f'<inertial><origin xyz="0.15 0 0"/><mass value="{mass2}"/>'
                '<inertia ixx="1e-4" ixy="0" ixz="0" iyy="4e-3" iyz="0" izz="4e-3"/></inertial>')
    return f"""<robot name="two">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0.2 0 0"/><mass value="1"/>
    <inertia ixx="1e-4" ixy="0" ixz="0" iyy="1.4e-2" iyz="0" izz="1.4e-2"/></inertial></link>
  <link name="fore">{inertial}{visual}</link>
  <link name="hand"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.4 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="wrist" type="fixed"><parent link="fore"/><child link="hand"/><origin xyz="0.3 0 0"/></joint>
</robot>
"""


def three_link_urdf(folder: Path, fore: str) -> str:
    """A user's three-link arm in the x–z plane (joints about y, 0.1 m above its base box): link fore is ``fore``
    (collision geometry centred 0.15 m from the elbow; ``part.obj``, a 0.3 × 0.04 × 0.04 m box, is written beside)."""
    (folder / "part.obj").write_text("".join(f"v {x * 0.15:g} {y * 0.02:g} {z * 0.02:g}\n" for x in (-1, 1)
                                             for y in (-1, 1) for z in (-1, 1))
                                     + "f 1 2 4\nf 1 4 3\nf 5 7 8\nf 5 8 6\nf 1 5 6\nf 1 6 2\nf 3 4 8\nf 3 8 7\n"
                                       "f 1 3 7\nf 1 7 5\nf 2 6 8\nf 2 8 4\n")
    limit = '<limit lower="-3" upper="3" effort="10" velocity="5"/>'
    path = folder / "three.urdf"
    path.write_text(f"""<robot name="three">
  <link name="base"><collision><origin xyz="0 0 -0.05"/><geometry><box size="0.3 0.3 0.1"/></geometry>
    </collision></link>
  <link name="upper"><collision><origin xyz="0.2 0 0" rpy="0 1.5707963267948966 0"/>
    <geometry><cylinder radius="0.03" length="0.4"/></geometry></collision></link>
  <link name="fore"><collision><origin xyz="0.15 0 0" {'rpy="0 1.5707963267948966 0"' if 'cylinder' in fore else ''}/>
    <geometry>{fore}</geometry></collision></link>
  <link name="hand"><collision><geometry><sphere radius="0.04"/></geometry></collision></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 1 0"/>{limit}</joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.4 0 0"/>
    <axis xyz="0 1 0"/>{limit}</joint>
  <joint name="wrist" type="revolute"><parent link="fore"/><child link="hand"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 1 0"/>{limit}</joint>
</robot>
""")
    return str(path)


def assert_rounding_close(actual: ArrayLike, desired: ArrayLike, ulps: float) -> None:
    """``actual`` = ``desired`` up to ``ulps`` units in the last place of ``desired``'s largest magnitude.

    For the same numbers computed by two code paths that round differently (a batch and a single call go through
    differently vectorised numpy loops; SIMD and fused multiply-adds differ between CPUs). Absolute, scaled by the
    largest entry: the rounding of a sum or product is relative to its largest terms, so an entry near zero carries
    the rounding of its neighbours' size, not its own. NaN must be NaN in both.
    """
    desired = np.asarray(desired, dtype=float)
    scale = float(np.nanmax(np.abs(desired), initial=0.0))
    np.testing.assert_allclose(actual, desired, rtol=0, atol=ulps * EPS * max(scale, np.finfo(float).tiny))


def assert_same_numbers(actual, desired, rtol: float = RECOMPUTED_RTOL, atol: float = RECOMPUTED_ATOL,
                        where: str = "") -> None:
    """Two structures of the same shape (dicts, lists, tuples, dataclasses, strings, numbers; JSON, CSV rows)
    equal: keys, text and integers exactly, floats within ``rtol`` / ``atol``, NaN only where NaN.

    Strings are compared as text with numbers in it: the text between the numbers exactly, the numbers (decimal
    notation as written by ``repr`` or a format) within the tolerance.
    """
    if hasattr(desired, "__dataclass_fields__"):
        assert type(actual) is type(desired), f"{where}: {type(actual).__name__} is not {type(desired).__name__}"
        for name in desired.__dataclass_fields__:
            assert_same_numbers(getattr(actual, name), getattr(desired, name), rtol, atol, f"{where}.{name}")
    elif isinstance(desired, dict):
        assert isinstance(actual, dict) and actual.keys() == desired.keys(), f"{where}: keys {actual} ≠ {desired}"
        for key in desired:
            assert_same_numbers(actual[key], desired[key], rtol, atol, f"{where}[{key!r}]")
    elif isinstance(desired, list | tuple):
        assert isinstance(actual, list | tuple) and len(actual) == len(desired), f"{where}: {actual} ≠ {desired}"
        for k, (a, d) in enumerate(zip(actual, desired, strict=True)):
            assert_same_numbers(a, d, rtol, atol, f"{where}[{k}]")
    elif isinstance(desired, str):
        assert isinstance(actual, str), f"{where}: {actual!r} is not text"
        assert _NUMBER.split(actual) == _NUMBER.split(desired), f"{where}: the text differs:\n{actual}\n{desired}"
        found, expected = _NUMBER.findall(actual), _NUMBER.findall(desired)
        assert len(found) == len(expected), f"{where}: {len(found)} numbers, not {len(expected)}"
        np.testing.assert_allclose(np.array(found, float), np.array(expected, float), rtol=rtol, atol=atol,
                                   err_msg=where)
    elif isinstance(desired, bool | int | np.integer) or desired is None:
        assert actual == desired and type(actual) is type(desired), f"{where}: {actual!r} ≠ {desired!r}"
    else:
        assert isinstance(actual, float | np.floating | np.ndarray), f"{where}: {actual!r} is not a number"
        np.testing.assert_allclose(actual, desired, rtol=rtol, atol=atol, err_msg=where)


def assert_same_file_contents(actual: Path, desired: Path) -> None:
    """Two output files with the same contents up to rounding (:func:`assert_same_numbers`): JSON parsed, CSV read
    as rows of cells, any other text as text with numbers in it."""
    if desired.suffix == ".json":
        a, d = (json.loads(p.read_text()) for p in (actual, desired))
    elif desired.suffix == ".csv":
        a, d = (list(csv.reader(io.StringIO(p.read_text()))) for p in (actual, desired))
    else:
        a, d = actual.read_text(), desired.read_text()
    assert_same_numbers(a, d, where=desired.name)


# ----------------------------------------------------------------------------------- design studies (sweeps)
def write_study(folder: Path, study: dict, name: str = "study.json") -> Path:
    """``study`` written as ``FOLDER/NAME`` (JSON)."""
    path = folder / name
    path.write_text(json.dumps(study))
    return path


def rows(folder: Path) -> dict[int, dict[str, str]]:
    """A sweep's results.csv: candidate index → its row (column → cell text)."""
    from armlab.analysis.sweep import RESULTS

    with open(folder / RESULTS, newline="") as handle:
        return {int(r["candidate"]): r for r in csv.DictReader(handle)}


def objectives(folder: Path, columns: list[str]) -> dict[int, list[float]]:
    """A sweep's results.csv: candidate index → the values of ``columns``."""
    return {i: [float(r[c]) for c in columns] for i, r in rows(folder).items()}


def assert_same_objectives(actual: dict[int, list[float]], desired: dict[int, list[float]]) -> None:
    """Sweep results (candidate → objective values) computed in worker processes equal those computed here: the
    same candidates exactly, the values up to :data:`RECOMPUTED_RTOL` (another process's rounding)."""
    assert sorted(actual) == sorted(desired)
    for i in desired:
        np.testing.assert_allclose(actual[i], desired[i], rtol=RECOMPUTED_RTOL, atol=0, err_msg=f"candidate {i}")


def dh_transform(convention: str, a: float, alpha: float, d: float, theta: float) -> np.ndarray:
    """One DH transform, written out: standard Rz(θ)·Tz(d)·Tx(a)·Rx(α); modified (Craig 3.6) Rx(α)·Tx(a)·Rz(θ)·Tz(d)."""
    ca, sa, ct, st = np.cos(alpha), np.sin(alpha), np.cos(theta), np.sin(theta)
    if convention == "standard":
        return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d],
                         [0, 0, 0, 1]])
    return np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d], [0, 0, 0, 1]])


def rnea_in_dh_frames(rows, convention, links, q, qd, qdd, gravity):
    """Joint torques by recursive Newton–Euler written directly in the DH frames (world-frame vectors).

    ``rows``: (kind, a, alpha, d, theta) in radians; ``links``: (m, r, I) with the centre of mass r and the
    inertia I about it in DH frame i (RTB's convention). Joint i turns or slides along z of DH frame i−1
    (standard) or i (modified); link i is fixed to DH frame i. Base acceleration −g carries gravity.
    """
    T = [np.eye(4)]
    for (kind, a, alpha, d, theta), qi in zip(rows, q, strict=True):
        T.append(T[-1] @ dh_transform(convention, a, alpha, d + (qi if kind == "T" else 0),
                                      theta + (qi if kind == "R" else 0)))
    w, wd, ref, a_ref = np.zeros(3), np.zeros(3), np.zeros(3), -np.asarray(gravity, dtype=float)
    data = []
    for i, ((kind, *_), (m, r, inertia)) in enumerate(zip(rows, links, strict=True)):
        joint = T[i] if convention == "standard" else T[i + 1]
        z, p = joint[:3, 2], joint[:3, 3]
        a_p = a_ref + np.cross(wd, p - ref) + np.cross(w, np.cross(w, p - ref))
        if kind == "R":
            wd = wd + z * qdd[i] + np.cross(w, z * qd[i])
            w = w + z * qd[i]
            a_ref = a_p
        else:
            a_ref = a_p + z * qdd[i] + 2 * np.cross(w, z * qd[i])
        ref = p
        R = T[i + 1][:3, :3]
        c, Iw = T[i + 1][:3, 3] + R @ r, R @ inertia @ R.T
        a_c = a_ref + np.cross(wd, c - ref) + np.cross(w, np.cross(w, c - ref))
        data.append((kind, z, ref, c, m * a_c, Iw @ wd + np.cross(w, Iw @ w)))
    tau, f, moment, next_ref = np.zeros(len(rows)), np.zeros(3), np.zeros(3), np.zeros(3)
    for i in reversed(range(len(rows))):
        kind, z, ref, c, F, N = data[i]
        moment = N + np.cross(c - ref, F) + moment + np.cross(next_ref - ref, f)  # about the joint point
        f, next_ref = F + f, ref
        tau[i] = z @ (moment if kind == "R" else f)
    return tau
