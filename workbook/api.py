"""The Python API: compute a preset, read a workbook back, verify it.

    >>> import crankbook
    >>> r = crankbook.compute("thesis", speed=3000)
    >>> r.series()["torque"].max()                      # N·m, on the 0–720° grid
    >>> r.to_excel("output/thesis-3000.xlsx")
    >>> crankbook.read("output/thesis-3000.xlsx").scalars["mean_torque"]

Values are in sheet units (the units of the README's named-range tables); bad
input raises the same one-line errors as the command line, as subclasses of
crankbook.CrankbookError.
"""
from pathlib import Path

from crankbook.results import Results, compute, read, results_for

__all__ = ["Results", "compute", "read", "results_for", "verify"]


def verify(path, engine="libreoffice", progress=None):
    """Recalculate a workbook (or a list of workbooks, in one engine start) in a
    spreadsheet engine and compare every q_ name with numpy evaluated on the
    workbook's own inputs.

    Parameters
    ----------
    path : str, pathlib.Path or a list of them
    engine : {'libreoffice', 'gnumeric'}
    progress : bool or None
        Show progress on stderr (None: when it is a terminal).

    Returns
    -------
    pandas.DataFrame, or a list of them for a list of paths
        One row per q_ name: ``name``, ``unit``, ``error`` (largest |engine − numpy|),
        ``allowed`` (the tolerance), ``cached_error`` (largest |stored − engine|) and
        ``ok``; its ``attrs`` hold ``status`` (the workbook's status text) and
        ``valid`` (q_inputs_valid).
    """
    from crankbook.reading.verification import verify_workbooks
    if isinstance(path, (list, tuple)):
        return verify_workbooks([Path(p) for p in path], engine=engine, progress=progress)
    return verify_workbooks([Path(path)], engine=engine, progress=progress)[0]
