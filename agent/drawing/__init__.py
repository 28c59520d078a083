"""RoboViz debug drawing from the agent (REFERENCE §5.5): packets, the agent's beliefs as shapes, a UDP sender.

Off by default; ``python -m agent --roboviz-draw [HOST:PORT]`` or ``NAO3D_ROBOVIZ_DRAW=HOST:PORT`` turns it on.
"""

from agent.drawing.beliefs import belief_packets, set_name
from agent.drawing.udp import DEFAULT_DRAW_PORT, ENV_VAR, RoboVizDrawer, drawer_from_env, parse_address

__all__ = ["DEFAULT_DRAW_PORT", "ENV_VAR", "RoboVizDrawer", "belief_packets", "drawer_from_env", "parse_address",
           "set_name"]
