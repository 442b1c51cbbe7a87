"""rqt_graph: rqt's rqt_graph as a page of the zros view in the browser (docs/rqt.md)."""
