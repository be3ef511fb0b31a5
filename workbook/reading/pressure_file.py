"""Measured cylinder-pressure traces from CSV or xlsx files (or two columns of numbers).

Two columns: crank angle [deg] (0 = TDC of the intake stroke, firing TDC at 360°,
any range such as −360…360) and absolute pressure [MPa]; an optional header row
(a first row of which neither cell is a number); rows in any order.  Or, as a test
bench records several speeds: a header row ``angle, 1000, 2000, …`` and one pressure
column per speed (r/min), every row a crank angle and a pressure for each speed.  The trace is
wrapped into one working cycle, sorted and closed (a point before 0° and one after
the cycle) so that the workbook's interpolation covers every grid angle.  A crank
angle that occurs twice (−360° and 360° are one angle) keeps the mean of its
pressures when they agree within REPEAT_TOLERANCE, else the file is refused.
Nothing is dropped silently.
"""
import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crankbook.errors import PressureFileError
from crankbook.spec.params import NUMBER
from crankbook.reading.xlsx_reader import Unreadable, XlsxBook, sheet_rows
from crankbook.support.paths import require_file

MAX_GAP = 30.0             # deg: a coarser trace does not describe the cycle
MAX_PRESSURE = 50.0        # MPa: beyond any engine; such numbers are kPa or bar
MAX_ROWS = 200_000
MAX_SPEEDS = 24            # pressure columns of one file (the operating points' limit)
MAX_SPEED = 30000.0        # r/min, as the speed parameter's bound
MAX_BYTES = 20 * 1024 * 1024
REPEAT_TOLERANCE = 0.02    # relative: one angle measured twice (e.g. −360° and 360°)
SAME_ANGLE = 1e-9          # deg: angles closer than this are one angle


def _rows_from_csv(path):
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise PressureFileError(f"pressure file {path}: not UTF-8 text; save it as CSV "
                                f"(UTF-8) with two columns") from None
    try:
        dialect = csv.Sniffer().sniff(text[:4096], delimiters=",;\t ")
    except csv.Error:
        dialect = csv.excel
    try:
        return [row for row in csv.reader(text.splitlines(), dialect)
                if any(c.strip() for c in row)]
    except csv.Error as error:            # a field beyond the csv module's limit, …
        raise PressureFileError(f"pressure file {path}: not a readable CSV ({error})") from None


def _rows_from_xlsx(path):
    """The first sheet's rows, read by the bounded reader (a hostile file is refused)."""
    try:
        book = XlsxBook(path)
        try:
            rows = sheet_rows(book, limit=MAX_ROWS)
        finally:
            book.close()
    except Unreadable as reason:
        raise PressureFileError(f"pressure file {path}: {reason}") from None
    except (RecursionError, MemoryError, ValueError, KeyError, TypeError) as error:
        raise PressureFileError(f"pressure file {path}: cannot be read as xlsx "
                                f"({type(error).__name__})") from None
    return [row for row in rows if any(c is not None and str(c).strip() for c in row)]


def _number(value):
    """A float from a cell: a number, or plain ASCII decimal text; else None."""
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, (int, float)):
        return float(value) if math.isfinite(value) else None
    text = str(value).strip()
    return float(text) if NUMBER.match(text) else None


@dataclass(frozen=True)
class Traces:
    """What a pressure file holds: one trace (``speeds`` empty, ``pressures`` (M,)) or
    one per speed (``speeds`` in r/min, ``pressures`` (M, len(speeds))), at the
    crank angles ``angles`` (M,), closed over the cycle."""
    angles: np.ndarray
    pressures: np.ndarray
    speeds: tuple = ()

    def column(self, speed):
        """The trace of one speed [MPa]."""
        return self.pressures[:, self.speeds.index(speed)]


def _rows_of_file(path):
    path = Path(path)
    require_file(path, PressureFileError, "pressure file")
    if path.stat().st_size > MAX_BYTES:
        raise PressureFileError(f"pressure file {path}: larger than "
                                f"{MAX_BYTES // 2 ** 20} MB")
    suffix = path.suffix.lower()
    if suffix in (".csv", ".txt", ".tsv"):
        return _rows_from_csv(path)
    if suffix == ".xlsx":
        return _rows_from_xlsx(path)
    raise PressureFileError(f"pressure file {path}: use a .csv or .xlsx file "
                            f"(crank angle [deg], then pressure [MPa]: one column, or one per "
                            f"speed headed by the speed in r/min)")


def read_trace(path, cycle=720.0):
    """(angles [deg], pressures [MPa]) of the one trace in ``path``, ready for the
    workbook of a ``cycle``-degree working cycle."""
    return _trace_of_rows(f"pressure file {path}", _rows_of_file(path), cycle)


def read_traces(path, cycle=720.0):
    """The Traces in ``path``: two columns (crank angle, pressure), or a crank-angle
    column headed ``angle`` and one pressure column per speed headed by the speed in
    r/min, as a test bench records them."""
    return traces_of_rows(f"pressure file {path}", _rows_of_file(path), cycle)


def trace_from_columns(what, angles, pressures, cycle=720.0):
    """A trace from two columns of numbers (the API's DataFrame), checked like a file."""
    return _trace_of_rows(what, [[a, p] for a, p in zip(list(angles), list(pressures))], cycle)


def _filled(row):
    return [c for c in row if c is not None and str(c).strip() != ""]


def traces_of_rows(what, rows, cycle=720.0):
    """Traces from rows as a file holds them (see :func:`read_traces`)."""
    if not rows or max(len(_filled(r)) for r in rows[:MAX_ROWS + 1]) <= 2:
        angles, pressures = _trace_of_rows(what, rows, cycle)
        return Traces(angles, pressures)
    header, body = rows[0], rows[1:]
    cells = [str(c).strip() if c is not None else "" for c in header]
    while cells and not cells[-1]:
        cells.pop()
    if _number(cells[0]) is not None:
        raise PressureFileError(f"{what}: a file of several pressure columns needs a header "
                                f"row: angle, then the speed of each column in r/min")
    speeds = []
    for number, text in enumerate(cells[1:], start=2):
        speed = _number(text)
        if speed is None or not 0 < speed <= MAX_SPEED:
            raise PressureFileError(f"{what}, column {number}: header {text[:30]!r} is not a "
                                    f"speed in r/min (> 0 and ≤ {MAX_SPEED:g})")
        if speed in speeds:
            raise PressureFileError(f"{what}, column {number}: speed {speed:g} r/min appears "
                                    f"twice")
        speeds.append(speed)
    if len(speeds) > MAX_SPEEDS:
        raise PressureFileError(f"{what}: {len(speeds)} speeds, at most {MAX_SPEEDS}")
    angles, columns = None, []
    for index, speed in enumerate(speeds, start=1):
        column_rows = [[row[0] if len(row) > 0 else None,
                        row[index] if len(row) > index else None] for row in body]
        closed_angles, pressures = _trace_of_rows(f"{what}, column {speed:g} r/min",
                                                  column_rows, cycle, numbered_from=2)
        if angles is not None and not np.array_equal(angles, closed_angles):
            raise PressureFileError(f"{what}, column {speed:g} r/min: its crank angles differ "
                                    f"from the first column's (every pressure needs a value "
                                    f"in every row)")
        angles = closed_angles
        columns.append(pressures)
    return Traces(angles, np.column_stack(columns), tuple(speeds))


DECIMAL_COMMA = re.compile(r"[+-]?[0-9]+,[0-9]+\Z")


def _comma_hint(cell):
    """Why a European CSV's number is not one: a decimal comma."""
    if DECIMAL_COMMA.match(str(cell).strip()):
        return (" (a decimal comma, as a European CSV writes it: save the file with '.' as "
                "the decimal sign)")
    return ""


def _trace_of_rows(what, rows, cycle, numbered_from=1):
    if len(rows) > MAX_ROWS:
        raise PressureFileError(f"{what}: more than {MAX_ROWS} rows")
    angles, pressures = [], []
    for number, row in enumerate(rows, start=numbered_from):
        cells = _filled(row)
        if len(cells) != 2:
            raise PressureFileError(f"{what}, row {number}: needs exactly two columns, crank "
                                    f"angle [deg] and pressure [MPa] (found {len(cells)})")
        angle, pressure = _number(cells[0]), _number(cells[1])
        if number == 1 and angle is None and pressure is None:
            continue                          # a header row
        if angle is None:
            raise PressureFileError(f"{what}, row {number}: crank angle {str(cells[0])[:30]!r} "
                                    f"is not a number{_comma_hint(cells[0])}")
        if pressure is None:
            raise PressureFileError(f"{what}, row {number}: pressure {str(cells[1])[:30]!r} "
                                    f"is not a number{_comma_hint(cells[1])}")
        if pressure <= 0:
            raise PressureFileError(f"{what}, row {number}: pressure {pressure:g} MPa must be "
                                    f"> 0 (absolute pressure)")
        if abs(angle) > 100 * cycle:
            raise PressureFileError(f"{what}, row {number}: crank angle {angle:g}° is far "
                                    f"outside the cycle")
        angles.append(angle)
        pressures.append(pressure)
    if len(angles) < 2:
        raise PressureFileError(f"{what}: needs at least two points, found {len(angles)}")
    if max(pressures) > MAX_PRESSURE:
        raise PressureFileError(f"{what}: pressures up to {max(pressures):g} look like kPa or "
                                f"bar; the pressure column must be in MPa")
    return close_cycle(what, np.array(angles), np.array(pressures), cycle)


def close_cycle(what, angles, pressures, cycle=720.0):
    """Wrap into [0, cycle), merge repeats, sort, check coverage, and add one point
    beyond each end."""
    wrapped = np.mod(angles, cycle)
    wrapped = np.where(cycle - wrapped < SAME_ANGLE, 0.0, wrapped)
    order = np.argsort(wrapped, kind="stable")
    wrapped, pressures = wrapped[order], pressures[order]
    merged_a, merged_p = [], []
    for angle, pressure in zip(wrapped, pressures):
        if merged_a and angle - merged_a[-1][0] < SAME_ANGLE:
            merged_a[-1].append(angle)
            merged_p[-1].append(pressure)
        else:
            merged_a.append([angle])
            merged_p.append([pressure])
    for group_a, group_p in zip(merged_a, merged_p):
        if max(group_p) - min(group_p) > REPEAT_TOLERANCE * max(group_p):
            raise PressureFileError(
                f"{what}: crank angle {group_a[0]:g}° (mod {cycle:g}°) appears "
                f"{len(group_p)} times with pressures {min(group_p):g} and {max(group_p):g} "
                f"MPa, more than {REPEAT_TOLERANCE:.0%} apart")
    wrapped = np.array([a[0] for a in merged_a])
    pressures = np.array([float(np.mean(p)) for p in merged_p])
    if len(wrapped) < 2:
        raise PressureFileError(f"{what}: needs at least two distinct crank angles")
    gaps = np.diff(np.concatenate([wrapped, [wrapped[0] + cycle]]))
    worst = int(np.argmax(gaps))
    if gaps[worst] > MAX_GAP:
        start = wrapped[worst]
        raise PressureFileError(
            f"{what}: crank angles must cover the whole 0–{cycle:g}° cycle; nothing between "
            f"{start:g}° and {(start + gaps[worst]) % cycle:g}° (gap {gaps[worst]:g}°, at most "
            f"{MAX_GAP:g}° allowed)")
    angles = np.concatenate([[wrapped[-1] - cycle], wrapped, [wrapped[0] + cycle]])
    pressures = np.concatenate([[pressures[-1]], pressures, [pressures[0]]])
    return angles, pressures
