"""Every path and `zros` command that README.md, examples/README.md and docs/*.md show a user still works.

The documents are read when the test runs, so a page or command added later is checked too.
What is checked, cheaply (nothing is started):
- repository paths (`configs/x.launch.yaml`, `docs/bag.md`, `[link](other.md)`) in the text, in
  inline code and on command lines of code blocks exist (other lines of a code block are
  program output, whose file names are examples);
- each `zros ...` command parses with the real argument parser (verb, sub-verb, options);
- `zros run PKG EXE` names an executable zros finds;
- `zros launch FILE ...` resolves with `--print`.
A failure names the document and line, e.g. `docs/multi-machine.md:19: configs/teleop.launch.yaml
does not exist`. Not checked: commands with placeholders (`<pkg>`, `[OPTIONS]`, `...`, `a|b`,
`TOPIC`), error messages quoted in the text (`zros run: ...`), code blocks marked ```text
(program output), and launch files and packages that are the reader's own (`zros launch
robot.launch.yaml`, `zros run my_pkg my_node`: a package named `my_...`).
An inline `zros bag info` or `zros bag record/play` names verbs: they must exist, arguments
may be left out.
"""
from __future__ import annotations

import contextlib
import io
import re
import shlex
import subprocess
import sys
from pathlib import Path
from typing import Iterator, NamedTuple

from conftest import REPO

TOP_DIRS = ('configs', 'docs', 'examples', 'nodes', 'interfaces', 'benchmarks', 'tests', 'zros', '.ci')
_PATH = re.compile(r'(?<![\w/.$~-])((?:%s)/[\w./-]*\w)' % '|'.join(re.escape(d) for d in TOP_DIRS))
_LINK = re.compile(r'\]\(([^)\s#]+)(?:#[^)]*)?\)')
_INLINE_CODE = re.compile(r'`([^`]+)`')
_PLACEHOLDER = re.compile(r'[<>\[\]|{}]|\.\.\.|…|\bNAME\b|\bDIR\b|\bFILE\b|\bWS\b')
_ENV_ASSIGNMENT = re.compile(r'^[A-Z_][A-Z0-9_]*=\S*$')
_UPPER_PLACEHOLDER = re.compile(r'^[A-Z][A-Z_]+$')   # PKG, TOPIC, EXECUTABLE


def _readers_own(package: str) -> bool:
    """`my_pkg`, `my_robot`: the package a tutorial has the reader create."""
    return package.startswith('my_')


class Mention(NamedTuple):
    where: str      # 'docs/bag.md:12'
    text: str


def documents() -> list[Path]:
    return [REPO / 'README.md', REPO / 'examples' / 'README.md', *sorted((REPO / 'docs').glob('*.md'))]


def _lines(doc: Path) -> Iterator[tuple[int, str, bool]]:
    """(line number, text, inside a fenced code block) for each line of `doc`; the lines of a
    block marked ```text (program output) are left out."""
    fenced = output = False
    for number, line in enumerate(doc.read_text(encoding='utf-8').splitlines(), 1):
        if line.lstrip().startswith('```'):
            fenced = not fenced
            output = fenced and line.strip()[3:].strip() in ('text', 'output')
            continue
        if not output:
            yield number, line, fenced


def path_mentions() -> Iterator[tuple[Mention, Path]]:
    for doc in documents():
        rel = doc.relative_to(REPO)
        for number, line, fenced in _lines(doc):
            where = f'{rel}:{number}'
            if fenced and _words(line.split(' #')[0]) is None and 'zros ' not in line:
                continue   # a block's output lines (error examples, trees) name files only as examples
            for match in _LINK.finditer(line):
                target = match.group(1)
                if '://' not in target and not target.startswith('mailto:'):
                    yield Mention(where, target), (doc.parent / target)
            for match in _PATH.finditer(line):
                text = match.group(1).rstrip('.')
                if any(_UPPER_PLACEHOLDER.match(part) for part in Path(text).with_suffix('').parts):
                    continue   # nodes/PKG/EXE.py names a pattern
                if Path(text).suffix or match.group(0).endswith('/'):   # a file, not a key expression
                    yield Mention(where, text), REPO / text


class Command(NamedTuple):
    mention: Mention
    argv: list[str]
    inline: bool    # an inline code span (may name a verb without its arguments)


def command_mentions() -> Iterator[Command]:
    """Each `zros ...` command: whole lines of code blocks and inline code spans, split at
    `&&`, `;`, `|` and a trailing `&`, without environment assignments and comments."""
    for doc in documents():
        rel = doc.relative_to(REPO)
        for number, line, fenced in _lines(doc):
            candidates = [line.split(' #')[0]] if fenced else _INLINE_CODE.findall(line)
            for candidate in candidates:
                for part in re.split(r'\s(?:&&|;|\||&)\s|\s&$|\$\(|^\s*\$\s', candidate):
                    words = _words(part)
                    if words:
                        yield Command(Mention(f'{rel}:{number}', part.strip()), words, not fenced)


def _words(text: str) -> list[str] | None:
    text = text.strip().strip('"\'()')
    if not text or _PLACEHOLDER.search(text):
        return None
    try:
        words = shlex.split(text)
    except ValueError:
        return None
    while words and _ENV_ASSIGNMENT.match(words[0]):
        words = words[1:]
    if len(words) < 2 or words[0] != 'zros' or words[1].endswith(':'):   # `zros run: <error>` is output
        return None
    if any(_UPPER_PLACEHOLDER.match(word) for word in words[1:]):
        return None
    return words[1:]


def _parse_error(argv: list[str]) -> str | None:
    """None when the real parser accepts argv; else what it said."""
    from zros.cli.main import build_parser
    parser = build_parser()
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            parser.parse_args(argv)
    except SystemExit as exc:
        if exc.code:
            return err.getvalue().strip().splitlines()[-1] if err.getvalue().strip() else f'exit {exc.code}'
    return None


def _check_run(argv: list[str]) -> str | None:
    from zros.ament_index_python.executables import Executables
    from zros.config import split_session_options
    _, rest = split_session_options(argv[1:])
    if not rest or rest[0] in ('-h', '--help'):
        return None
    if len(rest) < 2:
        return 'zros run needs a package and an executable'
    if _readers_own(rest[0]):
        return None
    if Executables().name(rest[0], rest[1]) is None:
        return f"no executable '{rest[1]}' in package '{rest[0]}'"
    return None


def test_every_documented_path_exists():
    missing = [f'{mention.where}: {mention.text} does not exist'
               for mention, path in path_mentions() if not path.exists()]
    assert not missing, 'dead paths in the docs:\n' + '\n'.join(missing)


def _verb_alternatives(argv: list[str]) -> list[list[str]]:
    """`bag record/play/info` -> `bag record`, `bag play`, `bag info`."""
    if len(argv) > 1 and '/' in argv[1] and not argv[1].startswith(('/', '-', '.', '~')) and '.' not in argv[1]:
        return [[argv[0], choice, *argv[2:]] for choice in argv[1].split('/')]
    return [argv]


def _launch_target(argv: list[str]) -> bool:
    """Whether `zros launch ARGS` names a launch file of this repository or a package's."""
    positional = [a for a in argv[1:] if not a.startswith('-') and ':=' not in a]
    if not positional:
        return False
    first = positional[0]
    if _readers_own(first):
        return False
    return (REPO / first).is_file() or (not Path(first).suffix and len(positional) >= 2)


def test_every_documented_command_parses():
    problems = []
    launches: dict[tuple[str, ...], Mention] = {}
    for mention, whole, inline in command_mentions():
        for argv in _verb_alternatives(whole):
            if argv[0] == 'run':
                problem = _check_run(argv)
            else:
                problem = _parse_error(argv)
                if inline and problem and 'arguments are required' in problem:
                    problem = None   # `zros bag info` in a sentence names the verb
                if problem is None and argv[0] == 'launch' and _launch_target(argv) \
                        and not {'-h', '--help', '-s', '--show-args'} & set(argv):
                    launches.setdefault(tuple(argv[1:]), mention)
            if problem:
                problems.append(f'{mention.where}: `zros {" ".join(argv)}`: {problem}')
    for args, mention in launches.items():
        plan = subprocess.run([sys.executable, '-m', 'zros.cli.main', 'launch', '--print', *args], cwd=REPO,
                              capture_output=True, text=True, timeout=60)
        if plan.returncode != 0:
            lines = (plan.stderr.strip() or plan.stdout.strip() or f'exit {plan.returncode}').splitlines()
            problems.append(f'{mention.where}: `zros launch --print {" ".join(args)}`: {lines[-1]}')
    assert not problems, 'documented commands that fail:\n' + '\n'.join(problems)


def test_the_checker_sees_the_docs():
    """Guard against a checker that silently checks nothing."""
    commands = [command.argv for command in command_mentions()]
    assert len(commands) > 50 and ['topic', 'list'] in commands
    assert any(argv[0] == 'launch' for argv in commands) and any(argv[0] == 'run' for argv in commands)
    assert sum(1 for _ in path_mentions()) > 20
