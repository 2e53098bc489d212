"""URDF fuzzing (issue 13): mutants of the committed URDFs never crash, hang or leave debris.

Each mutant of ``models/*.urdf`` (elements dropped, duplicated or reordered; numbers made
extreme or non-finite; joint cycles, mimic, floating and planar joints; huge chains; XML entity
definitions; odd names) goes through ``armlab show FILE`` and ``armlab fk FILE``: each either
succeeds or prints exactly one line ``armlab: error: …`` and exits 2 — never a traceback, never
a hang (each case under a timeout), never a file left in the temp folder or beside the URDF.
A mutant armlab accepts must also build a Drake plant or be refused with ``ValueError``.
The cases come from the tables below and seeded generators: adding a case is one line.
"""

from __future__ import annotations

import copy
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from armlab.cli import main
from armlab.models import get_arm
from armlab.models.arm import MODELS_DIR

SOURCES = sorted(MODELS_DIR.glob("*.urdf"))

#: Numbers put in place of a number of the file.
EXTREMES = ["1e308", "-1e308", "1e-308", "0", "-0", "1e300", "nan", "inf", "-inf", "1e999", "-1e999", "NaN",
            "0x10", "", "1,5", "1e", "++1", "9" * 400]
#: Changes of one joint (by index among the movable joints): new type, or children added.
JOINT_CHANGES = [("floating", "type", "floating"), ("planar", "type", "planar"), ("floating", "type", "ball"),
                 ("floating", "type", ""), ("mimic", "mimic", '<mimic joint="joint1" multiplier="2"/>'),
                 ("mimic", "mimic", '<mimic joint="nonexistent"/>')]
#: XML headers defining entities (expansion bombs, external files): always refused.
ENTITY_HEADERS = [
    '<!DOCTYPE robot [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
    '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;">]>',
    '<!DOCTYPE robot [<!ENTITY secret SYSTEM "file:///etc/hostname">]>',
    '<!DOCTYPE robot SYSTEM "http://127.0.0.1:9/robot.dtd">',
]
#: Odd names for the first movable joint's child link (and the references to it).
NAMES = ["fo're", 'a"b', "", " ", "é—ü", "a" * 5000, "link1"]


def _tree(source: Path) -> ET.Element:
    return ET.parse(source).getroot()


def _text(root: ET.Element, header: str = "") -> str:
    return '<?xml version="1.0"?>\n' + header + ET.tostring(root, encoding="unicode")


def _parents(root: ET.Element) -> dict[ET.Element, ET.Element]:
    return {child: parent for parent in root.iter() for child in parent}


def _movable(root: ET.Element) -> list[ET.Element]:
    return [j for j in root.findall("joint") if j.get("type") != "fixed"]


def _numbers(root: ET.Element) -> list[tuple[ET.Element, str, int]]:
    """(element, attribute, token index) of every number in the file."""
    out = []
    for element in root.iter():
        for key, value in element.attrib.items():
            for k, token in enumerate(value.split()):
                try:
                    float(token)
                except ValueError:
                    continue
                out.append((element, key, k))
    return out


def _chain(root: ET.Element, n: int, kind: str) -> None:
    """Append ``n`` links on ``kind`` joints below the last movable joint's child."""
    last = _movable(root)[-1].find("child").get("link")
    for i in range(n):
        name = f"extra{i}"
        ET.SubElement(root, "link", name=name)
        joint = ET.SubElement(root, "joint", name=f"extra_joint{i}", type=kind)
        ET.SubElement(joint, "parent", link=last)
        ET.SubElement(joint, "child", link=name)
        ET.SubElement(joint, "origin", xyz="0.01 0 0")
        ET.SubElement(joint, "axis", xyz="0 0 1")
        last = name


#: Classes armlab must refuse (the others may load or be refused).
REFUSED = {"cycle", "mimic", "floating", "planar", "entities"}
#: Chains appended below the last joint: (links, joint type, refused?). 64 joints at most.
CHAINS = [(65, "revolute", True), (200, "continuous", True), (3000, "fixed", False), (64 - 6, "continuous", False)]


def _cases() -> list[tuple[str, str, str]]:
    """``(class, id, URDF text)`` for every mutant."""
    cases = []
    for s, source in enumerate(SOURCES):
        rng = np.random.default_rng(1000 + s)
        stem = source.stem
        for k in range(14):  # drop one element (anywhere in the tree)
            root = _tree(source)
            element = rng.choice(np.array(list(root.iter())[1:], dtype=object))
            _parents(root)[element].remove(element)
            cases.append(("drop", f"{stem}-drop{k}-{element.tag}", _text(root)))
        for k in range(8):  # duplicate one element next to itself
            root = _tree(source)
            element = rng.choice(np.array(list(root.iter())[1:], dtype=object))
            parent = _parents(root)[element]
            parent.insert(list(parent).index(element), copy.deepcopy(element))
            cases.append(("duplicate", f"{stem}-dup{k}-{element.tag}", _text(root)))
        for k in range(4):  # reorder the robot's children (and every element's children for k ≥ 2)
            root = _tree(source)
            for element in [root] + (list(root.iter()) if k >= 2 else []):
                children = list(element)
                for child in children:
                    element.remove(child)
                element.extend(children[i] for i in rng.permutation(len(children)))
            cases.append(("reorder", f"{stem}-reorder{k}", _text(root)))
        for k in range(18):  # one number made extreme, non-finite or not a number
            root = _tree(source)
            element, key, index = _numbers(root)[rng.integers(len(_numbers(root)))]
            tokens = element.get(key).split()
            tokens[index] = EXTREMES[(k + s) % len(EXTREMES)]
            element.set(key, " ".join(tokens))
            cases.append(("numbers", f"{stem}-num{k}-{element.tag}-{key}", _text(root)))
        for k, (parent_index, child_index, kind) in enumerate([(-1, 0, "fixed"), (-1, 1, "revolute"),
                                                               (0, 0, "fixed"), (2, 1, "fixed")]):
            root = _tree(source)  # a joint from a later link back to an earlier one (or to itself)
            links = [link.get("name") for link in root.findall("link")]
            joint = ET.SubElement(root, "joint", name=f"back{k}", type=kind)
            ET.SubElement(joint, "parent", link=links[parent_index])
            ET.SubElement(joint, "child", link=links[min(child_index, len(links) - 1)])
            ET.SubElement(joint, "limit", lower="-1", upper="1", effort="1", velocity="1")
            cases.append(("cycle", f"{stem}-cycle{k}", _text(root)))
        for k, (kind, what, value) in enumerate(JOINT_CHANGES):
            root = _tree(source)
            joint = _movable(root)[k % len(_movable(root))]
            if what == "type":
                joint.set("type", value)
            else:
                joint.append(ET.fromstring(value))
            cases.append((kind, f"{stem}-{kind}{k}", _text(root)))
        for k, header in enumerate(ENTITY_HEADERS):
            root = _tree(source)
            root.set("name", "&d;" if k == 0 else "&secret;")
            text = _text(root).replace("&amp;", "&")
            cases.append(("entities", f"{stem}-entity{k}", text.replace("\n<robot", f"\n{header}<robot", 1)))
        for k, name in enumerate(NAMES):
            root = _tree(source)
            old = _movable(root)[0].find("child").get("link")
            for element in root.iter():
                for key in ("name", "link"):
                    if element.get(key) == old and element.tag in ("link", "child", "parent"):
                        element.set(key, name)
            cases.append(("names", f"{stem}-name{k}", _text(root)))
    for k, (n, kind, refused) in enumerate(CHAINS):
        root = _tree(SOURCES[k % len(SOURCES)])
        _chain(root, n, kind)
        cases.append(("huge chain" + (" (refused)" if refused else ""), f"chain{k}-{n}-{kind}", _text(root)))
    return cases


CASES = _cases()
COUNTS = Counter(kind.removesuffix(" (refused)") for kind, _, _ in CASES)


def test_every_class_has_cases():
    """The classes of issue 13's URDF fuzz test, each with cases (``python -m pytest … -k counts -s`` prints them)."""
    print(dict(COUNTS), sum(COUNTS.values()))
    assert set(COUNTS) == {"drop", "duplicate", "reorder", "numbers", "cycle", "mimic", "floating", "planar",
                           "entities", "names", "huge chain"}
    assert sum(COUNTS.values()) >= 300


def _one_line_or_success(code: int, err: str, argv: list[str]) -> None:
    lines = err.strip().splitlines()
    if code == 0:
        assert not lines or all("Traceback" not in line for line in lines), (argv, err)
        return
    assert code == 2 and len(lines) == 1 and lines[0].startswith("armlab: error: "), (argv, code, err)


@pytest.mark.timeout(60)
@pytest.mark.usefixtures("private_tmp")
@pytest.mark.parametrize(("kind", "text"), [(kind, text) for kind, _, text in CASES],
                         ids=[case_id for _, case_id, _ in CASES])
def test_mutant(tmp_path, capfd, kind, text):
    folder = tmp_path / "arm"
    folder.mkdir()
    path = folder / "mutant.urdf"
    path.write_text(text)
    try:
        arm = get_arm(str(path))
    except ValueError as error:
        arm = None
        assert "\n" not in str(error) and str(path) in str(error), error
    if kind in REFUSED or kind.endswith("(refused)"):
        assert arm is None, f"a {kind} mutant must be refused"
    q = ",".join(["0"] * (arm.n if arm is not None else 1))
    for argv in (["show", str(path)], ["fk", str(path), "--q", q]):
        code = main(argv)
        _one_line_or_success(code, capfd.readouterr().err, argv)
        assert (code == 0) == (arm is not None), argv
    if arm is not None:
        try:
            arm.make_plant()
        except ValueError as error:
            assert "\n" not in str(error).strip(), error
    assert list(Path(tempfile.gettempdir()).iterdir()) == [] and list(folder.iterdir()) == [path]


SAMPLE = ["cycle", "entities", "huge chain (refused)", "mimic"]


@pytest.mark.parametrize("kind", SAMPLE)
def test_mutants_as_their_own_process(tmp_path, kind):
    """One case of each of these classes through ``python -m armlab`` with a timeout: one line, exit 2."""
    _, case_id, text = next(case for case in CASES if case[0] == kind)
    path = tmp_path / "mutant.urdf"
    path.write_text(text)
    folder = tmp_path / "tmp"
    folder.mkdir()
    for argv in (["show", str(path)], ["fk", str(path), "--q", "0"]):
        done = subprocess.run([sys.executable, "-m", "armlab", *argv], capture_output=True, text=True, timeout=120,
                              env={"TMPDIR": str(folder), "PATH": "/usr/bin:/bin"})
        _one_line_or_success(done.returncode, done.stderr, argv)
        assert done.returncode == 2, (case_id, argv, done.stderr)
    assert list(folder.iterdir()) == [] and sorted(tmp_path.iterdir()) == sorted([folder, path])
