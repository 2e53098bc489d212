"""Motor and gearbox catalogues: CSV files with datasheet units, held as SI arrays.

Motor catalogue columns (``*``: required; one row per motor):

    name*, rated_torque_Nm* (continuous), peak_torque_Nm*, rated_speed_rpm*, max_speed_rpm*,
    rotor_inertia_kgcm2*, mass_kg*, no_load_speed_rpm, stall_torque_Nm

``no_load_speed_rpm`` and ``stall_torque_Nm`` (both or neither) give the voltage-limited line of the
torque–speed envelope, |τ| ≤ T_stall·(1 − |ω|/ω_0); without them the envelope is |τ| ≤ peak up to the maximum
speed. Gearbox catalogue columns (all required):

    name, ratio, efficiency, rated_torque_Nm (output, continuous), peak_torque_Nm (output),
    max_input_speed_rpm, input_inertia_kgcm2, mass_kg

An unknown or missing column, a catalogue without rows, a value that is not a finite number ≥ 0 (> 0 for
torques, speeds and ratios), an efficiency outside (0, 1], a peak below the rated torque or a maximum below the
rated speed: a one-line ``ValueError`` naming the file, row and value.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armlab.files import read_input

__all__ = ["EXAMPLE_GEARBOXES", "EXAMPLE_MOTORS", "GEARBOX_COLUMNS", "MOTOR_COLUMNS", "Gearboxes", "Motors",
           "read_gearboxes", "read_motors"]

RPM = 2 * math.pi / 60  # rad/s per rpm
KGCM2 = 1e-4  # kg·m² per kg·cm²

#: Motor columns: name → (required, SI factor, must be > 0).
MOTOR_COLUMNS = {
    "rated_torque_Nm": (True, 1.0, True), "peak_torque_Nm": (True, 1.0, True),
    "rated_speed_rpm": (True, RPM, True), "max_speed_rpm": (True, RPM, True),
    "rotor_inertia_kgcm2": (True, KGCM2, True), "mass_kg": (True, 1.0, False),
    "no_load_speed_rpm": (False, RPM, True), "stall_torque_Nm": (False, 1.0, True),
}
#: Gearbox columns, as :data:`MOTOR_COLUMNS`.
GEARBOX_COLUMNS = {
    "ratio": (True, 1.0, True), "efficiency": (True, 1.0, True),
    "rated_torque_Nm": (True, 1.0, True), "peak_torque_Nm": (True, 1.0, True),
    "max_input_speed_rpm": (True, RPM, True), "input_inertia_kgcm2": (True, KGCM2, False),
    "mass_kg": (True, 1.0, False),
}


def _examples() -> Path:
    return Path(str(files("armlab.scripts.examples"))) / "catalogues"


#: The example catalogues shipped with armlab (illustrative values of the kind datasheets give, no vendor's).
EXAMPLE_MOTORS = "motors.csv"
EXAMPLE_GEARBOXES = "gearboxes.csv"


@dataclass(frozen=True)
class Motors:
    """A motor catalogue, SI, each array ``(M,)``: torques N·m, speeds rad/s, rotor inertia kg·m², mass kg;
    ``no_load_speed`` and ``stall_torque`` NaN where the catalogue gives no voltage line."""

    name: tuple[str, ...]
    rated_torque: NDArray[np.float64]
    peak_torque: NDArray[np.float64]
    rated_speed: NDArray[np.float64]
    max_speed: NDArray[np.float64]
    rotor_inertia: NDArray[np.float64]
    mass: NDArray[np.float64]
    no_load_speed: NDArray[np.float64]
    stall_torque: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.name)

    def envelope(self, index: NDArray[np.intp], speed: NDArray[np.float64]) -> NDArray[np.float64]:
        """The largest |τ| (N·m) motors ``index`` give at motor speeds ``speed`` (rad/s), broadcast together:
        the peak torque, below the voltage line T_stall·(1 − |ω|/ω_0) where there is one (the maximum speed is a
        check of its own)."""
        peak = self.peak_torque[index]
        line = self.stall_torque[index] * (1 - np.abs(speed) / self.no_load_speed[index])
        return np.where(np.isnan(line), peak, np.minimum(peak, np.maximum(line, 0.0)))


@dataclass(frozen=True)
class Gearboxes:
    """A gearbox catalogue, SI, each array ``(B,)``: ratio G (motor speed / output speed), efficiency η, output
    torques N·m, maximum input speed rad/s, inertia at the input kg·m², mass kg."""

    name: tuple[str, ...]
    ratio: NDArray[np.float64]
    efficiency: NDArray[np.float64]
    rated_torque: NDArray[np.float64]
    peak_torque: NDArray[np.float64]
    max_input_speed: NDArray[np.float64]
    input_inertia: NDArray[np.float64]
    mass: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.name)


def _read(path: str | Path, kind: str, columns: dict[str, tuple[bool, float, bool]]) -> dict[str, Any]:
    """The columns of a catalogue CSV in SI (missing optional ones NaN) and its names; checks per the module."""
    path = Path(path)
    where = f"{kind} catalogue {path.name}"
    text = read_input(path, f"--{kind}s {path}").decode("utf-8-sig")
    numbered = [(line, r) for line, r in enumerate(csv.reader(io.StringIO(text)), start=1)
                if any(cell.strip() for cell in r) and not r[0].lstrip().startswith("#")]  # "#": a comment
    if not numbered:
        raise ValueError(f"{where}: empty; expected a header row: name,{','.join(columns)}")
    header = [h.strip() for h in numbered[0][1]]
    allowed = ["name", *columns]
    unknown = [h for h in header if h not in allowed]
    if unknown:
        raise ValueError(f"{where}: unknown column {unknown[0]!r}; allowed: {', '.join(allowed)}")
    missing = [c for c in allowed if c not in header and (c == "name" or columns[c][0])]
    if missing:
        raise ValueError(f"{where}: missing column {missing[0]!r} (required: "
                         f"{', '.join(c for c in allowed if c == 'name' or columns[c][0])})")
    body = numbered[1:]
    if not body:
        raise ValueError(f"{where}: no rows: a catalogue needs at least one {kind}")
    names: list[str] = []
    for line, row in body:
        if len(row) != len(header):
            raise ValueError(f"{where} line {line}: {len(row)} cells; the header has {len(header)}")
        names.append(row[header.index("name")].strip() or f"{kind} {len(names) + 1}")
    out: dict[str, Any] = {"name": names, "line": np.array([line for line, _ in body])}
    for column, (required, factor, positive) in columns.items():
        values = np.full(len(body), np.nan)
        if column in header:
            j = header.index(column)
            for r, (line, row) in enumerate(body):
                cell = row[j].strip()
                if not cell and not required:
                    continue  # an optional value left out
                try:
                    value = float(cell)
                except ValueError:
                    value = math.nan
                if not math.isfinite(value) or value < 0 or (positive and value == 0):
                    allowed_text = "a finite number > 0" if positive else "a finite number ≥ 0"
                    raise ValueError(f"{where} line {line} ({names[r]}): {column} = {cell!r} is not allowed: "
                                     f"{allowed_text}")
                values[r] = value * factor
        out[column] = values
    return out


def _check_pair(where: str, c: dict[str, Any], low: str, high: str, what: str) -> None:
    """``ValueError`` for the first row whose column ``high`` is below its column ``low`` (``what``: "torque")."""
    unit, scale = ("rpm", 1 / RPM) if low.endswith("rpm") else ("N·m", 1.0)
    bad = np.asarray(c[high]) < np.asarray(c[low])  # not a bound: a catalogue's own numbers, as given
    if bad.any():
        k = int(np.argmax(bad))
        top, rated = np.asarray(c[high])[k] * scale, np.asarray(c[low])[k] * scale
        raise ValueError(f"{where} line {c['line'][k]} ({c['name'][k]}): {high} = {top:g} {unit} is below the rated "
                         f"{what} {rated:g} {unit}: it is at least the rated {what}")


def read_motors(path: str | Path | None = None) -> Motors:
    """A motor catalogue (see the module docstring); ``None``: the example :data:`EXAMPLE_MOTORS`."""
    path = _examples() / EXAMPLE_MOTORS if path is None else Path(path)
    c = _read(path, "motor", MOTOR_COLUMNS)
    where = f"motor catalogue {path.name}"
    names = list(c["name"])
    _check_pair(where, c, "rated_torque_Nm", "peak_torque_Nm", "torque")
    _check_pair(where, c, "rated_speed_rpm", "max_speed_rpm", "speed")
    line = np.isnan(c["no_load_speed_rpm"]), np.isnan(c["stall_torque_Nm"])
    if np.any(line[0] != line[1]):
        k = int(np.argmax(line[0] != line[1]))
        raise ValueError(f"{where} line {c['line'][k]} ({names[k]}): give no_load_speed_rpm and stall_torque_Nm "
                         "together (the voltage line) or neither")
    return Motors(tuple(names), c["rated_torque_Nm"], c["peak_torque_Nm"], c["rated_speed_rpm"], c["max_speed_rpm"],
                  c["rotor_inertia_kgcm2"], c["mass_kg"], c["no_load_speed_rpm"], c["stall_torque_Nm"])


def read_gearboxes(path: str | Path | None = None) -> Gearboxes:
    """A gearbox catalogue (see the module docstring); ``None``: the example :data:`EXAMPLE_GEARBOXES`."""
    path = _examples() / EXAMPLE_GEARBOXES if path is None else Path(path)
    c = _read(path, "gearbox", GEARBOX_COLUMNS)
    where = f"gearbox catalogue {path.name}"
    names = list(c["name"])
    eta = c["efficiency"]
    if np.any(eta > 1):
        k = int(np.argmax(eta > 1))
        raise ValueError(f"{where} line {c['line'][k]} ({names[k]}): efficiency = {eta[k]:g} is not allowed: "
                         "a number in (0, 1]")
    _check_pair(where, c, "rated_torque_Nm", "peak_torque_Nm", "torque")
    return Gearboxes(tuple(names), c["ratio"], eta, c["rated_torque_Nm"], c["peak_torque_Nm"],
                     c["max_input_speed_rpm"], c["input_inertia_kgcm2"], c["mass_kg"])
