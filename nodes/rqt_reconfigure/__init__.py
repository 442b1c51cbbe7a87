"""rqt_reconfigure: rqt's rqt_reconfigure as a page of the zros view in the browser (docs/rqt.md)."""
