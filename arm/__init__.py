"""arm: filled in by later issues."""
