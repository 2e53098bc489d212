"""Mesh files of a user's URDF confined to its folder and its ROS packages; the ones Drake cannot use left out.

Replaying someone else's URDF must not embed a file from elsewhere: every ``<mesh filename=…>``
(relative to the URDF's folder, or ``package://NAME/…`` of a package found for the URDF:
:func:`armlab.models.read_urdf.package_roots`), and every file a mesh names in turn (a glTF's buffers
and images, an OBJ's material libraries, an MTL's texture maps, a COLLADA file's images), must lie
inside the URDF's folder or a package's folder once symlinks and ``..`` are resolved; absolute paths
and URLs are refused.

A mesh that cannot be found (its file missing, its package not found) is a :class:`MeshWarning` and its
``<visual>`` or ``<collision>`` is left out: kinematics and dynamics do not need it. A collision mesh of a
kind Drake cannot make a convex hull of (:data:`COLLISION_SUFFIXES`: ROS's ``.stl`` and ``.dae``) is left
out too, with one warning, before any work (Drake would fail on it only when the geometry is first used).
"""

from __future__ import annotations

import json
import re
import struct
import warnings
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote

__all__ = ["COLLISION_SUFFIXES", "MeshWarning", "Meshes", "check_meshes", "check_references", "without_doctype"]

#: Mesh files Drake makes collision geometry of (a convex hull): others are left out of ``<collision>``.
COLLISION_SUFFIXES = (".obj", ".vtk", ".gltf")


class MeshWarning(UserWarning):
    """A mesh of a user's URDF that armlab leaves out (missing, or of a kind Drake cannot use there)."""


@dataclass(frozen=True)
class Meshes:
    """What :func:`check_meshes` found: each usable ``<mesh>`` element's file, and the elements left out.

    ``files``: mesh element → its file (resolved, inside the allowed folders); ``dropped``: the ``<visual>`` or
    ``<collision>`` elements whose mesh is missing or unusable (a warning said which).
    """

    files: dict[ET.Element, Path]
    dropped: set[ET.Element]


def without_doctype(text: str, what: str) -> str:
    """``text`` unless it defines a document type or entities (``<!DOCTYPE``, ``<!ENTITY``: entity expansion)
    outside its comments: then a ``ValueError`` naming ``what``."""
    if re.search(r"<!(DOCTYPE|ENTITY)", re.sub(r"<!--.*?-->", "", text, flags=re.DOTALL)):
        raise ValueError(f"{what}: XML document-type or entity definitions (<!DOCTYPE, <!ENTITY) are not allowed")
    return text


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
    ``None`` for a ``package://`` path whose package is not among ``packages`` (``{name: package.xml}``)."""
    if reference.startswith("package://"):
        package, _, rest = reference[len("package://"):].partition("/")
        if package not in packages:
            return None
        return _inside(packages[package].parent / rest, folders, what)
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
        root = ET.fromstring(without_doctype(mesh.read_text(encoding="utf-8", errors="replace"), str(mesh)))
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
    (``{name: package.xml}``, :func:`armlab.models.read_urdf.package_roots`); no absolute paths, URLs, ``..``
    or symlinks leading elsewhere: replaying someone else's URDF must not embed a file from elsewhere.

    A mesh not found and a collision mesh Drake cannot use are left out, each kind with one
    :class:`MeshWarning` (module docstring)."""
    folders = [path.resolve().parent] + [xml.parent.resolve() for xml in packages.values()]
    files: dict[ET.Element, Path] = {}
    dropped: set[ET.Element] = set()
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
                if role == "collision" and file.suffix.lower() not in COLLISION_SUFFIXES:
                    unusable.append(reference)
                    dropped.add(element)
                    continue
                files[mesh] = file
    if missing:
        warnings.warn(MeshWarning(
            f"{path}: {len(missing)} mesh(es) not found, their visuals and collisions left out (kinematics and "
            f"dynamics do not need them): {_listed(missing)}"
            + ("; a package:// mesh needs its package found: --package-path DIR or ROS_PACKAGE_PATH" if unfound
               else "")), stacklevel=3)
    if unusable:
        warnings.warn(MeshWarning(
            f"{path}: {len(unusable)} collision mesh(es) left out: Drake makes collision geometry only of "
            f"{', '.join(COLLISION_SUFFIXES)} files: {_listed(unusable)}"), stacklevel=3)
    return Meshes(files, dropped)


def _listed(references: list[str], most: int = 3) -> str:
    """The first ``most`` distinct ``references``, and how many more."""
    distinct = list(dict.fromkeys(references))
    more = f" and {len(distinct) - most} more" if len(distinct) > most else ""
    return ", ".join(map(repr, distinct[:most])) + more


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


def check_references(path: Path, references: Sequence[str], packages: dict[str, Path]) -> None:
    """``ValueError`` naming the file unless every file ``references`` name (relative to the folder of ``path``, an
    SDFormat or MJCF file, or ``package://`` of one of ``packages``), and every file those name, lies inside that
    folder or the packages' (the rules of :func:`check_meshes`), and exists."""
    folders = [path.resolve().parent] + [xml.parent.resolve() for xml in packages.values()]
    for reference in references:
        what = f"{path}: {reference!r}"
        file = _reference(reference, path.resolve().parent, packages, folders, what)
        if file is None:
            raise ValueError(f"{what} names a ROS package that is not found: --package-path DIR or ROS_PACKAGE_PATH")
        if not file.is_file():
            raise ValueError(f"{what}: no such file {file}")
        _check_pulled_in(path, file, folders)
