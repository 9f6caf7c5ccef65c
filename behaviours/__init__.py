"""behaviours: filled in by later issues."""
