"""One codec per fleet message, both directions in one module, on the CDR rules of
:mod:`fire_uav_common.cdr`: :mod:`.sensor_bundle` (the world writes, the agents read),
:mod:`.uav_state` (an agent writes, its peers read), :mod:`.perimeter_map` and :mod:`.fire_front`
(likewise), :mod:`.payload_request` (an agent writes, the world reads) and :mod:`.agent_pose` (an
agent's command and ``/tf`` pose estimate, written only). The nodes and the in-process harness use the same functions, so the harness sees the
numbers a ROS run sees (float32 fields, stamps of whole nanoseconds) without rounding anything by
hand. ROS-free.
"""
