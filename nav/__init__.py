"""nav: filled in by later issues."""
