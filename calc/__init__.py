"""Crank–connecting-rod physics: pure, vectorised numpy functions in SI units.

Angles are radians, lengths metres, pressures pascals, angular speeds rad/s.
Nothing here reads or writes files; the workbook layer converts to sheet units.
"""
