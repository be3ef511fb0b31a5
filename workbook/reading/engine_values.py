"""The values a spreadsheet engine computed, read from its export of every sheet as CSV.

Saving a recalculated workbook back as .xlsx is most of what an engine spends on it:
LibreOffice takes 13 s to load, recalculate and save the thesis workbook at 3°, and
6 s to load, recalculate and write each sheet's values as CSV; Gnumeric 5.5 s and
3.4 s.  ``verify`` and the cross-checks need the values only, so they ask for the CSV
(``recalc.computed_values``) and read it here, by the same (sheet, row, column)
blocks the defined names of the workbook they sent give.

The CSV files are the engine's, written from a workbook that passed the bounded
reader; each is still refused above a size limit before it is read.
A cell reads as the .xlsx reader gives it: a float, a str (text, or an error such as
``#DIV/0!``), a bool, or None when empty.  LibreOffice quotes every text cell, so its
text is told from its numbers exactly; Gnumeric quotes only what needs it, so a text
cell holding a number's digits reads as that number there (no crankbook result is
such a text: its q_ names hold numbers, or words such as the status cell's; the
firing order is a number per cylinder, joined as text only on the Summary, which no
name reads).  LibreOffice writes a number
formatted as a percentage or a date as it shows it ("33.3%", "1899-12-30"), so such a
cell reads as text; crankbook formats none so (its formats are fixed decimals,
exponents and words for 0 and 1, which LibreOffice writes as the number), and a
template that did would fail its engine cross-check.
"""
import re
from pathlib import Path

from crankbook.reading.xlsx_reader import Unreadable

MAX_SHEET_FILE = 200 * 1024 * 1024   # bytes of one sheet's CSV (the inline-6: ~20 MB)
# a field: quoted ("" is a quote inside it) or bare, then what ends it
FIELD = re.compile(r'(?:"([^"]*(?:""[^"]*)*)"|([^",\r\n]*))(,|\r\n|\n|\r|\Z)')
NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
BOOLEANS = {"TRUE": True, "FALSE": False}


def _bare(text):
    """A field written without quotes: a number, a bool, an error's text, or None."""
    if text == "":
        return None
    if NUMBER.match(text):
        return float(text)
    if text in BOOLEANS:
        return BOOLEANS[text]
    return text


def parse_rows(text):
    """The rows of a CSV text as lists of cell values."""
    rows, row, position, end = [], [], 0, len(text)
    while position < end:
        match = FIELD.match(text, position)
        if match is None:
            raise Unreadable(f"the engine's CSV is malformed in line {len(rows) + 1}")
        quoted, bare, stop = match.groups()
        row.append(quoted.replace('""', '"') if quoted is not None else _bare(bare))
        position = match.end()
        if stop != ",":
            rows.append(row)
            row = []
    if row:                              # the text ended on a comma: an empty last cell
        rows.append(row + [None])
    return rows


class ComputedValues:
    """One workbook's values as an engine computed them: ``values`` is the
    XlsxBook method of the same name, over the engine's CSV of each sheet."""

    def __init__(self, path, sheet_files):
        """``path``: the workbook the engine computed (for messages);
        ``sheet_files``: sheet name -> the engine's CSV of that sheet."""
        self.path = Path(path)
        self.sheet_files = dict(sheet_files)
        self._rows = {}                  # sheet -> its rows, once parsed

    def _sheet_rows(self, sheet):
        """The sheet's rows, parsed once (the whole file: a workbook's names reach
        most of its rows, and one pass over a file is cheaper than several)."""
        rows = self._rows.get(sheet)
        if rows is not None:
            return rows
        file = self.sheet_files.get(sheet)
        if file is None:
            raise Unreadable(f"the engine wrote no values for sheet {sheet!r}")
        if file.stat().st_size > MAX_SHEET_FILE:
            raise Unreadable(f"the engine's values of sheet {sheet!r} exceed "
                             f"{MAX_SHEET_FILE // 2 ** 20} MB")
        rows = self._rows[sheet] = parse_rows(file.read_text(encoding="utf-8-sig",
                                                             errors="replace"))
        return rows

    def values(self, sheet, min_row, min_col, max_row, max_col):
        """Cell values row by row (None for empty cells), as XlsxBook.values."""
        rows = self._sheet_rows(sheet)
        out = []
        for r in range(min_row - 1, max_row):
            row = rows[r] if r < len(rows) else []
            out.extend(row[c] if c < len(row) else None for c in range(min_col - 1, max_col))
        return out
