"""zros_view: the web view (zros.view) as a node, so a launch file can start it."""
