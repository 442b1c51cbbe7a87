"""rqt_gui: rqt's rqt_gui as a page of the zros view in the browser (docs/rqt.md)."""
