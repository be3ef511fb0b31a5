"""The results of one workbook: computed from a preset with numpy (``compute``) or
read back from a file through its names (``read``), both as a :class:`Results` in
sheet units.  crankbook.api re-exports them as the public API.
"""
from dataclasses import dataclass, field
from pathlib import Path

import sys
import warnings

import numpy as np

from crankbook.spec import params as parameters
from crankbook.errors import (BuildOptionError, CoarseStepWarning, CrankbookWarning,
                              GeometryError)
from crankbook.spec.evaluate import axis_sizes, build_grids, evaluate


@dataclass
class Results:
    """Every p_ value and q_ result of one workbook, in sheet units.

    Attributes
    ----------
    spec : crankbook.spec.model.WorkbookSpec
        The template the workbook follows.
    template : str
        Its name (``engine``, ``course_design``, …).
    preset : dict
        The preset's table (name, zh and en descriptions).
    values : dict
        Parameter key -> value (per-item parameters as lists, choices as indices).
    results : dict
        Quantity key -> value: float, or numpy array over a grid and/or items.
    """
    spec: object
    template: str
    preset: dict
    values: dict
    tables: dict
    steps: dict
    results: dict
    axis_sizes: dict = field(default_factory=dict)
    # the measured-pressure file compute() read, which no output may replace
    pressure_file: object = None

    # ------------------------------------------------------------ views
    @property
    def parameters(self):
        """Every p_ value: numbers, lists for per-item tables, words for choices."""
        out = {}
        for p in self.spec.parameters:
            value = self.values[p.key]
            if p.kind == "choice":
                value = p.choices[int(value) - 1]
            out[p.key] = list(value) if p.axis else value
        return out

    @property
    def grids(self):
        """The keys of the grids, the main grid (the workbook's crank angle) first."""
        return [g.key for g in self.spec.grids]

    @property
    def scalars(self):
        """Every q_ scalar as a pandas Series (per-item scalars as ``key[i]``)."""
        data = {}
        for q in self.spec.quantities():
            if q.is_series or q.key not in self.results:
                continue
            value = self.results[q.key]
            if q.items:
                for i, v in enumerate(np.atleast_1d(value), start=1):
                    data[f"{q.key}[{i}]"] = float(v)
            else:
                data[q.key] = float(value)
        import pandas as pd
        return pd.Series(data, dtype=float, name="value")

    def series(self, grid=None):
        """One row per grid point, indexed by the grid, one column per q_ series on it
        (per-item series as ``key[i]``), in sheet units.

        Parameters
        ----------
        grid : str, optional
            A key of :attr:`grids`; the main grid when None.
        """
        grid = grid or self.spec.grid.key
        if grid not in self.grids:
            raise BuildOptionError(f"unknown grid {grid!r}; grids are {', '.join(self.grids)}")
        import pandas as pd
        index = pd.Index(np.asarray(self.results[grid], dtype=float), name=grid)
        columns = {}
        for q in self.spec.series():
            if q.grid != grid or q.is_grid or q.key not in self.results:
                continue
            value = np.asarray(self.results[q.key], dtype=float)
            if q.items:
                for i in range(value.shape[1]):
                    columns[f"{q.key}[{i + 1}]"] = value[:, i]
            else:
                columns[q.key] = value
        return pd.DataFrame(columns, index=index)

    def __getitem__(self, key):
        """A q_ result or p_ value by key; a scalar result the workbook leaves blank
        (NaN: e.g. the non-uniformity of a torque that averages to zero) is None."""
        if key in self.results:
            value = self.results[key]
            if np.ndim(value) == 0 and not np.isfinite(value):
                return None
            return value
        if key in self.values:
            return self.values[key]
        if key in self.spec.quantity:        # read() of a workbook without this name
            raise KeyError(f"{key}: this workbook does not hold it (built before crankbook "
                           f"computed it, or its name was deleted): rebuild the workbook")
        raise KeyError(key)

    def __repr__(self):
        return (f"<crankbook.Results {self.template} (preset {self.preset.get('name')}): "
                f"{len(self.spec.parameters)} parameters, {len(self.results)} quantities>")

    def coarse_step_effect(self):
        """What a coarse main grid does to the template's compared results (p_max, the
        mean torque, the power), measured against a build at the template's own step:
        one line, or None where the step is not coarse."""
        coarse, step = _coarse(self.spec, self.steps)
        if coarse is None:
            return None
        fine = results_for(self.spec, self.preset, self.values, self.tables,
                           {**self.steps, "step": None})
        moved = [f"{key} {self[key]:.4g} ({100 * (self[key] / fine[key] - 1):+.2f} %)"
                 for key in coarse["compare"] if fine[key]]
        return (f"a {step:g}° grid step is coarser than {coarse['above']:g}° and reads the "
                f"peaks between its rows; against the {self.spec.grid.step:g}° grid: "
                + ", ".join(moved))

    def to_torsion_csv(self, directory):
        """Write ``stations.csv``, ``harmonics.csv`` and ``response.csv`` (the torsional
        system, each cylinder's torque harmonics and the forced response over the speed
        sweep) into ``directory``; see crankbook.writer.torsion_csv."""
        from crankbook.writer.torsion_csv import write
        return write(self, directory)

    def to_bearing_csv(self, path):
        """Write the two bearings' journal orbits over the second cycle to ``path`` (a
        .csv); see crankbook.writer.bearing_csv."""
        from crankbook.writer.bearing_csv import write
        return write(self, path)

    def to_excel(self, path, lang="zh"):
        """Write the formula-backed workbook the command line writes; return its path."""
        from crankbook.writer.build import write_workbook
        if lang not in ("zh", "en"):
            raise BuildOptionError(f"--lang {lang!r}: choose zh or en")
        return write_workbook(self, lang, path)


def _is_frame(value):
    """True for a pandas DataFrame; pandas is imported only when a result asks for a
    table (a command-line run never does), and a frame exists only if it was."""
    pandas = sys.modules.get("pandas")
    return pandas is not None and isinstance(value, pandas.DataFrame)


def _traces(spec, pressure):
    """The Traces of a file or DataFrame (two columns, or an angle column and one
    pressure column per speed headed by the speed in r/min)."""
    from crankbook.reading.pressure_file import read_traces, traces_of_rows
    if _is_frame(pressure):
        if pressure.shape[1] < 2:
            raise BuildOptionError("pressure: a DataFrame needs two columns, crank angle [°] "
                                   "and absolute pressure [MPa], or an angle column and one "
                                   "pressure column per speed named by the speed [r/min]")
        rows = pressure.astype(object).values.tolist()
        if pressure.shape[1] > 2:
            rows = [[str(c) for c in pressure.columns]] + rows
        return traces_of_rows("pressure DataFrame", rows, spec.cycle)
    return read_traces(pressure, spec.cycle)


def _trace_inputs(spec, traces, values, given, what):
    """(tables, values) for a measured trace: one trace goes into the Pressure sheet's
    trace block; a trace per speed also into the operating points (their speeds the
    file's unless ``operating_speed`` is given; each listed speed and the design speed
    need a column)."""
    values = dict(values)
    if "pressure_source" not in given and "pressure_source" in spec.parameter:
        values["pressure_source"] = 1.0
    if not traces.speeds:
        return {"trace_crank_angle": traces.angles, "trace_pressure": traces.pressures}, values
    if "operating_trace_pressure" not in spec.table_column:
        raise BuildOptionError(f"{what}: holds a trace for each of {len(traces.speeds)} "
                               f"speeds; the {spec.key} workbook takes one trace (two columns)")
    listed = [float(v) for v in values["operating_speed"]] if "operating_speed" in given \
        else list(traces.speeds)
    shown = ", ".join(f"{v:g}" for v in traces.speeds)
    for speed in listed:
        if speed not in traces.speeds:
            raise BuildOptionError(f"operating_speed {speed:g} r/min has no column in {what} "
                                   f"(its speeds: {shown} r/min)")
    if values["speed"] not in traces.speeds:
        raise BuildOptionError(f"speed = {values['speed']:g} r/min (the design speed) has no "
                               f"column in {what} (its speeds: {shown} r/min): set speed to "
                               f"one of them")
    values.update(operating_speed=listed, operating_trace_count=float(len(listed)))
    # each trace is tied to the speed of its column (a later edit of a speed in the
    # workbook is then caught by the trace-speed rules); typed values are the user's
    recorded = {"trace_speed": float(values["speed"]), "operating_trace_speed": listed}
    values.update({key: value for key, value in recorded.items() if key not in given})
    tables = {"trace_crank_angle": traces.angles, "trace_pressure": traces.column(values["speed"]),
              "operating_trace_pressure": np.column_stack([traces.column(v) for v in listed])}
    return tables, values


def compute(preset="thesis", *, group=None, pressure=None, step=None, **params):
    """Compute every quantity of a preset's workbook with numpy.

    Parameters
    ----------
    preset : str
        A preset name (``crankbook presets``): thesis, course-design, inline-4, ….
    group : int, optional
        A class group of the preset's group table, applied before ``params``.
    pressure : str, pathlib.Path or pandas.DataFrame, optional
        A measured cylinder-pressure trace: a .csv/.xlsx file or a two-column
        DataFrame (crank angle [°], absolute pressure [MPa]); or one trace per speed
        (an angle column, then one column per speed headed by the speed in r/min):
        the design speed takes its column, and the operating points the speeds of the
        file (or those of ``operating_speed``, each needing a column).  Sets
        ``pressure_source`` to 1 unless ``params`` sets it.
    step : float, optional
        Step of the main grid [°] (default: the template's, 1°).
    **params
        Parameter key -> value in its sheet unit (as ``--set``): a number, a list
        for a per-item parameter, a word for a choice.  Grid options other than the
        main step (``cam_step``) are accepted here too.

    Returns
    -------
    Results
    """
    spec, values, meta = parameters.load_preset(preset)
    if group is not None:
        values = parameters.apply_group(spec, values, meta, group)
    steps = {"step": step} if step is not None else {}
    for option in spec.grid_options():
        if option != "step" and option in params:
            steps[option] = params.pop(option)
    values = parameters.apply_overrides(spec, values, params)
    tables = {}
    if pressure is not None:
        what = "the pressure DataFrame" if _is_frame(pressure) else str(pressure)
        tables, values = _trace_inputs(spec, _traces(spec, pressure), values, params, what)
    values = parameters.validate(spec, values, tables=tables, grids=build_grids(spec, steps))
    results = results_for(spec, meta, values, tables, steps)
    if pressure is not None and not _is_frame(pressure):
        results.pressure_file = Path(pressure).resolve()     # a later chdir cannot hide it
    _warn_coarse_step(results, steps)
    _warn_status_notes(results)
    return results


def _warn_status_notes(results):
    """Every note the status cell shows after its ✓ (a slip such as grams typed for kg,
    a Holzer grid that finds no mode) is a warning on the command line and in Python
    too: legal inputs, so the build goes on."""
    known = {**results.values, **results.results}
    for note in results.spec.notes:
        if note.get("status") and float(known[note["when_nonzero"]]) != 0:
            warnings.warn(note["en"], CrankbookWarning, stacklevel=3)


def _coarse(spec, steps):
    """(the template's coarse_step, the main grid's step) when that step is above it,
    else (None, step)."""
    coarse, step = spec.coarse_step, steps.get("step")
    if not coarse or step is None or step <= coarse["above"]:
        return None, step
    return coarse, step


def _warn_coarse_step(results, steps):
    """A main grid coarser than the template's ``coarse_step`` reads the peaks between
    rows: one warning in words (measuring it costs a second build, which
    :meth:`Results.coarse_step_effect` makes on request)."""
    coarse, step = _coarse(results.spec, steps)
    if coarse is None:
        return
    first, *rest = coarse["compare"]
    warnings.warn(CoarseStepWarning(
        f"a {step:g}° grid step is coarser than {coarse['above']:g}° and reads the peaks "
        f"between its rows: {first} reads low and {' and '.join(rest)} shift; build at "
        f"{coarse['above']:g}° or finer to trust them (in Python, "
        f"Results.coarse_step_effect() measures by how much)"), stacklevel=3)


def results_for(spec, preset, values, tables=None, steps=None):
    """Results of validated ``values`` (the pipeline after the inputs are settled)."""
    tables, steps = tables or {}, dict(steps or {})
    grids = build_grids(spec, steps)
    results = evaluate(spec, values, tables, grids)
    _check_written_values(spec, values, results)
    _check_must_pass(spec, results)
    return Results(spec=spec, template=preset["template"], preset=preset, values=values,
                   tables=tables, steps=steps, results=results,
                   axis_sizes=axis_sizes(spec, values))


def _check_must_pass(spec, results):
    """A check marked must_pass (a computed condition no input rule can state, e.g. a
    roller larger than the cam's sharpest curvature) refuses the build in one line,
    naming the item."""
    for q in spec.quantities():
        if not q.must_pass:
            continue
        flags = np.atleast_1d(np.asarray(results[q.key], dtype=float))
        failed = np.flatnonzero(flags == 0)
        if failed.size:
            where = f"{spec.axis[q.items].label_en.lower()} {failed[0] + 1}: " if q.items else ""
            raise GeometryError(f"{where}q_{q.key} = 0: {q.en}")


def _check_written_values(spec, values, results):
    """A quantity the workbook holds as a number, not a formula (an optimum found in
    Python), must exist: GeometryError naming it and the inputs otherwise."""
    for q in spec.quantities():
        if q.formula is None and not q.is_grid and q.kind != "rule" and \
                not np.all(np.isfinite(np.asarray(results[q.key], dtype=float))):
            shown = ", ".join(f"{p.key} = {values[p.key]:g}" for p in spec.parameters
                              if p.kind == "number" and not p.axis)
            raise GeometryError(f"{q.en}: none exists for these inputs ({shown})")


def read(path, recalculate=False, progress=None):
    """The p_ and q_ values of a workbook crankbook wrote, through its names.

    Parameters
    ----------
    path : str, pathlib.Path or a list of them
        A list is recalculated in one engine start.
    recalculate : bool
        Recalculate in LibreOffice first (what an Excel user changed but saved
        without recalculating, or a file written by a script); otherwise the values
        stored in the file are read.
    progress : bool or None
        Show progress on stderr (None: when it is a terminal).

    Returns
    -------
    Results, or a list of them for a list of paths
        ``results`` holds the workbook's values, not a recomputation.
    """
    if isinstance(path, (list, tuple)):
        return read_workbooks([Path(p) for p in path], recalculate, progress)
    return read_workbooks([Path(path)], recalculate, progress)[0]


def read_workbooks(paths, recalculate=False, progress=None):
    """Results of each workbook; with ``recalculate``, all in one LibreOffice start."""
    from crankbook.reading import recalc
    from crankbook.reading.workbook_reader import stored_results
    from crankbook.support.progress import steps, waiting
    from crankbook.support.workspace import temporary_directory
    if not recalculate:
        return [Results(**stored_results(p)) for p in steps(paths, "read", progress=progress)]
    with temporary_directory("read") as tmp:
        with waiting(f"read: recalculating {len(paths)} workbook(s) in LibreOffice", progress):
            computed = recalc.computed_values(paths, tmp)
        return [Results(**stored_results(p, c))
                for p, c in steps(list(zip(paths, computed)), "read", progress=progress)]
