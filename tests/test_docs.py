"""What the README states about the numbers is what crankbook computes."""
from pathlib import Path

import crankbook

ROOT = Path(__file__).resolve().parent.parent


def test_the_series_against_exact_table_is_what_the_presets_give():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    series = crankbook.compute("thesis").scalars
    exact = crankbook.compute("thesis", exact_kinematics=1).scalars
    rows = {
        "peak acceleration (TDC)": ("piston_acceleration_max", "m/s²", "{:.0f}"),
        "acceleration at BDC": ("piston_acceleration_min", "m/s²", "{:.0f}"),
        "peak side force": ("side_force_max", "N", "{:.0f}"),
        "mean torque": ("mean_torque", "N·m", "{:.2f}"),
    }
    for words, (key, unit, shown) in rows.items():
        a, b = series[key], exact[key]
        cells = f"| {words} | {shown.format(a).replace('-', '−')} {unit} | " \
                f"{shown.format(b).replace('-', '−')} {unit} |"
        assert cells in text, cells
        change = (a - b) / abs(b) * 100
        if abs(change) > 0.005:
            assert f"{cells} {change:+.2f} %".replace("-", "−") in text, (words, change)


def test_the_stroke_study_numbers_in_the_readme():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    s = crankbook.compute("thesis").scalars
    for key in ("peak_inertia_force", "peak_side_force", "indicated_power"):
        assert f"{s[f'stroke_study_{key}_change']:.2f} %".replace("-", "−") in text, key
