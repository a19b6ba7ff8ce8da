"""Flags shared by sub-commands: numbers parsed with clear errors, the material of a sphere, and
the one way a command answers.

Numbers are parsed inside ``run`` (not by argparse) so a bad value gives one line naming the
flag and its range from the dispatcher (exit code 2), never a traceback.

Every command answers the same way: a readable summary on stdout by default, the same summary
as one JSON object with ``--json`` (``print_summary``); progress goes to stderr on a terminal
(``--quiet`` silences it); results go to ``--out``.
"""
from __future__ import annotations

from nfdmodel import Material, check_real, limits, reference_case

# The paper's reference case (Vu-Quoc & Zhang 1999, section 2): aluminium sphere on a rigid flat.
MATERIAL_DEFAULTS = {"R": reference_case.R, "E": reference_case.E, "nu": reference_case.NU,
                     "sigma_y": reference_case.SIGMA_Y, "rho": reference_case.RHO}
MATERIAL_HELP = {"R": "sphere radius [m] (> 0)", "E": "Young's modulus [Pa] (> 0)",
                 "nu": f"Poisson's ratio (0 <= nu < {limits.NU_MAX:g})", "sigma_y": "yield stress [Pa] (> 0)",
                 "rho": "density [kg/m^3] (> 0)"}
# allowed range of each material flag (check_real's keywords), as nfdmodel.Material states it
MATERIAL_RANGES = {"R": {"low": 0.0, "unit": "m"}, "E": {"low": 0.0, "unit": "Pa"},
                   "nu": {"low": 0.0, "low_inclusive": True, "high": limits.NU_MAX},
                   "sigma_y": {"low": 0.0, "unit": "Pa"}, "rho": {"low": 0.0, "unit": "kg/m^3"}}


def flag_name(key: str) -> str:
    """'sigma_y' -> '--sigma-y'"""
    return f"--{key.replace('_', '-')}"


def number(flag: str, text, default=None, **allowed) -> float:
    """``text`` as a finite float inside the ``allowed`` range (check_real's keywords), or
    ``default`` when the flag was not given."""
    return default if text is None else check_real(flag, text, text=True, **allowed)


def integer(flag: str, text, default: int, low: int, high: int) -> int:
    """``text`` as an integer in [low, high] (a ValueError naming the flag and the range)."""
    if text is None:
        return default
    value = number(flag, text, low=low, low_inclusive=True, high=high, high_inclusive=True)
    if value != int(value):
        raise ValueError(f"{flag} out of range: need an integer in [{low}, {high}], got {text}")
    return int(value)


def add_summary_arguments(parser, progress: bool = True) -> None:
    """--json and --quiet, the same in every command (``progress``: whether the command reports
    progress; one that does not accepts --quiet too, so a script passes it to every command)."""
    parser.add_argument("--json", action="store_true",
                        help="print the summary as one JSON object (default: a readable summary)")
    parser.add_argument("--quiet", action="store_true",
                        help="no progress messages on stderr" + ("" if progress else " (this command prints none)"))


def print_summary(ns, summary, lines) -> None:
    """The command's answer on stdout: ``summary`` as JSON with --json, else the readable ``lines``."""
    if ns.json:
        from calib import output

        print(output.to_json(summary), end="")
    else:
        print("\n".join(lines))


def add_material_arguments(parser) -> None:
    """--R --E --nu --sigma-y --rho, defaulting to the reference aluminium sphere."""
    for key, help_text in MATERIAL_HELP.items():
        parser.add_argument(flag_name(key), dest=key, default=None,
                            help=f"{help_text} (default {MATERIAL_DEFAULTS[key]:g})")


def material_flags(ns) -> dict:
    """The material flags the user gave (None for those left at their default)."""
    return {key: getattr(ns, key) for key in MATERIAL_DEFAULTS}


def material_from_args(ns) -> tuple[Material, float]:
    """(nfdmodel.Material, R [m]) from the namespace; an error names the flag and its range."""
    values = {key: number(flag_name(key), text, MATERIAL_DEFAULTS[key], **MATERIAL_RANGES[key])
              for key, text in material_flags(ns).items()}
    return Material(values["E"], values["nu"], values["sigma_y"], values["rho"]), values["R"]


COUNTER_HELP = {"counter_E": "the counter-body's Young's modulus [Pa]: the sphere is pressed on a deformable body of "
                              "this material instead of a rigid flat (absent: the rigid flat)",
                "counter_nu": f"the counter-body's Poisson's ratio (0 <= nu < {limits.NU_MAX:g}; default the sphere's)",
                "counter_sigma_y": "the counter-body's yield stress [Pa] (absent: elastic)",
                "counter_R": "the counter-body's radius [m]: a sphere (absent: a flat)",
                "counter_rho": "the counter-body's density [kg/m^3]: required for a counter-sphere (its mass enters "
                               "the pair's m* = m1 m2 / (m1 + m2)); a flat (a held block, not in m*): default the "
                               "sphere's"}


# --kinematics (calibrate, impact): the flag's values and calib.fe.kinematics' names
KINEMATICS_FLAG = {"small": "small-strain", "finite": "finite-strain"}


def add_counter_arguments(parser, density: bool = True) -> None:
    """--counter-E --counter-nu --counter-sigma-y --counter-R [--counter-rho]: the deformable
    counter-body (``density``: the command's result depends on the pair's mass)."""
    for key, help_text in COUNTER_HELP.items():
        if density or key != "counter_rho":
            parser.add_argument(flag_name(key), dest=key, default=None, help=help_text)


def counter_from_args(ns, material: Material):
    """calib.fit.counter.CounterBody from the counter flags, None when none is given (the rigid
    flat); an error names the flag and its range (the ranges of nfdmodel.limits). A command with
    --counter-rho needs it for a counter-sphere (CounterBody.require_density)."""
    from nfdmodel.materials import check_radius
    from nfdmodel.validation import check_solid

    given = {key: getattr(ns, key, None) for key in COUNTER_HELP}
    if all(v is None for v in given.values()):
        return None
    if given["counter_E"] is None:
        named = ", ".join(flag_name(k) for k, v in given.items() if v is not None)
        raise ValueError(f"--counter-E out of range: need a Young's modulus > 0 Pa for the counter-body that {named} "
                         f"describe(s), got none")
    E = check_solid("E", number("--counter-E", given["counter_E"], **MATERIAL_RANGES["E"]), "--counter-E")
    nu = number("--counter-nu", given["counter_nu"], material.nu, **MATERIAL_RANGES["nu"])
    sigma_y = given["counter_sigma_y"]
    if sigma_y is not None:
        sigma_y = check_solid("sigma_y", number("--counter-sigma-y", sigma_y, **MATERIAL_RANGES["sigma_y"]),
                              "--counter-sigma-y")
    R = given["counter_R"]
    if R is not None:
        R = check_radius("--counter-R", number("--counter-R", R, **MATERIAL_RANGES["R"]))
    rho = given["counter_rho"]
    if rho is not None:
        rho = check_solid("rho", number("--counter-rho", rho, **MATERIAL_RANGES["rho"]), "--counter-rho")
    from calib.fit.counter import CounterBody

    counter = CounterBody(E, nu, sigma_y, R, rho)
    return counter.require_density() if hasattr(ns, "counter_rho") else counter


def material_folder_name(material: Material, radius: float) -> str:
    """The part of a default results folder's name that names a sphere other than the reference one."""
    return f"E{material.E:g}_nu{material.nu:g}_sy{material.sigma_y:g}_R{radius:g}"


def counter_folder_name(counter) -> str:
    """The part of a default results folder's name that names a counter-body (calibrate, hertz)."""
    return (f"on_E{counter.E:g}_nu{counter.nu:g}_sy{'-elastic' if counter.sigma_y is None else f'{counter.sigma_y:g}'}"
            f"_{'flat' if counter.R is None else f'R{counter.R:g}'}"
            + ("" if getattr(counter, "rho", None) is None else f"_rho{counter.rho:g}"))


def is_reference(ns) -> bool:
    """True when no material flag differs from the reference case and no counter-body is given."""
    if any(getattr(ns, key, None) is not None for key in COUNTER_HELP):
        return False
    return all(text is None or number(flag_name(k), text) == MATERIAL_DEFAULTS[k]
               for k, text in material_flags(ns).items())


def with_v_max(scene, text):
    """``scene`` with its calibration window set by ``--v-max`` (None: as the scene says)."""
    if text is None:
        return scene
    import dataclasses

    from nfdmodel.validation import check_solid

    v_max = number("--v-max", text, low=0.0, unit="m/s")
    check_solid("v_in", v_max)
    if scene.calibration_ship is None:
        raise ValueError(f"--v-max sets the calibration window: scene {scene.source} has no [calibration]")
    return dataclasses.replace(scene, calibration_v_max=v_max, calibration_v_max_from_collision=False)


HARDENING_HELP = {
    "hardening_modulus": "isotropic hardening of the sphere: the plastic modulus H [Pa] of the linear flow curve "
                         "sigma_y = sigma_Y + H eps_p (eps_p the equivalent plastic strain; the paper's hardening "
                         "coefficient K; 0 <= H <= E; default and 0: perfectly plastic)",
    "flow_curve": "isotropic hardening of the sphere by a tabulated flow curve: a CSV with the columns "
                  "plastic_strain,stress (true values, from plastic strain 0 at --sigma-y, stress never falling); "
                  "not with --hardening-modulus",
    "flow_curve_extrapolation": "beyond the --flow-curve table's last point: flat (the default: the last stress) or "
                                "slope (the last segment's slope)",
}


def add_hardening_arguments(parser) -> None:
    """--hardening-modulus --flow-curve --flow-curve-extrapolation: the sphere's isotropic hardening."""
    for key, help_text in HARDENING_HELP.items():
        parser.add_argument(flag_name(key), dest=key, default=None,
                            metavar={"hardening_modulus": "H", "flow_curve": "CSV"}.get(key, "flat|slope"),
                            help=help_text)


def flow_curve_from_args(ns, material: Material):
    """The sphere's flow curve (calib.fe.flow_curve) from the hardening flags, None for perfect
    plasticity (no flag, or --hardening-modulus 0: every figure then the perfectly plastic one's);
    an error of one line names the flag, its range, or the table's file and column."""
    modulus, path, extrapolation = (getattr(ns, key, None) for key in HARDENING_HELP)
    if modulus is not None and path is not None:
        raise ValueError("--hardening-modulus and --flow-curve both give the flow curve: give one of them")
    if extrapolation is not None and path is None:
        raise ValueError("--flow-curve-extrapolation extends a --flow-curve table: give the table too")
    if extrapolation is not None and extrapolation not in ("flat", "slope"):
        raise ValueError(f"--flow-curve-extrapolation must be one of flat, slope, got {extrapolation!r}")
    # calib.fe only here: a command that takes these flags runs the FE anyway
    from calib.fe.flow_curve import LinearHardening, read_flow_curve

    if modulus is not None:
        modulus = number("--hardening-modulus", modulus, low=0.0, low_inclusive=True, high=material.E,
                         high_inclusive=True, unit="Pa (the plastic modulus, at most E)")
        return LinearHardening(material.sigma_y, modulus) if modulus > 0 else None
    if path is None:
        return None
    try:
        return read_flow_curve(path, extrapolation or "flat", sigma_y=material.sigma_y)
    except ValueError as exc:
        hint = " (give --sigma-y as the table's first stress)" if "must start at sigma_y" in str(exc) else ""
        raise ValueError(f"--flow-curve: {exc}{hint}") from None


def refuse_flow_curve(ns, command: str) -> None:
    """--flow-curve (--flow-curve-extrapolation) refused in one line by a command answering from the vz master
    table's hardening sheet (calib.fit.vz_hardening), which holds linear hardening only."""
    given = hardening_given(ns)
    if given is not None and (given != "--hardening-modulus" or getattr(ns, "flow_curve", None) is not None):
        raise ValueError(f"{given}: nfdcal {command} takes linear hardening only (--hardening-modulus H, the vz master "
                         f"table's hardening sheet); for a tabulated flow curve run the FE, nfdcal calibrate "
                         f"--flow-curve CSV with its --E --nu --sigma-y --R")


def hardening_given(ns) -> str | None:
    """The first hardening flag given (its name), None when none is."""
    return next((flag_name(key) for key in HARDENING_HELP if getattr(ns, key, None) is not None), None)


def refuse_hardening(ns, command: str, why: str) -> None:
    """A command answering from a master table (of perfectly plastic spheres, no hardening
    dimension) refuses the hardening flags in one line: why, and the calibration to run instead
    (--hardening-modulus 0, the perfectly plastic sphere, is answered)."""
    given = hardening_given(ns)
    if given == "--hardening-modulus" and getattr(ns, "flow_curve", None) is None:
        if number(given, ns.hardening_modulus, low=0.0, low_inclusive=True, unit="Pa") == 0:
            return                      # H = 0: the perfectly plastic sphere the tables hold
    if given is not None:
        raise ValueError(f"{given}: nfdcal {command} {why}; the master tables are of perfectly plastic spheres (no "
                         f"hardening dimension): run the FE of this sphere instead, nfdcal calibrate "
                         f"--hardening-modulus H (or --flow-curve CSV) with its --E --nu --sigma-y --R")


def hardening_folder_name(curve) -> str:
    """The part of a default results folder's name that names a hardening sphere."""
    record = curve.record()
    if record["flow_curve"] == "linear":
        return f"H{record['hardening_modulus']:g}"
    from pathlib import Path

    return f"flow-{Path(record['source']).stem}-{record['extrapolation']}"


def hardening_line(curve) -> str:
    """The sphere's flow curve (a FlowCurve, or its ``record()`` as a parameter file states it) in one line."""
    record = curve if isinstance(curve, dict) else curve.record()
    if record["flow_curve"] in ("swift", "ludwik"):
        return (f"isotropic hardening: the {record['flow_curve']} flow curve from sigma_Y = {record['sigma_y']:.4g} Pa, "
                f"K = {record['K']:.4g} Pa, n = {record['n']:g}")
    if record["flow_curve"] == "linear":
        return f"isotropic hardening: sigma_y = sigma_Y + H eps_p, H = {record['hardening_modulus']:.4g} Pa"
    return (f"isotropic hardening: the flow curve of {record['source']} ({len(record['stress'])} points to eps_p = "
            f"{record['plastic_strain'][-1]:.4g}, {record['stress'][-1]:.4g} Pa; beyond it {record['extrapolation']})")


def file_hardening_line(path) -> str | None:
    """The flow curve a parameter file states (a hardening calibration's), in one line; None when it
    states none (a perfectly plastic sphere's)."""
    import json
    from pathlib import Path

    try:
        record = json.loads(Path(path).read_text(encoding="utf-8")).get("hardening")
    except (OSError, ValueError, AttributeError):
        return None                     # the file's own reader reports what is wrong with it
    return None if not isinstance(record, dict) else f"the sphere's {hardening_line(record)}"


RATE_LAW_HELP = {
    "rate_law": "strain-rate dependence of the sphere's flow stress in the dynamic FE, sigma_y R(eps_dot): "
                "johnson-cook (R = 1 + C ln(max(eps_dot / eps_dot_0, 1))) or cowper-symonds (R = 1 + (eps_dot / D)^(1/q)); "
                "default: rate-independent",
    "jc_C": f"Johnson-Cook's rate constant C [-] (0 <= C <= {limits.JC_C_MAX:g}; required with --rate-law "
            f"johnson-cook)",
    "jc_reference_rate": f"Johnson-Cook's reference strain rate eps_dot_0 [1/s] ({limits.JC_REFERENCE_RATE_MIN:g} to "
                         f"{limits.JC_REFERENCE_RATE_MAX:g}; default 1)",
    "cs_D": f"Cowper-Symonds' rate constant D [1/s] ({limits.CS_D_MIN:g} to {limits.CS_D_MAX:g}; required with "
            f"--rate-law cowper-symonds)",
    "cs_q": f"Cowper-Symonds' exponent q [-] ({limits.CS_Q_MIN:g} to {limits.CS_Q_MAX:g}; required with --rate-law "
            f"cowper-symonds)",
}
RATE_LAW_FLAGS = {"johnson-cook": ("jc_C", "jc_reference_rate"), "cowper-symonds": ("cs_D", "cs_q")}


def add_rate_law_arguments(parser, rate_law_help: str | None = None, helps: dict | None = None) -> None:
    """--rate-law johnson-cook|cowper-symonds and its constants --jc-C --jc-reference-rate --cs-D --cs-q
    (``rate_law_help``: --rate-law's own help, default the dynamic FE's; ``helps``: other flags' help by key)."""
    for key, help_text in RATE_LAW_HELP.items():
        if key == "rate_law" and rate_law_help is not None:
            help_text = rate_law_help
        help_text = (helps or {}).get(key, help_text)
        parser.add_argument(flag_name(key), dest=key, default=None,
                            metavar={"rate_law": "johnson-cook|cowper-symonds", "jc_C": "C",
                                     "jc_reference_rate": "RATE", "cs_D": "D", "cs_q": "q"}[key], help=help_text)


def add_rate_form_argument(parser) -> None:
    """--rate-form fixed|relaxing: which rate-aware law --rate-law states (nfdmodel.rate_relaxing.rate_form_law)."""
    parser.add_argument("--rate-form", default=None, choices=("fixed", "relaxing"),
                        help="with --rate-law: the rate-aware law's form, relaxing (the default: the factor "
                             "follows the contact's strain rate and relaxes towards the turning point, "
                             "nfdmodel.rate_relaxing: within 2 %% in e of the dynamic FE; the plugin's rate ... "
                             "relaxing K) or fixed (R fixed at first contact, nfdmodel.rate_aware: off by up to 8 %%, "
                             "1.7-9x faster per compiled contact-step)")


def rate_form_from_args(ns) -> str:
    """The --rate-form given ("relaxing" without it); one line when it is given without --rate-law."""
    form = getattr(ns, "rate_form", None)
    if form is not None and getattr(ns, "rate_law", None) is None:
        raise ValueError("--rate-form is the form of the --rate-law law: give --rate-law johnson-cook or "
                         "cowper-symonds too")
    return form or "relaxing"


def rate_law_given(ns) -> str | None:
    """The first rate-law flag given (its name), None when none is."""
    return next((flag_name(key) for key in RATE_LAW_HELP if getattr(ns, key, None) is not None), None)


def rate_law_from_args(ns):
    """The sphere's rate law (calib.fe.rate_law) from --rate-law and its constants, None without them;
    an error of one line names the flag and its range."""
    name = getattr(ns, "rate_law", None)
    if name is None:
        given = rate_law_given(ns)
        if given is not None:
            raise ValueError(f"{given} is a constant of --rate-law: give --rate-law johnson-cook or cowper-symonds too")
        return None
    if name not in RATE_LAW_FLAGS:
        raise ValueError(f"--rate-law must be one of johnson-cook, cowper-symonds, got {name!r}")
    for other, keys in RATE_LAW_FLAGS.items():
        for key in keys:
            if other != name and getattr(ns, key) is not None:
                raise ValueError(f"{flag_name(key)} is a constant of --rate-law {other}, not of {name}")
    from calib.fe.rate_law import CowperSymondsRate, JohnsonCookRate

    if name == "johnson-cook":
        if ns.jc_C is None:
            raise ValueError(f"--rate-law johnson-cook needs --jc-C (its rate constant C, 0 <= C <= {limits.JC_C_MAX:g})")
        return JohnsonCookRate(number("--jc-C", ns.jc_C, low=0.0, low_inclusive=True, high=limits.JC_C_MAX,
                                      high_inclusive=True),
                               number("--jc-reference-rate", ns.jc_reference_rate, 1.0, low=limits.JC_REFERENCE_RATE_MIN,
                                      low_inclusive=True, high=limits.JC_REFERENCE_RATE_MAX, high_inclusive=True,
                                      unit="1/s"))
    for key in ("cs_D", "cs_q"):
        if getattr(ns, key) is None:
            raise ValueError(f"--rate-law cowper-symonds needs --cs-D and --cs-q (e.g. mild steel: 40.4 /s, 5)")
    return CowperSymondsRate(number("--cs-D", ns.cs_D, low=limits.CS_D_MIN, low_inclusive=True, high=limits.CS_D_MAX,
                                    high_inclusive=True, unit="1/s"),
                             number("--cs-q", ns.cs_q, low=limits.CS_Q_MIN, low_inclusive=True, high=limits.CS_Q_MAX,
                                    high_inclusive=True))


def rate_law_folder_name(law) -> str:
    """The part of a default results folder's name that names a rate-dependent sphere."""
    record = law.record()
    if record["rate_law"] == "johnson-cook":
        return f"jc{record['C']:g}_{record['reference_rate']:g}"
    return f"cs{record['D']:g}_{record['q']:g}"


def rate_law_line(law, where: str = " (dynamic FE)") -> str:
    """The sphere's rate law in one line (``where``: what it acts in, after "strain-rate dependence")."""
    record = law.record()
    if record["rate_law"] == "johnson-cook":
        return (f"strain-rate dependence{where}: Johnson-Cook, sigma_y (1 + C ln(max(eps_dot / eps_dot_0, 1))), "
                f"C = {record['C']:g}, eps_dot_0 = {record['reference_rate']:g} /s")
    return (f"strain-rate dependence{where}: Cowper-Symonds, sigma_y (1 + (eps_dot / D)^(1/q)), "
            f"D = {record['D']:g} /s, q = {record['q']:g}")


# the rate-aware law's e against the dynamic FE with the rate law, as measured (nfdmodel/README.md, The rate-aware
# law: bench_rate_aware.py, bench_rate_materials.py --dem, bench_rate_fit_data.py)
RATE_AWARE_ACCURACY = ("against the dynamic FE (nfdmodel/README.md): e within 1.4 % with Cowper-Symonds q 5 (R to "
                       "2.3, eps_dot 0.5-135 /s; 1.9 % against the FE at 3x its time steps) and Johnson-Cook C 0.05 "
                       "from 1e-3 /s; +3.5..+4.0 % with Johnson-Cook C 0.06 from 1 /s at 135 /s; to -8.3 % with a "
                       "strong Cowper-Symonds law (q 1-2); --rate-form relaxing: within 2 % in all these")
# the relaxing rate-aware law's, as measured (nfdmodel/README.md, The relaxing rate-aware law: bench_rate_materials.py)
RATE_RELAXING_ACCURACY = ("against the dynamic FE (nfdmodel/README.md): e within 1.98 % (rms 0.79 %) over 71 impacts "
                          "(Cowper-Symonds q 1-5, Johnson-Cook C 0.05-0.3 from 1e-3 and 1 /s; six spheres, mild steel "
                          "at 0.03-0.3 m/s), 1.98 % on the 35 its k and c were not fitted on")
