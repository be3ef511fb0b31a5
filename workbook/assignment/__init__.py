"""Class packs: per-student assignments (assign) and automatic grading (grade)."""
