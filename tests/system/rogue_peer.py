"""A rogue ROS participant on a mission's domain (tests/system/test_hardening.py).

usage: rogue_peer.py MODE OUT.json [SECONDS] [RATE_HZ]
- ``spoof``: the replay of a poisoning attempt: one UavState for UAV 1 with sequence 2**32-1 and one with NaN
  coordinates for UAV 2, then for SECONDS valid-looking forgeries: copies of genuine fleet
  messages (right step and sequence, other position, the genuine tag), PayloadRequests asking
  UAV 1 to drop, wild TwistStamped commands on /uav_1/cmd.
- ``fuzz``: random field values (NaN, inf, huge arrays, wrong ids, out-of-range enums) on every
  fleet and command topic for SECONDS.
- ``flood``: RATE_HZ copies of forged UavStates on /fleet/state for SECONDS.
It waits until the mission's /fleet/state has traffic, and writes what it sent to OUT.json.
"""

from __future__ import annotations

import copy
import json
import math
import random
import sys
import time

import rclpy
from fire_uav_common import topics
from fire_uav_msgs.msg import FireEstimate, FireEstimateArray, PayloadRequest, PerimeterMap, UavState
from geometry_msgs.msg import TwistStamped


def main() -> int:
    mode, out = sys.argv[1], sys.argv[2]
    seconds = float(sys.argv[3]) if len(sys.argv) > 3 else 10.0
    rate = float(sys.argv[4]) if len(sys.argv) > 4 else 200.0
    rclpy.init()
    node = rclpy.create_node("rogue")
    pub_state = topics.publisher(node, topics.FLEET_STATE_SPEC)
    pub_fires = topics.publisher(node, topics.FLEET_FIRES_SPEC)
    pub_perim = topics.publisher(node, topics.FLEET_PERIMETER_SPEC)
    pub_pay = {k: topics.publisher(node, topics.PAYLOAD_SPEC, k) for k in range(3)}
    pub_cmd = {k: topics.publisher(node, topics.CMD_SPEC, k) for k in range(3)}
    latest: dict[int, UavState] = {}
    node.create_subscription(UavState, "/fleet/state", lambda m: latest.__setitem__(m.uav_id, m), 100)
    sent: dict[str, int] = {}

    def count(kind: str) -> None:
        sent[kind] = sent.get(kind, 0) + 1

    deadline = time.monotonic() + 300
    while len(latest) < 3 and time.monotonic() < deadline:  # the mission is running
        rclpy.spin_once(node, timeout_sec=0.1)
    for _ in range(30):  # let a few steps pass
        rclpy.spin_once(node, timeout_sec=0.1)
    rnd = random.Random(7)
    if mode == "spoof":
        m = copy.deepcopy(latest[1])
        m.sequence = 2**32 - 1
        pub_state.publish(m)
        count("state seq 2**32-1 for uav 1")
        m = copy.deepcopy(latest[2])
        m.x_m = m.y_m = math.nan
        pub_state.publish(m)
        count("state NaN for uav 2")
    if mode == "flood":  # as fast as one process can: no copies, no spinning, no sleeping when late
        _flood(pub_state, latest[1], rnd, seconds, rate, count)
        mode = "done"
    t_end = time.monotonic() + seconds if mode != "done" else 0.0
    period = 1.0 / rate
    next_t = time.monotonic()
    while time.monotonic() < t_end:
        rclpy.spin_once(node, timeout_sec=0.0)
        if mode == "spoof":
            for g in list(latest.values()):
                f = copy.deepcopy(g)
                f.x_m += 500.0
                f.sequence += 1
                f.step += 1
                f.fires_sequence += 1  # and a forged fire picture: it rides in the state
                f.fires.append(FireEstimate(fire_id=99, x_m=0.0, y_m=0.0, extent_m=50.0))
                pub_state.publish(f)
                count("forged state")
            req = PayloadRequest(uav_id=1, action=1, target_fire_id=0)
            if 1 in latest:
                req.header.stamp = latest[1].header.stamp
            pub_pay[1].publish(req)
            count("forged payload drop")
            c = TwistStamped()
            c.header.stamp = req.header.stamp
            c.twist.linear.x, c.twist.angular.z = 5.0, 3.0
            pub_cmd[1].publish(c)
            count("forged cmd")
        elif mode == "fuzz":
            _fuzz_once(rnd, pub_state, pub_fires, pub_perim, pub_pay, pub_cmd, latest, count)
        elif mode == "flood":
            if 1 in latest:
                f = copy.deepcopy(latest[1])
                f.sequence = rnd.randrange(1, 2**32)
                f.step = rnd.randrange(0, 2**32)
                pub_state.publish(f)
                count("flood state")
        next_t += period
        delay = next_t - time.monotonic()
        if delay > 0:
            time.sleep(delay)
    with open(out, "w") as fh:
        json.dump(sent, fh)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


def _flood(pub, genuine: UavState, rnd: random.Random, seconds: float, rate: float, count) -> None:
    m = copy.deepcopy(genuine)
    t0 = time.monotonic()
    n = 0
    while (now := time.monotonic()) < t0 + seconds:
        m.sequence = rnd.randrange(1, 2**32)
        m.step = rnd.randrange(0, 2**32)
        pub.publish(m)
        n += 1
        ahead = t0 + n / rate - now
        if ahead > 0.001:
            time.sleep(ahead)
    for _ in range(n):
        count("flood state")


def _val(rnd: random.Random) -> float:
    return rnd.choice([math.nan, math.inf, -math.inf, 1e308, -1e308, 0.0, rnd.uniform(-1e6, 1e6)])


def _fuzz_once(rnd, pub_state, pub_fires, pub_perim, pub_pay, pub_cmd, latest, count) -> None:
    step = max((m.step for m in latest.values()), default=0)
    s = UavState(
        uav_id=rnd.randrange(256),
        sequence=rnd.randrange(2**32),
        step=rnd.choice([step, rnd.randrange(2**32)]),
    )
    s.x_m, s.y_m, s.z_m, s.yaw_rad = _val(rnd), _val(rnd), _val(rnd), _val(rnd)
    s.objective = rnd.randrange(256)
    s.alive_peers = [rnd.randrange(256) for _ in range(rnd.choice([0, 5, 5000]))]
    s.sent_per_topic = [rnd.randrange(65536) for _ in range(rnd.choice([0, 3, 3000]))]
    s.final = rnd.random() < 0.5
    fires = [
        FireEstimate(
            fire_id=rnd.randrange(2**32),
            status=rnd.randrange(256),
            x_m=_val(rnd),
            extent_m=_val(rnd),
        )
        for _ in range(rnd.choice([0, 3, 2000]))
    ]
    s.fires_sequence, s.fires = rnd.randrange(2**32), fires  # the fire picture rides in the state
    pub_state.publish(s)
    count("fuzz state")
    # /fleet/fires: no agent listens any more; the recorder and the bridge still follow it
    f = FireEstimateArray(uav_id=rnd.randrange(256), sequence=rnd.randrange(2**32), step=step)
    f.fires = fires
    pub_fires.publish(f)
    count("fuzz fires")
    p = PerimeterMap(uav_id=rnd.randrange(256), sequence=rnd.randrange(2**32), fire_id=rnd.randrange(-5, 5))
    n = rnd.choice([0, 7, 20000])
    p.outer_distance_m = [float(_val(rnd)) for _ in range(n)]
    p.outer_visit_time_s = [float(_val(rnd)) for _ in range(rnd.choice([0, n]))]
    pub_perim.publish(p)
    count("fuzz perimeter")
    k = rnd.randrange(3)
    r = PayloadRequest(
        uav_id=rnd.randrange(256), action=rnd.randrange(256), target_fire_id=rnd.randrange(-5, 5)
    )
    r.cmd_linear_x_mps = _val(rnd)
    pub_pay[k].publish(r)
    count("fuzz payload")
    c = TwistStamped()
    c.twist.linear.x, c.twist.linear.z, c.twist.angular.z = _val(rnd), _val(rnd), _val(rnd)
    pub_cmd[k].publish(c)
    count("fuzz cmd")


if __name__ == "__main__":
    sys.exit(main())
