"""The report's ``faults`` (mission/patrol/faults.py): each stretch a fault lasted, one still going
shown so far, in the order they began."""
from mission.patrol.faults import Faults


def test_each_stretch_is_one_entry_with_its_start_and_duration():
    blind = {"now": False}
    f = Faults({"lidar_blind": lambda: blind["now"]}, t0=10.0)
    for k in range(100):  # 10 s at 10 Hz: blind from 12.0 to 14.5, and again from 18.0
        t = 10.0 + k / 10
        blind["now"] = 12.0 <= t < 14.5 or t >= 18.0
        f.tick(t)
    assert f.sections() == {"faults": [{"kind": "lidar_blind", "t": 2.0, "duration_s": 2.5},
                                       {"kind": "lidar_blind", "t": 8.0, "duration_s": 1.9}]}
