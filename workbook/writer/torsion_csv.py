"""`crankbook export torsion WORKBOOK -o DIR` (and ``Results.to_torsion_csv``): the
equivalent system and the excitation as a torsional-vibration tool reads them.

* ``stations.csv`` — station (1 = the front pulley, then one per throw, the last the
  flywheel), name, J [kg·m²], k [N·m/rad] of the shaft to the next station (blank
  for the last).
* ``harmonics.csv`` — cylinder, order k, a_k and b_k [N·m]: cylinder i's gas and
  inertia torque M_i(α) = Σ a_k·cos(kα) + b_k·sin(kα) in the common crank angle α
  of cylinder 1 (its own harmonics turned by its firing angle φ_i: M_i(α) =
  M(α − φ_i + 360°)), and its throw.

The numbers are the workbook's (read through its names, as stored), in the units
above; the files are written whole into DIR or not at all.
"""
import math

import numpy as np

from crankbook.support.csv_safety import csv_text
from crankbook.errors import BuildOptionError
from crankbook.support.workspace import staged_directory


def rows(results):
    """(stations rows, harmonics rows) of a Results (computed or read)."""
    needed = ("station_inertia", "section_stiffness", "torque_order", "cylinder_torque_cosine",
              "cylinder_torque_sine")
    missing = [k for k in needed if k not in results.results]
    if missing:
        raise BuildOptionError(f"export torsion: the workbook has no {missing[0]} (an engine "
                               f"workbook built by this crankbook has)")
    inertia = np.atleast_1d(np.asarray(results["station_inertia"], dtype=float))
    stiffness = np.atleast_1d(np.asarray(results["section_stiffness"], dtype=float))
    stations = [["station", "name", "J [kg·m²]", "k to next [N·m/rad]"]]
    for number, value in enumerate(inertia, start=1):
        name = "pulley" if number == 1 else "flywheel" if number == inertia.size \
            else f"throw {number - 1}"
        stations.append([number, name, float(value),
                         float(stiffness[number - 1]) if number < inertia.size else ""])
    orders = np.atleast_1d(np.asarray(results["torque_order"], dtype=float))
    a = np.atleast_1d(np.asarray(results["cylinder_torque_cosine"], dtype=float))
    b = np.atleast_1d(np.asarray(results["cylinder_torque_sine"], dtype=float))
    firing = np.atleast_1d(np.asarray(results.parameters["firing_angle"], dtype=float))
    throw = np.atleast_1d(np.asarray(results.parameters["throw"], dtype=float))
    harmonics = [["cylinder", "throw", "order", "a_k [N·m]", "b_k [N·m]"]]
    for cylinder, (phi, t) in enumerate(zip(firing, throw), start=1):
        delta = math.radians(phi - 360.0)
        for k, ak, bk in zip(orders, a, b):
            c, s = math.cos(k * delta), math.sin(k * delta)
            harmonics.append([cylinder, int(t), float(k), float(ak * c - bk * s),
                              float(ak * s + bk * c)])
    return stations, harmonics


def write(results, directory):
    """Write stations.csv and harmonics.csv into ``directory`` (replaced whole)."""
    stations, harmonics = rows(results)
    with staged_directory(directory, replace=True) as staging:
        (staging / "stations.csv").write_text(csv_text(stations), encoding="utf-8",
                                              newline="")
        (staging / "harmonics.csv").write_text(csv_text(harmonics), encoding="utf-8",
                                               newline="")
    return directory
