"""The console's screens: the main one (every panel) and the yes / no question."""
