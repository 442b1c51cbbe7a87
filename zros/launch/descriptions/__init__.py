"""launch.descriptions: descriptions of what a launch runs, kept apart from the actions that run
them (`ExecuteLocal(process_description=Executable(cmd=[...]))`)."""
from __future__ import annotations

from zros.launch.descriptions.executable import Executable

__all__ = ['Executable']
