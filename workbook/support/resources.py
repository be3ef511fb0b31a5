"""The package data (crankbook.templates), found through importlib.resources.

Every TOML file is read from here, so a wheel installed anywhere behaves exactly
like the source tree.  Names are names, never paths: a name with a separator or a
dot is refused before anything is opened.
"""
import re
import tomllib
from functools import lru_cache
from importlib.resources import files

PACKAGE = "crankbook.templates"
SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*\Z")


def root():
    """The templates folder as an importlib.resources Traversable."""
    return files(PACKAGE)


def folder(*parts):
    node = root()
    for part in parts:
        node = node.joinpath(part)
    return node


def is_safe_name(name):
    """True for a plain name (letters, digits, '-', '_'): no path, no dot, no space."""
    return isinstance(name, str) and len(name) <= 64 and bool(SAFE_NAME.match(name))


def names(*parts, suffix=".toml"):
    """Sorted stems of the files with ``suffix`` in a templates folder."""
    node = folder(*parts)
    if not node.is_dir():
        return []
    return sorted(entry.name[:-len(suffix)] for entry in node.iterdir()
                  if entry.name.endswith(suffix) and entry.is_file()
                  and is_safe_name(entry.name[:-len(suffix)]))


def exists(*parts):
    return folder(*parts).is_file()


@lru_cache(maxsize=None)
def read_toml(*parts):
    """The parsed TOML file templates/<parts…> (cached: treat as read-only)."""
    return tomllib.loads(folder(*parts).read_text(encoding="utf-8"))


def read_text(*parts):
    return folder(*parts).read_text(encoding="utf-8")
