"""Named TOML data files (claims, assignments, groups): one loader, one error.

A name is a name from the list, never a path: anything else is refused before a
file is opened.
"""
from crankbook.support import resources
from crankbook.errors import UnknownPresetError


def names_in(folder):
    return resources.names(folder)


def read_named(folder, name, what, extra_choices=()):
    """The parsed templates/<folder>/<name>.toml, or UnknownPresetError listing the choices."""
    if not resources.is_safe_name(name) or not resources.exists(folder, f"{name}.toml"):
        choices = ", ".join([*names_in(folder), *extra_choices])
        shown = name if len(str(name)) <= 40 else str(name)[:40] + "…"
        raise UnknownPresetError(f"unknown {what} {shown!r}; choose one of: {choices}")
    return resources.read_toml(folder, f"{name}.toml")
