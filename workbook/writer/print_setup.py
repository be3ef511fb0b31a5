"""Page setup shared by the sheet writers: A4 landscape, one page wide, headers
repeated on every page."""
import math
import re
from functools import lru_cache

from crankbook.writer.layout import FIRST_ROW

A4 = 9
PRINTABLE_POINTS = (842 - 2 * 0.7 * 72, 595 - 2 * 0.75 * 72)   # A4 landscape less the
                                                                # default margins
# a key (Consolas 10 pt, or LibreOffice's fallback DejaVu Sans Mono where Consolas is
# missing: 8 px a glyph) in a column whose unit is the default font's digit (7 px)
KEY_COLUMNS_PER_CHARACTER = 1.15
READABLE_SCALE = 0.62             # 10-point text printed at 6.2 points
NO_PRINT = (0, 16383, 0, 16383)   # a print area on an always-empty cell: the sheet is
                                  # skipped when the whole workbook prints


def key_width(keys, minimum):
    """Width (characters) of a column of keys in the key style that shows the longest
    whole: a key cannot wrap, and its neighbour (the value) stops it at the column's
    edge on the screen and on paper."""
    # a Latin character counts 1 (0.85 of a column at Arial 10), a CJK glyph twice
    # that: an axis's named items ("杆身失稳（运动平面内）") are keys too
    longest = max((_glyphs_width(k) / 0.85 for k in keys), default=0)
    return max(minimum, math.ceil(longest * KEY_COLUMNS_PER_CHARACTER + 1))


@lru_cache(maxsize=8192)       # the same labels come back on every sheet and every student
def text_lines(text, width, size=10, bold=False):
    """Lines a wrapped text takes in a cell ``width`` characters wide (Arial ``size``
    pt), by wrapping it word by word as the engines do, on the generous side, so a
    row sized by it never cuts its text (an engine does not fit a row to wrapped text
    it loads with a height of its own).  Widths measured in LibreOffice's PDFs at
    10 pt, in a column's characters: a CJK glyph 1.7 (a line may break after any), a
    Latin letter 0.85, a Greek letter or symbol 1.0; all scale with the font, bold
    5 % wider."""
    scale = size / 10 * (1.05 if bold else 1.0)
    room = max(width - 1, 1)                                    # the cell's padding
    return sum(_wrapped_lines(line, room, scale) for line in str(text).split("\n"))


def _glyphs_width(text):
    """Characters of column ``text`` takes at Arial 10 (see ``text_lines``); the
    supplemental mathematical operators (⨯ in the seeds' extracted formulas) come from
    a wide fallback font, as wide as a CJK glyph."""
    return sum(1.7 if ord(ch) > 0x2E7F or 0x2A00 <= ord(ch) <= 0x2AFF
               else 0.85 if ord(ch) < 0x80 else 1.0 for ch in text)


def _wrapped_lines(line, room, scale):
    lines, used = 1, 0.0
    for token in re.findall(r"[\u2e80-\uffff]|[^\s\u2e80-\uffff]+\s*|\s+", line):
        size = scale * _glyphs_width(token.rstrip())
        if used and used + size > room:                         # the word moves down
            lines, used = lines + 1, 0.0
        while size > room:                                      # a word wider than the cell
            lines, size = lines + 1, size - room
        used += size + scale * 0.85 * (len(token) - len(token.rstrip()))
    return lines


def format_words_width(fmt):
    """Characters of column the widest word a number format shows needs ("balanced
    平衡"): a number shown through a text format cannot spill into the next cell."""
    words = re.findall(r'"([^"]*)"', fmt or "")
    return max((_glyphs_width(word) + 2 for word in words), default=0)


def line_height(size=10):
    """Points of one line of Arial ``size`` pt in a row."""
    return round(size * 1.25, 1)


def row_points(texts, bold=False):
    """Points of a row whose wrapped cells hold ``texts`` — [(text, width in
    characters)] — as tall as the longest (at most Excel's 409), so a printed row
    never runs into the next."""
    lines = max(text_lines(text, width, bold=bold) for text, width in texts)
    return min(409.0, lines * line_height() + 1.5)


def wrapped_texts(ws, row, texts, fmt):
    """Texts wrapped in their cells — ``texts`` {column: (text, width in characters)}
    — and the row as tall as the longest."""
    for col, (text, width) in texts.items():
        ws.write(row, col, text, fmt)
    ws.set_row(row, row_points(texts.values()))


def wrapped_title(ws, row, text, widths, fmt):
    """A title merged across the table's columns (``widths`` in characters), wrapped,
    its row as tall as its lines: a printed page never cuts it."""
    last = len(widths) - 1
    if last < 1:
        ws.write(row, 0, text, fmt)
        return
    size = fmt.font_size
    lines = text_lines(text, sum(widths), size, fmt.bold)
    ws.merge_range(row, 0, row, last, text, fmt)
    ws.set_row(row, lines * line_height(size) + 4)


def landscape_report(ws, layout, sheet_spec, rows, last_col, chart_col):
    """A series table: portrait when it has a few columns (a whole coarse-step table
    on one page), landscape when wide; one page wide either way."""
    ws.set_paper(A4)
    if last_col <= 8:
        ws.set_portrait()
    else:
        ws.set_landscape()
    ws.set_margins(left=0.5, right=0.4, top=0.5, bottom=0.5)
    ws.fit_to_pages(1, 0)
    ws.repeat_rows(FIRST_ROW - 3, FIRST_ROW - 1)
    ws.repeat_columns(0, 0)


def wide_table_page(ws, widths, who_columns):
    """A4 landscape for a table of many columns (a gradebook), its header row on every
    page: one page wide where that keeps its text at READABLE_SCALE or larger, else at
    that scale over pages across, each starting with the ``who_columns`` first columns
    (whose row it is)."""
    ws.set_paper(A4)
    ws.set_landscape()
    ws.repeat_rows(0)
    if print_scale(widths) >= READABLE_SCALE:
        ws.fit_to_pages(1, 0)
    else:
        ws.set_print_scale(round(100 * READABLE_SCALE))
        ws.repeat_columns(0, who_columns - 1)


def print_scale(widths, printable=PRINTABLE_POINTS[0]):
    """The fraction of full size at which columns ``widths`` (characters) fit across
    ``printable`` points: LibreOffice draws a character of the columns' Arial 10 eight
    pixels wide (Excel seven), so the estimate holds for both."""
    return min(1.0, printable * 4 / 3 / sum(8 * w + 5 for w in widths))


def row_height(ws, row, unset):
    """Points of a worksheet's ``row`` as set (xlsxwriter keeps pixels), else ``unset``."""
    return ws.row_sizes[row][0] * 0.75 if row in ws.row_sizes else unset


def landscape_page(ws, widths=None, last_row=None):
    """A4 landscape, one page wide (tables of a few dozen rows).  Given the columns'
    ``widths`` (characters) and the last printed row, a table whose last page would
    hold under a third of a page is shrunk onto one page fewer instead, and one
    estimated to end near a page's foot is held to its estimated pages."""
    ws.set_paper(A4)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)
    if widths is None:
        return
    scale = print_scale(widths)
    # LibreOffice makes a row of its own height up to 17 pt tall (with CJK glyphs)
    points = sum(row_height(ws, row, 17) for row in range(last_row + 1))
    pages = points * scale / PRINTABLE_POINTS[1]
    if pages > 1 and pages % 1 < 1 / 3:
        ws.fit_to_pages(1, int(pages))
    elif pages % 1 > 0.85:
        # the estimate is near a page's end, and the engines' fonts can spill a few
        # rows onto a page of their own: at most the pages estimated (no effect when
        # they fit anyway; an engine never enlarges)
        ws.fit_to_pages(1, math.ceil(pages))
