"""Where the rewritten files go: the launch's log directory, so they stay beside its logs."""
from __future__ import annotations

import os
import tempfile
from typing import Any


def write_rewritten(context: Any, source: str, text: str) -> str:
    """Write `text` to a new file named after `source`; its path."""
    folder = getattr(context, 'log_dir', '') or None
    if folder:
        os.makedirs(folder, exist_ok=True)
    stem, suffix = os.path.splitext(os.path.basename(source))
    with tempfile.NamedTemporaryFile('w', prefix=f'{stem}_', suffix=suffix or '.yaml', dir=folder,
                                     delete=False, encoding='utf-8') as handle:
        handle.write(text)
    return handle.name


def read_source(path: str, what: str) -> str:
    """The source file's text; SubstitutionError (one line) when it cannot be read."""
    from zros.launch.errors import SubstitutionError
    try:
        with open(path, encoding='utf-8') as handle:
            return handle.read()
    except OSError as exc:
        raise SubstitutionError(f'{what}: cannot read {path!r}: {exc.strerror}') from None
