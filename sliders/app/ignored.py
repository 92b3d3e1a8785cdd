"""Options a scene sets that its study ignores: each a warning at its key path, never silence.

A valid scene may set an option that has no effect on its study: friction in a static study
(a static solve has no sliding speed), a slider's or point load's ``kernel`` without
``smearing``, ``mu_static``'s Stribeck speed without ``mu_static``, ``study.every`` when
nothing keeps states (no VTU, no renders of every state), ``study.planar`` with the bordered
back end (which solves every dof) or in a modes study. The result is what it would be
without the option, which is not what the scene asks for: :func:`ignored_options` lists
them, and ``fvslider check`` and ``run`` print each as a warning (the scene stays valid).
Only keys the scene writes count (pydantic's ``model_fields_set``): a default is never
reported.
"""

from __future__ import annotations

from sliders.app.errors import Problem
from sliders.app.schema import DynamicStudy, ModesStudy, PointLoad, Scene


def ignored_options(scene: Scene) -> list[Problem]:
    """Every option ``scene`` writes that its study ignores, at its key path, with why."""
    study = scene.study
    found: list[Problem] = []
    dynamic = isinstance(study, DynamicStudy)
    for i, slider in enumerate(scene.slider):
        path = f"slider[{i}]"
        if slider.friction is not None and not dynamic:
            found.append(
                Problem(
                    f"{path}.friction",
                    f"a {study.kind} study ignores friction (a static solve has no sliding "
                    "speed): it acts in dynamic studies only",
                )
            )
        if slider.friction is not None and "v_stribeck" in slider.friction.model_fields_set:
            if slider.friction.mu_static is None:
                found.append(
                    Problem(
                        f"{path}.friction.v_stribeck",
                        "ignored without mu_static (the Stribeck speed shapes the fall from "
                        "the static coefficient)",
                        slider.friction.v_stribeck,
                    )
                )
        if "kernel" in slider.model_fields_set and slider.smearing == 0:
            found.append(_unsmeared(f"{path}.kernel", slider.kernel))
    for i, load in enumerate(scene.load):
        if isinstance(load, PointLoad) and "kernel" in load.model_fields_set:
            if load.smearing == 0:
                found.append(_unsmeared(f"load[{i}].kernel", load.kernel))
    if isinstance(study, ModesStudy) and "planar" in study.model_fields_set:
        found.append(
            Problem(
                "study.planar",
                "ignored: a modes study solves the three-dimensional problem (the modes of "
                "both planes)",
                study.planar,
            )
        )
    if isinstance(study, DynamicStudy) and "every" in study.model_fields_set:
        output = scene.output
        if not output.vtu and output.png != "all":
            found.append(
                Problem(
                    "study.every",
                    "ignored: it thins the states kept for output.vtu and output.png = "
                    "'all', and the scene asks for neither",
                    study.every,
                )
            )
    if study.method == "bordered" and "planar" in study.model_fields_set and study.planar:
        found.append(
            Problem(
                "study.planar",
                "ignored with method = 'bordered', which solves every dof (a planar solve "
                "runs on the condensed back end)",
                study.planar,
            )
        )
    return found


def _unsmeared(path: str, kernel: str) -> Problem:
    return Problem(path, "ignored with smearing = 0 (a kernel shapes a smeared load)", kernel)
