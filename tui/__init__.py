"""tui: filled in by later issues."""
