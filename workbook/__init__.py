"""crankbook: formula-backed Excel workbooks of crank–connecting-rod mechanisms."""
__version__ = "0.1.0"
