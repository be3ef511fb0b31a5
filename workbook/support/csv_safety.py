"""CSV that no spreadsheet executes and every LMS matches.

A text field that a spreadsheet would read as a formula (starting with = + - @,
a tab or a carriage return) gets a leading apostrophe; student ids never need it,
because the roster refuses ids that start with those characters, so an id in
every CSV an LMS imports (lms-import.csv, the Canvas and Moodle files) is exactly
the id the LMS knows.  The files people open in a spreadsheet (gradebook.csv, the
class manifest) write an all-digit id as ``="023105010004"`` (KeptText), which
Excel, LibreOffice and WPS show as the id itself — leading zeros and all twelve
digits — and crankbook reads back as the id.
"""
import csv
import io
import re

FORMULA_START = ("=", "+", "-", "@", "\t", "\r", "\n")
KEPT = re.compile(r'(?<![^,\n])"=""([0-9]+)"""(?=,|\n)')


class KeptText(str):
    """An id a spreadsheet must show as typed (all digits: Excel and LibreOffice would
    drop its leading zeros or show 12 digits as 2.31E+11): written ``="0231…"``,
    which both show as the text itself; :func:`as_typed` reads it back."""


def kept_text(value):
    """``value`` as :class:`KeptText` when a spreadsheet would take it for a number."""
    return KeptText(value) if isinstance(value, str) and value.isdigit() else value


def safe(value):
    """A CSV field that no spreadsheet will execute (numbers pass unchanged); a text
    that starts with an apostrophe gets one more, so :func:`as_typed` gives every
    text back exactly."""
    if isinstance(value, KeptText):
        return f'="{value}"'
    if isinstance(value, str) and value.startswith(FORMULA_START + ("'",)):
        return "'" + value
    return value


def as_typed(value):
    """The text :func:`safe` was given: a field crankbook's own CSV (the class
    manifest) stores is read back as the student or teacher typed it ('=HYPERLINK…'
    stays a name, escaped again only where it is written to a CSV)."""
    if isinstance(value, str) and value.startswith('="') and value.endswith('"') and \
            value[2:-1].isdigit():
        return value[2:-1]
    if isinstance(value, str) and value.startswith("'") and \
            value[1:2] and value[1:].startswith(FORMULA_START + ("'",)):
        return value[1:]
    return value


def csv_text(rows):
    """The rows as CSV text (UTF-8 with the caller's encoding), every field made safe;
    text in double quotes (an id such as "0231" stays text where a reader honours
    them), numbers bare."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n", quoting=csv.QUOTE_NONNUMERIC)
    for row in rows:
        writer.writerow([safe(v) for v in row])
    # a kept id goes unquoted, ="0231…", the form Excel evaluates to the text itself
    # (quoted, it would be read as the literal text ="0231…")
    return KEPT.sub(r'="\1"', buffer.getvalue())
