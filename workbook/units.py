"""Sheet units: conversion factors to SI and number formats (templates/units.toml)."""
import tomllib
from functools import lru_cache
from pathlib import Path

UNITS_FILE = Path(__file__).resolve().parent.parent / "templates" / "units.toml"


@lru_cache(maxsize=None)
def _table():
    with open(UNITS_FILE, "rb") as handle:
        return tomllib.load(handle)["unit"]


def si_factor(unit):
    """Factor that turns a value in ``unit`` into SI."""
    try:
        return _table()[unit]["si"]
    except KeyError:
        raise KeyError(f"unit {unit!r} is not defined in {UNITS_FILE.name}") from None


def number_format(unit):
    """Excel number format for cells in ``unit``."""
    return _table()[unit]["format"]


def known(unit):
    return unit in _table()
