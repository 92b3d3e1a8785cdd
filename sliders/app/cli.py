"""The ``fvslider`` command: check and run scenes, list and reproduce the paper's studies.

Exit codes: 0 success; 1 a run that did not fully succeed (a solve failed, a sweep point
failed; what was computed is written); 2 an invalid scene or command line, or a file or
directory that cannot be read or written (one message per problem on stderr, nothing
written); 130 interrupted by Ctrl-C (a sweep writes the points it completed).

``check`` does everything ``run`` does but solve: the scene's three validation phases (with
the mesh and restart files it names opened and matched to the model, its drives on their
lines, its force elements' geometry and what the chosen back end runs), a warning for every
option the study ignores (:func:`sliders.app.ignored.ignored_options`), the output
directory (``--out`` or the default; created and removed again to be sure), and the renderer
``output.png`` needs.  ``run`` first removes what interrupted runs
left beside its output directory (:func:`fvbeam.io.remove_leftovers`), and says so.  A dynamic
run keeps a checkpoint beside its output directory, from which ``run --resume DIR`` goes on
(:mod:`sliders.app.checkpoint`; 0 and "nothing to resume" when ``DIR`` holds the finished run).

The command's own modules are imported when a command needs them: ``import sliders`` and
``import fvbeam`` import a public name's module on its first use (PEP 562), so ``fvslider
--help`` imports none of numba, scipy, scikit-fem, pydantic, numpy (nor the installed entry
points, read by ``studies`` and ``reproduce`` only), and ``fvslider check`` never imports
matplotlib or pyvista.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import importlib.util
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sliders.app.model import Model

EXAMPLES = """\
examples:
  fvslider check studies/scenes/fig4_sliding_beams.toml
  fvslider run studies/scenes/fig4_sliding_beams.toml --out results/sliding_beams
  fvslider run studies/scenes/pushed_body.toml --resume results/pushed_body   # after a kill
  fvslider campaign studies/campaigns/landing_gear.toml --out results/drops
  fvslider studies
  fvslider reproduce               # every figure study into results/
  fvslider reproduce fig1 --out out
  fvslider compile                 # compile the numba kernels once (make does it)

scenes are documented in docs/scenes.md, a first one in docs/tutorial.md; exit codes:
0 ok, 1 a solve failed, 2 invalid scene or arguments, or a file that cannot be read or
written (nothing is written), 130 interrupted (Ctrl-C keeps what was computed)
"""

#: What each command does, in one sentence: its line in ``fvslider --help``, the description
#: of its own ``--help`` and its row of the command tables of README.md and docs/scenes.md
#: (``tests/test_docs.py`` holds them equal).
COMMANDS = {
    "check": "everything run does but solving: validate the scene, open the files it names, "
    "check the output directory",
    "run": "validate a scene, solve its study, write its results (CSV tables, and the VTU "
    "states and renders the scene asks for) into the output directory",
    "campaign": "run a scene over a matrix, a list or a random sample of values of its keys, "
    "in parallel (Dask), into one table of cases (docs/campaigns.md)",
    "studies": "list the paper's figure studies",
    "reproduce": "run the paper's figure studies (all of them by default), write their CSV "
    "tables and plots, print their errors against their references",
    "compile": "compile the numba kernels into their cache (make does it after installing; "
    "else the first solve does it)",
}

#: Entry-point group in which the figure studies register their modules (``pyproject.toml``):
#: the library finds them by name and never imports them itself.
STUDY_GROUP = "fvslider.studies"
#: Figure names drawn by another figure's study.
ALIASES = {"fig5": "fig4"}


def _load(path: Path) -> Model:
    """The scene at ``path`` validated and built (raises ``SceneError``)."""
    from sliders.app.model import Model
    from sliders.app.scene import load_scene

    return Model(load_scene(path), source=str(path))


def _out(args: argparse.Namespace) -> Path:
    """The output directory of ``run`` (``--out`` or ``--resume``, default
    ``results/SCENE``)."""
    given = args.out if args.out is not None else getattr(args, "resume", None)
    return given if given is not None else Path("results") / args.scene.stem


def _validated(args: argparse.Namespace) -> Model | None:
    """Everything ``run`` checks before solving: the scene (its three phases, the files it
    points to included), the output location and the renderer ``output.png`` needs.  Every
    problem is printed on stderr; ``None`` if there is any."""
    from fvbeam.io import OUTPUT_MARKER, OutputError, check_replaceable
    from sliders.app.errors import SceneError
    from sliders.app.ignored import ignored_options

    messages, model = [], None
    try:
        model = _load(args.scene)
    except SceneError as exc:
        messages.append(str(exc))
    else:
        for problem in ignored_options(model.scene):
            print(f"{args.scene}: warning: {problem}", file=sys.stderr)
    try:
        check_replaceable(_out(args), OUTPUT_MARKER)
    except OutputError as exc:
        messages.append(f"fvslider: {exc}")
    if model is not None:
        output = model.scene.output
        for key, value, module in (
            ("png", output.png, "pyvista"),
            ("animation", output.animation, "pyvista"),
            ("animation", output.animation, "imageio"),
        ):
            if value != "none" and importlib.util.find_spec(module) is None:
                messages.append(
                    f"fvslider: output.{key} needs {module}: pip install 'fvslider[render]'"
                )
    for message in messages:
        print(message, file=sys.stderr)
    return None if messages else model


def _check(args: argparse.Namespace) -> int:
    model = _validated(args)
    if model is None:
        return 2
    from sliders.app.schema import DynamicStudy, SweepStudy

    scene, spec = model.scene, model.scene.study
    study: str = spec.kind
    if isinstance(spec, SweepStudy) and spec.parameter is not None:
        study += f" over {spec.parameter.kind}, {len(spec.sweep_values())} values"
    if isinstance(spec, DynamicStudy):
        study += f" to t = {spec.t_end:g} s, step {spec.step:g} s, {len(scene.drive)} drives"
    print(
        f"{args.scene}: valid ({len(scene.beam)} beams, {len(scene.body)} bodies, "
        f"{len(scene.slider)} sliders; {study}; output {_out(args)})"
    )
    return 0


def _run(args: argparse.Namespace) -> int:
    from fvbeam.io import writer

    model = _validated(args)
    if model is None:
        return 2
    out = _out(args)
    with writer(out, f"fvslider run {args.scene}"):
        return _run_into(args, model, out)


def _run_into(args: argparse.Namespace, model: Model, out: Path) -> int:
    """``fvslider run`` into ``out``, which this process is the one writer of."""
    from fvbeam.io import OUTPUT_MARKER, remove_leftovers
    from sliders.app import checkpoint
    from sliders.app.run import Results, run
    from sliders.app.tables import write_results

    removed = remove_leftovers(out, OUTPUT_MARKER) + remove_leftovers(
        checkpoint.checkpoint_directory(out), checkpoint.MARKER
    )
    if removed:
        print(
            f"removed {len(removed)} temporary director{'y' if len(removed) == 1 else 'ies'} "
            f"left beside {out} by interrupted runs: {', '.join(p.name for p in removed)}",
            file=sys.stderr,
        )
    if model.scene.study.kind == "dynamic":
        return _run_dynamic(model, out, resume=args.resume is not None)
    if args.resume is not None:
        print(
            f"fvslider: --resume: a {model.scene.study.kind} study has no checkpoints "
            "(only dynamic studies do)",
            file=sys.stderr,
        )
        return 2
    results = run(model, progress=True)
    assert isinstance(results, Results)  # a dynamic study went to _run_dynamic
    write_results(results, out)
    done = len(results.samples)
    print(f"{done} of {results.planned} samples in {results.seconds:.2f} s, written to {out}")
    if results.kinematics:
        print(results.kinematics, file=sys.stderr if results.kinematics_warning else sys.stdout)
    for sample in results.failures[:5]:
        value = "" if sample.value is None else f" (value {sample.value:g})"
        print(f"  sample {sample.index}{value} failed: {sample.error}", file=sys.stderr)
    if len(results.failures) > 5:
        print(f"  ... {len(results.failures) - 5} more failures in samples.csv", file=sys.stderr)
    if results.interrupted:
        print("interrupted: the completed samples are written", file=sys.stderr)
        return 130
    return 1 if results.failures else 0


def _run_dynamic(model: Model, out: Path, resume: bool) -> int:
    from sliders.app.checkpoint import Complete
    from sliders.app.run_dynamic import integrate, write_dynamic

    try:
        outcome = integrate(model, progress=True, out=out, resume=resume)
        if outcome.state is None:  # not even the start: nothing to write
            what = f"failed: {outcome.error}" if outcome.error else "interrupted"
            print(f"fvslider: {what}; nothing written to {out}", file=sys.stderr)
            return 1 if outcome.error else 130
        write_dynamic(outcome, out)
    except Complete as done:
        print(done)
        return 0
    except ValueError as exc:
        print(f"fvslider: {exc}", file=sys.stderr)
        return 2
    steps = outcome.recorder.count("history") - 1
    reached = "" if outcome.state is None else f" to t = {outcome.state.t:.6g} s"
    print(f"{max(steps, 0)} steps{reached} in {outcome.seconds:.2f} s, written to {out}")
    if outcome.state is not None:
        from sliders.app.run_exact import dynamic_choice

        choice = dynamic_choice(model, outcome.state.q)
        if choice.statement:
            print(choice.statement, file=sys.stderr if choice.warning else sys.stdout)
    if outcome.error:
        print(f"  failed: {outcome.error}", file=sys.stderr)
        return 1
    if outcome.interrupted:
        print(
            f"interrupted: the steps computed are written; --resume {out} goes on",
            file=sys.stderr,
        )
        return 130
    return 0


def _campaign(args: argparse.Namespace) -> int:
    from sliders.app.campaign import command

    return command(args.campaign, args.out, args.workers, args.scheduler, args.resume, args.keep)


def registered_studies() -> dict[str, str]:
    """The paper's figure studies registered under :data:`STUDY_GROUP`: key (``fig4`` draws
    Figures 4 and 5) to module name, in key order."""
    import importlib.metadata  # a tenth of a second: only the figure studies need it

    found = {ep.name: ep.value for ep in importlib.metadata.entry_points(group=STUDY_GROUP)}
    return dict(sorted(found.items()))


def describe(key: str) -> str:
    """The first line of a study's docstring, read without importing it."""
    module = registered_studies()[key]
    spec = importlib.util.find_spec(module)
    if spec is None or spec.origin is None:
        raise ValueError(f"study {key!r}: its module {module} is not installed")
    doc = ast.get_docstring(ast.parse(Path(spec.origin).read_text())) or ""
    return doc.splitlines()[0] if doc else ""


def _studies(args: argparse.Namespace) -> int:
    for key, module in registered_studies().items():
        path = "/".join(module.split(".")) + ".py"
        print(f"{key:5s} {path:30s} {describe(key)}")
    return 0


def _reproduce(args: argparse.Namespace) -> int:
    from fvbeam.io import check_writable

    check_writable(args.out)
    registered = registered_studies()
    keys = list(dict.fromkeys(args.figures or list(registered)))
    plot = importlib.util.find_spec("matplotlib") is not None
    if not plot:
        print(
            "matplotlib is not installed: CSV only (pip install 'fvslider[plot]' for the PNGs)",
            file=sys.stderr,
        )
    table = []
    for key in keys:
        module = importlib.import_module(registered[key])
        start = time.perf_counter()
        rows = module.reproduce(args.out, plot_png=plot)
        seconds = time.perf_counter() - start
        table += [(key, case, error, reference, seconds) for case, error, reference in rows]
    print(f"\n{'figure':7s}{'case':40s}{'max error':>11s}  {'seconds':>8s}  reference")
    for key, case, error, reference, seconds in table:
        print(f"{key:7s}{case:40s}{error:11.3g}  {seconds:8.1f}  {reference}")
    print(f"written to {args.out}")
    return 0


def _compile(args: argparse.Namespace) -> int:
    from sliders.sliding_beams.model import compile_kernels

    print("compiling the numba kernels into their cache (once per checkout)...", flush=True)
    start = time.perf_counter()
    compile_kernels()
    print(f"compiled in {time.perf_counter() - start:.1f} s")
    return 0


def _figure(name: str) -> str:
    """A figure name as its study's key (``fig5`` is drawn by ``fig4``)."""
    key = ALIASES.get(name, name)
    registered = registered_studies()
    if key not in registered:
        choices = ", ".join(list(registered) + list(ALIASES))
        raise argparse.ArgumentTypeError(f"unknown figure {name!r} (choose from {choices})")
    return key


def _parser(named: bool = True) -> argparse.ArgumentParser:
    """The command line's parser; ``named``: name the registered figure studies in the
    help of ``reproduce`` (reading the installed entry points, a few tenths of a second, is
    left to the command lines that can show or use them)."""
    figures = (
        f"figures to run, from {', '.join(list(registered_studies()) + list(ALIASES))}"
        if named
        else "figures to run (fvslider studies lists them)"
    )
    parser = argparse.ArgumentParser(
        prog="fvslider",
        description="Finite-volume beams and deformable slider joints: "
        "run scenes (TOML) and the paper's studies.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    commands = parser.add_subparsers(title="commands", required=True, metavar="COMMAND")
    run = commands.add_parser(
        "run",
        help=COMMANDS["run"],
        description=COMMANDS["run"],
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    run.add_argument("scene", type=Path, metavar="SCENE.toml")
    where = run.add_mutually_exclusive_group()
    where.add_argument(
        "--out",
        type=Path,
        metavar="DIR",
        help="output directory, replaced whole (default results/SCENE)",
    )
    where.add_argument(
        "--resume",
        type=Path,
        metavar="DIR",
        help="go on with the dynamic run into DIR from its last checkpoint (DIR.checkpoint)",
    )
    run.set_defaults(command=_run)
    check = commands.add_parser("check", help=COMMANDS["check"], description=COMMANDS["check"])
    check.add_argument("scene", type=Path, metavar="SCENE.toml")
    check.add_argument(
        "--out",
        type=Path,
        metavar="DIR",
        help="the output directory run would write (default results/SCENE)",
    )
    check.set_defaults(command=_check)
    campaign = commands.add_parser(
        "campaign", help=COMMANDS["campaign"], description=COMMANDS["campaign"]
    )
    campaign.add_argument("campaign", type=Path, metavar="CAMPAIGN.toml")
    campaign.add_argument(
        "--out",
        type=Path,
        required=True,
        metavar="DIR",
        help="output directory: cases.csv, cases.parquet",
    )
    campaign.add_argument(
        "--workers", type=int, default=2, help="local worker processes (default 2)"
    )
    campaign.add_argument(
        "--scheduler", metavar="ADDRESS", help="a running Dask scheduler to use instead"
    )
    campaign.add_argument(
        "--resume", action="store_true", help="keep the finished cases in --out, run the rest"
    )
    campaign.add_argument(
        "--keep", action="store_true", help="keep each case's tables in DIR/runs/case_NNNNNN"
    )
    campaign.set_defaults(command=_campaign)
    studies = commands.add_parser(
        "studies", help=COMMANDS["studies"], description=COMMANDS["studies"]
    )
    studies.set_defaults(command=_studies)
    reproduce = commands.add_parser(
        "reproduce", help=COMMANDS["reproduce"], description=COMMANDS["reproduce"]
    )
    reproduce.add_argument(
        "figures",
        nargs="*",
        metavar="FIG",
        type=_figure,
        help=f"{figures} (default: all)",
    )
    reproduce.add_argument(
        "--out",
        type=Path,
        default=Path("results"),
        metavar="DIR",
        help="output directory (default results/)",
    )
    reproduce.set_defaults(command=_reproduce)
    compile_ = commands.add_parser(
        "compile", help=COMMANDS["compile"], description=COMMANDS["compile"]
    )
    compile_.set_defaults(command=_compile)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``); return the exit code."""
    argv = sys.argv[1:] if argv is None else argv
    args = _parser(named="reproduce" in argv).parse_args(argv)
    from fvbeam.io import OutputError
    from sliders.app.errors import SceneError

    try:
        return args.command(args)
    except SceneError as exc:
        print(exc, file=sys.stderr)
        return 2
    except OutputError as exc:
        print(f"fvslider: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # any other file problem: one line, no traceback
        where = f"{exc.filename}: " if exc.filename is not None else ""
        print(f"fvslider: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
