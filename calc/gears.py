"""Involute spur gears with profile shift: the timing gears of the course design
(seed 001: crank gear, idler, camshaft gear; the worked report R07 §2.1).

Angles in radians, lengths in metres.  A gear train is a sequence of gears in mesh
order (crank gear first, camshaft gear last); mesh i pairs gears i and i + 1.

References
----------
Seed 001 (guide: m = 3.5 mm, α = 20°, ha* = 1; report R07 §2.1); 孙桓《机械原理》
(profile-shifted gears: no-backlash equation, centre-distance modification, tip
reduction, contact ratio, base tangent length).
"""
import numpy as np


def involute(alpha):
    """inv α = tan α − α [rad]."""
    alpha = np.asarray(alpha, dtype=float)
    return np.tan(alpha) - alpha


def inverse_involute(value, iterations=30):
    """α with inv α = ``value``, by Newton's method from α0 = (3·value)^(1/3) [rad]
    (what the workbook's Newton cells do: Excel has no inverse involute)."""
    value = np.asarray(value, dtype=float)
    alpha = np.cbrt(3 * value)
    for _ in range(iterations):
        alpha = alpha - (involute(alpha) - value) / np.tan(alpha) ** 2
    return alpha


def minimum_shift(teeth, addendum_coefficient):
    """x_min = ha*·(17 − z)/17 for z < 17, else 0: no undercut (α = 20°) [-]."""
    teeth = np.asarray(teeth, dtype=float)
    return np.where(teeth < 17, addendum_coefficient * (17 - teeth) / 17, 0.0)


def reference_diameter(teeth, module):
    """d = m·z [m]."""
    return module * np.asarray(teeth, dtype=float)


def base_diameter(reference_diameter, pressure_angle):
    """d_b = d·cos α [m]."""
    return np.asarray(reference_diameter) * np.cos(pressure_angle)


def centre_distance(teeth_1, teeth_2, module):
    """Reference centre distance a = m·(z1 + z2)/2 [m]."""
    return module * (teeth_1 + teeth_2) / 2


def working_pressure_angle_involute(shift_1, shift_2, teeth_1, teeth_2, pressure_angle):
    """inv α′ = 2·tan α·(x1 + x2)/(z1 + z2) + inv α [rad] (no backlash)."""
    return 2 * np.tan(pressure_angle) * (shift_1 + shift_2) / (teeth_1 + teeth_2) \
        + involute(pressure_angle)


def working_centre_distance(centre_distance, pressure_angle, working_pressure_angle):
    """a′ = a·cos α/cos α′ [m]."""
    return centre_distance * np.cos(pressure_angle) / np.cos(working_pressure_angle)


def centre_distance_modification(working_centre_distance, centre_distance, module):
    """y = (a′ − a)/m [-]."""
    return (working_centre_distance - centre_distance) / module


def tip_reduction(shift_1, shift_2, modification):
    """Δy = x1 + x2 − y [-]."""
    return shift_1 + shift_2 - modification


def addendum(addendum_coefficient, shift, tip_reduction, module):
    """h_a = (ha* + x − Δy)·m [m]."""
    return (addendum_coefficient + np.asarray(shift) - np.asarray(tip_reduction)) * module


def dedendum(addendum_coefficient, clearance_coefficient, shift, module):
    """h_f = (ha* + c* − x)·m [m]."""
    return (addendum_coefficient + clearance_coefficient - np.asarray(shift)) * module


def tip_pressure_angle(base_diameter, tip_diameter):
    """α_a = acos(d_b/d_a) [rad]."""
    return np.arccos(np.asarray(base_diameter) / np.asarray(tip_diameter))


def tooth_thickness(module, shift, pressure_angle):
    """Reference-circle tooth thickness s = πm/2 + 2xm·tan α [m]."""
    return np.pi * module / 2 + 2 * np.asarray(shift) * module * np.tan(pressure_angle)


def tip_thickness(tooth_thickness, reference_diameter, tip_diameter, pressure_angle,
                  tip_pressure_angle):
    """s_a = s·r_a/r − 2r_a·(inv α_a − inv α) [m]."""
    ra = np.asarray(tip_diameter) / 2
    return np.asarray(tooth_thickness) * ra / (np.asarray(reference_diameter) / 2) \
        - 2 * ra * (involute(tip_pressure_angle) - involute(pressure_angle))


def teeth_spanned(teeth, shift, pressure_angle):
    """k = round(z/π·(tan α_x − 2x·tan α/z − inv α) + 0.5), α_x = acos(z·cos α/(z + 2x)),
    a tie rounded up (z/9 + 0.5 is a tie for z = 36: rounding noise must not decide it)."""
    teeth = np.asarray(teeth, dtype=float)
    alpha_x = np.arccos(teeth * np.cos(pressure_angle) / (teeth + 2 * np.asarray(shift)))
    return np.floor(teeth / np.pi * (np.tan(alpha_x) - 2 * np.asarray(shift)
                                     * np.tan(pressure_angle) / teeth
                                     - involute(pressure_angle)) + 1.000000001)


def base_tangent_length(teeth, shift, module, pressure_angle, teeth_spanned):
    """W_k = m·cos α·[π(k − 0.5) + z·inv α] + 2xm·sin α [m]."""
    return module * np.cos(pressure_angle) * (np.pi * (np.asarray(teeth_spanned) - 0.5)
                                              + np.asarray(teeth) * involute(pressure_angle)) \
        + 2 * np.asarray(shift) * module * np.sin(pressure_angle)


def contact_ratio(teeth_1, teeth_2, tip_pressure_angle_1, tip_pressure_angle_2,
                  working_pressure_angle):
    """ε = [z1(tan α_a1 − tan α′) + z2(tan α_a2 − tan α′)]/2π [-]."""
    return (teeth_1 * (np.tan(tip_pressure_angle_1) - np.tan(working_pressure_angle))
            + teeth_2 * (np.tan(tip_pressure_angle_2) - np.tan(working_pressure_angle))) \
        / (2 * np.pi)


def train(teeth, shift, module, pressure_angle, addendum_coefficient, clearance_coefficient):
    """Every quantity of a gear train in mesh order, as a dict of arrays (per gear:
    d, da, df, db, ha, hf, αa, s, s_a, k, W; per mesh: a, α′, a′, y, Δy, ε)."""
    z = np.asarray(teeth, dtype=float)
    x = np.asarray(shift, dtype=float)
    a = centre_distance(z[:-1], z[1:], module)
    alpha_w = inverse_involute(working_pressure_angle_involute(x[:-1], x[1:], z[:-1], z[1:],
                                                               pressure_angle))
    a_w = working_centre_distance(a, pressure_angle, alpha_w)
    y = centre_distance_modification(a_w, a, module)
    dy = tip_reduction(x[:-1], x[1:], y)
    # a gear in two meshes (an idler) takes the larger tip reduction
    gear_dy = np.maximum(np.append(dy, -np.inf), np.insert(dy, 0, -np.inf))
    d = reference_diameter(z, module)
    ha = addendum(addendum_coefficient, x, gear_dy, module)
    hf = dedendum(addendum_coefficient, clearance_coefficient, x, module)
    da, df, db = d + 2 * ha, d - 2 * hf, base_diameter(d, pressure_angle)
    alpha_a = tip_pressure_angle(db, da)
    s = tooth_thickness(module, x, pressure_angle)
    k = teeth_spanned(z, x, pressure_angle)
    return {"d": d, "ha": ha, "hf": hf, "da": da, "df": df, "db": db, "alpha_a": alpha_a,
            "s": s, "s_a": tip_thickness(s, d, da, pressure_angle, alpha_a), "k": k,
            "W": base_tangent_length(z, x, module, pressure_angle, k),
            "a": a, "alpha_w": alpha_w, "a_w": a_w, "y": y, "dy": dy,
            "epsilon": contact_ratio(z[:-1], z[1:], alpha_a[:-1], alpha_a[1:], alpha_w)}


# ---------------------------------------------------------------- the workbook's columns
def mesh_count(teeth):
    """Meshes of a train: one fewer than its gears."""
    return int(np.size(teeth)) - 1


def mesh_numbers(teeth):
    """1 … number of meshes."""
    return np.arange(1, np.size(teeth), dtype=float)


def mesh_centre_distances(teeth, module):
    """a of each mesh [m]."""
    z = np.asarray(teeth, dtype=float)
    return centre_distance(z[:-1], z[1:], module)


def mesh_involutes(teeth, shift, pressure_angle):
    """inv α′ of each mesh [rad]."""
    z, x = np.asarray(teeth, dtype=float), np.asarray(shift, dtype=float)
    return working_pressure_angle_involute(x[:-1], x[1:], z[:-1], z[1:], pressure_angle)


def newton_iterates(involute_value, step_index):
    """α_k of Newton's method on inv α = value, one row per step, one column per mesh
    (the workbook's cells, step for step) [rad]."""
    value = np.asarray(involute_value, dtype=float)
    rows = [np.cbrt(3 * value)]
    for _ in range(np.size(step_index) - 1):
        a = rows[-1]
        rows.append(a - (np.tan(a) - a - value) / np.tan(a) ** 2)
    return np.vstack(rows)


def last_iterate(iterates):
    """The converged α′ of each mesh [rad]."""
    return np.asarray(iterates, dtype=float)[-1]


def mesh_tip_reductions(shift, modification):
    """Δy = x1 + x2 − y of each mesh [-]."""
    x = np.asarray(shift, dtype=float)
    return x[:-1] + x[1:] - np.asarray(modification, dtype=float)


def gear_tip_reduction(tip_reduction):
    """Per gear the larger Δy of the meshes it is in [-]."""
    dy = np.asarray(tip_reduction, dtype=float)
    before = np.concatenate([[-np.inf], dy])
    after = np.concatenate([dy, [-np.inf]])
    return np.maximum(before, after)


def plus_twice(base, extra):
    """base + 2·extra (a tip diameter)."""
    return np.asarray(base) + 2 * np.asarray(extra)


def minus_twice(base, extra):
    """base − 2·extra (a root diameter)."""
    return np.asarray(base) - 2 * np.asarray(extra)


def mesh_contact_ratios(teeth, tip_pressure_angle, working_pressure_angle):
    """ε of each mesh [-]."""
    z, aa = np.asarray(teeth, dtype=float), np.asarray(tip_pressure_angle, dtype=float)
    return contact_ratio(z[:-1], z[1:], aa[:-1], aa[1:], working_pressure_angle)


def gear_checks(gear_shift, gear_min_shift, gear_tip_thickness, gear_min_tip_thickness,
                gear_module):
    """1 per gear with x ≥ x_min and s_a ≥ the smallest tip thickness, else 0."""
    return np.where((np.asarray(gear_shift) >= np.asarray(gear_min_shift) - 1e-6)
                    & (np.asarray(gear_tip_thickness) >= gear_min_tip_thickness * gear_module),
                    1.0, 0.0)


def tip_not_pointed(tip_thickness):
    """1 per gear whose tip is thicker than nothing, else 0."""
    return np.where(np.asarray(tip_thickness) > 0, 1.0, 0.0)


def train_ratio(teeth):
    """Crank to camshaft: z_last/z_first (idlers do not change it) [-]."""
    z = np.asarray(teeth, dtype=float)
    return z[-1] / z[0]
