"""Mesh files of a user's URDF confined to its folder and its ROS package.

Replaying someone else's URDF must not embed a file from elsewhere: every ``<mesh filename=…>``
(relative to the URDF's folder, or ``package://NAME/…`` of a package the URDF declares), and every
file a mesh names in turn (a glTF's buffers and images, an OBJ's material libraries, an MTL's
texture maps), must lie inside the URDF's folder or its package's folder once symlinks and ``..``
are resolved; absolute paths and URLs are refused.
"""

from __future__ import annotations

import json
import struct
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from urllib.parse import unquote

__all__ = ["check_meshes"]


def _inside(path: Path, folders: Sequence[Path], what: str) -> Path:
    """``path`` with symlinks and ``..`` resolved, if it lies inside one of ``folders``; else an error."""
    real = path.resolve()
    if not any(real.is_relative_to(folder) for folder in folders):
        shown = str(real) if path.is_symlink() or ".." in path.parts else str(path)
        raise ValueError(f"{what}: {shown} lies outside the URDF's folder and its ROS package "
                         f"({', '.join(map(str, folders))}): armlab reads no files from elsewhere")
    return real


def _reference(reference: str, base: Path, packages: dict[str, Path], folders: Sequence[Path], what: str) -> Path:
    """A file named by a URDF mesh (``package://`` or relative to ``base``), checked to lie inside ``folders``."""
    if reference.startswith("package://"):
        package, _, rest = reference[len("package://"):].partition("/")
        if package not in packages:
            raise ValueError(f"{what}: {reference!r} names package {package!r}, but the URDF's folder and the two "
                             f"above it declare {', '.join(map(repr, packages)) or 'no package (package.xml)'}")
        return _inside(packages[package].parent / rest, folders, what)
    if "://" in reference or reference.startswith(("/", "\\")) or Path(reference).is_absolute():
        raise ValueError(f"{what}: {reference!r} is an absolute path or URL: name files relative to the URDF's "
                         "folder or as package://NAME/… of its ROS package")
    return _inside(base / reference, folders, what)


def _pulled_in(mesh: Path) -> list[str]:
    """The files a mesh file names: a glTF's buffer and image URIs, an OBJ's material libraries, an MTL's maps."""
    suffix = mesh.suffix.lower()
    if not mesh.is_file() or suffix not in (".gltf", ".glb", ".obj", ".mtl"):
        return []
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


def check_meshes(path: Path, root: ET.Element, packages: dict[str, Path]) -> None:
    """``ValueError`` naming the file unless every mesh of the URDF ``path`` (``root`` its parsed XML), and
    every file those meshes name, lies inside the URDF's folder or its declared ROS ``packages``
    (``{name: package.xml}``, :func:`armlab.models.read_urdf.package_roots`); no absolute paths, URLs, ``..``
    or symlinks leading elsewhere: replaying someone else's URDF must not embed a file from elsewhere."""
    folders = [path.resolve().parent] + [xml.parent.resolve() for xml in packages.values()]
    for mesh in root.iter("mesh"):
        what = f"{path}: mesh {mesh.get('filename')!r}"
        pending = [_reference(mesh.get("filename") or "", path.resolve().parent, packages, folders, what)]
        seen: set[Path] = set()
        while pending:
            file = pending.pop()
            if file in seen:
                continue
            seen.add(file)
            pending.extend(_reference(name, file.parent, {}, folders, f"{path}: {file.name} names {name!r}")
                           for name in _pulled_in(file))
