"""foxglove_bridge: Foxglove's WebSocket protocol over the zros graph (docs/web-tools.md)."""
