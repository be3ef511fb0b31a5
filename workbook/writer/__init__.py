"""Writers, one per part of the workbook file; build.py puts them together."""
