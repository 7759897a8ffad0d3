"""Laboratory commands: fit, record, decay."""

from __future__ import annotations


from faultslip import ranges
from faultslip.cli.common import _emit, _locked, _number, _outputs
from faultslip.errors import FaultslipError, InputError
from faultslip.friction.fitting import fit_figure, fit_rate_law, read_friction_data
from faultslip.friction.materials import save_user_fit
from faultslip.io.atomic import save_figure
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip.lab.records import analyze_record, free_decay, free_decay_from_record, hysteresis_figure, read_record
from faultslip.units import to_si


def cmd_fit(args) -> int:
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.data])["plot"]
    if not 0 <= args.bootstrap <= 100_000:
        raise FaultslipError(f"--bootstrap must lie between 0 and 100000 samples, got {args.bootstrap}")
    if args.loss not in ("linear", "soft_l1", "huber", "cauchy"):
        raise FaultslipError(f"--loss must be linear, soft_l1, huber or cauchy, got {args.loss!r}")
    if args.seed < 0:
        raise FaultslipError(f"--seed must not be negative, got {args.seed}")
    modulus = None
    if args.shear_modulus:

        modulus = ranges.check("shear_modulus", to_si(args.shear_modulus, "pressure", "shear modulus"))
    fixed = None if args.mu_m is None else _number(args.mu_m, "mu_m")
    data = read_friction_data(args.data, fixed_mu_m=fixed)
    fit = fit_rate_law(data, loss=args.loss, bootstrap=args.bootstrap, seed=args.seed, fixed_mu_m=fixed)
    report = fit.report(f"faultslip fit: {args.data}")
    if plot:

        with _locked(plot):
            save_figure(fit_figure(data, fit), plot, dpi=150)
        report.note(f"plot written to {args.plot}")
    if args.name:  # only after the fit succeeded: a failed fit never touches the registry

        path = save_user_fit(args.name, fit, shear_modulus=modulus, note=args.note or "")
        report.note(f"saved as {args.name!r} in {path}; use it with 'faultslip fault --lithology {args.name} ...'")
    return _emit(report, args.json)


def cmd_record(args) -> int:
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.record])["plot"]
    if args.velocity not in ("auto", "differentiate", "integrate"):
        raise FaultslipError(f"--velocity must be auto, differentiate or integrate, got {args.velocity!r}")
    for flag, kind, name in (("stiffness", "stiffness", "stiffness"), ("normal_load", "force", "normal_load"),
                             ("mass", "mass", "mass"), ("platform_speed", "speed", "platform_speed")):
        if getattr(args, flag):
            ranges.check(name, to_si(getattr(args, flag), kind, f"--{flag.replace('_', '-')}"))
    if args.dashpot and not to_si(args.dashpot, "damping", "dashpot") >= 0:
        raise FaultslipError(f"--dashpot must not be negative, got {args.dashpot}")
    record = read_record(args.record)
    speed = to_si(args.platform_speed, "speed", "platform speed") if args.platform_speed else None
    analysis = analyze_record(record, to_si(args.mass, "mass", "mass") if args.mass else
                              to_si(args.normal_load, "force", "normal load") / 9.80665,
                              to_si(args.stiffness, "stiffness", "stiffness"), to_si(args.normal_load, "force", "normal load"),
                              speed, to_si(args.dashpot, "damping", "dashpot") if args.dashpot else 0.0,
                              velocity_method=args.velocity)
    report = analysis.report(f"faultslip record analysis: {args.record}")
    if plot:

        with _locked(plot):
            save_figure(hysteresis_figure(analysis), plot, dpi=150)
        report.note(f"mu against sliding speed drawn to {args.plot}")
    return _emit(report, args.json)


def cmd_decay(args) -> int:
    stiffness = to_si(args.stiffness, "stiffness", "stiffness")
    if args.record:
        result = free_decay_from_record(read_record(args.record), stiffness)
    else:
        if args.ratio is None or args.cycles is None or args.frequency is None:
            raise InputError("give a free-decay record, or --ratio, --cycles and --frequency")
        frequency = to_si(args.frequency, "frequency", "damped frequency")  # rad/s is converted to Hz
        result = free_decay(_number(args.ratio, "amplitude ratio"), _number(args.cycles, "cycles"), frequency, stiffness)
    return _emit(result.report(), args.json)
