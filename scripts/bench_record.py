#!/usr/bin/env python3
"""Recorder benchmark: CPU and bytes per mission-second for fleet-shaped synthetic traffic,
and the report's run time on a synthetic 10-minute mission bag.

  scripts/bench_record.py [--uavs 5 14] [--seconds 20] [--domain 45]
  scripts/bench_record.py publish --uavs N --seconds S   (the traffic source alone; used by tests)

Traffic per UAV at 10 Hz (1 sim s per wall s): SensorBundle (10 gyro, 3 altimeter, 1 GPS,
1 fire detection), UavState, FireEstimateArray (2 fires), TwistStamped; plus /clock at 10 Hz
and one transient-local MissionEvent on /world/events at start. Run after `source scripts/env.sh`.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RECORDER = ROOT / "ros2_ws/install/fire_uav_recording/lib/fire_uav_recording/recorder"


def publish(uavs: int, seconds: float, rate_hz: float = 10.0) -> int:
    """Publish fleet-shaped traffic for ``seconds`` of wall time (then exit 0)."""
    import rclpy
    from builtin_interfaces.msg import Time
    from fire_uav_common import topics
    from fire_uav_common.constants import EventType
    from fire_uav_common.ros_io import spin
    from fire_uav_common.stamps import s_to_ns, to_time_msg
    from fire_uav_msgs.msg import (
        FireEstimate,
        FireEstimateArray,
        GpsFix,
        MissionEvent,
        SensorBundle,
        UavState,
    )
    from geometry_msgs.msg import TwistStamped
    from rclpy.node import Node
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import Imu, Range

    rclpy.init()
    node = Node("bench_publisher")
    pc = topics.publisher(node, topics.CLOCK_SPEC)
    ps = [topics.publisher(node, topics.SENSORS_SPEC, uav_id=k) for k in range(uavs)]
    pcmd = [topics.publisher(node, topics.CMD_SPEC, uav_id=k) for k in range(uavs)]
    pst = topics.publisher(node, topics.FLEET_STATE_SPEC)
    pf = topics.publisher(node, topics.FLEET_FIRES_SPEC)
    pe = topics.publisher(node, topics.WORLD_EVENTS_SPEC)
    ev = MissionEvent()
    ev.type = EventType.IGNITION
    ev.uav_id = ev.peer_id = -1
    ev.fire_id = 0
    ev.detail = "bench ignition"
    pe.publish(ev)
    state = {"k": 0}
    t_end = time.monotonic() + seconds

    def tick() -> None:
        k = state["k"] = state["k"] + 1
        c = Clock(clock=to_time_msg(s_to_ns(k / rate_hz), Time))
        pc.publish(c)
        for u in range(uavs):
            b = SensorBundle()
            b.header.stamp = c.clock
            b.uav_id, b.step, b.control_period_s = u, k, 1.0 / rate_hz
            b.gyro = [Imu() for _ in range(10)]
            b.altimeter = [Range() for _ in range(3)]
            b.gps = [GpsFix()]
            ps[u].publish(b)
            s = UavState()
            s.header.stamp = c.clock
            s.uav_id, s.sequence, s.step = u, k, k
            s.x_m, s.y_m, s.z_m = 100.0 + u, 200.0, 30.0
            s.covariance = [0.1] * 16
            s.alive_peers = list(range(uavs))
            pst.publish(s)
            fa = FireEstimateArray()
            fa.header.stamp = c.clock
            fa.uav_id, fa.sequence, fa.step = u, k, k
            fa.fires = [FireEstimate(fire_id=i, x_m=300.0, y_m=400.0, extent_m=50.0) for i in range(2)]
            pf.publish(fa)
            cmd = TwistStamped()
            cmd.header.stamp = c.clock
            cmd.twist.linear.x = 50.0
            pcmd[u].publish(cmd)
        if time.monotonic() >= t_end:
            raise SystemExit(0)

    node.create_timer(1.0 / rate_hz, tick)
    spin(node)  # until the timer's SystemExit at t_end or Ctrl-C
    return 0


def _cpu_s(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def stop(proc: subprocess.Popen, timeout: float = 10.0) -> int:
    """SIGINT, then SIGKILL after ``timeout``; return the exit code."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            return proc.wait(timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
    return proc.wait()


def bench_recorder(uavs: int, seconds: float, workdir: Path) -> dict[str, float]:
    bag = workdir / f"bench_{uavs}"
    pub = subprocess.Popen(
        [sys.executable, __file__, "publish", "--uavs", str(uavs), "--seconds", str(seconds + 4)]
    )
    rec = None
    try:
        time.sleep(1.5)
        rec = subprocess.Popen(
            [
                str(RECORDER),
                "--ros-args",
                "-p",
                f"output:={bag}",
                "-p",
                f"uav_count:={uavs}",
                "--log-level",
                "warn",
            ]
        )
        time.sleep(2.0)  # discovery and subscription
        cpu0, t0 = _cpu_s(rec.pid), time.monotonic()
        time.sleep(seconds)
        cpu1, t1 = _cpu_s(rec.pid), time.monotonic()
        rc = stop(rec)
    finally:
        if rec is not None:
            stop(rec)
        stop(pub)
    from fire_uav_common.stamps import ns_to_s
    from fire_uav_recording import open_bag

    with open_bag(bag) as b:
        span_s = ns_to_s(b.reader.end_time - b.reader.start_time)
        count = b.reader.message_count
    size = sum(p.stat().st_size for p in bag.iterdir())
    return {
        "uavs": uavs,
        "exit_code": rc,
        "cpu_percent": 100 * (cpu1 - cpu0) / (t1 - t0),
        "messages": count,
        "mission_s": span_s,
        "msgs_per_s": count / span_s,
        "bytes_per_mission_s": size / span_s,
        "bag_bytes": size,
    }


def bench_report(workdir: Path, uavs: int = 14, minutes: float = 10.0) -> dict[str, float]:
    from fire_report.synthetic import SyntheticMission, write_synthetic_mission

    bag = workdir / "synthetic_10min"
    t0 = time.monotonic()
    write_synthetic_mission(
        bag, SyntheticMission(uav_count=uavs, duration_s=60 * minutes, lost_final=tuple(range(3, 3 + uavs)))
    )
    t1 = time.monotonic()
    out = subprocess.run(
        [sys.executable, "-m", "fire_report", str(bag), "-o", str(workdir / "report")],
        capture_output=True,
        text=True,
    )
    t2 = time.monotonic()
    size = sum(p.stat().st_size for p in bag.iterdir())
    return {
        "uavs": uavs,
        "mission_s": 60 * minutes,
        "bag_bytes": size,
        "write_s": t1 - t0,
        "report_s": t2 - t1,
        "report_exit": out.returncode,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", nargs="?", default="bench", choices=("bench", "publish"))
    ap.add_argument("--uavs", type=int, nargs="+", default=[5, 14])
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--domain", type=int, default=None, help="ROS_DOMAIN_ID (default: inherited, else 45)")
    args = ap.parse_args()
    if args.domain is not None or "ROS_DOMAIN_ID" not in os.environ:
        os.environ["ROS_DOMAIN_ID"] = str(args.domain if args.domain is not None else 45)
    if args.mode == "publish":
        return publish(args.uavs[0], args.seconds)
    with tempfile.TemporaryDirectory(prefix="bench_record_") as tmp:
        work = Path(tmp)
        for n in args.uavs:
            r = bench_recorder(n, args.seconds, work)
            print(
                f"recorder {n:2d} UAVs: CPU {r['cpu_percent']:5.1f}%  {r['msgs_per_s']:6.0f} msg/s  "
                f"{r['bytes_per_mission_s'] / 1024:7.1f} KiB per mission-second  "
                f"({r['messages']} msgs over {r['mission_s']:.1f} s, exit {r['exit_code']})"
            )
        r = bench_report(work)
        print(
            f"report: synthetic {r['mission_s'] / 60:.0f}-min mission, {r['uavs']} UAVs, "
            f"{r['bag_bytes'] / 2**20:.1f} MiB bag: written in {r['write_s']:.1f} s, "
            f"report in {r['report_s']:.1f} s (exit {r['report_exit']})"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
