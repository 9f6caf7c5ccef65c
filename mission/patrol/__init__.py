"""The patrol: the mission file, the tree, the report."""
