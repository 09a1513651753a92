"""The measurement file of a calibration: TOML naming CSV files, and the parameters to fit.

Schema (paths relative to the TOML file; ``docs/calibration.md`` has an example)::

    name = "prototype 3, bench of 2024-05-02"    # free text

    [free]                  # free tip amplitudes, no preload (the paper's Figs. 5-6)
    file = "free.csv"       #   columns voltage_V, frequency_Hz (or the key below),
                            #   tangential_um and/or normal_um
    frequency_Hz = 40e3     #   the drive frequency when the CSV has no frequency column
    sigma_relative = 0.03   #   standard deviation as a share of each value, and/or
    sigma = { tangential_um = 0.02, normal_um = 0.02 }   # absolute, in the column's unit
                            #   (added in quadrature), or per row: a column
                            #   sigma_tangential_um in the CSV

    [admittance]            # the free stator's admittance at the drive electrodes
    file = "admittance.csv" #   frequency_Hz and conductance_S, susceptance_S
                            #   (or abs_Y_S, phase_deg)

    [speed]                 # steady slider speed
    file = "speed.csv"      #   voltage_V, preload_N, load_N (optional, 0), velocity_m_s,
    frequency_Hz = 40e3     #   frequency_Hz (a column or this key)

    [power]                 # electrical input power at no load (the steady engine's)
    file = "power.csv"      #   voltage_V, preload_N, input_power_W, frequency_Hz

    [parameters]            # what to fit: start value and bounds, SI units
    C_l = { start = 150, min = 50, max = 500 }
    a_mu = { start = 0.1, min = 0.0, max = 0.3 }

Each column's unit is its name's tail after the quantity (``velocity_mm_s``,
``tangential_nm``, ``frequency_kHz``); :data:`UNITS` lists them. A table may also be an
array of tables (``[[speed]]``), one per CSV.
"""

from __future__ import annotations

import csv
import io
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from calibration.parameters import EXCLUSIVE, PARAMETERS, FitParameter

LENGTH = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "nm": 1e-9}
FORCE = {"N": 1.0, "mN": 1e-3}
SIEMENS = {"S": 1.0, "mS": 1e-3, "uS": 1e-6}
UNITS: dict[str, dict[str, float]] = {
    "voltage": {"V": 1.0, "kV": 1e3},
    "frequency": {"Hz": 1.0, "kHz": 1e3},
    "tangential": LENGTH, "normal": LENGTH,
    "preload": FORCE, "load": FORCE,
    "velocity": {"m_s": 1.0, "mm_s": 1e-3, "um_s": 1e-6},
    "conductance": SIEMENS, "susceptance": SIEMENS, "abs_Y": SIEMENS,
    "phase": {"deg": math.pi / 180.0, "rad": 1.0},
    "input_power": {"W": 1.0, "mW": 1e-3},
}
"""Quantity -> {unit as written in a column name: SI value of one unit}."""

KINDS: dict[str, dict[str, tuple[str, ...]]] = {
    "free": {"inputs": ("voltage", "frequency"), "optional": ("frequency",),
             "measured": ("tangential", "normal")},
    "admittance": {"inputs": ("frequency",), "optional": (),
                   "measured": ("conductance", "susceptance", "abs_Y", "phase")},
    "speed": {"inputs": ("voltage", "preload", "load", "frequency"),
              "optional": ("load", "frequency"), "measured": ("velocity",)},
    "power": {"inputs": ("voltage", "preload", "load", "frequency"),
              "optional": ("load", "frequency"), "measured": ("input_power",)},
}
"""Measurement kind -> its input columns (``optional``: may be missing) and measured ones."""
STEADY_KINDS = ("speed", "power")
"""Kinds the steady engine predicts (a solve per row and model evaluation)."""

TABLE_KEYS = ("file", "frequency_Hz", "sigma", "sigma_relative")
MAX_CSV_BYTES = 10_000_000
"""Largest measurement CSV read (bytes)."""
MAX_ROWS = 10_000
"""Most rows of one CSV: every speed row is a steady-engine solve per model evaluation."""


class MeasurementError(ValueError):
    """A measurement file, or a CSV it names, that cannot be used; the message names the file
    and its key or column."""


@dataclass(frozen=True)
class DataSet:
    """One CSV of measurements, in SI units.

    Attributes
    ----------
    kind : {"free", "admittance", "speed", "power"}
    path : Path
        The CSV file.
    inputs : dict of str to ndarray
        Input quantity -> values (SI): ``voltage`` (V), ``frequency`` (Hz), ``preload``,
        ``load`` (N).
    observed : dict of str to ndarray
        Measured quantity -> values (SI; NaN where a row leaves it empty).
    sigma : dict of str to ndarray
        Measured quantity -> standard deviation of each value (SI).
    columns : dict of str to str
        Quantity -> the column name it was read from (for plots and messages).
    """

    kind: str
    path: Path
    inputs: dict[str, np.ndarray]
    observed: dict[str, np.ndarray]
    sigma: dict[str, np.ndarray]
    columns: dict[str, str] = field(default_factory=dict)

    @property
    def points(self) -> int:
        """Number of measured values (the residuals this set gives)."""
        return int(sum(np.count_nonzero(np.isfinite(v)) for v in self.observed.values()))


@dataclass(frozen=True)
class Measurements:
    """A loaded measurement file.

    Attributes
    ----------
    path : Path
    name : str
    sets : tuple of DataSet
    parameters : tuple of FitParameter
        In the file's order.
    """

    path: Path
    name: str
    sets: tuple[DataSet, ...]
    parameters: tuple[FitParameter, ...]


def _number(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(
            value):
        raise MeasurementError(f"{where} must be a finite number, got {value!r}")
    return float(value)


def split_column(name: str) -> tuple[str, str] | None:
    """``(quantity, unit)`` of a column name (``velocity_mm_s`` -> ``velocity``, ``mm_s``);
    None when no known quantity starts it."""
    for quantity in sorted(UNITS, key=len, reverse=True):
        if name.startswith(quantity + "_"):
            return quantity, name[len(quantity) + 1:]
    return None


def _read_csv(path: Path, where: str) -> tuple[list[str], list[list[str]]]:
    """Header and rows of a CSV (lines starting with ``#`` are comments)."""
    from fem.small_file import FileTooLarge, NotRegularFile, read_small_text

    if path.is_dir():
        raise MeasurementError(f"{where} {path} is a folder; name a CSV file")
    if not path.exists():
        raise MeasurementError(f"{where}: CSV file not found: {path}")
    try:
        text = read_small_text(path, MAX_CSV_BYTES)
    except NotRegularFile as exc:
        raise MeasurementError(f"{where} {path} is {exc.what}, not a CSV file") from None
    except FileTooLarge as exc:
        raise MeasurementError(f"{where} {path} has {exc.size} bytes, above "
                               f"{MAX_CSV_BYTES}") from None
    except UnicodeDecodeError as exc:
        raise MeasurementError(f"{where} {path}: not UTF-8 text ({exc.reason})") from None
    lines = [ln for ln in io.StringIO(text) if ln.strip() and not ln.lstrip().startswith("#")]
    rows = [[c.strip() for c in r] for r in csv.reader(lines)]
    if not rows:
        raise MeasurementError(f"{where} {path} is empty (a header line and rows needed)")
    if len(rows) - 1 > MAX_ROWS:
        raise MeasurementError(f"{where} {path} has {len(rows) - 1} rows, above {MAX_ROWS}")
    return rows[0], rows[1:]


def _columns(kind: str, header: list[str], where: str) -> dict[str, tuple[int, str, float]]:
    """Quantity (``sigma_`` prefixed for per-row deviations) -> (column index, name, SI
    factor) of a CSV header; unknown columns and units are refused, naming them."""
    spec = KINDS[kind]
    allowed = (*spec["inputs"], *spec["measured"])
    out: dict[str, tuple[int, str, float]] = {}
    for i, name in enumerate(header):
        sigma = name.startswith("sigma_")
        parsed = split_column(name[6:] if sigma else name)
        if parsed is None or parsed[0] not in allowed or (sigma and parsed[0] not in
                                                          spec["measured"]):
            cols = ", ".join(f"{q}_<unit>" for q in allowed)
            raise MeasurementError(f"{where}: column {name!r} is not one of {cols} (or "
                                   f"sigma_<measured column>)")
        quantity, unit = parsed
        if unit not in UNITS[quantity]:
            raise MeasurementError(f"{where}: column {name!r} has the unit {unit!r}; "
                                   f"{quantity} takes {', '.join(UNITS[quantity])}")
        key = f"sigma_{quantity}" if sigma else quantity
        if key in out:
            raise MeasurementError(f"{where}: two columns give {key} ({out[key][1]!r}, "
                                   f"{name!r})")
        out[key] = (i, name, UNITS[quantity][unit])
    return out


def _values(rows: list[list[str]], index: int, name: str, where: str,
            empty_ok: bool) -> np.ndarray:
    out = np.empty(len(rows))
    for r, row in enumerate(rows):
        text = row[index] if index < len(row) else ""
        if not text and empty_ok:
            out[r] = np.nan
            continue
        try:
            out[r] = float(text)
        except ValueError:
            out[r] = np.nan
        if not math.isfinite(out[r]):
            raise MeasurementError(f"{where}: row {r + 2} column {name!r} must be a finite "
                                   f"number, got {text!r}")
    return out


def _sigma(table: dict, kind: str, cols: dict, observed: dict[str, np.ndarray],
           rows: list[list[str]], where: str) -> dict[str, np.ndarray]:
    """Standard deviation of each measured value (SI): per-row columns, else the table's
    absolute ``sigma`` and ``sigma_relative`` in quadrature."""
    rel = _number(table["sigma_relative"], f"{where} sigma_relative") \
        if "sigma_relative" in table else 0.0
    if not 0.0 <= rel < 1.0:
        raise MeasurementError(f"{where} sigma_relative must lie in [0, 1), got {rel:g}")
    given = table.get("sigma", {})
    if not isinstance(given, dict):
        raise MeasurementError(f"{where} sigma must be a table of column = standard "
                               f"deviation, e.g. {{ velocity_m_s = 1e-3 }}, got {given!r}")
    absolute: dict[str, float] = {}
    names = {cols[q][1]: q for q in observed}
    for col, value in given.items():
        if col not in names:
            raise MeasurementError(f"{where} sigma names {col!r}, which is not a measured "
                                   f"column of the CSV ({', '.join(names)})")
        v = _number(value, f"{where} sigma.{col}")
        if v < 0:
            raise MeasurementError(f"{where} sigma.{col} must be >= 0, got {v:g}")
        absolute[names[col]] = v * cols[names[col]][2]
    out = {}
    for q, y in observed.items():
        if f"sigma_{q}" in cols:
            i, name, scale = cols[f"sigma_{q}"]
            s = _values(rows, i, name, where, empty_ok=True) * scale
        else:
            s = np.hypot(absolute.get(q, 0.0), rel * np.abs(y))
        bad = np.flatnonzero(np.isfinite(y) & ~(s > 0))
        if bad.size:
            raise MeasurementError(
                f"{where}: row {bad[0] + 2} of {cols[q][1]!r} has no standard deviation > 0; "
                f"give sigma = {{ {cols[q][1]} = ... }}, sigma_relative, or a column "
                f"sigma_{cols[q][1]} (a relative one alone is 0 at a value of 0)")
        out[q] = s
    return out


def _data_set(kind: str, table, base_dir: Path, where: str) -> DataSet:
    """One measurement table and its CSV."""
    if not isinstance(table, dict):
        raise MeasurementError(f"{where} must be a table with file = \"data.csv\"")
    for key in table:
        if key not in TABLE_KEYS:
            raise MeasurementError(f"{where}: unknown key {key!r}; allowed: "
                                   f"{', '.join(TABLE_KEYS)}")
    if not isinstance(table.get("file"), str) or not table["file"].strip():
        raise MeasurementError(f"{where} file must name a CSV file (a string)")
    path = Path(table["file"])
    path = path if path.is_absolute() else base_dir / path
    header, rows = _read_csv(path, f"{where} file")
    src = f"{where} file {path.name}"
    cols = _columns(kind, header, src)
    spec = KINDS[kind]
    inputs: dict[str, np.ndarray] = {}
    for q in spec["inputs"]:
        if q in cols:
            inputs[q] = _values(rows, cols[q][0], cols[q][1], src, False) * cols[q][2]
        elif q == "frequency" and "frequency_Hz" in table:
            f = _number(table["frequency_Hz"], f"{where} frequency_Hz")
            inputs[q] = np.full(len(rows), f)
        elif q == "load":
            inputs[q] = np.zeros(len(rows))
        else:
            extra = " (or the key frequency_Hz)" if q == "frequency" else ""
            raise MeasurementError(f"{src}: missing column {q}_<unit> ({', '.join(UNITS[q])})"
                                   f"{extra}")
    if "frequency_Hz" in table and "frequency" in cols:
        raise MeasurementError(f"{where} frequency_Hz and the column "
                               f"{cols['frequency'][1]!r} both give the frequency; keep one")
    observed = {q: _values(rows, cols[q][0], cols[q][1], src, True) * cols[q][2]
                for q in spec["measured"] if q in cols}
    _check_measured(kind, observed, src)
    for q, lo in (("voltage", 0.0), ("frequency", 0.0), ("preload", 0.0)):
        if q in inputs and not np.all(inputs[q] > lo if q == "frequency" else inputs[q] >= lo):
            raise MeasurementError(f"{src}: {q} must be {'>' if q == 'frequency' else '>='} 0")
    if not rows:
        raise MeasurementError(f"{src} has a header and no rows")
    sigma = _sigma(table, kind, cols, observed, rows, where)
    return DataSet(kind, path, inputs, observed, sigma,
                   {q: name for q, (_, name, _) in cols.items()})


def _check_measured(kind: str, observed: dict[str, np.ndarray], src: str) -> None:
    """The measured columns a kind needs: one amplitude, one speed, an admittance pair."""
    if kind == "admittance":
        pairs = ({"conductance", "susceptance"}, {"abs_Y", "phase"})
        if not any(p <= set(observed) for p in pairs) or len(observed) not in (2, 4):
            raise MeasurementError(f"{src}: give conductance_<unit> and susceptance_<unit>, "
                                   f"or abs_Y_<unit> and phase_<unit>")
    elif not observed:
        need = " and/or ".join(f"{q}_<unit>" for q in KINDS[kind]["measured"])
        raise MeasurementError(f"{src}: missing column {need}")


def _parameters(table, src: str) -> tuple[FitParameter, ...]:
    """The ``[parameters]`` table."""
    if not isinstance(table, dict) or not table:
        raise MeasurementError(f"{src}: [parameters] must name at least one parameter to fit, "
                               f"e.g. C_l = {{ start = 150, min = 50, max = 500 }}; allowed: "
                               f"{', '.join(PARAMETERS)}")
    out = []
    for name, spec in table.items():
        where = f"{src}: [parameters] {name}"
        if name not in PARAMETERS:
            raise MeasurementError(f"{where} is not a parameter that can be fitted; allowed: "
                                   f"{', '.join(PARAMETERS)}")
        if not isinstance(spec, dict) or set(spec) != {"start", "min", "max"}:
            raise MeasurementError(f"{where} must be {{ start = ..., min = ..., max = ... }} "
                                   f"({PARAMETERS[name][0]}), got {spec!r}")
        start, lo, hi = (_number(spec[k], f"{where} {k}") for k in ("start", "min", "max"))
        if not lo < hi:
            raise MeasurementError(f"{where}: min = {lo:g} must be below max = {hi:g}")
        if not lo <= start <= hi:
            raise MeasurementError(f"{where}: start = {start:g} must lie in [min, max] = "
                                   f"[{lo:g}, {hi:g}]")
        out.append(FitParameter(name, start, lo, hi))
    for a, b in EXCLUSIVE:
        if a in table and b in table:
            raise MeasurementError(f"{src}: [parameters] {a} and {b} set the same damping; "
                                   f"fit one of them")
    return tuple(out)


def load_measurements(path: str | Path) -> Measurements:
    """Read a measurement file and the CSV files it names (module docstring).

    Raises
    ------
    MeasurementError
        A message naming the file, its key or the CSV's column and what is allowed.
    """
    from fem.small_file import FileTooLarge, NotRegularFile, read_small_text

    path = Path(path)
    if path.is_dir():
        raise MeasurementError(f"measurement file {path} is a folder; name its .toml file")
    if not path.exists():
        raise MeasurementError(f"measurement file not found: {path}")
    try:
        data = tomllib.loads(read_small_text(path, MAX_CSV_BYTES))
    except (NotRegularFile, FileTooLarge, UnicodeDecodeError) as exc:
        raise MeasurementError(f"{path}: not a measurement file ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise MeasurementError(f"{path}: not valid TOML: {exc}") from None
    allowed = ("name", "parameters", *KINDS)
    for key in data:
        if key not in allowed:
            raise MeasurementError(f"{path}: unknown key {key!r} at top level; allowed: "
                                   f"{', '.join(allowed)}")
    sets = []
    for kind in KINDS:
        tables = data.get(kind)
        if tables is None:
            continue
        many = isinstance(tables, list)
        for i, t in enumerate(tables if many else [tables], start=1):
            where = f"{path}: [[{kind}]] #{i}" if many else f"{path}: [{kind}]"
            sets.append(_data_set(kind, t, path.parent, where))
    if not sets:
        raise MeasurementError(f"{path}: no measurements; give at least one of "
                               f"{', '.join(f'[{k}]' for k in KINDS)}")
    params = _parameters(data.get("parameters"), str(path))
    fitted_c0 = any(p.name == "C0_F" for p in params)
    if fitted_c0 != any(s.kind == "admittance" for s in sets):
        raise MeasurementError(
            f"{path}: [parameters] C0_F enters the admittance only, and the file has no "
            "[admittance]" if fitted_c0 else f"{path}: [admittance] needs [parameters] C0_F "
            "(the clamped capacitance of the driven electrodes, F), which the set lacks")
    name = data.get("name", path.stem)
    return Measurements(path, str(name), tuple(sets), params)
