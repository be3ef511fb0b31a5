"""The audit of the source documents' numbers and of returned workbooks.

- ``claims``    every printed number of a seed, its recomputation and its verdict
                (templates/claims/*.toml)
- ``book``      the audit workbook: each claim beside a live formula
- ``returned``  a workbook someone edited, recalculated and checked name by name
"""
