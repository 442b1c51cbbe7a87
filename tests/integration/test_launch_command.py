"""`$(command ...)`: the one substitution that runs a program (the other substitutions:
tests/unit/test_launch_parse.py)."""
from __future__ import annotations

import pytest

from unit.test_launch_parse import PY, Ctx
from zros.launch.template import SubstitutionError


def test_command(tmp_path):
    ctx = Ctx()
    assert ctx("$(command 'echo hello world')") == 'hello world\n'   # as printed, as launch keeps it
    script = tmp_path / 'warns.py'
    script.write_text("import sys\nsys.stderr.write('warned')\nprint('out')\n")
    code = f'{PY} {script}'
    with pytest.raises(SubstitutionError, match=r'executed command showed stderr output\. Command: .*warns\.py \(stderr: warned\)'):
        ctx(f"$(command '{code}')")
    assert ctx(f"$(command '{code}' ignore)") == 'out\n'
    assert ctx(f"$(command '{code}' capture)") == 'out\nwarned'
    with pytest.raises(SubstitutionError, match=r'executed command failed\. Command: .* \(exit code 3'):
        ctx(f"$(command '{PY} -c \"raise SystemExit(3)\"')")
    with pytest.raises(SubstitutionError, match="file not found: 'no-such-program-zz'"):
        ctx("$(command no-such-program-zz)")
