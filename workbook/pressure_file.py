"""Measured cylinder-pressure traces from CSV or xlsx files.

Two columns: crank angle [deg] (0 = TDC of the intake stroke, firing TDC at 360°,
any range such as −360…360) and absolute pressure [MPa]; an optional header row;
rows in any order.  The trace is wrapped into one 720° cycle, sorted and closed
(a point below 0° and one above 720°) so that the workbook's interpolation covers
every grid angle.
"""
import csv
import math
from pathlib import Path

import numpy as np

from workbook.errors import PressureFileError

CYCLE = 720.0
MAX_GAP = 30.0          # deg: a coarser trace does not describe the cycle
MAX_PRESSURE = 50.0     # MPa: beyond any engine; such numbers are kPa or bar
MAX_ROWS = 200_000


def _rows_from_csv(path):
    text = path.read_text(encoding="utf-8-sig", errors="replace")
    try:
        dialect = csv.Sniffer().sniff(text[:4096], delimiters=",;\t ")
    except csv.Error:
        dialect = csv.excel
    return [row for row in csv.reader(text.splitlines(), dialect) if any(c.strip() for c in row)]


def _rows_from_xlsx(path):
    import openpyxl
    try:
        book = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as error:
        raise PressureFileError(f"pressure file {path}: cannot be read as xlsx "
                                f"({type(error).__name__})") from None
    sheet = book.worksheets[0]
    rows = [list(r) for r in sheet.iter_rows(values_only=True)
            if any(c is not None and str(c).strip() for c in r)]
    book.close()
    return rows


def _number(value):
    if isinstance(value, (int, float)):
        return float(value)
    return float(str(value).strip())


def read_trace(path):
    """(angles [deg], pressures [MPa]) of the trace in ``path``, ready for the workbook."""
    path = Path(path)
    if not path.is_file():
        raise PressureFileError(f"pressure file {path}: no such file")
    suffix = path.suffix.lower()
    if suffix in (".csv", ".txt", ".tsv"):
        rows = _rows_from_csv(path)
    elif suffix == ".xlsx":
        rows = _rows_from_xlsx(path)
    else:
        raise PressureFileError(f"pressure file {path}: use a .csv or .xlsx file "
                                f"(two columns: crank angle deg, pressure MPa)")
    if len(rows) > MAX_ROWS:
        raise PressureFileError(f"pressure file {path}: more than {MAX_ROWS} rows")
    angles, pressures = [], []
    for number, row in enumerate(rows, start=1):
        cells = [c for c in row if c is not None and str(c).strip() != ""]
        if len(cells) < 2:
            raise PressureFileError(f"pressure file {path}, row {number}: needs two columns, "
                                    f"crank angle [deg] and pressure [MPa]")
        try:
            angle = _number(cells[0])
        except ValueError:
            if number == 1 and not angles:
                continue                     # a header row
            raise PressureFileError(f"pressure file {path}, row {number}: crank angle "
                                    f"{cells[0]!r} is not a number") from None
        try:
            pressure = _number(cells[1])
        except ValueError:
            raise PressureFileError(f"pressure file {path}, row {number}: pressure "
                                    f"{cells[1]!r} is not a number") from None
        if not (math.isfinite(angle) and math.isfinite(pressure)):
            raise PressureFileError(f"pressure file {path}, row {number}: values must be finite")
        if pressure <= 0:
            raise PressureFileError(f"pressure file {path}, row {number}: pressure {pressure:g} "
                                    f"MPa must be > 0 (absolute pressure)")
        angles.append(angle)
        pressures.append(pressure)
    if len(angles) < 2:
        raise PressureFileError(f"pressure file {path}: needs at least two points, "
                                f"found {len(angles)}")
    if max(pressures) > MAX_PRESSURE:
        raise PressureFileError(f"pressure file {path}: pressures up to {max(pressures):g} look "
                                f"like kPa or bar; the pressure column must be in MPa")
    return close_cycle(path, np.array(angles), np.array(pressures))


def close_cycle(path, angles, pressures):
    """Wrap into [0, 720), sort, check coverage, and add one point beyond each end."""
    wrapped = np.mod(angles, CYCLE)
    order = np.argsort(wrapped, kind="stable")
    wrapped, pressures = wrapped[order], pressures[order]
    keep = np.ones(len(wrapped), bool)
    for i in range(1, len(wrapped)):
        if wrapped[i] == wrapped[i - 1]:
            if not math.isclose(pressures[i], pressures[i - 1], rel_tol=1e-6):
                raise PressureFileError(
                    f"pressure file {path}: crank angle {wrapped[i]:g}° (mod 720°) appears twice "
                    f"with different pressures")
            keep[i] = False
    wrapped, pressures = wrapped[keep], pressures[keep]
    if len(wrapped) < 2:
        raise PressureFileError(f"pressure file {path}: needs at least two distinct crank angles")
    gaps = np.diff(np.concatenate([wrapped, [wrapped[0] + CYCLE]]))
    worst = int(np.argmax(gaps))
    if gaps[worst] > MAX_GAP:
        start = wrapped[worst]
        raise PressureFileError(
            f"pressure file {path}: crank angles must cover the whole 0–720° cycle; "
            f"nothing between {start:g}° and {(start + gaps[worst]) % CYCLE:g}° "
            f"(gap {gaps[worst]:g}°, at most {MAX_GAP:g}° allowed)")
    angles = np.concatenate([[wrapped[-1] - CYCLE], wrapped, [wrapped[0] + CYCLE]])
    pressures = np.concatenate([[pressures[-1]], pressures, [pressures[0]]])
    return angles, pressures
