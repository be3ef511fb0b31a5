"""``python -m crankbook``."""
from crankbook.cli import main

raise SystemExit(main())
