"""Motor and gearbox catalogues: CSV files with datasheet units, held as SI arrays.

Motor catalogue columns (``*``: required; one row per motor; every other column optional, and a check whose
columns a catalogue (or a row: an empty cell) leaves out is reported "not checked (no column X)", never passed):

    name*, rated_torque_Nm* (continuous, S1), peak_torque_Nm*, rated_speed_rpm*, max_speed_rpm*,
    rotor_inertia_kgcm2*, mass_kg*, no_load_speed_rpm, stall_torque_Nm

``no_load_speed_rpm`` and ``stall_torque_Nm`` (both or neither) give the voltage-limited line of the
torque–speed envelope as the datasheet draws it, |τ| ≤ T_stall·(1 − |ω|/ω_0); without them the envelope is
|τ| ≤ peak up to the maximum speed. The motor's electrics, winding, brake and drive (:data:`MOTOR_COLUMNS`;
a three-phase permanent-magnet servo motor, line-to-line values as its datasheet gives them):

* ``torque_constant_Nm_A`` K_t (N·m per A RMS), ``back_emf_V_krpm`` K_e (V RMS line to line per 1000 rpm),
  ``resistance_ohm`` R (line to line, at 25 °C), ``inductance_mH`` L (line to line), ``pole_pairs`` p;
* the winding → housing → ambient thermal model: ``thermal_resistance_winding_K_W`` R_th1 (winding to
  housing), ``thermal_resistance_housing_K_W`` R_th2 (housing to ambient, mounted as the datasheet states),
  ``thermal_time_constant_winding_s`` τ_w, ``thermal_time_constant_motor_s`` τ_m (so C_w = τ_w/R_th1 and
  C_h = τ_m/R_th2) and ``max_winding_temperature_C`` (the insulation's limit);
* ``brake_holding_torque_Nm`` (the holding brake's static torque), ``max_inertia_ratio`` (the load inertia at
  the motor over the rotor's that the maker allows; default 10);
* the motor's drive (amplifier): ``drive_continuous_current_A``, ``drive_peak_current_A`` (RMS),
  ``drive_peak_time_s`` (how long it gives the peak current from cold: its I²t), ``bus_voltage_V`` (the DC link
  at its nominal supply), ``bus_max_voltage_V`` (where its braking chopper switches on), ``bus_capacitance_uF``
  (the DC link's capacitors), ``braking_resistor_W`` and ``braking_resistor_ohm`` (its braking resistor's
  continuous power and resistance; its peak power is V_max²/R).

Gearbox catalogue columns (``*``: required):

    name*, ratio*, efficiency*, rated_torque_Nm* (output, continuous: T_N), peak_torque_Nm* (output),
    max_input_speed_rpm*, input_inertia_kgcm2*, mass_kg*, life_basis, rated_life_h, rated_input_speed_rpm

``life_basis`` says how its life is rated: ``strain-wave`` (Harmonic Drive's L50 = L_n·(n_N/n_av)·(T_N/T_av)³
with ``rated_life_h`` L_n and ``rated_input_speed_rpm`` n_N) or ``rating`` (a planetary gearbox's catalogue
rating: ``rated_life_h`` at T_N and n_N).

An unknown or missing column, a catalogue without rows, a value that is not a finite number ≥ 0 (> 0 for
torques, speeds, ratios and the electrical, thermal and drive values), an efficiency outside (0, 1], a peak below
the rated torque (or current), a maximum below the rated speed (or bus voltage), a ``life_basis`` other than
those two: a one-line ``ValueError`` naming the file, row and value. Where real values come from (the datasheet
field names): ``scripts/examples/catalogues/README.md``.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass, field, fields
from importlib.resources import files
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from armlab.files import check_name, csv_rows, read_input
from armlab.limits import check_range
from armlab.values import decimal, shown

__all__ = ["EXAMPLE_GEARBOXES", "EXAMPLE_MOTORS", "GEARBOX_COLUMNS", "LIFE_BASES", "MOTOR_COLUMNS", "Gearboxes",
           "Motors", "read_gearboxes", "read_motors"]

RPM = 2 * math.pi / 60  # rad/s per rpm
KGCM2 = 1e-4  # kg·m² per kg·cm²
V_KRPM = 1 / (1000 * RPM)  # V·s/rad per V/krpm

#: Motor columns: name → (required, SI factor, must be > 0, the :class:`Motors` field).
MOTOR_COLUMNS = {
    "rated_torque_Nm": (True, 1.0, True, "rated_torque"), "peak_torque_Nm": (True, 1.0, True, "peak_torque"),
    "rated_speed_rpm": (True, RPM, True, "rated_speed"), "max_speed_rpm": (True, RPM, True, "max_speed"),
    "rotor_inertia_kgcm2": (True, KGCM2, True, "rotor_inertia"), "mass_kg": (True, 1.0, False, "mass"),
    "no_load_speed_rpm": (False, RPM, True, "no_load_speed"), "stall_torque_Nm": (False, 1.0, True, "stall_torque"),
    "torque_constant_Nm_A": (False, 1.0, True, "torque_constant"),
    "back_emf_V_krpm": (False, V_KRPM, True, "back_emf"),
    "resistance_ohm": (False, 1.0, True, "resistance"), "inductance_mH": (False, 1e-3, True, "inductance"),
    "pole_pairs": (False, 1.0, True, "pole_pairs"),
    "thermal_resistance_winding_K_W": (False, 1.0, True, "thermal_resistance_winding"),
    "thermal_resistance_housing_K_W": (False, 1.0, True, "thermal_resistance_housing"),
    "thermal_time_constant_winding_s": (False, 1.0, True, "time_constant_winding"),
    "thermal_time_constant_motor_s": (False, 1.0, True, "time_constant_motor"),
    "max_winding_temperature_C": (False, 1.0, True, "max_winding_temperature"),
    "brake_holding_torque_Nm": (False, 1.0, True, "brake_torque"),
    "max_inertia_ratio": (False, 1.0, True, "max_inertia_ratio"),
    "drive_continuous_current_A": (False, 1.0, True, "drive_continuous_current"),
    "drive_peak_current_A": (False, 1.0, True, "drive_peak_current"),
    "drive_peak_time_s": (False, 1.0, True, "drive_peak_time"),
    "bus_voltage_V": (False, 1.0, True, "bus_voltage"), "bus_max_voltage_V": (False, 1.0, True, "bus_max_voltage"),
    "bus_capacitance_uF": (False, 1e-6, True, "bus_capacitance"),
    "braking_resistor_W": (False, 1.0, True, "braking_resistor_power"),
    "braking_resistor_ohm": (False, 1.0, True, "braking_resistance"),
}
#: Gearbox columns, as :data:`MOTOR_COLUMNS` (``life_basis`` is text: one of :data:`LIFE_BASES`).
GEARBOX_COLUMNS = {
    "ratio": (True, 1.0, True, "ratio"), "efficiency": (True, 1.0, True, "efficiency"),
    "rated_torque_Nm": (True, 1.0, True, "rated_torque"), "peak_torque_Nm": (True, 1.0, True, "peak_torque"),
    "max_input_speed_rpm": (True, RPM, True, "max_input_speed"),
    "input_inertia_kgcm2": (True, KGCM2, False, "input_inertia"), "mass_kg": (True, 1.0, False, "mass"),
    "life_basis": (False, 1.0, True, "life_basis"), "rated_life_h": (False, 1.0, True, "rated_life"),
    "rated_input_speed_rpm": (False, RPM, True, "rated_input_speed"),
}
#: A gearbox's ``life_basis``: its code in :class:`Gearboxes` (NaN: none given).
LIFE_BASES = {"strain-wave": 1.0, "rating": 2.0}
_TEXT = ("life_basis",)


class _Optional:
    """What the catalogues share: an optional column's field left empty (the default) becomes NaN, one per row;
    each field's catalogue column (:meth:`column`, from the class's ``_COLUMNS``)."""

    name: tuple[str, ...]
    _COLUMNS: ClassVar[dict[str, tuple[bool, float, bool, str]]]

    @classmethod
    def column(cls, name: str) -> str:
        """The catalogue column of the field ``name`` (``"torque_constant"`` → ``"torque_constant_Nm_A"``)."""
        return next(c for c, spec in cls._COLUMNS.items() if spec[3] == name)

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]  # every subclass is a dataclass
            value = getattr(self, f.name)
            if isinstance(value, np.ndarray) and value.size == 0 and len(self.name):
                object.__setattr__(self, f.name, np.full(len(self.name), np.nan))

    def __len__(self) -> int:
        return len(self.name)


def _examples() -> Path:
    return Path(str(files("armlab.scripts.examples"))) / "catalogues"


#: The example catalogues shipped with armlab (illustrative values of the kind datasheets give, no vendor's).
EXAMPLE_MOTORS = "motors.csv"
EXAMPLE_GEARBOXES = "gearboxes.csv"


def _none() -> NDArray[np.float64]:
    return np.empty(0)


@dataclass(frozen=True)
class Motors(_Optional):
    """A motor catalogue, SI, each array ``(M,)`` (module docstring, :data:`MOTOR_COLUMNS`): torques N·m, speeds
    rad/s, rotor inertia kg·m², mass kg; K_t N·m/A, K_e V·s/rad (RMS line to line), R Ω (line to line, 25 °C), L H,
    thermal resistances K/W, time constants s, the winding's limit °C, currents A (RMS), voltages V, capacitance F,
    powers W. An optional value not given is NaN (an optional field left out: NaN for every motor)."""

    name: tuple[str, ...]
    rated_torque: NDArray[np.float64]
    peak_torque: NDArray[np.float64]
    rated_speed: NDArray[np.float64]
    max_speed: NDArray[np.float64]
    rotor_inertia: NDArray[np.float64]
    mass: NDArray[np.float64]
    no_load_speed: NDArray[np.float64] = field(default_factory=_none)
    stall_torque: NDArray[np.float64] = field(default_factory=_none)
    torque_constant: NDArray[np.float64] = field(default_factory=_none)
    back_emf: NDArray[np.float64] = field(default_factory=_none)
    resistance: NDArray[np.float64] = field(default_factory=_none)
    inductance: NDArray[np.float64] = field(default_factory=_none)
    pole_pairs: NDArray[np.float64] = field(default_factory=_none)
    thermal_resistance_winding: NDArray[np.float64] = field(default_factory=_none)
    thermal_resistance_housing: NDArray[np.float64] = field(default_factory=_none)
    time_constant_winding: NDArray[np.float64] = field(default_factory=_none)
    time_constant_motor: NDArray[np.float64] = field(default_factory=_none)
    max_winding_temperature: NDArray[np.float64] = field(default_factory=_none)
    brake_torque: NDArray[np.float64] = field(default_factory=_none)
    max_inertia_ratio: NDArray[np.float64] = field(default_factory=_none)
    drive_continuous_current: NDArray[np.float64] = field(default_factory=_none)
    drive_peak_current: NDArray[np.float64] = field(default_factory=_none)
    drive_peak_time: NDArray[np.float64] = field(default_factory=_none)
    bus_voltage: NDArray[np.float64] = field(default_factory=_none)
    bus_max_voltage: NDArray[np.float64] = field(default_factory=_none)
    bus_capacitance: NDArray[np.float64] = field(default_factory=_none)
    braking_resistor_power: NDArray[np.float64] = field(default_factory=_none)
    braking_resistance: NDArray[np.float64] = field(default_factory=_none)

    _COLUMNS: ClassVar[dict[str, tuple[bool, float, bool, str]]] = MOTOR_COLUMNS

    def envelope(self, index: NDArray[np.intp], speed: NDArray[np.float64]) -> NDArray[np.float64]:
        """The largest |τ| (N·m) motors ``index`` give at motor speeds ``speed`` (rad/s), broadcast together:
        the peak torque, below the voltage line T_stall·(1 − |ω|/ω_0) where there is one (the maximum speed is a
        check of its own)."""
        peak = self.peak_torque[index]
        line = self.stall_torque[index] * (1 - np.abs(speed) / self.no_load_speed[index])
        return np.where(np.isnan(line), peak, np.minimum(peak, np.maximum(line, 0.0)))


@dataclass(frozen=True)
class Gearboxes(_Optional):
    """A gearbox catalogue, SI, each array ``(B,)``: ratio G (motor speed / output speed), efficiency η, output
    torques N·m, maximum input speed rad/s, inertia at the input kg·m², mass kg; ``life_basis`` a code of
    :data:`LIFE_BASES`, ``rated_life`` L_n (h), ``rated_input_speed`` n_N (rad/s); NaN where not given."""

    name: tuple[str, ...]
    ratio: NDArray[np.float64]
    efficiency: NDArray[np.float64]
    rated_torque: NDArray[np.float64]
    peak_torque: NDArray[np.float64]
    max_input_speed: NDArray[np.float64]
    input_inertia: NDArray[np.float64]
    mass: NDArray[np.float64]
    life_basis: NDArray[np.float64] = field(default_factory=_none)
    rated_life: NDArray[np.float64] = field(default_factory=_none)
    rated_input_speed: NDArray[np.float64] = field(default_factory=_none)
    _COLUMNS: ClassVar[dict[str, tuple[bool, float, bool, str]]] = GEARBOX_COLUMNS


def _read(path: str | Path, kind: str, columns: dict[str, tuple[bool, float, bool, str]]) -> dict[str, Any]:
    """The columns of a catalogue CSV in SI (missing optional ones NaN) and its names; checks per the module."""
    path = Path(path)
    where = f"{kind} catalogue {path.name}"
    text = read_input(path, f"--{kind}s {path}").decode("utf-8-sig")
    numbered = [(line, r) for line, r in enumerate(csv_rows(io.StringIO(text), where), start=1)
                if any(cell.strip() for cell in r) and not r[0].lstrip().startswith("#")]  # "#": a comment
    if not numbered:
        raise ValueError(f"{where}: empty; expected a header row: name,{','.join(columns)}")
    header = [h.strip() for h in numbered[0][1]]
    allowed = ["name", *columns]
    twice = [h for k, h in enumerate(header) if h in header[:k]]
    if twice:
        raise ValueError(f"{where}: column {shown(twice[0])} is given twice; give each column once")
    unknown = [h for h in header if h not in allowed]
    if unknown:
        raise ValueError(f"{where}: unknown column {shown(unknown[0])}; allowed: {', '.join(allowed)}")
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
        names.append(check_name(row[header.index("name")].strip(), f"{where} line {line}: name")
                     or f"{kind} {len(names) + 1}")
    out: dict[str, Any] = {"name": names, "line": np.array([line for line, _ in body])}
    for column, (required, factor, positive, _) in columns.items():
        values = np.full(len(body), np.nan)
        if column in header:
            j = header.index(column)
            for r, (line, row) in enumerate(body):
                cell = row[j].strip()
                if not cell and not required:
                    continue  # an optional value left out
                if column in _TEXT:
                    if cell not in LIFE_BASES:
                        raise ValueError(f"{where} line {line} ({names[r]}): {column} = {shown(cell)} is not "
                                         f"allowed: one of {', '.join(LIFE_BASES)} (or empty)")
                    values[r] = LIFE_BASES[cell]
                    continue
                try:
                    value = decimal(cell)  # a plain decimal, as every number read from text
                except ValueError:
                    value = math.nan
                if not math.isfinite(value) or value < 0 or (positive and value == 0):
                    allowed_text = "a finite number > 0" if positive else "a finite number ≥ 0"
                    raise ValueError(f"{where} line {line} ({names[r]}): {column} = {shown(cell)} is not allowed: "
                                     f"{allowed_text}")
                if value > 0:  # zero: a column that may be 0 (mass, input inertia), not a datasheet number
                    check_range(value, f"{where} line {line} ({names[r]}): {column}", key="catalogue")
                values[r] = value * factor
        out[column] = values
    return out


def _check_pair(where: str, c: dict[str, Any], low: str, high: str, what: str) -> None:
    """``ValueError`` for the first row whose column ``high`` is below its column ``low`` (``what``: "torque"); rows
    without both values pass."""
    unit, scale = {"rpm": ("rpm", 1 / RPM), "Nm": ("N·m", 1.0), "A": ("A", 1.0), "V": ("V", 1.0)}[low.rsplit("_", 1)[1]]
    bad = np.asarray(c[high]) < np.asarray(c[low])  # not a bound: a catalogue's own numbers, as given (NaN: False)
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
    _check_pair(where, c, "drive_continuous_current_A", "drive_peak_current_A", "current")
    _check_pair(where, c, "bus_voltage_V", "bus_max_voltage_V", "bus voltage")
    line = np.isnan(c["no_load_speed_rpm"]), np.isnan(c["stall_torque_Nm"])
    if np.any(line[0] != line[1]):
        k = int(np.argmax(line[0] != line[1]))
        raise ValueError(f"{where} line {c['line'][k]} ({names[k]}): give no_load_speed_rpm and stall_torque_Nm "
                         "together (the voltage line) or neither")
    return Motors(tuple(names), **{spec[3]: c[column] for column, spec in MOTOR_COLUMNS.items()})


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
    return Gearboxes(tuple(names), **{spec[3]: c[column] for column, spec in GEARBOX_COLUMNS.items()})
