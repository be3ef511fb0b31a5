"""The oil's dynamic viscosity at the film's temperature: typed, or read off an SAE
grade by a published viscosity–temperature fit.

Seireg and Dandage fitted the viscosity–temperature charts of the straight SAE grades
10 … 60 with one exponential per grade,

    μ = μ₀ · exp(b / (T_F + 95)),        μ, μ₀ in µreyn (10⁻⁶ lbf·s/in²), T_F in °F,

the form Shigley tabulates (Table 12-1) beside its viscosity–temperature charts.  In kelvin,
T_F + 95 = 1.8·T − 364.67.  A grade fixes an oil only loosely: SAE J300 sets a band
of kinematic viscosity at 100 °C, and the fit runs near its lower edge (SAE 40 at
100 °C: 10.2 mPa·s, about 12.4 mm²/s at 0.82 g/cm³ against J300's 12.5–16.3). A
multigrade's or a particular oil's own data sheet is the better source: type its
viscosity at the film's temperature.

Units SI at the interface: Pa·s and K.

References
----------
A. Seireg, S. Dandage, "Empirical design procedure for the thermodynamic behavior of
journal bearings", *Trans. ASME, J. Lubrication Technology* 104 (1982) 135–148.
R. G. Budynas, J. K. Nisbett, *Shigley's Mechanical Engineering Design*, 9th ed.,
§12-6 and Table 12-1 (the fit's constants, μ₀ in µreyn and b in °F).
SAE J300, *Engine Oil Viscosity Classification* (the bands at 100 °C).
"""
import numpy as np

REYN = 4.4482216152605 / 0.0254 ** 2       # 1 lbf·s/in² in Pa·s (6894.757…)

# Shigley Table 12-1 after Seireg and Dandage: grade -> (μ₀ [µreyn], b [°F])
SAE_VISCOSITY_FIT = {
    10: (0.0158, 1157.5),
    20: (0.0136, 1271.6),
    30: (0.0141, 1360.0),
    40: (0.0121, 1474.4),
    50: (0.0170, 1509.6),
    60: (0.0187, 1564.0),
}
# The template's choice words, in order: index 1 is the typed value, 2… the grades.
OIL_GRADES = ("typed",) + tuple(f"SAE{grade}" for grade in SAE_VISCOSITY_FIT)


def sae_viscosity(sae_grade, oil_temperature):
    """An SAE grade's dynamic viscosity at a temperature by Seireg and Dandage's fit.

    Parameters
    ----------
    sae_grade : int
        10, 20, 30, 40, 50 or 60.
    oil_temperature : array_like
        The oil's temperature [K].

    Returns
    -------
    numpy.ndarray
        μ [Pa·s].
    """
    base, slope = SAE_VISCOSITY_FIT[sae_grade]
    return base * 1e-6 * REYN * np.exp(slope / (1.8 * np.asarray(oil_temperature) - 364.67))


def film_viscosity(oil_grade, oil_viscosity, oil_temperature):
    """The viscosity the film is computed with.

    Parameters
    ----------
    oil_grade : array_like
        The choice's 1-based index into ``OIL_GRADES``: 1 = the typed viscosity,
        2 … 7 = SAE 10 … SAE 60 at ``oil_temperature``.
    oil_viscosity : array_like
        The typed dynamic viscosity [Pa·s].
    oil_temperature : array_like
        The film's temperature [K].

    Returns
    -------
    numpy.ndarray
        μ [Pa·s].
    """
    index = np.asarray(oil_grade, dtype=float)
    fitted = np.zeros(np.broadcast(index, oil_temperature).shape)
    for position, grade in enumerate(SAE_VISCOSITY_FIT, start=2):
        fitted = np.where(index == position, sae_viscosity(grade, oil_temperature), fitted)
    return np.where(index == 1, oil_viscosity, fitted)
