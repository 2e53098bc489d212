"""Security (issue 13): no generated URDF goes through a shared temp path; a URDF reads no files from elsewhere.

The temp-folder attacks are those of a second local user against the old cache
``$TMPDIR/armlab-urdf/<name>-<sha1[:12]>.urdf`` (written through ``….<digest>.tmp``): tampering
(a planted URDF under the expected name), a symlink (a write through it) and denial (a folder
the user cannot write). They run as root with a private TMPDIR (``tempfile.tempdir`` in-process,
``TMPDIR`` for the subprocess), so root's own rights are what a careless write would use.
"""

from __future__ import annotations

import base64
import hashlib
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import data, two_link_urdf

from armlab.cli import main
from armlab.models import get_arm

TABLE = data("two_link_masses_dh.csv")
_SIMULATE = ["simulate", "--from", "0,0", "--to", "0.5,0.5", "--tf", "0.3"]
HOSTILE = TABLE.replace("R,0.4,", "R,0.6,")  # the same arm with a longer forearm: tool at 1.1 m, not 0.9 m


def _old_cache_names(text: str, name: str) -> tuple[str, str]:
    """The names the old ``Arm.urdf_path`` used for a generated URDF: the file and its temporary."""
    digest = hashlib.sha1(text.encode()).hexdigest()[:12]
    return f"{name}-{digest}.urdf", f"{name}-{digest}.{digest}.tmp"


def _arm_file(tmp_path: Path) -> Path:
    path = tmp_path / "table.csv"
    path.write_text(TABLE)
    return path


def _plant_tool(arm, q) -> np.ndarray:
    plant = arm.make_plant()
    ctx = plant.CreateDefaultContext()
    plant.SetPositions(ctx, q)
    return plant.CalcRelativeTransform(ctx, plant.world_frame(), plant.GetFrameByName(arm.tool_name)).translation()


@pytest.mark.slow
def test_tampering_a_planted_urdf_is_never_loaded(tmp_path, private_tmp, capsys):
    path = _arm_file(tmp_path)
    arm = get_arm(str(path))
    hostile = tmp_path / "hostile.csv"
    hostile.write_text(HOSTILE)
    cache = private_tmp / "armlab-urdf"
    cache.mkdir(mode=0o777)
    planted = get_arm(str(hostile)).urdf().replace('name="hostile"', 'name="table"')
    for name in _old_cache_names(arm.urdf(), arm.name):
        (cache / name).write_text(planted)
    np.testing.assert_allclose(_plant_tool(arm, [0.0, 0.0]), [0.9, 0, 0], atol=1e-12)
    out = tmp_path / "run"
    assert main(["simulate", str(path), "--from", "0,0", "--to", "0.5,0.5", "--tf", "0.5", "--out", str(out)]) == 0
    log = np.genfromtxt(out / "log.csv", delimiter=",", names=True)
    q = np.column_stack([log["q1"], log["q2"]])
    tool = np.column_stack([log["x"], log["y"], log["z"]])  # the simulated plant's tool point
    np.testing.assert_allclose(tool, arm.forward(q).tool[:, :3, 3], atol=1e-9)  # the file's arm, not the plant
    assert sorted(p.name for p in cache.iterdir()) == sorted(_old_cache_names(arm.urdf(), arm.name))


@pytest.mark.slow
def test_symlink_no_write_through_a_planted_link(tmp_path, private_tmp, capsys):
    path = _arm_file(tmp_path)
    arm = get_arm(str(path))
    victim = tmp_path / "victim.txt"
    victim.write_text("root's file\n")
    cache = private_tmp / "armlab-urdf"
    cache.mkdir(mode=0o777)
    for name in _old_cache_names(arm.urdf(), arm.name):
        (cache / name).symlink_to(victim)
    for argv in (["show", str(path)], ["fk", str(path), "--q", "0.1,0.2"], ["ik", str(path), "--target", "0.5,0.5,0"],
                 _SIMULATE + [str(path), "--out", str(tmp_path / "run")]):
        assert main(argv) == 0, argv
    _plant_tool(arm, [0.1, 0.2])
    assert victim.read_text() == "root's file\n"


@pytest.mark.slow
@pytest.mark.parametrize("blocker", ["read-only folder", "a file"])
def test_denial_a_foreign_cache_folder_breaks_nothing(tmp_path, private_tmp, capsys, blocker):
    path = _arm_file(tmp_path)
    cache = private_tmp / "armlab-urdf"
    if blocker == "a file":
        cache.write_text("not a folder")
    else:
        cache.mkdir(mode=0o555)
    for argv in (["show", str(path)], ["fk", str(path), "--q", "0.1,0.2"],
                 _SIMULATE + [str(path), "--out", str(tmp_path / "run")]):
        assert main(argv) == 0, (argv, capsys.readouterr().err)
    assert sorted(p.name for p in private_tmp.iterdir()) == ["armlab-urdf"]


def test_no_file_in_the_temp_folder_from_a_separate_process(tmp_path):
    """``armlab show`` and ``fk`` of a DH arm as their own process, TMPDIR private: nothing is left in it."""
    path = _arm_file(tmp_path)
    folder = tmp_path / "tmp"
    folder.mkdir()
    env = dict(os.environ, TMPDIR=str(folder))
    for argv in (["show", str(path)], ["fk", str(path), "--q", "0.1,0.2"]):
        done = subprocess.run([sys.executable, "-m", "armlab", *argv], env=env, capture_output=True, text=True,
                              timeout=120)
        assert done.returncode == 0, done.stderr
    assert list(folder.iterdir()) == []


# --------------------------------------------------------------------------- files a URDF pulls in
SECRET = b"SECRET-MARKER-7f3a9c"


def _gltf(buffer_uri: str, image_uri: str | None = None, size: int = 36 + len(SECRET)) -> str:
    """A one-triangle glTF whose buffer is ``buffer_uri`` (36 bytes of positions, then anything)."""
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"uri": buffer_uri, "byteLength": size}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [0.3, 0.05, 0]}],
    }
    if image_uri is not None:
        document["images"] = [{"uri": image_uri}]
    return json.dumps(document)


def _embedded(html: str, secret: bytes) -> bool:
    """Whether ``secret`` is in ``html`` as text or inside any base64 blob (how Meshcat embeds files)."""
    if secret.decode() in html:
        return True
    for blob in re.findall(r"[A-Za-z0-9+/]{40,}={0,2}", html):
        for start in range(4):  # a blob cut at any offset still decodes from some start
            chunk = blob[start:]
            chunk = chunk[: len(chunk) - len(chunk) % 4]
            try:
                if secret in base64.b64decode(chunk):
                    return True
            except ValueError:
                continue
    return False


@pytest.fixture
def robot(tmp_path) -> Path:
    """A folder holding a URDF (``two.urdf``), a triangle's positions and, one level up, a secret file."""
    folder = tmp_path / "robot"
    folder.mkdir()
    positions = np.array([[0, 0, 0], [0.3, 0, 0], [0, 0.05, 0]], dtype=np.float32).tobytes()
    (tmp_path / "secret.bin").write_bytes(positions + SECRET)
    (folder / "inside.bin").write_bytes(positions + SECRET)  # the same bytes, where a mesh may read them
    return folder


def _simulate(urdf: Path, out: Path) -> int:
    return main(["simulate", str(urdf), "--from", "0,0", "--to", "1,1", "--dt", "0.05", "--out", str(out)])


@pytest.mark.slow
def test_a_replay_embeds_a_glb_buffer_inside_the_folder(robot, capsys):
    """The control: a mesh inside the URDF's folder is embedded in replay.html (so the check below can see it)."""
    (robot / "tri.gltf").write_text(_gltf("inside.bin"))
    (robot / "two.urdf").write_text(two_link_urdf(mesh="tri.gltf"))
    assert _simulate(robot / "two.urdf", robot.parent / "ok") == 0
    assert _embedded((robot.parent / "ok" / "replay.html").read_text(), SECRET)


@pytest.mark.parametrize(
    ("files", "mesh", "refused"),
    [
        ({"tri.gltf": _gltf("../secret.bin")}, "tri.gltf", "tri.gltf names '../secret.bin'"),
        ({"tri.gltf": _gltf("/etc/hostname")}, "tri.gltf", "tri.gltf names '/etc/hostname'"),
        ({"tri.gltf": _gltf("..%2Fsecret.bin")}, "tri.gltf", "names '../secret.bin'"),
        ({"tri.gltf": _gltf("inside.bin", image_uri="../../../../../../etc/hostname")}, "tri.gltf", "etc/hostname"),
        ({"tri.gltf": _gltf("file:///etc/hostname")}, "tri.gltf", "absolute path or URL"),
        ({}, "../secret.bin", "lies outside the URDF's folder"),
        ({}, "/etc/hostname", "'/etc/hostname' is an absolute path"),
        ({}, "file:///etc/hostname", "absolute path or URL"),
        ({"fore.obj": "mtllib ../secret.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}, "fore.obj", "secret.mtl"),
        ({"fore.obj": "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
          "m.mtl": "newmtl a\nmap_Kd /etc/hostname\n"}, "fore.obj", "m.mtl names '/etc/hostname'"),
    ],
)
def test_a_replay_of_a_hostile_urdf_cannot_embed_other_files(robot, capsys, files, mesh, refused):
    for name, text in files.items():
        (robot / name).write_text(text)
    (robot / "two.urdf").write_text(two_link_urdf(mesh=mesh))
    out = robot.parent / "run"
    assert _simulate(robot / "two.urdf", out) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("armlab: error: ") and refused in err[0], err
    assert "two.urdf" in err[0] and not out.exists()


def test_a_symlink_leaving_the_folder_is_refused(robot, capsys):
    (robot / "tri.gltf").write_text(_gltf("link.bin"))
    (robot / "link.bin").symlink_to(robot.parent / "secret.bin")
    (robot / "two.urdf").write_text(two_link_urdf(mesh="tri.gltf"))
    assert _simulate(robot / "two.urdf", robot.parent / "run") == 2
    assert "secret.bin lies outside the URDF's folder" in capsys.readouterr().err
    (robot / "mesh.gltf").symlink_to(robot / "tri.gltf")  # a link inside the folder is fine, its target is not
    (robot / "link.bin").unlink()
    (robot / "link.bin").symlink_to(robot / "inside.bin")
    (robot / "two.urdf").write_text(two_link_urdf(mesh="mesh.gltf"))
    assert get_arm(str(robot / "two.urdf")).n == 2


def test_a_glb_is_read_for_its_uris(robot):
    """A binary glTF's JSON chunk is checked like a .gltf file."""
    text = _gltf("../secret.bin").encode()
    text += b" " * (-len(text) % 4)
    (robot / "tri.glb").write_bytes(b"glTF" + (2).to_bytes(4, "little") + (20 + len(text)).to_bytes(4, "little")
                                    + len(text).to_bytes(4, "little") + b"JSON" + text)
    (robot / "two.urdf").write_text(two_link_urdf(mesh="tri.glb"))
    with pytest.raises(ValueError, match=r"tri\.glb names '\.\./secret\.bin'"):
        get_arm(str(robot / "two.urdf"))


def test_a_package_path_cannot_climb_out_of_its_package(tmp_path):
    package = tmp_path / "my_robot"
    (package / "urdf").mkdir(parents=True)
    (package / "package.xml").write_text('<?xml version="1.0"?>\n<!-- a ROS package -->\n'
                                         "<package><name>my_robot</name></package>")
    (tmp_path / "outside.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (package / "urdf" / "two.urdf").write_text(two_link_urdf(mesh="package://my_robot/../outside.obj"))
    with pytest.raises(ValueError, match=r"outside\.obj lies outside the URDF's folder and its ROS package"):
        get_arm(str(package / "urdf" / "two.urdf"))
    (package / "urdf" / "two.urdf").write_text(two_link_urdf(mesh="../../outside.obj"))
    with pytest.raises(ValueError, match=r"outside\.obj lies outside"):
        get_arm(str(package / "urdf" / "two.urdf"))


# ---- issue 36, items 1, 4 and 5: the files an <include>d file names are confined; an include cycle is refused
_MJCF = (DATA_FORMATS := Path(__file__).parent / "data" / "formats") / "two_link.xml"
_SDF = DATA_FORMATS / "two_link.sdf"
_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n"


def _run_limited(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    """``armlab ARGS`` as a process in ``cwd`` with 3 GB of address space (an include without end fails fast)."""
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30)); "
            "from armlab.cli import main; sys.exit(main(sys.argv[1:]))")
    return subprocess.run([sys.executable, "-c", code, *args], cwd=cwd, capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize(("main_file", "files", "refused"), [
    ("a.xml", {"inc.xml": '<mujoco><asset><mesh name="o" file="../outside.obj"/></asset></mujoco>'},
     "outside.obj lies outside"),
    ("a.xml", {"inc.xml": '<mujoco><include file="inc2.xml"/></mujoco>',
               "inc2.xml": '<mujoco><asset><mesh name="o" file="{outside}"/></asset></mujoco>'},
     "is an absolute path"),
    ("a.xml", {"inc.xml": '<mujoco><compiler meshdir=".."/><asset><mesh name="o" file="outside.obj"/></asset>'
                          "</mujoco>"}, "outside.obj lies outside"),
    ("a.sdf", {"sub/inc.sdf": '<sdf version="1.9"><model name="v"><link name="v"><visual name="v"><geometry><mesh>'
                              "<uri>../../outside.obj</uri></mesh></geometry></visual></link></model></sdf>"},
     "outside.obj lies outside"),
    ("a.xml", {"inc.xml": '<mujoco><include file="a.xml"/></mujoco>'},
     "<include> 'a.xml' includes a.xml, which includes it: recursive includes are not allowed"),
])
def test_an_included_file_names_no_file_from_elsewhere(tmp_path, main_file, files, refused):
    """The outside mesh is a FIFO: a process that opened it would wait for a writer (the timeout); the refusal
    comes before any parse, naming the file."""
    os.mkfifo(tmp_path / "outside.obj")
    folder = tmp_path / "m"
    (folder / "sub").mkdir(parents=True)
    (folder / "in.obj").write_text(_OBJ)
    include = "inc.xml" if main_file.endswith(".xml") else "sub/inc.sdf"
    text = (_MJCF.read_text().replace("<worldbody>", f'<include file="{include}"/><worldbody>') if main_file.endswith(
        ".xml") else _SDF.read_text().replace("</model>", f"</model><include><uri>{include}</uri></include>", 1))
    (folder / main_file).write_text(text)
    for name, content in files.items():
        (folder / name).write_text(content.replace("{outside}", str(tmp_path / "outside.obj")))
    result = _run_limited(["show", f"m/{main_file}"], tmp_path)
    assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith("armlab: error: m/") and refused in result.stderr, result.stderr
    if main_file.endswith(".xml") and "../outside.obj" in files[include]:  # the control: a mesh inside is read
        (folder / include).write_text(files[include].replace("../outside.obj", "in.obj"))
        assert _run_limited(["show", f"m/{main_file}"], tmp_path).returncode == 0


@pytest.mark.parametrize("main_file", ["self.sdf", "self.xml"])
def test_a_file_that_includes_itself_is_refused_before_drake_parses_it(tmp_path, main_file):
    """Item 4: Drake's SDFormat parser crashed (SIGSEGV) on a file including itself through its ROS package; item 5:
    Drake's MJCF parser grew without end."""
    (tmp_path / "package.xml").write_text("<package><name>pk</name></package>")
    name = main_file if main_file.endswith(".xml") else f"package://pk/{main_file}"
    text = (_MJCF.read_text().replace("<worldbody>", f'<include file="{name}"/><worldbody>')
            if main_file.endswith(".xml") else
            _SDF.read_text().replace("</model>", f"</model><include><uri>{name}</uri></include>", 1))
    (tmp_path / main_file).write_text(text)
    result = _run_limited(["show", main_file], tmp_path)
    assert result.returncode == 2, result.stderr[-300:]
    assert result.stderr == (f"armlab: error: {main_file}: <include> {name!r} includes itself: recursive "
                             "includes are not allowed\n")
