"""What every export needs of a workbook's results: numbers, not blank cells.

A workbook whose inputs break a rule holds blank results by design, and one saved
without calculated values (openpyxl's save, read without ``recalculate=True``) reads
as NaN; a CSV of either would look like data to the tool that reads it.
"""
import numpy as np

from crankbook.errors import CrankbookError, WorkbookReadError


def require_numbers(results, keys, command):
    """Raise a WorkbookReadError naming the first of ``keys`` with no number, and why."""
    for key in keys:
        values = np.asarray(results.results[key], dtype=object).ravel()
        numbers = [v for v in values if isinstance(v, (int, float)) and np.isfinite(v)]
        if numbers:
            continue
        raise WorkbookReadError(f"{command}: the workbook's {key} is blank: {_why(results)}")


def _why(results):
    """The broken rule in its own words, or the other reason a result is blank."""
    from crankbook.spec import params
    try:
        params.validate(results.spec, dict(results.values), tables=results.tables)
    except CrankbookError as error:
        return f"its inputs break a rule ({error})"
    return ("it holds no calculated values (saved by a program that does not calculate); "
            "read it with recalculate=True")
