"""``nfdcal run SCENE``: run a scene (a TOML file, or the name of a built-in scene).

    nfdcal run reference              # the paper's case: calibration + collisions
    nfdcal run my_scene.toml --out results/my_scene
    nfdcal run --dry-run steel        # the plan: stages, meshes (cached or to build), estimated time
    nfdcal run --list                 # the built-in scenes

The scene is validated before anything runs (an unknown key, a wrong type or a value out of
range is one line naming the file and the key, exit code 2). Progress goes to stderr when it is
a terminal (silence it with --quiet). Scene format: calib/scenes/schema.py.
"""
from __future__ import annotations

from calib.commands.common import add_summary_arguments, print_summary, with_v_max


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("run", help="run a scene (TOML): materials, mesh, stages, outputs",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", nargs="?", help="scene file (.toml) or built-in scene name")
    parser.add_argument("--dry-run", action="store_true", help="print the plan and exit")
    parser.add_argument("--list", action="store_true", help="list the built-in scenes")
    parser.add_argument("--out", default=None, help="output folder (default: the scene's, else results/scenes/NAME)")
    parser.add_argument("--v-max", default=None, metavar="V",
                        help="calibrate every material for impacts up to V [m/s] (replaces the scene's load-path"
                             " peaks: calib.fit.impact_window)")
    add_summary_arguments(parser)
    parser.set_defaults(run=run)


def run(ns) -> int:
    from calib import scenes
    from calib.commands.progress import progress_reporter

    if ns.list:
        builtin = {name: scenes.load_scene(path).description for name, path in sorted(scenes.builtin_scenes().items())}
        print_summary(ns, builtin, [f"{name:<14} {description}" for name, description in builtin.items()])
        return 0
    if not ns.scene:
        raise ValueError("SCENE is required: a scene file (.toml) or a built-in scene name (see --list)")
    scene = with_v_max(scenes.load_scene(ns.scene), ns.v_max)
    stages = scenes.plan(scene)
    if ns.dry_run:
        folder = scene.out_dir(ns.out)
        print_summary(ns, scenes.plan_summary(scene, stages, folder), scenes.format_plan(scene, stages, folder))
        return 0
    with progress_reporter(ns.quiet, sum(s.estimate_s for s in stages)) as progress:
        summary = scenes.run_scene(scene, ns.out, progress=progress)
    print_summary(ns, summary, scenes.summary_lines(summary))
    return 0
