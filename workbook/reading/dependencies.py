"""Which cells a formula depends on, far enough to tell whether an answer's value is
the grading machine's rather than the student's calculation.

A handed-in workbook may compute an answer from a helper cell, a defined name or
a chain of them that ends in ``CELL("filename")``, ``INFO("system")``,
``WEBSERVICE``, ``FILTERXML``, ``RTD``, a DDE link or another file.  Recalculated
on the grader's machine, such an answer would carry the grader's paths, system or
network to the student, so the answer is refused with a reason.  The trace follows
cell references, ranges (only the formula cells inside them), whole rows and
columns, sheet references and defined names (global or local to a sheet); a
shared formula's follower is read as its master moved to its place.  A formula
that picks its reference at run time (``INDIRECT``, ``OFFSET``) in a workbook that
holds such a function anywhere counts as depending on it, and so does a chain too
long to follow within the budget: the rule errs towards refusing.

Everything here reads the bounded reader's cells (crankbook.reading.xlsx_reader);
nothing is evaluated.
"""
import re

# the functions whose value is the machine's (paths, system) or the network's
ENVIRONMENT = re.compile(r"(?<![A-Za-z0-9_.])(?:_xlfn\.)?(?:CELL|INFO|WEBSERVICE|FILTERXML|RTD|"
                         r"DDE|FILENAME)\s*\(", re.I)
# another file: OOXML's [n] index of an external link, a bracketed file name, a
# URL or UNC path, a DDE topic (app|topic!item)
EXTERNAL = re.compile(r"\[\d+\]|\[[^\]]*\.(?:xl[a-z]*|ods|csv|txt)\]|file:|https?:|\\\\|"
                      r"[A-Za-z0-9_]\|", re.I)
# a reference whose target is chosen when the formula runs
DYNAMIC = re.compile(r"(?<![A-Za-z0-9_.])(?:INDIRECT|OFFSET)\s*\(", re.I)
STRING = re.compile(r'"(?:[^"]|"")*"')
SHEET = r"(?:'(?:[^']|'')+'|[^\s'!:,()+\-*/^&=<>;{}\"]+)"
REFERENCE = re.compile(
    rf"(?:(?P<sheet>{SHEET})!)?(?:"
    r"(?P<c1>\$?[A-Za-z]{1,3})(?P<r1>\$?[0-9]{1,7})(?::(?P<c2>\$?[A-Za-z]{1,3})(?P<r2>\$?[0-9]{1,7}))?"
    r"|(?P<cc1>\$?[A-Za-z]{1,3}):(?P<cc2>\$?[A-Za-z]{1,3})"
    r"|(?P<rr1>\$?[0-9]{1,7}):(?P<rr2>\$?[0-9]{1,7}))(?![A-Za-z0-9_(])")
NAME = re.compile(r"(?<![A-Za-z0-9_.$!'\\])([A-Za-z_\\\u00c0-\uffff][A-Za-z0-9_.\u00c0-\uffff]*)"
                  r"(?![A-Za-z0-9_.\u00c0-\uffff]*\s*[(!])")
LAST_ROW, LAST_COL = 1_048_576, 16_384
BUDGET = 200_000                    # cells and names looked at per answer, at most


def tainted(text):
    """Whether a formula or a name's text asks the machine, the network or another
    file directly."""
    if not text:
        return False
    bare = STRING.sub('""', text)
    return bool(ENVIRONMENT.search(text) or EXTERNAL.search(bare))


def _column_number(letters):
    number = 0
    for char in letters.upper():
        number = number * 26 + ord(char) - 64
    return number


def _column_letters(number):
    letters = ""
    while number > 0:
        number, rest = divmod(number - 1, 26)
        letters = chr(65 + rest) + letters
    return letters


def moved(text, rows, cols):
    """A formula moved ``rows`` down and ``cols`` right, as a shared formula's
    follower reads its master: relative parts move, ``$`` parts stay."""
    def move_column(part):
        if part.startswith("$"):
            return part
        return _column_letters(max(1, _column_number(part) + cols))

    def move_row(part):
        if part.startswith("$"):
            return part
        return str(max(1, int(part) + rows))

    def one(match):
        sheet = f"{match.group('sheet')}!" if match.group("sheet") else ""
        if match.group("c1"):
            out = move_column(match.group("c1")) + move_row(match.group("r1"))
            if match.group("c2"):
                out += ":" + move_column(match.group("c2")) + move_row(match.group("r2"))
        elif match.group("cc1"):
            out = move_column(match.group("cc1")) + ":" + move_column(match.group("cc2"))
        else:
            out = move_row(match.group("rr1")) + ":" + move_row(match.group("rr2"))
        return sheet + out

    pieces, last = [], 0
    for literal in STRING.finditer(text):      # never move what is inside a string
        pieces.append(REFERENCE.sub(one, text[last:literal.start()]))
        pieces.append(literal.group())
        last = literal.end()
    pieces.append(REFERENCE.sub(one, text[last:]))
    return "".join(pieces)


def _sheet_name(raw, here):
    if raw is None:
        return here
    return raw[1:-1].replace("''", "'") if raw.startswith("'") else raw


def references(text, here):
    """(cells and ranges, names) a formula of sheet ``here`` refers to: ranges as
    (sheet, first row, first column, last row, last column)."""
    bare = STRING.sub('""', text)
    ranges = []
    for match in REFERENCE.finditer(bare):
        sheet = _sheet_name(match.group("sheet"), here)
        if match.group("c1"):
            c1 = _column_number(match.group("c1").lstrip("$"))
            r1 = int(match.group("r1").lstrip("$"))
            c2 = _column_number(match.group("c2").lstrip("$")) if match.group("c2") else c1
            r2 = int(match.group("r2").lstrip("$")) if match.group("r2") else r1
        elif match.group("cc1"):
            c1 = _column_number(match.group("cc1").lstrip("$"))
            c2 = _column_number(match.group("cc2").lstrip("$"))
            r1, r2 = 1, LAST_ROW
        else:
            r1, r2 = int(match.group("rr1").lstrip("$")), int(match.group("rr2").lstrip("$"))
            c1, c2 = 1, LAST_COL
        ranges.append((sheet, min(r1, r2), min(c1, c2), max(r1, r2), max(c1, c2)))
    rest = REFERENCE.sub(" ", bare)
    names = [m.group(1) for m in NAME.finditer(rest)
             if m.group(1).upper() not in ("TRUE", "FALSE")]
    return ranges, names


class MachineTrace:
    """Answers of one workbook checked for a dependence on the machine."""

    def __init__(self, book):
        self.book = book
        self.sheets = [s for s in book.sheetnames if s not in book.chart_sheets]
        self._anywhere = None
        self._formula_cells = {}
        self._clean = set()          # nodes whose whole chain was followed: nothing found

    @property
    def anywhere(self):
        """Whether the workbook asks the machine or another file anywhere at all."""
        if self._anywhere is None:
            book = self.book
            self._anywhere = bool(book.external_links) or \
                any(tainted(t) for t in (*book.defined_names.values(),
                                         *book.local_names.values())) or \
                any(tainted(book.formula_at(s, r, c)) for s in self.sheets
                    for r, c in self._cells_of(s))
        return self._anywhere

    def _cells_of(self, sheet):
        if sheet not in self._formula_cells:
            self._formula_cells[sheet] = self.book.formula_cells(sheet)
        return self._formula_cells[sheet]

    def depends(self, sheet, row, col):
        """Whether the cell's value depends on the machine (see the module docstring)."""
        if not self.anywhere:
            return False
        book = self.book
        start = ("cell", sheet, row, col)
        seen, queue, work = {start}, [start], 0
        while queue:
            node = queue.pop()
            if node in self._clean:
                continue
            work += 1
            if work > BUDGET:
                return True
            if node[0] == "name":
                text = book.defined_names.get(node[1]) or book.local_names.get(node[1])
                here = node[2]
            else:
                _, here, r, c = node
                text = book.formula_at(here, r, c) if here in self.sheets else None
            if text is None:
                continue
            if text == "" or tainted(text) or DYNAMIC.search(text):
                return True                 # unreadable follower, or the machine itself
            ranges, names = references(text, here)
            for target, r1, c1, r2, c2 in ranges:
                if target not in self.sheets:
                    continue
                if r1 == r2 and c1 == c2:
                    found = [(r1, c1)]
                else:
                    cells = self._cells_of(target)
                    work += len(cells)
                    found = [(r, c) for r, c in cells if r1 <= r <= r2 and c1 <= c <= c2]
                    # an array formula's area overlapping the range: its master
                    found += [(a, b) for a, b, a2, b2 in book.array_areas(target)
                              if a <= r2 and a2 >= r1 and b <= c2 and b2 >= c1]
                for r, c in found:
                    next_node = ("cell", target, r, c)
                    if next_node not in seen:
                        seen.add(next_node)
                        queue.append(next_node)
            for name in names:
                if name in book.defined_names or name in book.local_names:
                    next_node = ("name", name, here)
                    if next_node not in seen:
                        seen.add(next_node)
                        queue.append(next_node)
        self._clean |= seen
        return False
