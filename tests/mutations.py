"""A seeded corpus of damaged and hostile workbooks, made from the project's own files.

Each mutation takes the bytes of a good .xlsx and returns the bytes of a bad one, the
way a careless user, a broken upload or an attacker would make it: flipped bytes, a
truncated file, zip parts deleted, renamed, duplicated or recompressed, and defined
names, cells and parts rewritten to point at whole sheets, missing sheets, chart
sheets, other files, or to hold 0, 1e308, text and entity declarations.  The same
seed gives the same corpus.
"""
import io
import random
import re
import zipfile

HOSTILE_REFERENCES = [
    "'{sheet}'!$A$1:$XFD$1048576",          # a whole sheet
    "'{sheet}'!$A:$XFD",                    # every column
    "'{sheet}'!$B:$B",                      # a whole column
    "'{sheet}'!$3:$3",                      # a whole row
    "'{sheet}!$B$2",                        # an unterminated quote
    "'No such sheet'!$B$2",                 # a missing sheet
    "[1]Sheet1!$A$1",                       # another file
    "'{sheet}'!$B$2:$B$900000",             # far larger than the template's shape
    "#REF!",
    "'{sheet}'!$ZZZZ$1",                    # not a cell
    "",
]
HOSTILE_VALUES = ["0", "1e308", "-1e308", "NaN", "1e-320", "-0", "abc", "1" * 400]


def _parts(data):
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        return [(info, archive.read(info.filename)) for info in archive.infolist()]


def _zip(parts, method=zipfile.ZIP_DEFLATED):
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", method) as archive:
        for info, body in parts:
            name = info.filename if isinstance(info, zipfile.ZipInfo) else info
            archive.writestr(name, body)
    return buffer.getvalue()


def flip_bytes(data, rng):
    out = bytearray(data)
    for _ in range(rng.randint(1, 12)):
        out[rng.randrange(len(out))] = rng.randrange(256)
    return bytes(out)


def truncate(data, rng):
    return data[:rng.randrange(1, len(data))]


def append_junk(data, rng):
    return data + bytes(rng.randrange(256) for _ in range(rng.randint(1, 4096)))


def delete_part(data, rng):
    parts = _parts(data)
    parts.pop(rng.randrange(len(parts)))
    return _zip(parts)


def rename_part(data, rng):
    parts = _parts(data)
    index = rng.randrange(len(parts))
    info, body = parts[index]
    parts[index] = (info.filename + rng.choice(["x", ".bak", "/"]), body)
    return _zip(parts)


def duplicate_part(data, rng):
    parts = _parts(data)
    parts.append(parts[rng.randrange(len(parts))])
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return _zip(parts)


def stored(data, rng):
    return _zip(_parts(data), zipfile.ZIP_STORED)


def damage_compressed(data, rng):
    """Flip bytes inside one compressed part's data (a CRC or zlib error)."""
    out = bytearray(data)
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        infos = [i for i in archive.infolist() if i.compress_size > 16]
    info = rng.choice(infos)
    start = info.header_offset + 30 + len(info.filename.encode()) + len(info.extra)
    for _ in range(4):
        out[start + rng.randrange(info.compress_size)] ^= 0xFF
    return bytes(out)


def _rewrite(data, name, change):
    parts = []
    for info, body in _parts(data):
        if info.filename == name:
            body = change(body)
        parts.append((info, body))
    return _zip(parts)


def _first_sheet_name(data):
    book = dict((i.filename, b) for i, b in _parts(data))["xl/workbook.xml"].decode()
    return re.search(r'<sheet name="([^"]+)"', book).group(1)


def hostile_name(data, rng):
    """Point one defined name (a_, p_, q_) at a hostile reference."""
    sheet = _first_sheet_name(data)
    reference = rng.choice(HOSTILE_REFERENCES).format(sheet=sheet)

    def change(body):
        text = body.decode()
        names = re.findall(r'<definedName name="([^"]+)"[^>]*>', text)
        target = rng.choice([n for n in names if n[:2] in ("a_", "p_", "q_")] or names)
        return re.sub(rf'(<definedName name="{re.escape(target)}"[^>]*>)[^<]*(<)',
                      lambda m: m.group(1) + reference.replace("&", "&amp;")
                      .replace("<", "&lt;") + m.group(2), text, count=1).encode()
    return _rewrite(data, "xl/workbook.xml", change)


def shrink_name(data, rng):
    """Shorten one block name (q_ or a_ over several rows) to fewer rows."""
    def change(body):
        text = body.decode()
        blocks = [(name, int(first), int(last)) for name, first, last in re.findall(
            r'<definedName name="([qa]_[^"]+)"[^>]*>[^<]*\$(\d+):\$[A-Z]+\$(\d+)<', text)
            if int(last) > int(first)]
        name, first, last = rng.choice(blocks)
        end = first + rng.randint(0, min(4, last - first - 1))
        return re.sub(rf'(<definedName name="{re.escape(name)}"[^>]*>[^<]*\${first}:\$[A-Z]+\$)'
                      rf'{last}<', lambda m: f"{m.group(1)}{end}<", text, count=1).encode()
    return _rewrite(data, "xl/workbook.xml", change)


def _edit_a_sheet(data, rng, change):
    """``change`` (text -> text) applied to one worksheet part chosen at random."""
    parts = _parts(data)
    sheets = [i for i, (info, _) in enumerate(parts)
              if info.filename.startswith("xl/worksheets/sheet")]
    index = rng.choice(sheets)
    info, body = parts[index]
    parts[index] = (info, change(body.decode()).encode())
    return _zip(parts)


def hostile_value(data, rng):
    """Replace some numeric cached values of a sheet with extreme or non-numbers."""
    def change(text):
        values = list(re.finditer(r"<v>([^<]*)</v>", text))
        for match in rng.sample(values, min(len(values), rng.randint(1, 5))):
            text = text.replace(match.group(0), f"<v>{rng.choice(HOSTILE_VALUES)}</v>", 1)
        return text
    return _edit_a_sheet(data, rng, change)


def entity_declaration(data, rng):
    """An entity declaration, in UTF-8 or UTF-16, in some part."""
    bomb = b'<?xml version="1.0"?><!DOCTYPE x [<!ENTITY a "aaaa"><!ENTITY b "&a;&a;">]>'
    parts = _parts(data)
    xml = [i for i, (info, _) in enumerate(parts) if info.filename.endswith(".xml")]
    index = rng.choice(xml)
    info, body = parts[index]
    body = re.sub(rb"^<\?xml[^>]*\?>", b"", body)
    body = bomb + body
    if rng.random() < 0.5:
        body = b"\xff\xfe" + body.decode().replace('version="1.0"?>',
                                                   'version="1.0" encoding="UTF-16"?>',
                                                   1).encode("utf-16-le")
    parts[index] = (info, body)
    return _zip(parts)


def macro_part(data, rng):
    """A macro part under an innocent or a usual name."""
    parts = _parts(data)
    name = rng.choice(["xl/vbaProject.bin", "xl/VBAPROJECT.BIN", "xl/macros/code.bin",
                       "xl/media/image1.png"])
    parts.append((name, b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + b"Attribute VB_Name = x" * 4))
    return _zip(parts)


def damaged_formula(data, rng):
    """Unbalanced quotes and parentheses in formulas."""
    def change(text):
        text = re.sub(r"<f>([^<]{3})", lambda m: "<f>\"'(" + m.group(1), text, count=5)
        return re.sub(r'<f t="shared"([^>]*)>', r'<f t="shared" ref="ZZ" si="x"\1>', text)
    return _edit_a_sheet(data, rng, change)


MACHINE = ['CELL("filename")', 'INFO("system")', '[1]Sheet1!$A$1', 'INDIRECT("A"&ROW())',
           'WEBSERVICE("http://x")', '_xlfn.FILTERXML("<a/>","a")']


def _answer_cell(data, rng):
    """(sheet part, cell) of one a_ name's first cell."""
    parts = dict((i.filename, b) for i, b in _parts(data))
    book = parts["xl/workbook.xml"].decode()
    rels = parts["xl/_rels/workbook.xml.rels"].decode()
    found = re.findall(r'<definedName name="a_[^"]+"[^>]*>\'?([^\'!<]+)\'?!\$([A-Z]+)\$(\d+)', book)
    sheet, column, row = rng.choice(found)
    rid = re.search(rf'<sheet name="{re.escape(sheet)}"[^>]*r:id="([^"]+)"', book)
    target = re.search(rf'Id="{rid.group(1)}"[^>]*Target="([^"]+)"|Target="([^"]+)"[^>]*'
                       rf'Id="{rid.group(1)}"', rels)
    return "xl/" + (target.group(1) or target.group(2)).lstrip("/").replace("xl/", ""), \
        f"{column}{row}"


def machine_chain(data, rng):
    """An answer computed from the machine: directly, through another cell, through
    itself (a cycle), through a huge range or a shared formula with no master; the
    cached values kept, so only the reference chain tells."""
    part, cell = _answer_cell(data, rng)

    def change(body):
        text = body.decode()
        others = [c for c in re.findall(r'<c r="([A-Z]+\d+)"', text) if c != cell]
        helper = rng.choice(others)
        taint = rng.choice(MACHINE)
        answer = rng.choice([f"{helper}*1", f"SUM(A1:{helper})", cell, f"{helper}&{cell}",
                             taint])
        for ref, formula in ((helper, taint), (cell, answer)):
            element = rf'<c r="{ref}"(?:[^>]*/>|[^>]*>.*?</c>)'
            shape = rng.choice(["plain", "shared", "array"])
            f = {"plain": f"<f>{formula}</f>",
                 "shared": f'<f t="shared" si="7" ref="{ref}:{ref}">{formula}</f>',
                 "array": f'<f t="array" ref="{ref}:XFD1048576">{formula}</f>'}[shape]
            new = f'<c r="{ref}" t="str">{f.replace("&", "&amp;")}<v>0</v></c>'
            text = re.sub(element, lambda m: new, text, count=1, flags=re.S)
        if rng.random() < 0.3:                 # a follower whose master is missing
            text = re.sub(r'<c r="([A-Z]+\d+)"([^>]*)>(<v>)', r'<c r="\1"\2><f t="shared" si="99"/>\3',
                          text, count=3)
        return text.encode()
    return _rewrite(data, part, change)


def planted_parts(data, rng):
    """What a hostile hand-in carries for the returned file: an external link part, a
    hyperlink, a hidden sheet state."""
    parts = _parts(data)
    parts.append(("xl/externalLinks/externalLink1.xml",
                  b'<externalLink xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/'
                  b'main"><externalBook/></externalLink>'))
    out = []
    for info, body in parts:
        name = info if isinstance(info, str) else info.filename
        if name == "xl/workbook.xml" and rng.random() < 0.5:
            body = re.sub(rb'<sheet ([^>]*?)(?: state="[^"]*")?([^>]*)>', rb'<sheet \1\2 state="veryHidden">',
                          body, count=1)
        if name.startswith("xl/worksheets/sheet") and rng.random() < 0.5:
            body = body.replace(b"</worksheet>", b'<hyperlinks><hyperlink ref="A1" '
                                b'location="x"/></hyperlinks></worksheet>')
        out.append((info, body))
    return _zip(out)


def not_a_workbook(data, rng):
    return rng.choice([b"", b"PK\x03\x04", b"\xd0\xcf\x11\xe0" + b"\0" * 600,
                       "学生作业".encode("gbk") * 50, _zip([("hello.txt", b"hi")])])


MUTATIONS = [flip_bytes, truncate, append_junk, delete_part, rename_part, duplicate_part,
             stored, damage_compressed, hostile_name, shrink_name, hostile_value, entity_declaration,
             macro_part, damaged_formula, not_a_workbook, machine_chain, planted_parts]


def corpus(data, count, seed):
    """``count`` (mutation name, bytes) made from ``data``; the same seed, the same list."""
    rng = random.Random(seed)
    out = []
    for number in range(count):
        mutation = MUTATIONS[number % len(MUTATIONS)]
        try:
            out.append((mutation.__name__, mutation(data, rng)))
        except (ValueError, IndexError, zipfile.BadZipFile, AttributeError):
            out.append((mutation.__name__, flip_bytes(data, rng)))
    return out
