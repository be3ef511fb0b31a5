"""Open untrusted workbooks safely: bounded in size and time, never running macros,
refusing what could hang or exhaust the machine.  Every refusal is a reason string
for the gradebook's `unreadable` status, never an exception."""
import signal
import zipfile
from contextlib import contextmanager
from pathlib import Path

import openpyxl

MAX_FILE = 20 * 1024 * 1024           # bytes on disk
MAX_UNPACKED = 100 * 1024 * 1024      # bytes, all members together
MAX_RATIO = 200                       # per member: uncompressed / compressed
MAX_MEMBERS = 2000
TIME_LIMIT = 30                       # seconds to parse one workbook
OLE_MAGIC = b"\xd0\xcf\x11\xe0"


class Unreadable(Exception):
    """Why a submission could not be read."""


def check_container(path):
    """Raise Unreadable with the reason when ``path`` is not a plain, sane .xlsx."""
    path = Path(path)
    size = path.stat().st_size
    if size > MAX_FILE:
        raise Unreadable(f"file is {size / 1e6:.0f} MB, more than {MAX_FILE // 2**20} MB")
    with open(path, "rb") as handle:
        head = handle.read(8)
    if head.startswith(OLE_MAGIC):
        raise Unreadable("password-protected (encrypted) or legacy .xls workbook")
    if path.suffix.lower() == ".xlsm":
        raise Unreadable("macro-enabled workbook (.xlsm): not opened; save as .xlsx")
    if not zipfile.is_zipfile(path):
        raise Unreadable("not an .xlsx file (not a zip container)")
    try:
        with zipfile.ZipFile(path) as archive:
            members = archive.infolist()
            if len(members) > MAX_MEMBERS:
                raise Unreadable(f"{len(members)} parts in the zip: not a workbook")
            names = {m.filename for m in members}
            if "xl/vbaProject.bin" in names:
                raise Unreadable("contains macros (vbaProject.bin): not opened")
            if "xl/workbook.xml" not in names:
                raise Unreadable("a zip file but not an .xlsx workbook")
            total = 0
            for member in members:
                total += member.file_size
                if total > MAX_UNPACKED:
                    raise Unreadable("unpacks to more than 100 MB (zip bomb?)")
                if member.file_size > MAX_RATIO * max(member.compress_size, 1) and \
                        member.file_size > 1024 * 1024:
                    raise Unreadable(f"{member.filename} is compressed {MAX_RATIO}:1 or more "
                                     f"(zip bomb?)")
            for member in members:
                if member.filename.endswith((".xml", ".rels")):
                    with archive.open(member) as stream:
                        chunk = stream.read(MAX_UNPACKED)
                    if b"<!DOCTYPE" in chunk or b"<!ENTITY" in chunk:
                        raise Unreadable(f"{member.filename} declares XML entities "
                                         f"(entity bomb?): not parsed")
    except zipfile.BadZipFile as error:
        raise Unreadable(f"corrupt zip ({error})") from None


@contextmanager
def time_limit(seconds):
    def stop(signum, frame):
        raise Unreadable(f"took longer than {seconds} s to read")
    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def open_untrusted(path, data_only=True):
    """An openpyxl workbook of a checked file, or Unreadable."""
    check_container(path)
    try:
        with time_limit(TIME_LIMIT):
            return openpyxl.load_workbook(path, data_only=data_only, read_only=False,
                                          keep_vba=False, keep_links=False)
    except Unreadable:
        raise
    except Exception as error:  # openpyxl raises many kinds for broken files
        raise Unreadable(f"cannot be read as a workbook ({type(error).__name__})") from None
