"""Mesh files of a user's URDF confined to its folder and its ROS packages; the ones Drake cannot use left out.

Replaying someone else's URDF must not embed a file from elsewhere: every ``<mesh filename=…>``
(relative to the URDF's folder, or ``package://NAME/…`` of a package found for the URDF:
:func:`armlab.models.read_urdf.package_roots`), and every file a mesh names in turn (a glTF's buffers
and images, an OBJ's material libraries, an MTL's texture maps, a COLLADA file's images), must lie
inside the URDF's folder or a package's folder once symlinks and ``..`` are resolved; absolute paths
and URLs are refused.

A mesh that cannot be found (its file missing, its package not found) is a :class:`MeshWarning` and its
``<visual>`` or ``<collision>`` is left out: kinematics and dynamics do not need it. A collision mesh is its
convex hull (Drake's ``Convex``, what Drake does with a mesh that is not convex): Drake reads
:data:`COLLISION_SUFFIXES` itself; ROS's STL and COLLADA (:data:`HULL_SUFFIXES`) armlab reads, their vertices
(:func:`mesh_points`: an STL's, binary or text; a COLLADA file's, through its scene's node transforms and its
``<unit meter>``, its ``<up_axis>`` not applied), and registers their hull with the plant
(:class:`Hull`, :func:`armlab.models.plant.add_arm_plant`). One that has no hull (fewer than four vertices off one
plane, an unreadable file) or is of another kind is left out, with one warning, before any work.
"""

from __future__ import annotations

import json
import struct
import warnings
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import unquote

import numpy as np
from numpy.typing import NDArray

from armlab.values import shown

__all__ = [
    "COLLISION_SUFFIXES",
    "HULL_SUFFIXES",
    "MAX_XML_DEPTH",
    "Hull",
    "MeshWarning",
    "Meshes",
    "Shape",
    "check_meshes",
    "check_references",
    "mesh_points",
    "parse_xml",
]

#: Mesh files Drake makes collision geometry of (a convex hull) itself.
COLLISION_SUFFIXES = (".obj", ".vtk", ".gltf")
#: Mesh files whose vertices armlab reads (:func:`mesh_points`) for Drake to make the convex hull of.
HULL_SUFFIXES = (".stl", ".dae")


class MeshWarning(UserWarning):
    """A mesh of a user's URDF that armlab leaves out (missing, or of a kind Drake cannot use there)."""


@dataclass(frozen=True)
class Hull:
    """A collision mesh Drake cannot read, as the vertices of its convex hull: on the URDF link ``link``, at
    ``pose`` (4×4 nested tuples, the ``<collision>``'s origin in the link's frame), ``points`` ``(N, 3)`` (m, the
    mesh's ``scale`` applied), named ``name`` (the ``<collision>``'s name, or the link's and a number)."""

    link: str
    pose: tuple[tuple[float, ...], ...]
    points: NDArray[np.float64]
    name: str


@dataclass(frozen=True)
class Shape:
    """A collision shape of an SDFormat or MJCF file's link, for the plant to register on the arm's link ``link``
    (its generated URDF's name: ``base_link``, ``link1`` …) at ``pose`` (4×4 nested tuples, in that link's frame
    {i}): ``kind`` ``"box"`` (``size``: its three edges, m), ``"sphere"`` (radius), ``"cylinder"`` and
    ``"capsule"`` (radius, length along its z), ``"ellipsoid"`` (its three semi-axes) or ``"convex"`` (the convex
    hull of the mesh ``file``, checked inside the file's folder, ``size`` its scale per axis); named ``name``."""

    link: str
    pose: tuple[tuple[float, ...], ...]
    kind: str
    size: tuple[float, ...]
    name: str
    file: str | None = None


@dataclass(frozen=True)
class Meshes:
    """What :func:`check_meshes` found: each usable ``<mesh>`` element's file, and the elements left out.

    ``files``: mesh element → its file (resolved, inside the allowed folders); ``dropped``: the ``<visual>`` or
    ``<collision>`` elements whose mesh is missing or unusable (a warning said which); ``hulls``: the
    ``<collision>`` elements of an STL or COLLADA mesh (left out of Drake's URDF too) → its vertices (m, ``(N, 3)``,
    the mesh's ``scale`` applied), for their convex hull.
    """

    files: dict[ET.Element, Path]
    dropped: set[ET.Element]
    hulls: dict[ET.Element, NDArray[np.float64]] = field(default_factory=dict)


#: The deepest nesting of elements a user's XML file may have (an MJCF arm of 64 joints nests ~70 bodies): deeper,
#: the file is refused before anything walks its tree (ElementTree writes a tree back recursively).
MAX_XML_DEPTH = 256


class _Refusing(ET.TreeBuilder):
    """ElementTree's tree builder, refusing (``ValueError``) a document type (the parser's own DOCTYPE hook, called
    at ``<!DOCTYPE``, before any entity of it is declared: without one no entity can be) and nesting deeper than
    :data:`MAX_XML_DEPTH`."""

    def __init__(self, what: str) -> None:
        super().__init__()
        self.what = what
        self.depth = 0

    def doctype(self, name: str, pubid: str | None, system: str | None) -> None:
        raise ValueError(f"{self.what}: XML document-type or entity definitions (<!DOCTYPE, <!ENTITY) are not "
                         "allowed")

    def start(self, tag: str, attrs: dict[str, str]) -> ET.Element:
        self.depth += 1
        if self.depth > MAX_XML_DEPTH:
            raise ValueError(f"{self.what}: elements nested more than {MAX_XML_DEPTH} deep are not allowed")
        return super().start(tag, attrs)

    def end(self, tag: str) -> ET.Element:
        self.depth -= 1
        return super().end(tag)


def parse_xml(text: str, what: str) -> ET.Element:
    """The root element of the XML ``text`` (a user's file, named ``what`` in errors): ``ValueError`` for a document
    type or entity definitions (entity expansion, external entities; refused by the parser's own DOCTYPE hook, so
    no comment, processing instruction or CDATA section can hide one) or nesting deeper than
    :data:`MAX_XML_DEPTH`; ``xml.etree.ElementTree.ParseError`` for text that is not XML."""
    parser = ET.XMLParser(target=_Refusing(what))
    parser.feed(text)
    return parser.close()


def _inside(path: Path, folders: Sequence[Path], what: str) -> Path:
    """``path`` with symlinks and ``..`` resolved, if it lies inside one of ``folders``; else an error."""
    real = path.resolve()
    if not any(real.is_relative_to(folder) for folder in folders):
        shown = str(real) if path.is_symlink() or ".." in path.parts else str(path)
        raise ValueError(f"{what}: {shown} lies outside the URDF's folder and its ROS package "
                         f"({', '.join(map(str, folders))}): armlab reads no files from elsewhere")
    return real


def _reference(reference: str, base: Path, packages: dict[str, Path], folders: Sequence[Path],
               what: str) -> Path | None:
    """A file named by a URDF mesh (``package://`` or relative to ``base``), checked to lie inside ``folders``;
    ``None`` for a ``package://`` path whose package is not among ``packages`` (``{name: package folder}``)."""
    if reference.startswith("package://"):
        package, _, rest = reference[len("package://"):].partition("/")
        if package not in packages:
            return None
        return _inside(packages[package] / rest, folders, what)
    if "://" in reference or reference.startswith(("/", "\\")) or Path(reference).is_absolute():
        raise ValueError(f"{what}: {reference!r} is an absolute path or URL: name files relative to the URDF's "
                         "folder or as package://NAME/… of its ROS package")
    return _inside(base / reference, folders, what)


def _pulled_in(mesh: Path) -> list[str]:
    """The files a mesh file names: a glTF's buffer and image URIs, an OBJ's material libraries, an MTL's maps."""
    suffix = mesh.suffix.lower()
    if not mesh.is_file() or suffix not in (".gltf", ".glb", ".obj", ".mtl", ".dae"):
        return []
    if suffix == ".dae":
        return _collada_images(mesh)
    if suffix in (".gltf", ".glb"):
        data = mesh.read_bytes()
        if suffix == ".glb":  # header (magic, version, length), then the JSON chunk (length, type, data)
            if len(data) < 20 or data[:4] != b"glTF":
                raise ValueError(f"{mesh}: not a binary glTF file")
            (length,) = struct.unpack_from("<I", data, 12)
            data = data[20:20 + length]
        try:
            document = json.loads(data)
            uris = [item["uri"] for key in ("buffers", "images") for item in document.get(key, []) if "uri" in item]
        except (ValueError, TypeError, AttributeError, KeyError):
            raise ValueError(f"{mesh}: not a glTF file (its JSON cannot be read)") from None
        if not all(isinstance(uri, str) for uri in uris):
            raise ValueError(f"{mesh}: a glTF uri is not a string")
        return [unquote(uri) for uri in uris if not uri.startswith("data:")]
    names = []
    with mesh.open(encoding="utf-8", errors="replace") as lines:
        for line in lines:
            words = line.split()
            if suffix == ".obj" and words[:1] == ["mtllib"]:
                names.extend(words[1:])
            elif suffix == ".mtl" and words and words[0].lower().startswith(("map_", "bump", "disp", "decal", "refl",
                                                                             "norm")):
                names.extend(words[-1:])
    return names


def _collada_images(mesh: Path) -> list[str]:
    """The image files a COLLADA (``.dae``) mesh names: its ``<init_from>`` paths (1.4) or their ``<ref>`` (1.5)."""
    try:
        root = parse_xml(mesh.read_text(encoding="utf-8", errors="replace"), str(mesh))
    except ET.ParseError:  # not XML (an empty file, a Git LFS pointer): no viewer reads anything through it
        return []
    names = []
    for element in root.iter():
        if element.tag.rpartition("}")[2] == "init_from":
            ref = next((child for child in element if child.tag.rpartition("}")[2] == "ref"), None)
            text = (element.text if ref is None else ref.text) or ""
            if text.strip():
                names.append(unquote(text.strip()))
    return names


def check_meshes(path: Path, root: ET.Element, packages: dict[str, Path]) -> Meshes:
    """The meshes of the URDF ``path`` (``root`` its parsed XML): ``ValueError`` naming the file unless every
    mesh, and every file those meshes name, lies inside the URDF's folder or one of the ROS ``packages``
    (``{name: package folder}``, :func:`armlab.models.read_urdf.package_roots`); no absolute paths, URLs, ``..``
    or symlinks leading elsewhere: replaying someone else's URDF must not embed a file from elsewhere.

    A mesh not found and a collision mesh Drake cannot use are left out, each kind with one
    :class:`MeshWarning` (module docstring)."""
    folders = [path.resolve().parent] + [folder.resolve() for folder in packages.values()]
    files: dict[ET.Element, Path] = {}
    dropped: set[ET.Element] = set()
    hulls: dict[ET.Element, NDArray[np.float64]] = {}
    missing, unusable = [], []
    unfound = 0  # of the missing: the package:// ones whose package is not found
    for role in ("visual", "collision"):
        for element in root.iter(role):
            for mesh in element.iter("mesh"):
                reference = mesh.get("filename") or ""
                what = f"{path}: mesh {reference!r}"
                file = _reference(reference, path.resolve().parent, packages, folders, what)
                unfound += file is None
                if file is None or not file.is_file():
                    missing.append(reference)
                    dropped.add(element)
                    continue
                _check_pulled_in(path, file, folders)
                if role == "collision" and file.suffix.lower() in HULL_SUFFIXES:
                    try:
                        hulls[element] = mesh_points(file) * _scale(mesh, what)
                        continue
                    except ValueError as error:
                        unusable.append(f"{reference} ({error})")
                        dropped.add(element)
                        continue
                if role == "collision" and file.suffix.lower() not in COLLISION_SUFFIXES:
                    unusable.append(reference)
                    dropped.add(element)
                    continue
                files[mesh] = file
    if missing:
        warnings.warn(MeshWarning(
            f"{path}: {len(missing)} mesh(es) not found, their visuals and collisions left out (kinematics and "
            f"dynamics do not need them): {listed(missing)}"
            + ("; a package:// mesh needs its package found: --package-path DIR or ROS_PACKAGE_PATH" if unfound
               else "")), stacklevel=3)
    if unusable:
        warnings.warn(MeshWarning(
            f"{path}: {len(unusable)} collision mesh(es) left out: a collision mesh is the convex hull of an "
            f"{', '.join((*COLLISION_SUFFIXES, *HULL_SUFFIXES))} file's vertices: {listed(unusable)}"), stacklevel=3)
    return Meshes(files, dropped, hulls)


def _scale(mesh: ET.Element, what: str) -> NDArray[np.float64]:
    """A ``<mesh>``'s ``scale`` (three numbers, or one; default 1) as ``(3,)``."""
    parts = (mesh.get("scale") or "1 1 1").split()
    try:
        values = [float(part) for part in parts]
    except ValueError:
        values = []
    if len(values) not in (1, 3) or not all(np.isfinite(values)):
        raise ValueError(f"{what}: scale {mesh.get('scale')!r} is not allowed: give three numbers")
    return np.broadcast_to(np.array(values), (3,)).copy()


def mesh_points(file: Path) -> NDArray[np.float64]:
    """The vertices ``(N, 3)`` of an STL (binary or text) or COLLADA (``.dae``) mesh file, in its units (a COLLADA
    file's ``<unit meter>`` applied, through its scene's node transforms); ``ValueError`` saying why when they
    span no volume (fewer than four points off one plane) or the file cannot be read."""
    data = file.read_bytes()
    if file.suffix.lower() == ".stl":
        points = _stl_points(data)
    else:
        points = _collada_points(data, str(file))
    if len(points) < 4 or not np.all(np.isfinite(points)):
        raise ValueError(f"{len(points)} vertices: a hull needs four or more, finite")
    spread = np.linalg.svd(points - points.mean(axis=0), compute_uv=False)
    if spread[2] <= 1e-9 * max(spread[0], 1e-300):
        raise ValueError("its vertices lie in one plane: no hull of any volume")
    return points


def _stl_points(data: bytes) -> NDArray[np.float64]:
    """An STL's vertices: binary (80-byte header, a triangle count, 50 bytes a triangle) when the size says so, else
    the ``vertex x y z`` lines of a text STL."""
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if len(data) == 84 + 50 * count:
            triangles = np.frombuffer(data, dtype=np.dtype([("normal", "<f4", 3), ("vertices", "<f4", (3, 3)),
                                                            ("attribute", "<u2")]), count=count, offset=84)
            return np.unique(triangles["vertices"].reshape(-1, 3).astype(float), axis=0)
    rows = []
    for line in data.decode("utf-8", errors="replace").splitlines():
        words = line.split()
        if words[:1] == ["vertex"] and len(words) == 4:
            try:
                rows.append([float(v) for v in words[1:]])
            except ValueError:
                raise ValueError(f"a vertex line {line.strip()!r} is not three numbers") from None
    return np.unique(np.array(rows, dtype=float).reshape(-1, 3), axis=0)


def _local(tag: str) -> str:
    return tag.rpartition("}")[2]


def _node_transform(node: ET.Element) -> NDArray[np.float64]:
    """A COLLADA ``<node>``'s transform: its ``<matrix>``, ``<translate>``, ``<rotate>`` (axis, degrees) and
    ``<scale>`` children, in document order."""
    X = np.eye(4)
    for child in node:
        kind = _local(child.tag)
        values = [float(v) for v in (child.text or "").split()]
        step = np.eye(4)
        if kind == "matrix" and len(values) == 16:
            step = np.array(values).reshape(4, 4)
        elif kind == "translate" and len(values) == 3:
            step[:3, 3] = values
        elif kind == "scale" and len(values) == 3:
            step = np.diag([*values, 1.0])
        elif kind == "rotate" and len(values) == 4:
            axis, angle = np.array(values[:3]), np.radians(values[3])
            axis = axis / (np.linalg.norm(axis) or 1.0)
            K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
            step[:3, :3] = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
        X = X @ step
    return X


def _collada_points(data: bytes, what: str) -> NDArray[np.float64]:
    """A COLLADA document's vertices: each ``<instance_geometry>`` of its scene's nodes through the nodes'
    transforms (every geometry as it is, if the scene places none), times its ``<unit meter>``."""
    try:
        root = parse_xml(data.decode("utf-8", errors="replace"), what)
    except ET.ParseError as error:
        raise ValueError(f"not a COLLADA file: {error}") from None
    elements = list(root.iter())
    arrays = {e.get("id"): np.array((e.text or "").split(), dtype=float) for e in elements
              if _local(e.tag) == "float_array"}
    sources = {}
    for source in (e for e in elements if _local(e.tag) == "source"):
        array = next((e for e in source.iter() if _local(e.tag) == "float_array"), None)
        accessor = next((e for e in source.iter() if _local(e.tag) == "accessor"), None)
        if array is not None and array.get("id") in arrays:
            stride = int(accessor.get("stride", "3")) if accessor is not None else 3
            values = arrays[array.get("id")]
            sources[source.get("id")] = values[: len(values) // stride * stride].reshape(-1, stride)[:, :3]
    geometries: dict[str | None, NDArray[np.float64]] = {}
    for geometry in (e for e in elements if _local(e.tag) == "geometry"):
        found = [sources[(i.get("source") or "").lstrip("#")] for v in geometry.iter() if _local(v.tag) == "vertices"
                 for i in v if _local(i.tag) == "input" and i.get("semantic") == "POSITION"
                 and (i.get("source") or "").lstrip("#") in sources]
        if found:
            geometries[geometry.get("id")] = np.concatenate(found)
    placed: list[NDArray[np.float64]] = []

    def visit(node: ET.Element, X: NDArray[np.float64]) -> None:
        X = X @ _node_transform(node)
        for child in node:
            kind = _local(child.tag)
            if kind == "instance_geometry" and (child.get("url") or "").lstrip("#") in geometries:
                points = geometries[(child.get("url") or "").lstrip("#")]
                placed.append(points @ X[:3, :3].T + X[:3, 3])
            elif kind == "node":
                visit(child, X)

    for scene in (e for e in elements if _local(e.tag) == "visual_scene"):
        for node in (child for child in scene if _local(child.tag) == "node"):
            visit(node, np.eye(4))
    unit = next((float(e.get("meter", "1")) for e in elements if _local(e.tag) == "unit"), 1.0)
    points = np.concatenate(placed) if placed else (np.concatenate(list(geometries.values())) if geometries
                                                    else np.zeros((0, 3)))
    return np.unique(points * unit, axis=0)


def listed(names: Sequence[str], most: int = 3) -> str:
    """The first ``most`` distinct ``names`` (each quoted and cut: :func:`armlab.values.shown`), and how many more:
    a message names a few of a file's many, in one line of bounded length."""
    distinct = list(dict.fromkeys(names))
    more = f" and {len(distinct) - most} more" if len(distinct) > most else ""
    return ", ".join(map(shown, distinct[:most])) + more


def _check_pulled_in(path: Path, mesh: Path, folders: Sequence[Path]) -> None:
    """``ValueError`` unless every file ``mesh`` names, and every file those name, lies inside ``folders``."""
    pending, seen = [mesh], set()
    while pending:
        file = pending.pop()
        if file in seen:
            continue
        seen.add(file)
        for name in _pulled_in(file):
            named = _reference(name, file.parent, {}, folders, f"{path}: {file.name} names {name!r}")
            if named is None:
                raise ValueError(f"{path}: {file.name} names {name!r}: a file a mesh names is relative to the mesh")
            pending.append(named)


def check_references(path: Path, references: Sequence[str], packages: dict[str, Path],
                     base: Path | None = None) -> list[Path]:
    """The files ``references`` name (relative to the folder of ``base``, default ``path``, an SDFormat or MJCF file
    or one it includes, or ``package://`` of one of ``packages``), resolved; ``ValueError`` naming the file unless
    each, and every file those name, lies inside the folder of ``path`` or the packages' (the rules of
    :func:`check_meshes`), and exists."""
    folders = [path.resolve().parent] + [folder.resolve() for folder in packages.values()]
    base = path if base is None else base
    out = []
    for reference in references:
        what = f"{base}: {reference!r}"
        file = _reference(reference, base.resolve().parent, packages, folders, what)
        if file is None:
            raise ValueError(f"{what} names a ROS package that is not found: --package-path DIR or ROS_PACKAGE_PATH")
        if not file.is_file():
            raise ValueError(f"{what}: no such file {file}")
        _check_pulled_in(path, file, folders)
        out.append(file)
    return out
