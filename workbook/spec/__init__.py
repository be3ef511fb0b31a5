"""The template language: what a workbook holds, read from templates/*.toml.

- ``model``         the dataclasses of a spec (parameters, quantities, sheets, charts)
- ``loader``        reads a template and its libraries into a Spec
- ``check``         the checks a template must pass before it is used
- ``placeholders``  the {key:part|unit} syntax, parsed once
- ``formulas``      compiles templates into Excel formulas
- ``evaluate``      the same quantities with numpy (the calc functions)
- ``units``         sheet units and their SI factors (templates/units.toml)
- ``params``        parameter values: presets, groups, --set, validation

A new quantity is a calc function plus an entry in a template; see docs/templates.md.
"""
