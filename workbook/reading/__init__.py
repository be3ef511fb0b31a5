"""Reading workbooks back: the bounded xlsx reader, values through the named ranges,
recalculation in LibreOffice or Gnumeric, the one rule by which a spreadsheet's
number agrees with numpy, and verify.

- ``xlsx_reader``      a bounded reader of hostile .xlsx files (sizes, entities, zips)
- ``workbook_reader``  the p_/q_ values of a workbook crankbook wrote
- ``recalc``           LibreOffice headless and ssconvert --recalc
- ``engine_values``    what an engine computed, from its CSV of every sheet
- ``compare``          the agreement rule (peak-relative with a rounding floor)
- ``verification``     recalculate and compare every q_ name (crankbook verify)
- ``pressure_file``    measured cylinder-pressure traces (.csv, .xlsx)
"""
