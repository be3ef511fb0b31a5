"""Data of crankbook: workbook templates, presets, groups, claims, assignments and units.

Nothing here is code; the files are read through importlib.resources
(crankbook.support.resources), so they work the same from a wheel and from the source tree.
"""
