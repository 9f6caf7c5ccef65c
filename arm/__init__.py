"""The arm: named presets today; limits, gripper sign, dead-band re-assert and the trajectory
controller arrive with the arm issue.
"""
