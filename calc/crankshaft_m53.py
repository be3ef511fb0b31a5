"""Crankshaft fatigue by IACS UR M53, "Calculation of crankshafts for I.C. engines".

The rule checks one throw, statically determinate between the centres of its two
main journals, at three places: the crankpin fillet, the journal fillet and the
outlet of the crankpin's oil bore.  At each it forms an equivalent alternating stress
σ_v from nominal stresses times stress-concentration factors (closed-form fits of
FVV's strain-gauge measurements, valid only inside stated ranges of the throw's
ratios), a fatigue strength σ_DW of the material, the diameter and the notch radius,
and asks for the acceptability factor Q = σ_DW/σ_v ≥ 1.15.

* Lengths (§2.1): L3 between the main journals' centres, L2 from a main journal's
  centre to the crankpin's (L3/2 for a symmetric throw), L1 from a main journal's
  centre to the web's centre.  A rod force F at L2 gives the web, at L1, the bending
  moment F·L1·(L3 − L2)/L3 and the shear force F·(L3 − L2)/L3, and the crankpin's
  centre (the oil bore) F·L2·(L3 − L2)/L3.
* Nominal alternating stresses: half the range over the working cycle of the web's
  bending σ_BN = M_BN/W_eqw (W_eqw = B·W²/6) and shear σ_QN = Q_N/(B·W) from the radial
  force, the oil bore's bending σ_BON = M_BON/W_e (M_BO = M_BT·cos ψ + M_BR·sin ψ), and
  the pin's and journal's torsion τ_N = M_TN/W_P.
* Stress concentration factors (§3) of the ratios to the crankpin diameter D:
  r = R/D, s = S/D (S = (D + D_G)/2 − E the overlap), w = W/D, b = B/D, d_O, d_G, d_H
  (bores), t_H, t_G (recesses).  Outside the ranges the fits were made for the rule
  asks for measured or finite-element factors: the values are still computed here,
  and :func:`validity` says which ratio is out.
* σ_v = √((σ_B + σ_add)² + 3τ²) in the fillets; at the oil bore
  σ_v = ⅓·σ_BO·(1 + 2·√(1 + 9/4·(τ_TO/σ_BO)²)), written without the division.
* σ_DW = K·(0.42·σ_T + 39.3)·[0.264 + 1.073·D^−0.2 + (785 − σ_T)/4900
  + (196/σ_T)·√(1/R_X)] in MPa and mm (§6), with the journal's diameter in the
  journal fillet, R_X the fillet radius or half the oil bore, K ≤ 1 at the oil bore.

Where printed copies of the rule differ in a constant (0.85 or 0.857 in α_T's f(b),
1.527 or 1.5276 in β_B's f(s, w)), the longer IACS figure is used.

Units SI at the interface (m, N, N·m, Pa); the rule's own unit system (mm, MPa) is
used inside the fatigue-strength fit only.

References
----------
IACS UR M53 "Calculation of crankshafts for I.C. engines", Rev. 1 (Dec 2004) and later:
§2 stresses, §3 stress concentration factors, §4 additional bending stresses, §5
equivalent alternating stress, §6 fatigue strength, §7 acceptability criteria (the
section layout checked against Rev. 1's table of contents; the constants were not
checked against a second copy of the text).
DNV-CG-0037 "Calculation of crankshafts for reciprocating internal combustion
engines" (the same method and factors).
"""
from typing import NamedTuple

import numpy as np

TARGET_Q = 1.15                 # §7: the acceptability factor asked for
FORGING_FACTOR = {1: 1.05, 2: 1.0, 3: 0.93}    # K: grain-flow forged, free forged, cast
PLACES = 3                      # pin fillet, journal fillet, oil bore

# the ranges the factors were fitted in (§3.1), each (name, low, high)
VALIDITY = (("r_H", 0.03, 0.13), ("r_G", 0.03, 0.13), ("s", -np.inf, 0.5),
            ("w", 0.2, 0.8), ("b", 1.1, 2.2), ("d_O", 0.0, 0.2), ("d_G", 0.0, 0.8),
            ("d_H", 0.0, 0.8))


# ---------------------------------------------------------------- the throw's statics
def span(typed, main_journal_length, web_thickness, crankpin_length):
    """L3: the distance between the centres of the throw's main journals [m]
    (L_main + 2·W + L_pin), or the typed value (0 = derived)."""
    derived = main_journal_length + 2 * web_thickness + crankpin_length
    return typed if typed > 0 else derived


def pin_position(typed, m53_l3):
    """L2: from a main journal's centre to the crankpin's, L3/2 for a symmetric throw
    [m], or the typed value (0 = derived)."""
    return typed if typed > 0 else m53_l3 / 2


def web_position(typed, main_journal_length, web_thickness):
    """L1: from a main journal's centre to the web's centre [m], or typed (0 =
    derived)."""
    return typed if typed > 0 else main_journal_length / 2 + web_thickness / 2


def web_moment(load, m53_l1, m53_l2, m53_l3):
    """The moment a force on the pin puts on the web's centre, F·L1·(L3 − L2)/L3
    [N·m]."""
    return np.asarray(load, dtype=float) * m53_l1 * (m53_l3 - m53_l2) / m53_l3


def web_shear(load, m53_l2, m53_l3):
    """The shear force it puts through the web, F·(L3 − L2)/L3 [N]."""
    return np.asarray(load, dtype=float) * (m53_l3 - m53_l2) / m53_l3


def oil_bore_moment(pin_tangential_load, pin_radial_load, m53_l2, m53_l3, oil_bore_angle):
    """M_BO = M_BT·cos ψ + M_BR·sin ψ at the crankpin's centre, M = F·L2·(L3 − L2)/L3
    [N·m]; ψ [rad]."""
    lever = m53_l2 * (m53_l3 - m53_l2) / m53_l3
    return lever * (np.asarray(pin_tangential_load, dtype=float) * np.cos(oil_bore_angle)
                    + np.asarray(pin_radial_load, dtype=float) * np.sin(oil_bore_angle))


def alternating(values):
    """Half the range of a cycle, ½(max − min) [same unit]."""
    v = np.asarray(values, dtype=float)
    return (np.nanmax(v) - np.nanmin(v)) / 2


# ---------------------------------------------------------------- nominal stresses
def web_bending_stress(m53_moment, web_width, web_thickness):
    """σ_BN = M_BN/W_eqw, W_eqw = B·W²/6 [Pa]."""
    return m53_moment / (web_width * web_thickness ** 2 / 6)


def web_compression_stress(m53_shear, web_width, web_thickness):
    """σ_QN = Q_N/(B·W) [Pa]."""
    return m53_shear / (web_width * web_thickness)


def round_bending_stress(moment, diameter, bore):
    """M/W_e, W_e = π/32·(D⁴ − d⁴)/D [Pa]."""
    return moment / (np.pi / 32 * (diameter ** 4 - bore ** 4) / diameter)


def round_torsion_stress(torque, diameter, bore):
    """M_T/W_P, W_P = π/16·(D⁴ − d⁴)/D [Pa]."""
    return torque / (np.pi / 16 * (diameter ** 4 - bore ** 4) / diameter)


def alternating_torque(alternating_torque_typed, alternating_torque_journal, check_throw):
    """M_TN: the typed value, or (0) the larger forced-response synthesis torque of the
    two shaft sections beside the throw (sections t and t + 1) [N·m]."""
    if alternating_torque_typed > 0:
        return float(alternating_torque_typed)
    torque = np.asarray(alternating_torque_journal, dtype=float)
    t = int(round(check_throw))
    beside = torque[t - 1:t + 1]
    return float(np.nanmax(beside)) if np.isfinite(beside).any() else np.nan


def torque_from_response(alternating_torque_typed):
    """1 when M_TN comes from the forced response, 0 when typed."""
    return float(not alternating_torque_typed > 0)


# ---------------------------------------------------------------- ratios
class Ratios(NamedTuple):
    r_H: float
    r_G: float
    s: float
    w: float
    b: float
    d_O: float
    d_G: float
    d_H: float
    t_H: float
    t_G: float


def fillet(typed, fillet_radius):
    """A fillet's radius: typed, or (0) the crankshaft's one fillet radius [m]."""
    return typed if typed > 0 else fillet_radius


def ratios(crankpin_diameter, main_journal_diameter, crank_radius, web_thickness, web_width,
           pin_fillet, journal_fillet, oil_bore_diameter, main_journal_bore, crankpin_bore,
           pin_recess, journal_recess):
    """The rule's ratios to the crankpin diameter D [-]."""
    d = crankpin_diameter
    overlap = (crankpin_diameter + main_journal_diameter) / 2 - crank_radius
    return Ratios(pin_fillet / d, journal_fillet / d, overlap / d, web_thickness / d,
                  web_width / d, oil_bore_diameter / d, main_journal_bore / d,
                  crankpin_bore / d, pin_recess / d, journal_recess / d)


def overlap_used(s):
    """s as the fits read it: below −0.5 it is taken as −0.5 (§3.1)."""
    return max(s, -0.5)


def _inside(values, *names):
    return all(low <= values[name] <= high for name, low, high in VALIDITY if name in names)


class OutOfRange(NamedTuple):
    fillet_out: float
    overlap_out: float
    web_out: float
    bore_out: float


def out_of_range(r_H, r_G, s, w, b, d_O, d_G, d_H):
    """1 for each group of ratios with one outside the rule's range (§3.1): the fillets
    (r_H, r_G), the overlap s, the web (w, b), the bores (d_O, d_G, d_H)."""
    values = dict(r_H=r_H, r_G=r_G, s=s, w=w, b=b, d_O=d_O, d_G=d_G, d_H=d_H)
    return OutOfRange(*(float(not _inside(values, *group)) for group in
                        (("r_H", "r_G"), ("s",), ("w", "b"), ("d_O", "d_G", "d_H"))))


def validity(r_H, r_G, s, w, b, d_O, d_G, d_H):
    """1 when every ratio lies in its range (§3.1), else 0."""
    values = dict(r_H=r_H, r_G=r_G, s=s, w=w, b=b, d_O=d_O, d_G=d_G, d_H=d_H)
    return float(_inside(values, *values))


# ---------------------------------------------------------------- stress concentration
def recess_factor(t_H, t_G, s):
    """f(recess) = 1 + (t_H + t_G)·(1.8 + 3.2·s)."""
    return 1 + (t_H + t_G) * (1.8 + 3.2 * s)


def alpha_b(r_H, s, w, b, d_G, d_H, t_H, t_G):
    """α_B, bending at the crankpin fillet (§3.2)."""
    s = overlap_used(s)
    f_sw = (-4.1883 + 29.2004 * w - 77.5925 * w ** 2 + 91.9454 * w ** 3 - 40.0416 * w ** 4
            + (1 - s) * (9.5440 - 58.3480 * w + 159.3415 * w ** 2 - 192.5846 * w ** 3
                         + 85.2916 * w ** 4)
            + (1 - s) ** 2 * (-3.8399 + 25.0444 * w - 70.5571 * w ** 2 + 87.0328 * w ** 3
                              - 39.1832 * w ** 4))
    f_w = 2.1790 * w ** 0.7171
    f_b = 0.6840 - 0.0077 * b + 0.1473 * b ** 2
    f_r = 0.2081 * r_H ** -0.5231
    f_dg = 0.9993 + 0.27 * d_G - 1.0211 * d_G ** 2 + 0.5306 * d_G ** 3
    f_dh = 0.9978 + 0.3145 * d_H - 1.5241 * d_H ** 2 + 2.4147 * d_H ** 3
    return 2.6914 * f_sw * f_w * f_b * f_r * f_dg * f_dh * recess_factor(t_H, t_G, s)


def torsion_factor(r, s, w, b):
    """0.8·f(r, s)·f(b)·f(w): α_T with the pin fillet's r, β_T with the journal's
    (the same number when the two fillets are alike, as the rule says) (§3.2–3.3)."""
    s = overlap_used(s)
    f_rs = r ** (-(0.322 + 0.1015 * (1 - s)))
    f_b = 7.8955 - 10.654 * b + 5.3482 * b ** 2 - 0.857 * b ** 3
    f_w = w ** -0.145
    return 0.8 * f_rs * f_b * f_w


def alpha_t(r_H, s, w, b):
    """α_T, torsion at the crankpin fillet."""
    return torsion_factor(r_H, s, w, b)


def beta_t(r_G, s, w, b):
    """β_T, torsion at the journal fillet."""
    return torsion_factor(r_G, s, w, b)


def beta_b(r_G, s, w, b, d_G, d_H, t_H, t_G):
    """β_B, bending at the journal fillet (§3.3)."""
    s = overlap_used(s)
    f_sw = (-1.7625 + 2.9821 * w - 1.5276 * w ** 2
            + (1 - s) * (5.1169 - 5.8089 * w + 3.1391 * w ** 2)
            + (1 - s) ** 2 * (-2.1567 + 2.3297 * w - 1.2952 * w ** 2))
    f_w = 2.2422 * w ** 0.7548
    f_b = 0.5616 + 0.1197 * b + 0.1176 * b ** 2
    f_r = 0.1908 * r_G ** -0.5568
    f_dg = 1.0012 - 0.6441 * d_G + 1.2265 * d_G ** 2
    f_dh = 1.0022 - 0.1903 * d_H + 0.0073 * d_H ** 2
    return 2.7146 * f_sw * f_w * f_b * f_r * f_dg * f_dh * recess_factor(t_H, t_G, s)


def beta_q(r_G, s, w, b, d_H, t_H, t_G):
    """β_Q, the radial force's shear at the journal fillet (§3.3)."""
    s = overlap_used(s)
    f_s = 0.4368 + 2.1630 * (1 - s) - 1.5212 * (1 - s) ** 2
    f_w = w / (0.0637 + 0.9369 * w)
    f_b = -0.5 + b
    f_r = 0.5331 * r_G ** -0.2038
    f_dh = 0.9937 - 1.1949 * d_H + 1.7373 * d_H ** 2
    return 3.0128 * f_s * f_w * f_b * f_r * f_dh * recess_factor(t_H, t_G, s)


def gamma_b(d_O):
    """γ_B, bending at the oil bore's outlet (§3.4)."""
    return 3 - 5.88 * d_O + 34.6 * d_O ** 2


def gamma_t(d_O):
    """γ_T, torsion at the oil bore's outlet (§3.4)."""
    return 4 - 6 * d_O + 30 * d_O ** 2


# ---------------------------------------------------------------- the three places
def equivalent_stresses(m53_alpha_b, m53_alpha_t, m53_beta_b, m53_beta_q, m53_beta_t,
                        m53_gamma_b, m53_gamma_t, m53_nominal_bending,
                        m53_nominal_compression, m53_nominal_oil_bore_bending,
                        m53_nominal_torsion_pin, m53_nominal_torsion_journal,
                        additional_bending_stress, oil_bore_diameter):
    """σ_v at the pin fillet, the journal fillet and the oil bore (§5; blank without an
    oil bore, or without M_TN) [Pa]."""
    pin = np.hypot(m53_alpha_b * m53_nominal_bending + additional_bending_stress,
                   np.sqrt(3) * m53_alpha_t * m53_nominal_torsion_pin)
    journal = np.hypot(m53_beta_b * m53_nominal_bending
                       + m53_beta_q * m53_nominal_compression + additional_bending_stress,
                       np.sqrt(3) * m53_beta_t * m53_nominal_torsion_journal)
    sigma = m53_gamma_b * m53_nominal_oil_bore_bending
    tau = m53_gamma_t * m53_nominal_torsion_pin
    oil = (sigma + 2 * np.sqrt(sigma ** 2 + 9 / 4 * tau ** 2)) / 3 \
        if oil_bore_diameter > 0 else np.nan
    return np.array([pin, journal, oil], dtype=float)


def fatigue_strength(tensile_strength, diameter, notch_radius, forging_factor):
    """σ_DW = K·(0.42·σ_T + 39.3)·[0.264 + 1.073·D^−0.2 + (785 − σ_T)/4900
    + (196/σ_T)·√(1/R_X)], the rule's fit in MPa and mm (§6) [Pa]."""
    sigma = np.asarray(tensile_strength, dtype=float) / 1e6
    d = np.asarray(diameter, dtype=float) * 1e3
    r = np.asarray(notch_radius, dtype=float) * 1e3
    return 1e6 * forging_factor * (0.42 * sigma + 39.3) * (
        0.264 + 1.073 * d ** -0.2 + (785 - sigma) / 4900 + 196 / sigma * np.sqrt(1 / r))


def fatigue_strengths(tensile_strength, crankpin_diameter, main_journal_diameter,
                      pin_fillet, journal_fillet, oil_bore_diameter, forging_kind):
    """σ_DW at the pin fillet (D, R_H), the journal fillet (D_G, R_G) and the oil bore
    (D, D_O/2, K at most 1) [Pa]; blank at an oil bore of no diameter."""
    k = FORGING_FACTOR[int(round(forging_kind))]
    pin = fatigue_strength(tensile_strength, crankpin_diameter, pin_fillet, k)
    journal = fatigue_strength(tensile_strength, main_journal_diameter, journal_fillet, k)
    oil = fatigue_strength(tensile_strength, crankpin_diameter, oil_bore_diameter / 2,
                           min(k, 1.0)) if oil_bore_diameter > 0 else np.nan
    return np.array([pin, journal, oil], dtype=float)


def acceptability(m53_fatigue_strength, m53_equivalent_stress):
    """Q = σ_DW/σ_v at each place (blank where σ_v is 0 or σ_DW blank) [-]."""
    strength = np.asarray(m53_fatigue_strength, dtype=float)
    stress = np.asarray(m53_equivalent_stress, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(stress > 0, strength / np.where(stress > 0, stress, 1), np.nan)


def verdict(m53_acceptability, m53_within_validity):
    """1 when every place's Q (those that have one) is at least 1.15 and the factors are
    valid, else 0."""
    q = np.asarray(m53_acceptability, dtype=float)
    q = q[np.isfinite(q)]
    return float(m53_within_validity == 1 and q.size > 0 and bool(np.all(q >= TARGET_Q)))


def target(throw):
    """The 1.15 asked for, at each place (the chart's second bars) [-]."""
    return np.full(PLACES, TARGET_Q)


def smallest(values):
    """The smallest value, NaN when there is none [same unit]."""
    v = np.asarray(values, dtype=float)
    return float(np.nanmin(v)) if np.isfinite(v).any() else np.nan


def place_numbers(throw):
    """1, 2, 3: the pin fillet, the journal fillet, the oil bore."""
    return np.arange(1.0, PLACES + 1)


def place_count(throw):
    """The three places the rule checks (an axis's size)."""
    return PLACES
