"""rqt_service_caller: rqt's rqt_service_caller as a page of the zros view in the browser (docs/rqt.md)."""
