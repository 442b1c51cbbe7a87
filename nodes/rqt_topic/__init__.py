"""rqt_topic: rqt's rqt_topic as a page of the zros view in the browser (docs/rqt.md)."""
