"""Collision geometry for every arm (issue 30, item 1): the library arms' capsules, a DH table's radius per link
(0: no shape), links that touch by construction filtered, ``package://`` by folder name, STL and COLLADA
collision meshes as convex hulls, ``armlab check``'s exit status."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from helpers import armlab_main, random_q, three_link_urdf
from numpy.testing import assert_allclose

import armlab
from armlab.collision.clearance import clearance
from armlab.collision.model import CollisionModel
from armlab.collision.scene import scene_from_dict
from armlab.models import get_arm
from armlab.models.library import LIBRARY
from armlab.models.write_urdf import touching_pairs


def _rest_poses(arm) -> dict[str, np.ndarray]:
    lower, upper = arm.limit_arrays()
    return {"zero": np.clip(np.zeros(arm.n), lower, upper), "home": np.array(arm.home)}


@pytest.mark.parametrize("name", LIBRARY)
def test_every_library_arm_is_free_of_itself_at_zero_and_home(name):
    """Each library arm has a shape on every link, and no pair touches at its zero pose (clipped into the limits:
    the Panda's joints 4 and 6 exclude 0) or its home pose, by numpy's closed forms and by Drake's query (GJK: never
    below the exact distance; on near-parallel capsules, as the Puma's upper arm and forearm at home, up to ~1 mm
    above it)."""
    arm = get_arm(name)
    assert all(body.collides for body in arm.bodies) and arm.home is not None
    model = CollisionModel(arm)
    assert model.numpy_ready and len(model.pairs) > 0
    for label, q in _rest_poses(arm).items():
        exact, drake = model.numpy(q), model.drake(q)
        assert exact.distance.min() > 0, (label, exact.names()[int(np.argmin(exact.distance))])
        assert drake.distance.min() > 0 and np.all(drake.distance >= exact.distance - 1e-9), label


def test_puma_exported_dh_table_with_radii_has_no_pair_in_contact_everywhere(tmp_path):
    """The issue's Puma: its DH table exported with its radii and read back, 200 random poses: link6–link4 (the
    wrist's coincident frames) is not a checked pair, and no checked pair is in contact at every pose."""
    puma = armlab.load("puma560")
    (path,) = armlab.export(puma, dh=tmp_path / "puma.csv")
    assert "radius" in path.read_text().splitlines()[3]
    copy = armlab.load(path)
    model = CollisionModel(copy)
    assert ("link6", "link4") not in model.pairs and ("link4", "link6") not in model.pairs
    found = model.distances(random_q(copy, np.random.default_rng(30), 200))
    assert not np.any(np.all(found.distance < 0, axis=0)), found.names()
    # the same clearances as the library arm's own (the table carries every radius; corners are recomputed)
    q = random_q(puma, np.random.default_rng(3), 20)
    assert_allclose(model.distances(q).distance, CollisionModel(puma).distances(q).distance, rtol=0, atol=1e-9)


def _planar(tmp_path, radii: str, a3: float = 0.3) -> str:
    """A planar 4R arm: links 0.4, 0 (a point: joints 2 and 3 coincide), a3, 0.2 m along x."""
    path = tmp_path / "planar.csv"
    rows = [f"R,0.4,0,0,0,-3,3,{radii[0]}", f"R,0,0,0,0,-3,3,{radii[1]}", f"R,{a3},0,0,0,-3,3,{radii[2]}",
            f"R,0.2,0,0,0,-3,3,{radii[3]}"]
    path.write_text("type,a,alpha,d,theta,lower,upper,radius\n" + "\n".join(rows) + "\n")
    return str(path)


def test_touching_by_construction_is_the_hand_case(tmp_path):
    """Link 2 has no length: links 1 and 3 meet at joints 2-3 whatever the joints do, so link3–link1 is filtered;
    link4–link2 is 0.3 m of link 3 apart, filtered only when the radii reach across it (0.16 + 0.15 > 0.3)."""
    arm = get_arm(_planar(tmp_path, ["0.05", "0.05", "0.05", "0.05"]))
    assert touching_pairs(arm.table, arm.bodies, arm.limits) == [("link3", "link1")]
    pairs = CollisionModel(arm).pairs
    assert ("link3", "link1") not in pairs and ("link4", "link2") in pairs and ("link4", "link1") in pairs
    wide = get_arm(_planar(tmp_path, ["0.05", "0.16", "0.05", "0.15"]))
    assert set(touching_pairs(wide.table, wide.bodies, wide.limits)) == {("link3", "link1"), ("link4", "link2")}
    # on the bound (0.15 + 0.15 = 0.3): the shapes touch when stretched, never overlap: filtered, by the one slack
    edge = get_arm(_planar(tmp_path, ["0.05", "0.15", "0.05", "0.15"]))
    assert ("link4", "link2") in touching_pairs(edge.table, edge.bodies, edge.limits)


def test_radius_zero_gives_a_link_no_shape(tmp_path, capsys):
    """radius 0: the link is never checked; its neighbours still are, and the table exports it as 0."""
    arm = get_arm(_planar(tmp_path, ["0.05", "0", "0.05", "0.05"]))
    assert [body.collides for body in arm.bodies] == [True, False, True, True]
    model = CollisionModel(arm)
    assert all("link2" not in pair for pair in model.pairs) and ("link4", "link1") in model.pairs
    # link 4 folded back over link 1 (q3 = q4 = 180°... within ±3 rad): the test's own distance at q = (0, 0, 0, 3)
    q = np.array([0.0, 0.0, 0.0, 0.0])
    (row,) = [r for r in clearance(arm, q) if r["pair"] == "link4–link1"]
    assert_allclose(row["distance"], 0.7 - 0.4 - 0.1, rtol=0, atol=1e-9)  # link 4 starts at x = 0.7, link 1 ends 0.4
    (path,) = armlab.export(arm, dh=tmp_path / "out.csv")
    assert [line.rsplit(",", 1)[1] for line in path.read_text().splitlines()[-4:]] == ["0.05", "0", "0.05", "0.05"]
    bad = tmp_path / "bad.csv"
    bad.write_text("type,a,alpha,d,theta,lower,upper,radius\nR,0.4,0,0,0,-3,3,\n")
    assert armlab_main("check", str(bad), "--q", "0").returncode == 2


def _table_scene() -> dict:
    return {"obstacles": [{"name": "table", "shape": "box", "size": [0.6, 0.6, 0.05], "xyz": [0.45, 0, 0.3]}]}


def test_check_exits_3_in_contact_and_0_when_clear(tmp_path):
    """armlab check: UR5 with its upper arm through a table (exit 3, the pair named); upright beside it (exit 0)."""
    import json

    scene = tmp_path / "table.json"
    scene.write_text(json.dumps(_table_scene()))
    arm = get_arm("ur5")
    down = np.radians([180, -30, 60, -90, -90, 0])  # facing +x, the upper arm rises through the table
    assert min(r["distance"] for r in clearance(arm, down, str(scene)) if "table" in r["pair"]) < 0
    result = armlab_main("check", "ur5", "--q", ",".join(map(str, down)), "--scene", str(scene))
    assert result.returncode == 3 and "in contact" in result.stdout and "–table" in result.stdout
    result = armlab_main("check", "ur5", "--q", "0,-90,0,-90,0,0", "--deg", "--scene", str(scene), "--json")
    assert result.returncode == 0 and not json.loads(result.stdout)["in_contact"]
    assert armlab_main("check", "ur5", "--q", ",".join(map(str, down)), "--scene", str(scene),
                       "--json").returncode == 3


def _box_points(half: np.ndarray) -> np.ndarray:
    return np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * half


#: A box's 12 triangles over :func:`_box_points`' corners (0-based).
_FACES = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6), (0, 2, 6),
          (0, 6, 4), (1, 5, 7), (1, 7, 3)]


def _stl(points: np.ndarray) -> bytes:
    body = b"".join(struct.pack("<12fH", 0, 0, 0, *points[a], *points[b], *points[c], 0) for a, b, c in _FACES)
    return b"armlab test box".ljust(80, b" ") + struct.pack("<I", len(_FACES)) + body


def _dae(points: np.ndarray, unit: float, shift: np.ndarray) -> str:
    """A COLLADA box in units of ``unit`` m, its node translated by ``shift`` (in those units)."""
    values = " ".join(f"{v:.17g}" for v in (points / unit).ravel())
    indices = " ".join(str(i) for face in _FACES for i in face)
    return f"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="{unit}"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="box"><mesh>
    <source id="pos"><float_array id="pos-array" count="24">{values}</float_array>
      <technique_common><accessor source="#pos-array" count="8" stride="3"/></technique_common></source>
    <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count="12"><input semantic="VERTEX" source="#verts" offset="0"/><p>{indices}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="n"><translate>{' '.join(map(str, -shift / unit))}
  </translate><node id="inner"><translate>{' '.join(map(str, shift / unit))}</translate>
  <instance_geometry url="#box"/></node></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"""


def _obj(points: np.ndarray) -> str:
    return "".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in points) + "".join(
        f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in _FACES)


def test_stl_and_collada_collision_meshes_are_their_convex_hulls(tmp_path):
    """The same box as an OBJ (Drake reads it), a binary STL and a COLLADA file in centimetres with nested node
    transforms (armlab reads them): the forearm's clearance to the floor is the same to 1e-9 m, and the test's own
    formula (the box's lowest corner) for every elbow angle. No mesh is left out."""
    import warnings

    half = np.array([0.15625, 0.015625, 0.015625])  # exact in a binary STL's float32
    points = _box_points(half)
    (tmp_path / "box.obj").write_text(_obj(points))
    (tmp_path / "box.stl").write_bytes(_stl(points))
    (tmp_path / "box.dae").write_text(_dae(points, 0.01, np.array([0.05, -0.02, 0.01])))
    floor = scene_from_dict({"obstacles": [{"name": "floor", "shape": "floor", "z": -0.05}]})
    arms = {}
    for kind in ("obj", "stl", "dae"):
        folder = tmp_path / kind
        folder.mkdir()
        (folder / f"box.{kind}").write_bytes((tmp_path / f"box.{kind}").read_bytes())
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # nothing left out
            arms[kind] = get_arm(three_link_urdf(folder, f'<mesh filename="box.{kind}"/>'))
    assert len(arms["stl"].collision_hulls) == 1 and arms["obj"].collision_hulls == ()
    for q2 in (0.0, 0.5, -1.0, 2.0):
        q = [0.0, q2, 0.0]
        rows = {kind: {r["pair"]: r["distance"] for r in clearance(arm, q, floor)} for kind, arm in arms.items()}
        # joints about +y turn x towards −z: the box's centre 0.15 m along (cos q2, 0, −sin q2) from (0.4, 0, 0.1)
        expected = 0.1 - 0.15 * np.sin(q2) - (half[0] * abs(np.sin(q2)) + half[2] * abs(np.cos(q2))) + 0.05
        for kind in arms:
            assert_allclose(rows[kind]["fore–floor"], expected, rtol=0, atol=1e-9, err_msg=kind)
    flat = tmp_path / "flat"
    flat.mkdir()
    (flat / "box.stl").write_bytes(_stl(points * [1, 1, 0]))
    with pytest.warns(UserWarning, match=r"collision mesh\(es\) left out.*one plane"):
        get_arm(three_link_urdf(flat, '<mesh filename="box.stl"/>'))


def test_package_found_by_its_folder_name(tmp_path):
    """example-robot-data's layout: its package.xml names it example_robot_descriptions, its URDFs say
    package://example-robot-data/…: found by the folder of that name on the package path, as Pinocchio finds it;
    the mesh is the one Pinocchio resolves."""
    import warnings

    share = tmp_path / "share"
    package = share / "example-robot-data"
    (package / "robots" / "meshy" / "urdf").mkdir(parents=True)
    (package / "robots" / "meshy" / "meshes").mkdir()
    (package / "package.xml").write_text('<?xml version="1.0"?><package format="2"><name>example_robot_descriptions'
                                         "</name><version>1.0.0</version><description>d</description>"
                                         '<maintainer email="a@b.c">a</maintainer><license>BSD</license></package>')
    mesh = package / "robots" / "meshy" / "meshes" / "box.stl"
    mesh.write_bytes(_stl(_box_points(np.array([0.15, 0.02, 0.02]))))
    urdf = three_link_urdf(package / "robots" / "meshy" / "urdf",
                           '<mesh filename="package://example-robot-data/robots/meshy/meshes/box.stl"/>')
    with pytest.warns(UserWarning, match="1 mesh"):
        assert get_arm(urdf).collision_hulls == ()  # not found without the package path
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        arm = armlab.load(urdf, package_paths=[share])
    assert len(arm.collision_hulls) == 1
    import pinocchio

    model = pinocchio.buildModelFromUrdf(urdf)
    geometry = pinocchio.buildGeomFromUrdf(model, urdf, pinocchio.GeometryType.COLLISION, package_dirs=[str(share)])
    (pin_mesh,) = [g.meshPath for g in geometry.geometryObjects if g.meshPath.endswith(".stl")]
    assert pin_mesh == str(mesh.resolve())


@pytest.mark.parametrize("name", LIBRARY)
def test_models_readme_gives_every_library_collision_radius(name):
    """models/README.md's table of the library arms' collision geometry gives each link's radius (mm) as the arm's
    module has it, and the pairs filtered by construction as the arm's URDF writes them."""
    from armlab.models.arm import MODELS_DIR

    text = (MODELS_DIR / "README.md").read_text()

    def radii_cell(line: str) -> bool:  # the geometry table's second cell: the radii, "90, 70, …"
        cells = line.split("|")
        return len(cells) == 7 and all(part.strip().replace(".", "").isdigit()
                                       for part in cells[2].split(";")[0].split(","))

    (row,) = [line for line in text.splitlines() if line.startswith(f"| `{name}` |") and radii_cell(line)]
    radii = row.split("|")[2].split(";")[0].split(",")
    arm = get_arm(name)
    assert [float(r) for r in radii] == [round(body.radius * 1e3, 1) for body in arm.bodies]
    filtered = touching_pairs(arm.table, arm.bodies, arm.limits)
    cell = row.split("|")[4]
    assert (cell.strip() == "none") == (not filtered)
    for a, b in filtered:
        shown = "base column" if b == "base_link" else b
        assert f"{a}–{shown}" in cell, (a, b, cell)
