"""perception: filled in by later issues."""
