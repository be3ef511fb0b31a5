"""Read a workbook back through its defined names (openpyxl)."""
import zipfile
from pathlib import Path

import openpyxl
from openpyxl.utils.cell import range_boundaries

from workbook.errors import WorkbookReadError


def open_workbook(path, data_only=True):
    """An openpyxl workbook, or WorkbookReadError saying why the file is not one."""
    path = Path(path)
    if not path.is_file():
        raise WorkbookReadError(f"{path}: no such file")
    if not zipfile.is_zipfile(path):
        raise WorkbookReadError(f"{path}: not an .xlsx workbook (not a zip container)")
    try:
        return openpyxl.load_workbook(path, data_only=data_only)
    except Exception as error:  # openpyxl raises many types for broken files
        raise WorkbookReadError(f"{path}: cannot be read as a workbook "
                                f"({type(error).__name__}: {error})") from None


def named_values(book, prefixes=("p_", "q_")):
    """name -> value (a single cell) or list of values (a range), for names with a
    given prefix."""
    out = {}
    for name, defined in book.defined_names.items():
        if not name.startswith(prefixes):
            continue
        destinations = list(defined.destinations)
        if len(destinations) != 1:
            continue
        sheet, reference = destinations[0]
        ws = book[sheet]
        min_col, min_row, max_col, max_row = range_boundaries(reference.replace("$", ""))
        cells = [ws.cell(row=r, column=c).value for r in range(min_row, max_row + 1)
                 for c in range(min_col, max_col + 1)]
        out[name] = cells[0] if len(cells) == 1 and min_row == max_row else cells
    return out


def named_addresses(book, prefixes=("q_",)):
    """name -> (sheet, first row, first column) of each named cell or range."""
    out = {}
    for name, defined in book.defined_names.items():
        if name.startswith(prefixes):
            destinations = list(defined.destinations)
            if len(destinations) == 1:
                sheet, reference = destinations[0]
                min_col, min_row, _, _ = range_boundaries(reference.replace("$", ""))
                out[name] = (sheet, min_row, min_col)
    return out
