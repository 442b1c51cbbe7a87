"""nav2_map_server: map_server, map_saver_cli and map_saver_server, with nav2's map file format (zros.map_io)."""
