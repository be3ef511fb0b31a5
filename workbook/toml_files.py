"""Named TOML data files (presets, claims, assignments): one loader, one error."""
import tomllib

from workbook.errors import UnknownPresetError


def names_in(directory):
    return sorted(path.stem for path in directory.glob("*.toml"))


def read_named(directory, name, what, extra_choices=()):
    """The parsed ``directory/<name>.toml``, or UnknownPresetError listing the choices."""
    path = directory / f"{name}.toml"
    if not path.is_file():
        choices = ", ".join([*names_in(directory), *extra_choices])
        raise UnknownPresetError(f"unknown {what} {name!r}; choose one of: {choices}")
    with open(path, "rb") as handle:
        return tomllib.load(handle)
