"""The answer key of one student, the same for `assign` (which writes it) and
`grade` (which recomputes it from the manifest's parameters, never from cells a
student could edit).

Where the assignment gives the cylinder pressure as a table (one value per
degree), the key is computed from that very table, interpolated linearly as the
statement tells the student: a student who follows the statement meets the key.
"""
import numpy as np

from crankbook.results import results_for
from crankbook.spec.evaluate import build_grids, evaluate


def given_trace(assignment, spec, values):
    """(angles, pressures) of the pressure table a student is given, or None."""
    if not assignment.given_trace:
        return None
    model = dict(values, pressure_source=0.0)
    grids = build_grids(spec, {"step": assignment.given_step})
    out = evaluate(spec, model, {}, grids, keys=[assignment.given_pressure])
    return np.asarray(grids[spec.grid.key], float), np.asarray(out[assignment.given_pressure], float)


def key_results(assignment, spec, preset, values):
    """The Results the key workbook holds for these parameters."""
    # the key says what it is (crankbook audit names it); never whose it is
    preset = dict(preset, role="key", assignment=assignment.key)
    trace = given_trace(assignment, spec, values)
    if trace is None:
        return results_for(spec, preset, values)
    tables = {"trace_crank_angle": trace[0], "trace_pressure": trace[1]}
    return results_for(spec, preset, dict(values, pressure_source=1.0), tables)


def answer_rows(assignment, lang, results, spec=None):
    """Row kind -> the labels of the rows of the answer sheets."""
    rows = {}
    if assignment.positions is not None:
        rows["positions"] = assignment.positions.labels(lang)
    if assignment.grid_angles is not None:
        rows["crank_angle"] = list(assignment.grid_angles)
    for grid, angles in assignment.row_angles.items():
        rows[grid] = list(angles)
    if spec is not None:
        for sheet in assignment.sheets:
            if sheet.rows in spec.axis:            # one row per gear, mesh, …
                count = len(np.atleast_1d(results[sheet.items[0]]))
                rows[sheet.rows] = [assignment.row_label(sheet.rows, lang, i + 1, count)
                                    or spec.axis[sheet.rows].label(lang, i + 1, size=count)
                                    for i in range(count)]
    return rows


def expected(assignment, spec, key, overrides=None):
    """Item key -> expected values in the order of the answer rows, with the key's
    alternatives: {"value": array, "alternatives": [array, …]}.

    ``overrides`` recomputes with a student's own upstream answers (consequential
    credit); None where they give no mechanism.
    """
    results = key.results
    if overrides:
        try:
            with np.errstate(all="ignore"):
                results = evaluate(spec, key.values, key.tables, _grids(spec, key),
                                   overrides=overrides)
        except Exception:                      # their own values may make no mechanism
            return None
    if assignment.grid_angles is not None:
        at_rows = evaluate(spec, key.values, key.tables, np.asarray(assignment.grid_angles, float),
                           overrides=overrides)
    order = assignment.positions.guide_rows(results) if assignment.positions else None
    at_angles = {}
    for grid, angles in assignment.row_angles.items():
        at_angles[grid] = evaluate(spec, key.values, key.tables,
                                   {**_grids(spec, key), grid: np.asarray(angles, float)},
                                   overrides=overrides)
    out = {}
    for item in assignment.items:
        def rows_of(name):
            q = spec.quantity[name]
            if q.is_series and q.grid in at_angles:
                return np.atleast_1d(np.asarray(at_angles[q.grid][name], float))
            if q.is_series and assignment.grid_angles is not None and q.grid == spec.grid.key:
                return np.atleast_1d(np.asarray(at_rows[name], float))
            value = np.atleast_1d(np.asarray(results[name], float))
            if q.is_series and order is not None and q.grid == assignment.positions.grid:
                return value[order]
            return value
        out[item.key] = {"value": rows_of(item.key),
                         "alternatives": [rows_of(a) for a in item.alternatives]}
    return out


def _grids(spec, key):
    return build_grids(spec, key.steps)
