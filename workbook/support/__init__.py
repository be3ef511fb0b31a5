"""Small helpers every layer may use (they import nothing of crankbook but its errors):
atomic file writes, temporary workspaces and locks, why a path is not a readable file,
CSV-injection safety, package data, TOML reading, exact decimal arithmetic, progress on
stderr."""
