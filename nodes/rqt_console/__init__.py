"""rqt_console: rqt's rqt_console as a page of the zros view in the browser (docs/rqt.md)."""
