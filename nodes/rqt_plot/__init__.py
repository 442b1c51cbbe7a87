"""rqt_plot: rqt's rqt_plot as a page of the zros view in the browser (docs/rqt.md)."""
