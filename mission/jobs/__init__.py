"""Jobs that run the robot to an end: the scripted drive, one navigation goal, the pot-approach
trial; with their reports and pictures."""
