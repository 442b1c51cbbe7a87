"""`python -m zros ...` is the `zros` command (used to start nodes with the same interpreter)."""
from zros.cli.main import entry_point

entry_point()
