"""CSV that no spreadsheet executes and every LMS matches.

A text field that a spreadsheet would read as a formula (starting with = + - @,
a tab or a carriage return) gets a leading apostrophe; student ids never need it,
because the roster refuses ids that start with those characters, so an id in
every CSV crankbook writes is exactly the id the LMS knows.
"""
import csv
import io

FORMULA_START = ("=", "+", "-", "@", "\t", "\r", "\n")


def safe(value):
    """A CSV field that no spreadsheet will execute (numbers pass unchanged); a text
    that starts with an apostrophe gets one more, so :func:`as_typed` gives every
    text back exactly."""
    if isinstance(value, str) and value.startswith(FORMULA_START + ("'",)):
        return "'" + value
    return value


def as_typed(value):
    """The text :func:`safe` was given: a field crankbook's own CSV (the class
    manifest) stores is read back as the student or teacher typed it ('=HYPERLINK…'
    stays a name, escaped again only where it is written to a CSV)."""
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
    return buffer.getvalue()
