"""rqt_graph's "Hide:" checkboxes, applied to the node/topic graph before it is drawn.

rqt_graph (ros-visualization/rqt_graph, dotcode.py) hides, by default:

- Dead sinks: topics nothing subscribes to
- Leaf topics: topics with a single connection (one publisher and no subscriber, or the reverse)
- Debug ("quiet"): viewers and debugging nodes and topics, by name: a name containing one of
  QUIET_NAMES (/rosout, /rviz, /rqt, /clock, /statistics, ...); zros adds hidden names (a part
  starting with '_': the CLI's nodes, action internals) and its own view node, /view
- Params: /parameter_events (ROS 1's dynamic_reconfigure topics in rqt_graph)
- tf: /tf and /tf_static. rqt_graph leaves this one off and groups them into one vertex instead;
  here it is on, since in a navigation stack nearly every node touches /tf

Names go first (Debug, tf, Params); dead sinks and leaf topics are then judged on what is left,
so a topic only a hidden viewer subscribes to counts as a dead sink. rqt_graph's "Unreachable"
has nothing to hide here: the graph holds only nodes that answer discovery.
"""
from __future__ import annotations

from typing import Any, NamedTuple

from zros.graph_content import is_hidden

__all__ = ['Hides', 'QUIET_NAMES', 'apply_hides']

#: rqt_graph's debugging names, matched as substrings as rqt_graph does (so /rviz2 and /rqt_graph too).
QUIET_NAMES = ('/diag_agg', '/runtime_logger', '/pr2_dashboard', '/rviz', '/rosout', '/cpu_monitor', '/monitor',
               '/hd_monitor', '/rxloggerlevel', '/clock', '/rqt', '/statistics')
ZROS_VIEW_NODE = '/view'       # `zros view` and `zros run zros_view view`
TF_TOPICS = ('/tf', '/tf_static')


class Hides(NamedTuple):
    """Which of rqt_graph's hides are on (all of them by default)."""

    dead_sinks: bool = True
    leaf_topics: bool = True
    debug: bool = True
    tf: bool = True
    params: bool = True


def apply_hides(content: dict[str, Any], hides: Hides = Hides()) -> dict[str, Any]:
    """`content` (zros.graph_content.graph_content's dict) without what `hides` hides.

    Edges to a hidden vertex go with it, and so does a topic left without any edge; nodes stay
    even without edges (rqt_graph shows every node).
    """
    def hidden_name(name: str) -> bool:
        return ((hides.debug and (is_hidden(name) or name == ZROS_VIEW_NODE
                                  or any(quiet in name for quiet in QUIET_NAMES)))
                or (hides.tf and name in TF_TOPICS)
                or (hides.params and name.rsplit('/', 1)[-1] == 'parameter_events'))
    nodes = [n for n in content['nodes'] if not hidden_name(n)]
    topics = {t: types for t, types in content['topics'].items() if not hidden_name(t)}
    shown = {'n:' + n for n in nodes} | {'t:' + t for t in topics}
    edges = [(s, d) for s, d in content['edges'] if s in shown and d in shown]
    connections = {'t:' + t: [0, 0] for t in topics}           # [publishers, subscribers]
    for src, dst in edges:
        if src in connections:
            connections[src][1] += 1
        else:
            connections[dst][0] += 1
    kept = {vertex for vertex, (pubs, subs) in connections.items()
            if pubs + subs > 0 and not (hides.dead_sinks and subs == 0)
            and not (hides.leaf_topics and pubs + subs < 2)}
    return {'nodes': nodes, 'topics': {t: types for t, types in topics.items() if 't:' + t in kept},
            'edges': [(s, d) for s, d in edges if (s in kept or d in kept)]}
