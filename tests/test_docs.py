"""The docs speak to users about the project as it is, and what they show is what it does.

- README.md, docs/*.md, the shipped scenes they show, the study scripts and every ``--help``
  of the command cite no issue numbers, speak of no sessions, and name no path outside the
  repository;
- the command tables of README.md and docs/scenes.md are the parser's: each command's usage
  and its sentence (``sliders.app.cli.COMMANDS``), which ``fvslider --help`` lists and
  ``fvslider COMMAND --help`` states; every example of the help parses;
- docs/tutorial.md runs as written: its scene files are written, its commands run and print
  what it shows, its Python sessions give what it shows (doctest), and every number of its
  prose is one of those it shows.
"""

from __future__ import annotations

import argparse
import contextlib
import doctest
import io
import re
import shlex
from pathlib import Path

import pytest

from sliders.app import cli

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SCENES = sorted((ROOT / "studies" / "scenes").glob("*.toml"))
#: The studies' scripts: their docstrings are their ``--help`` and ``fvslider studies``' lines.
STUDIES = sorted((ROOT / "studies").glob("*.py"))
TUTORIAL = ROOT / "docs" / "tutorial.md"
COMMAND_TABLES = [ROOT / "README.md", ROOT / "docs" / "scenes.md"]

#: An issue or pull request cited: "issue 13", "issues 4 and 13", "#13", "the issue's".
ISSUE = re.compile(r"\bissues?\s+#?\d|(?<![\w&/])#\d+\b|\bthe issue\b", re.I)
#: Development-history words: a session, a branch or a change as the text's "now".
HISTORY = re.compile(r"\bsessions?\b|\bthis (?:branch|change)\b", re.I)
#: A path leaving the repository: one that climbs out of it (``../x``) or an absolute path of
#: two components or more (``/work/x``); a single one (``/proc``, ``/sys``) names a filesystem.
OUTSIDE = re.compile(r"(?<![\w.)\]~-])(?:\.\./[\w.-]|/[A-Za-z_][\w.-]*/[\w.-])")


def helps() -> dict[str, str]:
    """Every help text of the command: ``fvslider --help``, each ``fvslider NAME --help`` and
    the list of studies, ``fvslider studies``."""
    texts = {"fvslider --help": cli._parser().format_help()}
    for name, parser in subparsers().items():
        texts[f"fvslider {name} --help"] = parser.format_help()
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        cli.main(["studies"])
    texts["fvslider studies"] = out.getvalue()
    return texts


def subparsers() -> dict[str, argparse.ArgumentParser]:
    (action,) = [a for a in cli._parser()._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(action.choices)


def words(text: str) -> str:
    return " ".join(text.split())


def texts() -> list[tuple[str, str]]:
    """(name, text) of every doc, shipped scene, study script and help."""
    return [
        *((str(p.relative_to(ROOT)), p.read_text()) for p in DOCS + SCENES + STUDIES),
        *helps().items(),
    ]


@pytest.mark.parametrize("pattern", [ISSUE, HISTORY, OUTSIDE], ids=["issues", "history", "paths"])
def test_no_issue_numbers_sessions_or_paths_outside_the_repository(pattern):
    found = [
        f"{name}:{number}: {line.strip()}"
        for name, text in texts()
        for number, line in enumerate(text.splitlines(), 1)
        if pattern.search(line)
    ]
    assert not found, "\n".join(found)


#: A repository path in the docs' text (``docs/scenes.md``, ``sliders/app/cli.py``).
REPOSITORY_PATH = re.compile(r"(?<![\w./-])((?:fvbeam|sliders|studies|tests|docs)/[\w./-]*\w)")


def test_every_repository_path_and_link_of_the_docs_exists():
    missing = [
        f"{doc.relative_to(ROOT)}: {path}"
        for doc in DOCS
        for path in REPOSITORY_PATH.findall(doc.read_text())
        if not (ROOT / path).exists()
    ]
    missing += [
        f"{doc.relative_to(ROOT)}: {link}"
        for doc in DOCS
        for link in re.findall(r"\]\(([\w./-]+\.md)(?:#[\w-]*)?\)", doc.read_text())
        if not (doc.parent / link).exists()
    ]
    assert not missing, "\n".join(missing)


def test_the_library_names_no_path_outside_the_repository():
    """The docstrings and comments of ``fvbeam`` and ``sliders`` (``help()`` shows them)."""
    found = [
        f"{path.relative_to(ROOT)}:{number}: {line.strip()}"
        for package in ("fvbeam", "sliders")
        for path in sorted((ROOT / package).rglob("*.py"))
        for number, line in enumerate(path.read_text().splitlines(), 1)
        if OUTSIDE.search(line)
    ]
    assert not found, "\n".join(found)


@pytest.mark.parametrize(
    "line", ["see issue 13", "issues 4 and 13", "(#12)", "Issue 14's", "the issue's 1 s"]
)
def test_the_issue_pattern_finds_citations(line):
    assert ISSUE.search(line)


@pytest.mark.parametrize("line", ["../shared/notes/x.md", "`/work/shared/DESIGN.md`"])
def test_the_path_pattern_finds_outside_paths(line):
    assert OUTSIDE.search(line)


@pytest.mark.parametrize("line", ["`/proc`, `/sys`", "GA/EJ", "docs/scenes.md", "v_t/v_eps"])
def test_the_path_pattern_passes_repository_paths_and_ratios(line):
    assert not OUTSIDE.search(line)


# -- the command table ---------------------------------------------------------------------------
def parser_rows() -> dict[str, tuple[str, str]]:
    """Per command, its usage (without ``[-h]``) and its sentence, as the parser has them."""
    rows = {}
    for name, parser in subparsers().items():
        usage = words(parser.format_usage()).removeprefix("usage: ").replace(" [-h]", "")
        rows[name] = (usage, cli.COMMANDS[name])
    return rows


def table_rows(doc: Path) -> dict[str, tuple[str, str]]:
    """The rows ``| `fvslider NAME ...` | sentence |`` of a doc's command table."""
    rows = {}
    for usage, sentence in re.findall(r"^\| `(fvslider [^`]*)` \| (.*) \|$", doc.read_text(), re.M):
        rows[usage.split()[1]] = (usage.replace("\\|", "|"), sentence)
    return rows


@pytest.mark.parametrize("doc", COMMAND_TABLES, ids=lambda p: p.name)
def test_the_docs_command_table_is_the_parsers(doc):
    expected = "\n".join(
        f"| `{usage.replace('|', chr(92) + '|')}` | {sentence} |"
        for usage, sentence in parser_rows().values()
    )
    assert table_rows(doc) == parser_rows(), f"the table's rows should read:\n{expected}"


def test_every_help_states_its_commands_sentence():
    main = words(cli._parser().format_help())
    for name, parser in subparsers().items():
        assert words(cli.COMMANDS[name]) in main, name
        assert words(parser.format_help()).find(words(cli.COMMANDS[name])) > 0, name


def test_every_example_of_the_help_parses():
    examples = [
        shlex.split(line.split("#")[0])[1:]
        for line in cli.EXAMPLES.splitlines()
        if line.strip().startswith("fvslider ")
    ]
    assert {argv[0] for argv in examples} == set(cli.COMMANDS)
    for argv in examples:
        assert cli._parser().parse_args(argv).command is not None


# -- the tutorial --------------------------------------------------------------------------------
BLOCK = re.compile(r"^```(\w+)\n(.*?)^```$", re.S | re.M)
CHECKER = doctest.OutputChecker()
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def run_command(line: str) -> str:
    """``fvslider ...`` run in this process; its stdout and stderr.  The exit code is 0, or
    the one a trailing ``# exit code N`` states."""
    command, _, comment = line.partition("#")
    argv = shlex.split(command)
    assert argv[0] == "fvslider", line
    stated = re.fullmatch(r"\s*exit code (\d+)\s*", comment)
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = cli.main(argv[1:])
    assert code == (int(stated[1]) if stated else 0), f"{line}: exit {code}\n{out.getvalue()}"
    return out.getvalue()


def console(block: str) -> None:
    """Each ``$ command`` of the block run; its output as the block shows it."""
    for chunk in re.split(r"^\$ ", block, flags=re.M)[1:]:
        line, _, shown = chunk.partition("\n")
        got = run_command(line)
        assert CHECKER.check_output(shown, got, FLAGS), f"$ {line}\nshown:\n{shown}\ngot:\n{got}"


def test_the_tutorial_runs_as_written(tmp_path, monkeypatch):
    """The scene files written, the commands run and the sessions replayed, in the order of
    the text, in an empty directory."""
    monkeypatch.chdir(tmp_path)
    text = TUTORIAL.read_text()
    globs: dict = {}
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    kinds = []
    for kind, block in BLOCK.findall(text):
        kinds.append(kind)
        if kind == "toml":
            name = block.splitlines()[0].removeprefix("# ").split(":")[0]
            (tmp_path / name).write_text(block)
        elif kind == "console":
            console(block)
        elif kind == "pycon":
            test = doctest.DocTestParser().get_doctest(block, globs, "tutorial", str(TUTORIAL), 0)
            out = io.StringIO()
            runner.run(test, out=out.write, clear_globs=False)
            assert runner.failures == 0, out.getvalue()
            globs = test.globs  # the next session goes on with these names
    assert {"toml", "console", "pycon"} <= set(kinds)
    assert runner.tries > 0


NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e-?\d+)?(?![\w.]*\w)")


def test_every_number_of_the_tutorial_prose_is_one_it_shows():
    """A number in the text is one that a block (a scene file, a command's output, a
    session) shows, so the test above has produced it."""
    text = TUTORIAL.read_text()
    blocks = " ".join(block for _, block in BLOCK.findall(text))
    shown = {abs(float(number)) for number in NUMBER.findall(blocks)}
    prose = re.sub(r"^#+ \d+\.", "", BLOCK.sub("", text), flags=re.M)  # headings' numbers
    quoted = NUMBER.findall(prose)
    assert quoted and [n for n in quoted if abs(float(n)) not in shown] == []


# -- the README's figures ------------------------------------------------------------------------
def test_the_readmes_figure_4_example_prints_what_the_readme_quotes(tmp_path, monkeypatch, capsys):
    """The sliding-beams example's printed stiffness, the analytic value beside it and their
    difference, as README.md quotes them."""
    from sliders.sliding_beams.exact import sliding_beams

    monkeypatch.chdir(tmp_path)  # the example writes sliding_beams.vtu
    text = (ROOT / "README.md").read_text()
    (block,) = [b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "k L^3" in b]
    exec(compile(block, "README.md", "exec"), {})
    printed = capsys.readouterr().out.strip()
    quote = re.search(
        r"It prints `(k L\^3 / EJ = ([\d.]+))`\. .*? is\s+([\d.]+), ([\d.]+) % below", text, re.S
    )
    assert quote is not None
    assert printed == quote[1]
    ours = float(quote[2])
    exact = sliding_beams(0.18, 0.6, 4.1e4, 1.1e8, "spherical")["k_norm"]
    assert quote[3] == f"{exact:.4f}"
    assert quote[4] == f"{100 * (ours / exact - 1):.2f}"


def test_the_docs_name_the_figures_reproduce_runs():
    """``make demo`` runs ``fvslider reproduce``: the figures README.md says it reproduces, and
    those docs/scenes.md says it runs, are the registered studies and their aliases
    (``fig5``, drawn by ``fig4``)."""
    (listed,) = re.findall(r"reproduces Figures ([\d, ]+) into", (ROOT / "README.md").read_text())
    figures = [*cli.registered_studies(), *cli.ALIASES]
    assert sorted(int(n) for n in listed.split(",")) == sorted(int(f[3:]) for f in figures)
    scenes = (ROOT / "docs" / "scenes.md").read_text()
    (sentence,) = re.findall(r"`reproduce` runs the figures `FIG` named (.*?) or all", scenes, re.S)
    assert sorted(re.findall(r"`(fig\d+)`", sentence)) == sorted(figures)


def test_the_readme_names_every_doc():
    text = (ROOT / "README.md").read_text()
    assert [d.name for d in DOCS[1:] if f"`{d.name}`" not in text] == []
