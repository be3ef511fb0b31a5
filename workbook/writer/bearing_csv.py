"""`crankbook export bearing WORKBOOK -o FILE.csv` (and ``Results.to_bearing_csv``): the
journal orbits of an engine workbook's two bearings over the second cycle, for a
bearing or plotting tool.

One row per crank angle and bearing: crank angle [°] (0 … 720, the cycle the
workbook's results read), bearing ("big end", in the rod's frame: u along the rod
toward the piston; "main N", in the engine's frame: u up), the eccentricity ratio's
components e_u/c and e_v/c, the film thickness h_min = c·(1 − ε) [µm], the film's peak
pressure p_max [MPa] (the short bearing's mid-plane, half-Sommerfeld) and whether the
row's step was held at the eccentricity limit (1: the film broke down there).  The
numbers are the workbook's (read through its names, as stored); short-bearing
mobility, optimistic at high eccentricity.  UTF-8 with a byte-order mark, written
whole or not at all.
"""
import numpy as np

from crankbook.errors import BuildOptionError
from crankbook.support.atomic import atomic_path
from crankbook.writer.exported import require_numbers
from crankbook.support.csv_safety import csv_text

ENCODING = "utf-8-sig"
NEEDED = ("orbit_angle", "orbit_eccentricity_x", "orbit_eccentricity_y", "film_thickness",
          "film_pressure", "orbit_clamped", "checked_journal")


def rows(results):
    """The rows of the orbit file (module docstring) of a Results."""
    missing = [k for k in NEEDED if k not in results.results]
    if missing:
        raise BuildOptionError(f"export bearing: the workbook has no {missing[0]} (an engine "
                               f"workbook built by this crankbook has)")
    require_numbers(results, ("checked_journal", "orbit_eccentricity_x"), "export bearing")
    angle = np.ravel(np.asarray(results["orbit_angle"], dtype=float))
    x = np.asarray(results["orbit_eccentricity_x"], dtype=float).reshape(angle.size, -1)
    y = np.asarray(results["orbit_eccentricity_y"], dtype=float).reshape(angle.size, -1)
    film = np.asarray(results["film_thickness"], dtype=float).reshape(angle.size, -1)
    pressure = np.asarray(results["film_pressure"], dtype=float).reshape(angle.size, -1)
    clamped = np.asarray(results["orbit_clamped"], dtype=float).reshape(angle.size, -1)
    journal = int(float(np.ravel(results["checked_journal"])[0]))
    names = ["big end", f"main {journal}"]
    out = [["crank angle [deg]", "bearing", "e_u/c", "e_v/c", "h_min [um]", "p_max [MPa]",
            "film broke down"]]
    for k in np.flatnonzero(angle >= 0):
        for j, name in enumerate(names):
            out.append([float(angle[k]), name, round(float(x[k, j]), 9),
                        round(float(y[k, j]), 9), round(float(film[k, j]), 6),
                        round(float(pressure[k, j]), 6), int(clamped[k, j])])
    return out


def write(results, path):
    """Write the orbit file to ``path`` (a .csv; replaced whole)."""
    from crankbook.writer.build import check_output
    table = rows(results)
    path = check_output(path, ".csv")
    with atomic_path(path) as temporary:
        with open(temporary, "w", encoding=ENCODING, newline="") as handle:
            handle.write(csv_text(table))
    return path
